/* The thermal effect: heat conduction integrated by explicit forward Euler
 * with lumped heat capacity. Diffusivity alpha = conductivity /
 * (rho heat-capacity); dt_e = 2/lambda_max(Ce^-1 Ke), which on simplices is
 * 2/((d+1) alpha s_max). The step scales with the square of the size. */
#include "common/diffusion.h"

static double thermal_diffusivity(const dtm_material *m) {
  return m->prop[DTM_PROP_CONDUCTIVITY] / (m->prop[DTM_PROP_RHO] * m->prop[DTM_PROP_HEAT_CAPACITY]);
}

static int thermal_element_dt(void *state, const dtm_batch *b, double *dt, double *len) {
  (void)state;
  return dtm_diffusion_element_dt(thermal_diffusivity, b, dt, len);
}

const dtm_effect_class dtm_effect_thermal = {
    .api_version = DTM_EFFECT_API_VERSION,
    .name = "thermal",
    .summary = "heat conduction, forward Euler with lumped capacity (conductivity, heat-capacity, rho)",
    .role = DTM_ROLE_LIMITS,
    .needs = DTM_PROP_BIT(DTM_PROP_CONDUCTIVITY) | DTM_PROP_BIT(DTM_PROP_HEAT_CAPACITY) |
             DTM_PROP_BIT(DTM_PROP_RHO),
    .exponent = 2.0,
    .element_dt = thermal_element_dt,
};
