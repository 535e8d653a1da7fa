/* The kernel's interface to the modules above it (the matrix-free operator
 * of src/spectral/): full-integration rules, reference shape functions, the
 * small dense Jacobian algebra, and the formulation check. Internal to
 * libdtmap (hidden symbols); effects use the public include/dtmap/kernel.h. */
#ifndef DTMAP_KERNEL_REFERENCE_H
#define DTMAP_KERNEL_REFERENCE_H

#include "dtmap/kernel.h"

#define DTM_K_NODES 27    /* most nodes among the types the kernels handle (hex27) */
#define DTM_K_DOF 81      /* most displacement unknowns (hex27, 3 per node) */
#define DTM_K_LEVEL_MAX 8 /* most Gauss points per direction of a levelled rule */
#define DTM_K_QP 512      /* most quadrature points of a rule (a levelled rule at DTM_K_LEVEL_MAX in 3D) */
#define DTM_K_RULE_C3D10 (DTM_K_LEVEL_MAX + 1) /* the "level" of CalculiX's C3D10 rule on tet10 (curved.c) */
#define DTM_K_FACETS 6                         /* of the linear parent: second-order types reuse it */
#define DTM_K_EDGES 12

/* A quadrature rule in rule coordinates p. These are Gmsh's reference
 * coordinates (u, v, w) except for the pyramid, where they are collapsed
 * coordinates (a, b, w) with u = (1 - w) a, v = (1 - w) b; the weights then
 * include the Duffy factor (1 - w)^2. */
typedef struct {
  int n;                 /* number of points */
  double p[DTM_K_QP][3]; /* rule coordinates of the points */
  double w[DTM_K_QP];    /* weights (sum = reference measure) */
} dtm_qrule;

/* Full-integration rule of a supported type (see quadrature.c): exact for
 * the stiffness and the consistent mass of straight-sided elements. */
void dtm_ref_rule(int type, dtm_qrule *q);
/* The levelled rule of type with n Gauss points per direction
 * (quadrature_level.c); returns n, or 0 (q->n = 0) for a type without
 * one (pyramids) or n outside [1, DTM_K_LEVEL_MAX]. For tet10, n =
 * DTM_K_RULE_C3D10 gives CalculiX's C3D10 rule (dtm_ref_rule_c3d10). */
int dtm_ref_rule_level(int type, int n, dtm_qrule *q);
/* The 4-point degree-2 rule on the unit tetrahedron (barycentric orbit
 * (a, a, a, 1 - 3a), a = (5 - sqrt 5)/20, weights 1/24) with which
 * CalculiX and Abaqus integrate C3D10 (quadrature.c). */
void dtm_ref_rule_c3d10(dtm_qrule *q);
/* The rule that integrates the element of type with coordinates x[nn][3]
 * in the discrete model (DTM_INTEGRATION_*), as the element kernels do
 * (curved.c): the full rule (returns 0), a levelled rule (returns its
 * level) or, under DTM_INTEGRATION_CALCULIX on tet10, CalculiX's rule
 * (returns DTM_K_RULE_C3D10). */
int dtm_ref_rule_elem(int type, const double *x, int model, dtm_qrule *q);
/* The level dtm_ref_rule_elem returns under DTM_INTEGRATION_CONVERGED,
 * without the rule, and into *rem the estimated remaining quadrature error
 * of the element at that level: the Frobenius norm of T_conv - T_level,
 * T the geometric stiffness tensor scaled by the element's lumped masses
 * per unit capacity (curved.c), 1/m^2, from the last changes of the level
 * search; 0 for an element integrated exactly (straight-sided) or without a
 * converged model (pyramids, inverted near a node). */
int dtm_ref_level_elem(int type, const double *x, double *rem);
/* 1 when curved elements of type get levelled rules (the second-order
 * types but pyramids), else 0. */
int dtm_ref_levelled(int type);
/* What a kept level saves (measure.c): an element whose converged level
 * (dtm_ref_rule_elem under DTM_INTEGRATION_CONVERGED: 0 for a straight-
 * sided element) is known. dtm_ref_rule_at gives the rule the model
 * integrates it with and returns what dtm_ref_rule_elem would (0, the level,
 * or DTM_K_RULE_C3D10), without the level search; dtm_elem_lumped_at and
 * dtm_elem_measure_at are dtm_elem_lumped_model and dtm_elem_measure with
 * that rule (level -1: searched, as they do). The same numbers, bitwise. */
int dtm_ref_rule_at(int type, int model, int level, dtm_qrule *q);
/* dtm_kernel_curvature without the level search (the analysis keeps the
 * levels: offset, jac_ratio and bounded only; level 0, settled 1). */
int dtm_kernel_curvature_shape(int type, const double *x, dtm_curvature *c);
int dtm_ref_rule_id(int type, int model, int level); /* what dtm_ref_rule_at returns, without q */
double dtm_elem_lumped_at(int type, const double *x, int model, int level, double *w);
/* The matrix of a solid 3D element with coordinates x[nn][3] integrated by
 * the rule id (what dtm_ref_rule_id gives: 0 the full rule, a level, or
 * DTM_K_RULE_C3D10), as the kernel assembles it (dtm_elem_assemble: a
 * curved element's level the search has just integrated comes back from
 * the per-thread memo, bitwise): the elastic stiffness K[3 nn][3 nn] of
 * moduli m (lam and mu), or the Laplacian K[nn][nn] when m is NULL, in the
 * global axes (a 3D element's frame only moves the origin). Returns -1, or
 * the first rule point where det J is not safely positive; -2 for a type
 * that is not a 3D solid or a rule without a table. */
int dtm_elem_matrix_at(int type, const double *x, int id, const dtm_elastic_moduli *m, double *K);
/* 1 for a tet10 with coordinates x[10][3] whose matrices the kernel takes
 * from the reference tensors (affine.c: every mid-edge node at its edge's
 * middle to 1e-14 of the edge, and det J safely positive): its map is
 * affine, so a rule of degree 2 integrates its stiffness exactly; else 0. */
int dtm_elem_affine(int type, const double *x);
double dtm_elem_measure_at(int type, const double *x, int level);
/* Shape functions N[nn] and their gradients dN[DTM_K_NODES][3] (all rows
 * written, unused ones zero) with respect to the reference coordinates
 * (u, v, w), at rule coordinates p. */
void dtm_ref_eval(int type, const double p[3], double *N, double (*dN)[3]);
/* Determinant of the d x d leading block of J (d = 1, 2, 3). */
double dtm_mat_det(int d, const double J[3][3]);
/* Product of the column lengths of the d x d block of J: |det J| never
 * exceeds it (Hadamard), so det J > 32 eps hadamard is "safely positive". */
double dtm_mat_hadamard(int d, const double J[3][3]);
/* K = J^-1 (d x d blocks), given dj = det J. */
void dtm_mat_inverse(int d, const double J[3][3], double dj, double K[3][3]);

/* Coordinates x[nn][3] (m) of a well-shaped element of type whose mean
 * edge length is h: equilateral triangle, regular tetrahedron, square,
 * cube, right prism on an equilateral triangle with square sides, pyramid
 * with all eight edges h, bar; second-order nodes at the mid-edges and
 * face and cell centres. DTM_ERR_INPUT for an unsupported type. */
int dtm_elem_regular(int type, double h, double *x);

/* Raise DTM_ERR_INPUT unless formulation f suits an element of dimension d. */
int dtm_form_check(int type, int d, int f);

#endif
