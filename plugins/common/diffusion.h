/* Shared implementation of the diffusion effects (thermal, hydraulic):
 * explicit forward Euler with lumped capacity, dt_e = 2/lambda_max(Ce^-1 Ke)
 * with the diffusivity D = conductivity / capacity each effect derives from
 * a material. */
#ifndef DTM_PLUGIN_DIFFUSION_H
#define DTM_PLUGIN_DIFFUSION_H

#include "dtmap/effect.h"

/* Conductivity k and capacity per volume c of a material (D = k/c). */
typedef void (*dtm_diffusion_coeffs_fn)(const dtm_material *m, double *k, double *c);

/* element_dt of a diffusion effect; the characteristic length is
 * sqrt(2 D dt), the element length for a 2-node bar (dt = h^2/(2 D)). */
int dtm_diffusion_element_dt(dtm_diffusion_coeffs_fn coeffs, const dtm_batch *b, double *dt, double *len);
/* coefficients() of a diffusion effect. */
int dtm_diffusion_coefficients(dtm_diffusion_coeffs_fn coeffs, const dtm_material *m, dtm_operator_coeffs *c);

#endif
