/* Shared implementation of the diffusion effects (thermal, hydraulic):
 * explicit forward Euler with lumped capacity, dt_e = 2/lambda_max(Ce^-1 Ke)
 * with the diffusivity D = conductivity / capacity each effect derives from
 * three properties of a material. An effect gives the names of its three
 * properties and how they combine; the rest is here. */
#ifndef DTM_PLUGIN_DIFFUSION_H
#define DTM_PLUGIN_DIFFUSION_H

#include "dtmap/effect.h"

/* Conductivity k and capacity per volume c from the effect's three
 * property values v[3] (in the order of its declaration). */
typedef void (*dtm_diffusion_combine_fn)(const double v[3], double *k, double *c);

typedef struct {
  int idx[3];                       /* catalogue indices of the three properties */
  dtm_diffusion_combine_fn combine; /* how they give k and c */
} dtm_diffusion_state;

/* create(): the state for the first three properties of props. */
int dtm_diffusion_create(const dtm_effect_args *a, const dtm_property *props, dtm_diffusion_combine_fn combine,
                         void **state);
/* element_dt of a diffusion effect; the characteristic length is
 * sqrt(2 D dt), the element length for a 2-node bar (dt = h^2/(2 D)). */
int dtm_diffusion_element_dt(void *state, const dtm_batch *b, double *dt, double *len);
/* coefficients() of a diffusion effect. */
int dtm_diffusion_coefficients(void *state, const dtm_material *m, const dtm_section *sec, dtm_operator_coeffs *c);

/* The class of a diffusion effect sym named name, with its summary, its
 * three properties (a dtm_property array) and how they combine. */
#define DTM_DIFFUSION_EFFECT(sym, ename, esummary, props, combine_fn)                                                  \
  static int sym##_create(const dtm_effect_args *a, void **state) {                                                    \
    return dtm_diffusion_create(a, props, combine_fn, state);                                                          \
  }                                                                                                                    \
  const dtm_effect_class sym = {.api_version = DTM_EFFECT_API_VERSION,                                                 \
                                .name = ename,                                                                         \
                                .summary = esummary,                                                                   \
                                .role = DTM_ROLE_LIMITS,                                                               \
                                .scheme = DTM_SCHEME_FORWARD_EULER,                                                    \
                                .exponent = 2.0,                                                                       \
                                .properties = props,                                                                   \
                                .create = sym##_create,                                                                \
                                .element_dt = dtm_diffusion_element_dt,                                                \
                                .coefficients = dtm_diffusion_coefficients,                                            \
                                .destroy = dtm_effect_free}

#endif
