/* The thermal effect: heat conduction integrated by explicit forward Euler
 * with lumped heat capacity. Conductivity k, capacity rho c, diffusivity
 * alpha = k/(rho c); dt_e = 2/lambda_max(Ce^-1 Ke), which on simplices is
 * 2/((d+1) alpha s_max). The step scales with the square of the size. */
#include "common/diffusion.h"

static void thermal_coeffs(const dtm_material *m, double *k, double *c) {
  *k = m->prop[DTM_PROP_CONDUCTIVITY];
  *c = m->prop[DTM_PROP_RHO] * m->prop[DTM_PROP_HEAT_CAPACITY];
}

static int thermal_element_dt(void *state, const dtm_batch *b, double *dt, double *len) {
  (void)state;
  return dtm_diffusion_element_dt(thermal_coeffs, b, dt, len);
}

static int thermal_coefficients(void *state, const dtm_material *m, dtm_operator_coeffs *c) {
  (void)state;
  return dtm_diffusion_coefficients(thermal_coeffs, m, c);
}

const dtm_effect_class dtm_effect_thermal = {
    .api_version = DTM_EFFECT_API_VERSION,
    .name = "thermal",
    .summary = "heat conduction, forward Euler with lumped capacity (conductivity, heat-capacity, rho)",
    .role = DTM_ROLE_LIMITS,
    .needs = DTM_PROP_BIT(DTM_PROP_CONDUCTIVITY) | DTM_PROP_BIT(DTM_PROP_HEAT_CAPACITY) | DTM_PROP_BIT(DTM_PROP_RHO),
    .exponent = 2.0,
    .element_dt = thermal_element_dt,
    .coefficients = thermal_coefficients,
};
