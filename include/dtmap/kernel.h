/* Element kernels: geometry, characteristic lengths and the largest
 * eigenvalue of the lumped element problems Me^-1 Ke (elasticity) and
 * Ce^-1 Ke (scalar diffusion) for the linear element types and the
 * second-order ones (Gmsh types 9 tri6, 10 quad9, 11 tet10, 12 hex27,
 * 13 prism18, 14 pyr14, 16 quad8, 17 hex20, 18 prism15, 19 pyr13, with
 * Gmsh's node ordering and shape functions). Pure math: no
 * Gmsh, no allocation, no global state, so effects and tests can call them
 * on any small element block. All coordinates are in metres, given as
 * x[nn][3] (every element carries three coordinates, even in 1D and 2D; a 2D
 * element may lie in any plane, a 1D element along any line). */
#ifndef DTMAP_KERNEL_H
#define DTMAP_KERNEL_H

#include "dtmap/export.h"

#include <stddef.h>

/* Element types use Gmsh's type codes (the second-order codes are listed
 * above; callers pass Gmsh's numbers). */
enum {
  DTM_LINE2 = 1,
  DTM_TRI3 = 2,
  DTM_QUAD4 = 3,
  DTM_TET4 = 4,
  DTM_HEX8 = 5,
  DTM_PRISM6 = 6,
  DTM_PYR5 = 7,
  /* second order (HRZ lumping, generic quadrature path) */
  DTM_TRI6 = 9,
  DTM_QUAD9 = 10,
  DTM_TET10 = 11,
  DTM_HEX27 = 12,
  DTM_PRISM18 = 13,
  DTM_PYR14 = 14,
  DTM_QUAD8 = 16,
  DTM_HEX20 = 17,
  DTM_PRISM15 = 18,
  DTM_PYR13 = 19
};
#define DTM_MAX_NODES 27 /* the largest element dtmap will ever handle */

/* Elastic formulations. */
typedef enum {
  DTM_FORM_3D = 0,
  DTM_FORM_PLANE_STRAIN = 1,
  DTM_FORM_PLANE_STRESS = 2,
  DTM_FORM_BAR = 3
} dtm_formulation;

/* Scene names of the formulations, in dtm_formulation order, as an
 * initialiser of a NULL-terminated list (the one place they are spelt). */
#define DTM_FORMULATION_NAMES                                                                                          \
  { "3d", "plane-strain", "plane-stress", "bar", NULL }
/* Scene name of formulation f ("unknown" for none). */
DTM_EXPORT const char *dtm_formulation_name(int f);
/* The formulation elements of dimension dim use unless the scene says
 * otherwise: 3d, plane-strain, bar. */
DTM_EXPORT dtm_formulation dtm_formulation_default(int dim);

/* Characteristic length definitions (the `length=` attribute). */
typedef enum {
  DTM_LEN_EIGEN = 0,        /* C_D * 2/sqrt(lambda_max(Me^-1 Ke)): provably safe */
  DTM_LEN_SAFE = 1,         /* 2/sqrt(d+1) (sum_a h_a^-2)^-1/2 on simplices,
                               2/sqrt(sum_a |grad N_a|^2_L2 / m_a) on any
                               type (m_a the lumped mass per unit density:
                               int N_a, or HRZ for second order): safe for
                               nu >= 0 */
  DTM_LEN_MIN_EDGE = 2,     /* shortest edge: unsafe */
  DTM_LEN_MIN_ALTITUDE = 3, /* smallest altitude; other types: smallest
                               width across a facet: unsafe */
  DTM_LEN_INRADIUS = 4,     /* 2 x inradius = 2 d V / facet measure: unsafe */
  DTM_LEN_VOLUME_AREA = 5   /* V / A_max: unsafe */
} dtm_length_kind;
/* Scene names of the length kinds, in dtm_length_kind order (initialiser). */
#define DTM_LENGTH_NAMES                                                                                               \
  { "eigen", "safe", "min-edge", "min-altitude", "inradius", "volume-area", NULL }

/* Material moduli prepared once per material for a formulation. */
typedef struct {
  int form;        /* dtm_formulation */
  double lam;      /* first Lame parameter seen by the formulation, Pa
                      (plane stress: 2 lam mu/(lam + 2 mu); bar: 0) */
  double mu;       /* shear modulus, Pa (bar: 0) */
  double modulus;  /* P-wave modulus lam + 2 mu, Pa (bar: E) */
  double rho;      /* density, kg/m^3 */
  double cd;       /* dilatational wave speed sqrt(modulus/rho), m/s */
  int integration; /* DTM_INTEGRATION_*: the discrete model of second-order
                      elements (dtm_elastic_moduli_init: converged) */
} dtm_elastic_moduli;

/* How second-order elements are integrated, i.e. which discrete model the
 * element bound and the global estimate are for (src/kernel/curved.c). */
enum {
  DTM_INTEGRATION_CONVERGED = 0, /* curved elements: rules raised until the
                                    element matrices settle; straight-sided
                                    ones: the full rules (the default) */
  DTM_INTEGRATION_FULL = 1,      /* the full rules on every element */
  DTM_INTEGRATION_CALCULIX = 2   /* CalculiX's C3D10: tet10 with its 4-point
                                    rule and CalculiX's own lumping
                                    (docs/curved.md); other types as
                                    converged */
};

/* The name of a DTM_INTEGRATION_* model as the scene and the report spell
 * it ("converged", "full", "calculix"); "unknown" otherwise. Static. */
DTM_EXPORT const char *dtm_integration_name(int model);

/* Fill m from E (Pa), nu, rho (kg/m^3). Returns DTM_ERR_INPUT (with a
 * message) when E <= 0, rho <= 0, nu outside (-1, 0.5), or any is not finite. */
DTM_EXPORT int dtm_elastic_moduli_init(dtm_formulation f, double E, double nu, double rho, dtm_elastic_moduli *m);

/* Topological dimension and node count of a type (either pointer may be
 * NULL); DTM_ERR_INPUT, with a message naming the Gmsh type code, for
 * types dtmap does not handle (line3, third and higher order, ...). */
DTM_EXPORT int dtm_elem_info(int type, int *dim, int *nn);
/* Human-readable name of a type ("tet4", "tet10"), or "unknown". */
DTM_EXPORT const char *dtm_elem_name(int type);
/* 1 for line2, tri3 and tet4: the types of the simplex closed forms; 0 for
 * every other type, tri6 and tet10 included. */
DTM_EXPORT int dtm_elem_is_simplex(int type);
/* The linear parent of a type (tet4 for tet10, quad4 for quad8 and quad9,
 * ...), the type itself for a linear type, 0 for an unsupported one. Its
 * node count is the number of corner nodes. */
DTM_EXPORT int dtm_elem_parent(int type);

/* Length (1D), area (2D) or volume (3D) of the element, m^d: the integral
 * of det J, so negative for an inverted 3D element; a warped quadrangle
 * counts its area projected on the mean plane of its corners. Exact for
 * linear types and for straight-sided second-order elements (mid-side
 * nodes at the middle); curved ones are integrated with the element's
 * rule. NaN for an unknown type. Raises no error. */
DTM_EXPORT double dtm_elem_measure(int type, const double *x);

/* Lumped weights w[nn], summing to 1; the lumped mass of node a is
 * rho * measure * w_a. Linear types: row sums, w_a = (integral of N_a) /
 * measure (1/(d+1) on simplices, 1/nn on parallelepipeds, 3/16 for the
 * base nodes and 1/4 for the apex of an affine pyramid). Second-order
 * types: HRZ (Hinton-Rock-Zienkiewicz), w_a = integral(N_a^2) /
 * sum_b integral(N_b^2), the consistent mass diagonal scaled to the
 * element's mass: row sums would give zero or negative corner masses
 * (tet10: -V/20), HRZ is always positive (tet10: 1/36 at corners, 4/27
 * at mid-edge nodes; tri6: 1/19 and 16/57). For linear simplices and
 * parallelogram quad4 / parallelepiped hex8 the two coincide. NaN for a
 * zero-measure element. */
DTM_EXPORT void dtm_elem_lumped_weights(int type, const double *x, double *w);
/* The same weights into w[nn] for the discrete model (DTM_INTEGRATION_*),
 * returning the element's measure integrated with that model's rule (m^d;
 * NaN for an unknown type). Under DTM_INTEGRATION_CALCULIX a tet10 gets
 * CalculiX's C3D10 lumping and its 4-point measure. */
DTM_EXPORT double dtm_elem_lumped_model(int type, const double *x, int model, double *w);

/* The shape of an element, for dtmap's invalid-element policy (see
 * src/kernel/shape.c): the scaled Jacobian det J / (product of the column
 * lengths of J) at every integration point of the element's full rule and
 * at every node. */
enum {
  DTM_SHAPE_VALID = 0,  /* safely positive everywhere */
  DTM_SHAPE_CORNER = 1, /* safely positive at every integration point, not
                           at some node: the element matrices are well
                           defined; dtmap analyses and flags it */
  DTM_SHAPE_FOLDED = 2, /* negative at some integration point: inverted or
                           folded, refused */
  DTM_SHAPE_FLAT = 3,   /* no safely positive integration point, none
                           negative (or the nodes span no line, plane or
                           volume): zero measure, refused */
  DTM_SHAPE_INSIDE = 4  /* tri6, tet10: safely positive at every node and
                           integration point, but not everywhere inside by
                           a Bernstein bound (src/kernel/bezier.c):
                           inverted between the sampling points, refused */
};
typedef struct {
  int status;          /* DTM_SHAPE_* */
  double min_jacobian; /* smallest scaled Jacobian over the integration
                          points and nodes, in [-1, 1] (1: right angles) */
  int node;            /* the node where it occurs, -1 at an integration
                          point (always -1 on linear simplices) */
  int point;           /* first integration point where det J is not safely
                          positive, -1 when none */
} dtm_shape;
/* Classify the element of type with coordinates x[nn][3] (m) into *s.
 * DTM_ERR_INPUT only for a type dtmap does not handle. Linear simplices
 * take a few ns (one constant Jacobian), hex8 about a microsecond. */
DTM_EXPORT int dtm_kernel_shape(int type, const double *x, dtm_shape *s);
/* One phrase for a DTM_SHAPE_* status, for messages. */
DTM_EXPORT const char *dtm_shape_describe(int status);

/* How curved a second-order element is (src/kernel/curved.c, bezier.c). */
typedef struct {
  double offset;    /* largest distance of a second-order node from where the
                       linear parent puts it, over its edge length (0:
                       straight-sided, and for linear types) */
  double jac_ratio; /* min det J / max det J over the element: on tri6 and
                       tet10 a lower bound from Bernstein coefficients
                       (bounded = 1), on the other types over the nodes and
                       the full rule's points; 1 when det J is constant */
  int bounded;      /* 1 when jac_ratio is a bound over the whole element */
  int level;        /* rule level the converged model integrates it with
                       (0: the full rule, for straight-sided elements) */
  int settled;      /* 0 when the levels stopped before the element settled */
} dtm_curvature;
/* Fill *c for the element of type with coordinates x[nn][3] (m). Linear
 * types get offset 0 and ratio 1. DTM_ERR_INPUT only for an unsupported
 * type. A straight-sided element costs a few node evaluations, a curved
 * one the converged rule's search (tens of microseconds on tet10). */
DTM_EXPORT int dtm_kernel_curvature(int type, const double *x, dtm_curvature *c);

/* Largest eigenvalue of Me^-1 Ke (1/s^2) for isotropic linear elasticity
 * with lumped mass (see dtm_elem_lumped_weights: row sums for linear
 * types, HRZ for second-order ones): closed form on linear simplices
 * (accurate to a few eps of the value the coordinates define), the
 * symmetric eigenproblem of the fully integrated element otherwise (quad
 * 2x2, hex 2x2x2, prism 3-point triangle x 2-point line, pyramid 3x3x3
 * collapsed Gauss; second order, exact for the mass and stiffness of
 * straight-sided elements: tri6 6-point degree 4, tet10 14-point degree
 * 5, quad8/quad9 3x3 and hex20/hex27 3x3x3 Gauss, prism15/prism18 6-point
 * triangle x 3-point Gauss, pyr13/pyr14 3x3 Gauss x 3-point Gauss-Jacobi
 * on the collapsed cube). The element's critical step is 2/sqrt(lambda).
 * 3D types need DTM_FORM_3D, 2D types plane strain or plane stress, line2
 * the bar. Returns 0, or DTM_ERR_INPUT for an inverted or degenerate
 * element (Jacobian determinant not safely positive at an integration
 * point of the rule; an element inverted only at a corner is analysed, see
 * dtm_kernel_shape), a type/formulation mismatch or an unsupported type. The kernel
 * does not know the element's Gmsh tag: a caller that wants it in the
 * message clears the error and raises its own. No allocation (second-order
 * element matrices, up to 81 x 81, live on the stack); tet4 takes ~0.1 us,
 * a straight-sided tet10 ~14-18 us of CPU (reference tensors,
 * src/kernel/affine.c), hex20 ~0.13 ms, hex27 ~0.2 ms, a curved tet10 at
 * level 6 ~0.1 ms with its level kept (dtm_kernel_elastic_lambda_at), 0.27
 * ms searching it (measured at load 12 on 2 cores). */
DTM_EXPORT int dtm_kernel_elastic_lambda(int type, const dtm_elastic_moduli *m, const double *x, double *lambda);
/* The same for an element whose converged rule level the caller kept
 * (level: what the level search of the "converged" model returned for
 * it, dtm_batch.level; 0 for a straight-sided element): the level search
 * (tens of microseconds on a curved tet10) is skipped, the result is the
 * same bitwise. level -1: searched, as dtm_kernel_elastic_lambda. */
DTM_EXPORT int dtm_kernel_elastic_lambda_at(int type, const dtm_elastic_moduli *m, const double *x, int level,
                                            double *lambda);
/* Elements the batched bound takes at once. */
#define DTM_KERNEL_LANES 4
/* dtm_kernel_elastic_lambda_at of count (1 .. DTM_KERNEL_LANES) elements of
 * one type, with moduli m[k], coordinates x[k] and kept levels level[k]
 * (NULL: searched, -1 each): lambda[k] is bitwise the one-element call's.
 * Types whose element problem is solved by the Householder reduction with
 * at most 30 unknowns (tet10, hex8, prism6, pyr5; quad8 and quad9 in the
 * plane) solve the count problems side by side in vector lanes (straight
 * tet10: 0.7x the time per element, bench/roofline.sh, docs/performance.md);
 * the others are taken one by one. On an error, *failed is the index of the element (the
 * lambdas before it are set) and the message is the one-element call's. */
DTM_EXPORT int dtm_kernel_elastic_lambda_lanes(int type, int count, const dtm_elastic_moduli *const *m,
                                               const double *const *x, const int *level, double *lambda, int *failed);

/* Largest eigenvalue of Ce^-1 Ke (1/s) for scalar diffusion with
 * diffusivity alpha (m^2/s) and lumped capacity (row sums for linear
 * types, HRZ for second-order ones), same rules as above. The
 * forward-Euler critical step is 2/lambda. On linear simplices
 * lambda = (d+1) alpha s_max.
 * DTM_ERR_INPUT for alpha not finite and > 0, a degenerate or inverted
 * element or an unsupported type. */
DTM_EXPORT int dtm_kernel_diffusion_lambda(int type, double alpha, const double *x, double *lambda);

/* Geometric length of the given kind (m); the definitions for each type
 * are listed in src/kernel/length.c. For a second-order type the geometric
 * kinds (MIN_EDGE, MIN_ALTITUDE, INRADIUS, VOLUME_AREA) are those of its
 * linear parent on the corner nodes (mid-side nodes and curvature are
 * ignored); DTM_LEN_SAFE uses the element itself with its HRZ masses.
 * DTM_LEN_EIGEN is not geometric and returns NaN here, as do an unknown
 * type and DTM_LEN_SAFE on a degenerate or inverted element. Raises no
 * error. */
DTM_EXPORT double dtm_kernel_length(int type, dtm_length_kind kind, const double *x);

/* Largest eigenvalue of the symmetric n x n matrix a (row-major, n >= 1,
 * destroyed), by cyclic Jacobi: within a few eps of the matrix norm. */
DTM_EXPORT double dtm_eig_sym_max(int n, double *a);

#endif
