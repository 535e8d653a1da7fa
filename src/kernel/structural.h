/* The kernel's interface for structural elements (internal to libdtmap,
 * like reference.h): the element matrices and the lumped-mass eigenvalue
 * bounds of a flat facet Reissner-Mindlin shell (tri3, quad4) and a
 * two-node 3D Timoshenko beam (line2), with six unknowns per node in
 * global axes, ordered (ux, uy, uz, rx, ry, rz) node after node: unknown
 * (a, i) sits at 6 a + i. Pure math, no allocation: every matrix lives on
 * the stack or in the caller's struct. docs/structural-kernels.md derives
 * the formulations, the closed forms the tests check and the comparison
 * with an independent Python code (tests/reference/shell_ref.py).
 *
 * Rotary inertia. With physical rotary inertia a Mindlin shell has a
 * thickness-shear mode of omega^2 = 12 k G / (rho t^2) (a beam: k G A /
 * (rho I)) whatever the element size, which for t << h governs the
 * explicit step. Explicit codes therefore scale the rotary inertia. Two
 * conventions:
 *
 *   DTM_ROTARY_PHYSICAL  J_a = (t^2/12) m_a for the shell, m_a the node's
 *     translational mass (rho t times the row sum, integral of N_a; this is
 *     rho t^3/12 A/nn on triangles and parallelograms), about each of the
 *     three global axes (the drilling rotation included). Beam: rho L/2
 *     (I_y + I_z) about the beam axis, rho L/2 I_y and rho L/2 I_z about
 *     the section's local y and z axes.
 *   DTM_ROTARY_SCALED  every rotary inertia of the element multiplied by
 *     one scale s >= 1, the smallest for which the element's largest
 *     eigenvalue lambda(s) = lambda_max(M(s)^-1 K) does not exceed the
 *     target T: the membrane eigenvalue lambda_membrane of the shell (the
 *     same element with the plane-stress membrane part alone: the step a
 *     membrane element of that size would get), the axial eigenvalue
 *     4 E / (rho L^2) of the beam (the truss step L/c). In formulas:
 *       s = max(1, lambda_max(M_r^-1/2 S M_r^-1/2) / T),
 *       S = K_rr + K_rt (T M_t - K_tt)^-1 K_tr,
 *     over the element's out-of-plane (shell: w and the two in-plane
 *     rotations) or transverse (beam: v, w and the three rotations)
 *     unknowns in the element frame, t translational, r rotational, M_t
 *     and M_r their physical lumped masses: K - T M(s) is negative
 *     semidefinite exactly when s T M_r >= S (Schur complement), and
 *     lambda(s) is non-increasing in s. No bisection is needed; the tests
 *     check s against a bisection on lambda(s). The membrane (axial) part
 *     does not couple with the rest in a straight or flat element, so
 *     lambda(s) >= T always and lambda_scaled = T whenever s > 1.
 *     T M_t - K_tt is positive definite, so s is finite, when the
 *     transverse problem with the rotations held fixed stays below T: for
 *     the shell whenever k <= 1 (its shear Laplacian is bounded by the
 *     membrane operator, see the docs page), for the beam when k G < E.
 *     Otherwise no finite scale reaches T: s = +inf and lambda_scaled is
 *     the limit s -> inf, the largest eigenvalue with the rotations held
 *     fixed.
 *
 * The critical central-difference step of an element is 2/sqrt(lambda). */
#ifndef DTMAP_KERNEL_STRUCTURAL_H
#define DTMAP_KERNEL_STRUCTURAL_H

#include "dtmap/kernel.h"

#define DTM_STRUCT_DOF 24 /* most unknowns of a structural element (quad4, 6 per node) */

/* Rotary inertia conventions (above). */
typedef enum { DTM_ROTARY_PHYSICAL = 0, DTM_ROTARY_SCALED = 1 } dtm_rotary_convention;

/* Material and section of a shell element. */
typedef struct {
  double E, nu, rho; /* Pa, -, kg/m^3 (nu in (-1, 0.5)) */
  double thickness;  /* t, m */
  double k_shear;    /* transverse shear correction k (0 means 5/6) */
} dtm_shell_section;

/* Eigenvalue bounds of one shell element (1/s^2). */
typedef struct {
  double lambda_membrane; /* plane stress alone: equals dtm_kernel_elastic_lambda of the same element with
                             dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, E, nu, rho) (t cancels) */
  double lambda_physical; /* full shell, DTM_ROTARY_PHYSICAL */
  double lambda_scaled;   /* full shell, DTM_ROTARY_SCALED */
  double scale;           /* s of DTM_ROTARY_SCALED, >= 1 (+inf: see above) */
} dtm_shell_lambda;

/* Matrices of one shell (nn = 3 or 4) or beam (nn = 2) element in global
 * axes. The shell's lumped mass is diagonal in any frame (the same mass
 * on the three translations, the same rotary inertia on the three
 * rotations of a node), so M is diag(m). The beam's rotary inertia is
 * diagonal in the beam's frame only: M is then node-block diagonal (3 x 3
 * rotary blocks, m holds the diagonal in the beam's frame). */
typedef struct {
  int nn;                                    /* node count */
  double K[DTM_STRUCT_DOF * DTM_STRUCT_DOF]; /* [6 nn][6 nn] stiffness, N/m, N, N m (row-major) */
  double M[DTM_STRUCT_DOF * DTM_STRUCT_DOF]; /* [6 nn][6 nn] lumped mass, kg and kg m^2 */
  double m[DTM_STRUCT_DOF];                  /* [6 nn] the lumped mass's diagonal in the element frame */
  double axes[3][3];                         /* element frame: rows e1, e2, e3 (shell: e3 the normal;
                                                beam: e1 the axis, e2 the section's y) */
} dtm_struct_matrices;

/* Bounds of a shell element of type DTM_TRI3 or DTM_QUAD4 with nodes
 * x[nn][3] (m) in any plane of space; a warped quad4 is projected on the
 * mean plane of its corners (Newell normal, as dtm_elem_local), with no
 * warping correction. Formulation: membrane plane stress (E t/(1-nu^2)),
 * bending (E t^3/(12(1-nu^2))) and transverse shear (k G t) with linear
 * u, w and rotations; quad4: membrane and bending 2x2 Gauss, shear at the
 * centre (selective reduced integration); tri3: membrane and bending
 * constant, shear by MITC3 (the tangential shear strain of each edge,
 * interpolated by the lowest-order Nedelec (rotated Raviart-Thomas) field,
 * Lee and Bathe 2004). The drilling rotation has no stiffness. Returns 0,
 * or DTM_ERR_INPUT for another type, bad material or section values, or a
 * degenerate or inverted element. */
int dtm_kernel_shell_lambda(int type, const dtm_shell_section *sec, const double *x, dtm_shell_lambda *out);
/* The element's matrices in global axes for convention conv (the scaled
 * one computes s as above). Same errors. */
int dtm_kernel_shell_matrices(int type, const dtm_shell_section *sec, const double *x, dtm_rotary_convention conv,
                              dtm_struct_matrices *out);

/* Material, section and orientation of a beam element. Local axes: e1
 * along the beam (node 0 to node 1), e2 the component of ref normal to e1
 * (normalised), e3 = e1 x e2. I_y = integral of z^2 dA (bending in the
 * e1-e3 plane, about e2), I_z = integral of y^2 dA. */
typedef struct {
  double E, nu, rho; /* Pa, -, kg/m^3 (G = E/(2(1+nu))) */
  double area;       /* A, m^2 */
  double iy, iz, jt; /* I_y, I_z and the torsion constant J_t, m^4 */
  double k_shear;    /* shear correction k on both axes (0 means 5/6) */
  double ref[3];     /* orientation vector; all zero: global z, or global y when the beam is within
                        about 8 degrees of z (|e1 . z| > 0.99). Refused when within 1e-6 rad of e1. */
  int isotropic;     /* 1: every rotary inertia rho L/2 min(I_y, I_z) (diagonal in any frame, the
                        conservative choice for a global diagonal mass); 0: as below */
} dtm_beam_section;

/* Eigenvalue bounds of one beam element (1/s^2). */
typedef struct {
  double lambda_axial;    /* 4 E / (rho L^2): the truss step L/c */
  double lambda_physical; /* DTM_ROTARY_PHYSICAL */
  double lambda_scaled;   /* DTM_ROTARY_SCALED */
  double scale;           /* s >= 1 (+inf when k G >= E) */
} dtm_beam_lambda;

/* Fill area, iy, iz and jt of s for a solid circle of radius r (A = pi
 * r^2, I_y = I_z = pi r^4/4, J_t = pi r^4/2) or a solid rectangle of width
 * b along e2 and height h along e3 (A = b h, I_y = b h^3/12, I_z = h
 * b^3/12, J_t by Saint-Venant's series for a >= c the longer and shorter
 * sides: J_t = a c^3/3 (1 - (192 c/(pi^5 a)) sum over odd n of
 * tanh(n pi a/(2 c))/n^5), summed to n = 9999: truncation below 1e-16).
 * The other fields are left alone. DTM_ERR_INPUT for a size not finite
 * and > 0. */
int dtm_beam_section_circle(double r, dtm_beam_section *s);
int dtm_beam_section_rect(double b, double h, dtm_beam_section *s);

/* What the scaled convention needs without the transverse eigenvalues:
 * out = {lambda_membrane, s} (lambda_scaled = lambda_membrane whenever s is
 * finite, see above) and the physical lumped mass's frame diagonal m[6 nn],
 * *nn the node count. Same errors as dtm_kernel_shell_lambda. */
int dtm_kernel_shell_scale(int type, const dtm_shell_section *sec, const double *x, double out[2], double *m, int *nn);
/* out = {lambda_membrane, s, lambda_physical} and m, *nn as above. */
int dtm_kernel_shell_physical(int type, const dtm_shell_section *sec, const double *x, double out[3], double *m,
                              int *nn);

/* Bounds of a two-node Timoshenko beam with nodes x[2][3] (m): axial E A,
 * torsion G J_t, bending E I_y, E I_z, shear k G A; linear interpolation of
 * displacements and rotations, shear at the midpoint (reduced
 * integration, locking-free; a single element gives a cantilever tip
 * deflection P L^3/(4 E I) + P L/(k G A)). Lumped mass rho A L/2 per node;
 * rotary inertia per the convention. DTM_ERR_INPUT for bad values, a
 * zero-length element or a ref parallel to it. */
int dtm_kernel_beam_lambda(const dtm_beam_section *sec, const double *x, dtm_beam_lambda *out);
/* out = {lambda_axial, s} and the physical mass's frame diagonal m[12], as
 * dtm_kernel_shell_scale. */
int dtm_kernel_beam_scale(const dtm_beam_section *sec, const double *x, double out[2], double *m);
/* The element's matrices in global axes for convention conv. */
int dtm_kernel_beam_matrices(const dtm_beam_section *sec, const double *x, dtm_rotary_convention conv,
                             dtm_struct_matrices *out);

/* The global matrices of one element of a shell or beam section s
 * (dtmap/section.h) under the section's rotary convention, with its
 * thickness or area; the beam's rotary inertia isotropic (min(I_y, I_z)),
 * so M is diagonal. Errors as dtm_section_element. */
struct dtm_section;
int dtm_section_matrices(const struct dtm_section *s, int type, double E, double nu, double rho, const double *x,
                         dtm_struct_matrices *out);

/* Helpers shared by the shell and the beam, on dense row-major blocks of
 * n <= DTM_STRUCT_DOF unknowns with diagonal masses m[n] > 0. */
/* lambda_max(diag(m)^-1/2 K diag(m)^-1/2) for K[n][n] (not modified). */
double dtm_struct_lumped_max(int n, const double *K, const double *m);
/* The scale s of DTM_ROTARY_SCALED for the block K[n][n], masses m[n],
 * rot[n] = 1 for rotational unknowns (their masses scaled), target T > 0
 * (formula above): +inf when T M_t - K_tt is not positive definite. */
double dtm_struct_rotary_scale(int n, const double *K, const double *m, const int *rot, double target);
/* Kg = T^T Kl T for the [6 nn][6 nn] Kl in the element frame, T the
 * block diagonal of the rotation axes (rows e1, e2, e3) on every triple
 * of translations and of rotations. */
void dtm_struct_to_global(int nn, const double axes[3][3], const double *Kl, double *Kg);
/* For the local K[6 nn][6 nn] and diagonal masses m[6 nn] (frame
 * unknowns u, v, w, rx, ry, rz) of an element whose reference block (the
 * per-node components comp_ref[nref]: membrane, axial) does not couple
 * with the transverse block comp_tr[ntr] (its translational components
 * first, rotations are components >= 3): out = {lambda of the reference
 * block (the target T), lambda physical, lambda scaled, s}. */
void dtm_struct_bounds(int nn, const double *K, const double *m, int nref, const int *comp_ref, int ntr,
                       const int *comp_tr, double out[4]);
/* out = {lambda of the reference block, s, lambda physical} of
 * dtm_struct_bounds, without the scaled eigenvalue (equal to the first
 * whenever s is finite). */
void dtm_struct_physical(int nn, const double *K, const double *m, int nref, const int *comp_ref, int ntr,
                         const int *comp_tr, double out[3]);
/* Only out = {lambda of the reference block, s} of dtm_struct_bounds. */
void dtm_struct_ref_scale(int nn, const double *K, const double *m, int nref, const int *comp_ref, int ntr,
                          const int *comp_tr, double out[2]);

/* The faster path of the bounds (issue 38), the same numbers to about
 * 1e-14 relative: the small eigenproblems by dtm_struct_eig_max, a tri3
 * from its constant gradients without the membrane block (the
 * plane-stress closed form gives its eigenvalue), and certificates
 * before eigenproblems: when one Cholesky factorisation proves T M_r - S
 * (the scale's Schur complement) or T M - K (the transverse block)
 * positive definite, no transverse eigenvalue exceeds T (Sylvester's law
 * of inertia): s = 1 and lambda physical = T without either eigenproblem.
 * need: which of s and lambda physical to compute (the other NaN unless a
 * certificate gives it). screen > T: lambda physical is NaN, not computed,
 * when a factorisation proves it below screen (the report's minimum over
 * a section needs only the elements above the largest found so far). The
 * functions above stay the reference path the tests compare this one
 * with. */
#define DTM_STRUCT_NEED_SCALE 1
#define DTM_STRUCT_NEED_PHYSICAL 2
/* out = {lambda of the reference block, s, lambda physical} as
 * dtm_struct_physical, per need and screen (0: none). */
void dtm_struct_bounds_fast(int nn, const double *K, const double *m, int nref, const int *comp_ref, int ntr,
                            const int *comp_tr, int need, double screen, double out[3]);
/* Largest eigenvalue of the symmetric a[n][n] (n <= DTM_STRUCT_DOF,
 * destroyed): Householder tridiagonalisation and Laguerre / multiple-root
 * Newton steps safeguarded by Sturm counts (shell_eig.c); within a few
 * ulps of |A| of the bisection of dtm_eig_sym_max_tridiag. NaN if an entry
 * is not finite. */
double dtm_struct_eig_max(int n, double *a);
/* dtm_kernel_shell_physical by the faster path: out = {lambda_membrane, s,
 * lambda_physical} per need and screen, m and *nn as there. Same errors. */
int dtm_kernel_shell_bounds(int type, const dtm_shell_section *sec, const double *x, int need, double screen,
                            double out[3], double *m, int *nn);
/* The same for a beam: out = {lambda_axial, s, lambda_physical}, m[12]
 * the physical mass's frame diagonal. Same errors as
 * dtm_kernel_beam_lambda. */
int dtm_kernel_beam_bounds(const dtm_beam_section *sec, const double *x, int need, double screen, double out[3],
                           double *m);
/* Only the physical lumped mass's frame diagonal m[6 nn] (and *nn) of a
 * shell, m[12] of a beam, with the same checks and errors. */
int dtm_kernel_shell_masses(int type, const dtm_shell_section *sec, const double *x, double *m, int *nn);
int dtm_kernel_beam_masses(const dtm_beam_section *sec, const double *x, double *m);

#endif
