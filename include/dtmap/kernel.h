/* Element kernels: geometry, characteristic lengths and the largest
 * eigenvalue of the lumped element problems Me^-1 Ke (elasticity) and
 * Ce^-1 Ke (scalar diffusion) for the linear element types. Pure math: no
 * Gmsh, no allocation, no global state, so effects and tests can call them
 * on any small element block. All coordinates are in metres, given as
 * x[nn][3] (every element carries three coordinates, even in 1D and 2D; a 2D
 * element may lie in any plane, a 1D element along any line). */
#ifndef DTMAP_KERNEL_H
#define DTMAP_KERNEL_H

#include <stddef.h>

/* Element types use Gmsh's type codes. */
enum {
  DTM_LINE2 = 1,
  DTM_TRI3 = 2,
  DTM_QUAD4 = 3,
  DTM_TET4 = 4,
  DTM_HEX8 = 5,
  DTM_PRISM6 = 6,
  DTM_PYR5 = 7
};
#define DTM_MAX_NODES 27 /* the largest element dtmap will ever handle */

/* Elastic formulations. */
typedef enum {
  DTM_FORM_3D = 0,
  DTM_FORM_PLANE_STRAIN = 1,
  DTM_FORM_PLANE_STRESS = 2,
  DTM_FORM_BAR = 3
} dtm_formulation;

/* Characteristic length definitions (the `length=` attribute). */
typedef enum {
  DTM_LEN_EIGEN = 0,        /* C_D * 2/sqrt(lambda_max(Me^-1 Ke)): provably safe */
  DTM_LEN_SAFE = 1,         /* 2/sqrt(d+1) (sum_a h_a^-2)^-1/2 on simplices: safe */
  DTM_LEN_MIN_EDGE = 2,     /* shortest edge: unsafe */
  DTM_LEN_MIN_ALTITUDE = 3, /* smallest altitude: unsafe */
  DTM_LEN_INRADIUS = 4,     /* 2 x inradius: unsafe */
  DTM_LEN_VOLUME_AREA = 5   /* V / A_max: unsafe */
} dtm_length_kind;

/* Material moduli prepared once per material for a formulation. */
typedef struct {
  int form;      /* dtm_formulation */
  double lam;    /* first Lame parameter seen by the formulation, Pa
                    (plane stress: 2 lam mu/(lam + 2 mu); bar: 0) */
  double mu;     /* shear modulus, Pa (bar: 0) */
  double modulus;/* P-wave modulus lam + 2 mu, Pa (bar: E) */
  double rho;    /* density, kg/m^3 */
  double cd;     /* dilatational wave speed sqrt(modulus/rho), m/s */
} dtm_elastic_moduli;

/* Fill m from E (Pa), nu, rho (kg/m^3). Returns DTM_ERR_INPUT (with a
 * message) when E <= 0, rho <= 0, nu outside (-1, 0.5), or any is not finite. */
int dtm_elastic_moduli_init(dtm_formulation f, double E, double nu, double rho,
                            dtm_elastic_moduli *m);

/* Topological dimension and node count of a type; DTM_ERR_INPUT for types
 * dtmap does not handle (second order included). */
int dtm_elem_info(int type, int *dim, int *nn);
/* Human-readable name of a type ("tet4"), or "unknown". */
const char *dtm_elem_name(int type);
/* 1 for line2, tri3 and tet4. */
int dtm_elem_is_simplex(int type);

/* Length (1D), area (2D) or volume (3D) of the element, m^d. */
double dtm_elem_measure(int type, const double *x);

/* Row-sum lumped weights w[nn]: w_a = (integral of N_a) / measure, summing
 * to 1. The lumped mass of node a is rho * measure * w_a. */
void dtm_elem_lumped_weights(int type, const double *x, double *w);

/* Largest eigenvalue of Me^-1 Ke (1/s^2) for isotropic linear elasticity
 * with row-sum lumped mass: closed form on simplices, the small symmetric
 * eigenproblem of the fully integrated element otherwise. The element's
 * critical step is 2/sqrt(lambda). Returns 0, or DTM_ERR_INPUT for an
 * inverted or degenerate element or a type/formulation mismatch. */
int dtm_kernel_elastic_lambda(int type, const dtm_elastic_moduli *m,
                              const double *x, double *lambda);

/* Largest eigenvalue of Ce^-1 Ke (1/s) for scalar diffusion with
 * diffusivity alpha (m^2/s) and row-sum lumped capacity. The forward-Euler
 * critical step is 2/lambda. On simplices lambda = (d+1) alpha s_max. */
int dtm_kernel_diffusion_lambda(int type, double alpha, const double *x,
                                double *lambda);

/* Geometric length of the given kind (m). DTM_LEN_EIGEN is not geometric
 * and returns NaN here. */
double dtm_kernel_length(int type, dtm_length_kind kind, const double *x);

/* Largest eigenvalue of the symmetric n x n matrix a (row-major, destroyed). */
double dtm_eig_sym_max(int n, double *a);

#endif
