/* Shared implementation of the diffusion effects (thermal, hydraulic):
 * explicit forward Euler with lumped capacity, dt_e = 2/lambda_max(Ce^-1 Ke)
 * from the diffusivity each effect derives from a material. */
#ifndef DTM_PLUGIN_DIFFUSION_H
#define DTM_PLUGIN_DIFFUSION_H

#include "dtmap/effect.h"

/* Diffusivity (m^2/s) of a material; the material has the effect's needs. */
typedef double (*dtm_diffusivity_fn)(const dtm_material *m);

/* element_dt for a diffusion effect whose state is a dtm_diffusivity_fn
 * pointer holder; the characteristic length is sqrt(2 D dt), which is the
 * element length for a 2-node bar (dt = h^2/(2 D)). */
int dtm_diffusion_element_dt(dtm_diffusivity_fn diffusivity, const dtm_batch *b,
                             double *dt, double *len);

#endif
