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
} damping_coeffs;

typedef struct {
  damping_coeffs all; /* the scene element's coefficients */
  int ixi, ia, ib;    /* catalogue indices of the per-material xi, alpha, beta */
} damping_state;

static int damping_create(const dtm_effect_args *a, void **state) {
  damping_state d;
  DTM_CHECK(dtm_effect_args_number(a, "xi", &d.all.xi));
  DTM_CHECK(dtm_effect_args_number(a, "alpha", &d.all.alpha));
  DTM_CHECK(dtm_effect_args_number(a, "beta", &d.all.beta));
  d.ixi = dtm_effect_args_property(a, "xi");
  d.ia = dtm_effect_args_property(a, "alpha");
  d.ib = dtm_effect_args_property(a, "beta");
  damping_state *s = malloc(sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  *s = d;
  *state = s;
  return DTM_OK;
}

/* The material's (xi, alpha, beta) if it gives any, else the scene's. */
static damping_coeffs coeffs_for(const damping_state *s, const dtm_material *m) {
  int hx = dtm_material_has(m, s->ixi), ha = dtm_material_has(m, s->ia), hb = dtm_material_has(m, s->ib);
  if (!hx && !ha && !hb) return s->all;
  return (damping_coeffs){hx ? dtm_material_get(m, s->ixi) : 0.0, ha ? dtm_material_get(m, s->ia) : 0.0,
                          hb ? dtm_material_get(m, s->ib) : 0.0};
}

/* xi at omega for the material. */
static double xi_at(const damping_state *s, const dtm_material *m, double omega) {
  damping_coeffs c = coeffs_for(s, m);
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
  damping_coeffs c = coeffs_for(state, m);
  *alpha = c.alpha;
  *beta = c.beta + 2.0 * c.xi / omega_top;
  return DTM_OK;
}

static const dtm_param params[] = {
    {"xi", DTM_PARAM_NUMBER, "0", 0, HUGE_VAL, 0, NULL, 0, "", "damping ratio at the element's top frequency"},
    {"alpha", DTM_PARAM_NUMBER, "0", 0, HUGE_VAL, 0, NULL, 0, "1/s", "Rayleigh mass-proportional coefficient"},
    {"beta", DTM_PARAM_NUMBER, "0", 0, HUGE_VAL, 0, NULL, 0, "s", "Rayleigh stiffness-proportional coefficient"},
    {NULL, 0, NULL, 0, 0, 0, NULL, 0, NULL, NULL}};

/* A material's own xi, alpha or beta replace the scene element's. */
static const dtm_property properties[] = {
    {"xi", "", 0, HUGE_VAL, 0, 0, "this material's damping ratio (replaces the effect's)"},
    {"alpha", "1/s", 0, HUGE_VAL, 0, 0, "this material's Rayleigh alpha (replaces the effect's)"},
    {"beta", "s", 0, HUGE_VAL, 0, 0, "this material's Rayleigh beta (replaces the effect's)"},
    {NULL, NULL, 0, 0, 0, 0, NULL}};

const dtm_effect_class dtm_effect_damping = {
    .api_version = DTM_EFFECT_API_VERSION,
    .name = "damping",
    .summary = "viscous damping: wave steps x (sqrt(1+xi^2) - xi) at omega_e = 2/dt_e (xi, or Rayleigh "
               "alpha and beta; per material too)",
    .role = DTM_ROLE_MODIFIES_WAVES,
    .scheme = DTM_SCHEME_NONE,
    .exponent = 0.0,
    .params = params,
    .properties = properties,
    .create = damping_create,
    .wave_factor = damping_factor,
    .rayleigh = damping_rayleigh,
    .destroy = dtm_effect_free,
};
