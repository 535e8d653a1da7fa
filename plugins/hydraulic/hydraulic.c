/* The hydraulic effect: pore-fluid diffusion integrated by explicit forward
 * Euler with lumped storage. Conductivity permeability/viscosity, capacity
 * storage, so D = permeability / (viscosity storage); the kernel is the
 * thermal one (plugins/common/diffusion.c). */
#include "common/diffusion.h"

static void hydraulic_coeffs(const dtm_material *m, double *k, double *c) {
  *k = m->prop[DTM_PROP_PERMEABILITY] / m->prop[DTM_PROP_VISCOSITY];
  *c = m->prop[DTM_PROP_STORAGE];
}

static int hydraulic_element_dt(void *state, const dtm_batch *b, double *dt, double *len) {
  (void)state;
  return dtm_diffusion_element_dt(hydraulic_coeffs, b, dt, len);
}

static int hydraulic_coefficients(void *state, const dtm_material *m, dtm_operator_coeffs *c) {
  (void)state;
  return dtm_diffusion_coefficients(hydraulic_coeffs, m, c);
}

const dtm_effect_class dtm_effect_hydraulic = {
    .api_version = DTM_EFFECT_API_VERSION,
    .name = "hydraulic",
    .summary = "pore-fluid diffusion, forward Euler with lumped storage (permeability, viscosity, storage)",
    .role = DTM_ROLE_LIMITS,
    .needs = DTM_PROP_BIT(DTM_PROP_PERMEABILITY) | DTM_PROP_BIT(DTM_PROP_VISCOSITY) | DTM_PROP_BIT(DTM_PROP_STORAGE),
    .exponent = 2.0,
    .element_dt = hydraulic_element_dt,
    .coefficients = hydraulic_coefficients,
};
