/* The damping effect: it limits nothing itself, it scales the steps of the
 * wave-type effects by sqrt(1 + xi^2) - xi, the exact central-difference
 * limit of a damped oscillator whose damping force uses the lagged
 * half-step velocity v_{n-1/2} (what fully explicit codes do; with a centred
 * velocity the limit would stay 2/omega). xi is the damping ratio at the
 * element's own top frequency omega_e = 2/dt_e: a constant xi, or Rayleigh
 * xi(omega) = alpha/(2 omega) + beta omega/2, so stiffness-proportional
 * damping is charged at the frequency that sets the step. A material's own
 * xi, alpha or beta replace the global ones for its elements. */
#include <math.h>
#include <stdlib.h>

#include "dtmap/effect.h"

typedef struct {
  double xi;    /* constant damping ratio */
  double alpha; /* Rayleigh mass coefficient, 1/s */
  double beta;  /* Rayleigh stiffness coefficient, s */
} damping_state;

static int damping_create(const dtm_effect_args *a, void **state) {
  damping_state d;
  DTM_CHECK(dtm_effect_args_double(a, "xi", 0.0, &d.xi));
  DTM_CHECK(dtm_effect_args_double(a, "alpha", 0.0, &d.alpha));
  DTM_CHECK(dtm_effect_args_double(a, "beta", 0.0, &d.beta));
  if (d.xi < 0 || d.alpha < 0 || d.beta < 0) return dtm_effect_args_error(a, "xi, alpha and beta must be >= 0");
  damping_state *s = malloc(sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  *s = d;
  *state = s;
  return DTM_OK;
}

/* The material's (xi, alpha, beta) if it gives any, else the global ones. */
static damping_state coeffs_for(const damping_state *s, const dtm_material *m) {
  const unsigned bx = DTM_PROP_BIT(DTM_PROP_XI), ba = DTM_PROP_BIT(DTM_PROP_ALPHA), bb = DTM_PROP_BIT(DTM_PROP_BETA);
  if (!(m->have & (bx | ba | bb))) return *s;
  return (damping_state){(m->have & bx) ? m->prop[DTM_PROP_XI] : 0.0, (m->have & ba) ? m->prop[DTM_PROP_ALPHA] : 0.0,
                         (m->have & bb) ? m->prop[DTM_PROP_BETA] : 0.0};
}

/* xi at omega for the material. */
static double xi_at(const damping_state *s, const dtm_material *m, double omega) {
  damping_state c = coeffs_for(s, m);
  return c.xi + c.alpha / (2.0 * omega) + c.beta * omega / 2.0;
}

/* sqrt(1 + xi^2) - xi, written as 1/(sqrt(1 + xi^2) + xi) so that it keeps
 * full precision when xi is large (stiffness-proportional damping). */
static int damping_factor(void *state, const dtm_material *m, double omega, double *factor) {
  double xi = xi_at(state, m, omega);
  *factor = 1.0 / (sqrt(1.0 + xi * xi) + xi);
  return DTM_OK;
}

/* Equivalent Rayleigh coefficients: a constant xi is charged to the
 * stiffness term at the top frequency, beta = 2 xi / omega_top, so that
 * xi(omega_top) is the scene's value. */
static int damping_rayleigh(void *state, const dtm_material *m, double omega_top, double *alpha, double *beta) {
  damping_state c = coeffs_for(state, m);
  *alpha = c.alpha;
  *beta = c.beta + 2.0 * c.xi / omega_top;
  return DTM_OK;
}

const dtm_effect_class dtm_effect_damping = {
    .api_version = DTM_EFFECT_API_VERSION,
    .name = "damping",
    .summary = "viscous damping: wave steps x (sqrt(1+xi^2) - xi) at omega_e = 2/dt_e (xi=, or Rayleigh "
               "alpha= beta=; per material too)",
    .role = DTM_ROLE_MODIFIES_WAVES,
    .needs = 0,
    .exponent = 0.0,
    .create = damping_create,
    .wave_factor = damping_factor,
    .rayleigh = damping_rayleigh,
    .destroy = dtm_effect_free,
};
