/* The semi-discrete problem behind a spectral effect, per material: which
 * equation (elastic waves or scalar diffusion) with which coefficients. An
 * effect fills it (dtm_effect_class.coefficients); the nodal bound, the
 * matrix-free operator (operator.h), the global estimate and `dtmap verify`
 * read it. Plain data, owned by the caller. */
#ifndef DTMAP_PROBLEM_H
#define DTMAP_PROBLEM_H

#include "dtmap/kernel.h"

enum {
  DTM_OP_NONE = 0,     /* not a spectral effect (e.g. a length rule) */
  DTM_OP_ELASTIC = 1,  /* M u'' + K u = 0, central differences, dt = 2/omega */
  DTM_OP_DIFFUSION = 2 /* C u' + K u = 0, forward Euler, dt = 2/lambda */
};
typedef struct {
  int kind;                          /* DTM_OP_* */
  double capacity;                   /* lumped "mass" per volume: rho (elastic), rho c
                                        (thermal), storage (hydraulic) */
  double conductivity;               /* diffusion: k, or permeability/viscosity */
  dtm_elastic_moduli mod;            /* elastic: moduli of the formulation */
  double section_factor;             /* thickness (m) or area (m^2) of the elements' section that
                                        multiplies stiffness and mass; 0: none (1). The core sets it. */
  int dt_is_bound;                   /* 1 when element_dt returns the element's own
                                        eigenvalue bound, 2/sqrt(lambda_e) or 2/lambda_e
                                        (undamped), so the nodal bound can reuse it */
  double E, nu;                      /* elastic: Young's modulus (Pa) and Poisson's ratio, for shell and beam
                                        sections, whose kernels need both whatever the formulation */
  const struct dtm_section *section; /* the elements' section (NULL: none). The core sets it;
                                        shell and beam sections add 3 rotations per node */
} dtm_operator_coeffs;

#endif
