/* The global, matrix-free (element-by-element) operators of a spectral
 * effect on a whole mesh: the lumped "mass" diagonal M and the stiffness K
 * of linear elasticity or scalar diffusion, their symmetric scaling
 * M^-1/2 K M^-1/2, Rayleigh damping C = alpha M + beta K element by element,
 * the Lanczos estimate of lambda_max(M^-1 K) with a residual bracket, and
 * the explicit time integration `dtmap verify` runs.
 * Unknowns: ncomp per node (elastic: d, the dimension of the space the
 * mesh spans: the analysed dimension for a 2D mesh in a plane z = const or
 * a 1D mesh along x, else 3, in the global x, y, z components; diffusion:
 * 1), numbered node-major: dof = node*ncomp + c. Elements of lower
 * dimension than d (trusses and membranes in 3D, curved surfaces) act in
 * their own tangent line or plane. */
#ifndef DTMAP_OPERATOR_H
#define DTMAP_OPERATOR_H

#include "dtmap/export.h"

#include <stddef.h>

#include "dtmap/mesh.h"
#include "dtmap/problem.h"
#include "dtmap/section.h"

typedef struct dtm_operator dtm_operator;

/* Per-material coefficients: coef[i] for the mesh's material index i
 * (dtm_block.mat), all of the same kind (DTM_OP_ELASTIC or DTM_OP_DIFFUSION);
 * alpha[i], beta[i] Rayleigh damping per material (NULL: undamped). The
 * operator copies what it needs; the mesh must outlive it. */
DTM_EXPORT int dtm_operator_create(const dtm_mesh *mesh, int kind, const dtm_operator_coeffs *coef, const double *alpha,
                                   const double *beta, int nmat, dtm_operator **out);
/* The same with sections: coef, alpha and beta have nmat (nsec + 1)
 * entries, slot mat + nmat (section + 1) for an element of material mat
 * and section index section (-1: none; dtm_block.section), each slot's
 * coefficients per unit measure with section_factor set (the operator
 * multiplies stiffness and mass by it). */
DTM_EXPORT int dtm_operator_create_sections(const dtm_mesh *mesh, int kind, const dtm_operator_coeffs *coef,
                                            const double *alpha, const double *beta, int nmat, int nsec,
                                            dtm_operator **out);
/* What an analysis kept per element that the operator would otherwise
 * compute again. */
typedef struct {
  const dtm_section_bounds *const *rot; /* [nblocks][n] each shell's and beam's bounds (dtm_section_element;
                                           nn = 0, or a NULL row: none): a shell's rotary-inertia scale is
                                           taken from there instead of being solved again; or NULL */
  const unsigned char *const *level;    /* [nblocks][n] each second-order element's converged rule level
                                           (the kernel's level search under the converged model: 0 for a
                                           straight-sided element; NULL rows for the others), or NULL */
} dtm_operator_kept;

/* The same with what an analysis kept (kept may be NULL). */
DTM_EXPORT int dtm_operator_create_kept(const dtm_mesh *mesh, int kind, const dtm_operator_coeffs *coef,
                                        const double *alpha, const double *beta, int nmat, int nsec,
                                        const dtm_operator_kept *kept, dtm_operator **out);
DTM_EXPORT void dtm_operator_destroy(dtm_operator **op);

/* A sparse symmetric matrix over an operator's unknowns in compressed
 * rows, both triangles stored, the columns of each row ascending (the
 * unknowns numbered as dtm_operator_apply's fields: node-major, then
 * shells' and beams' rotations). Masses in kg (2D: per unit thickness). */
typedef struct {
  size_t n;       /* rows = columns */
  size_t *rowptr; /* [n + 1] */
  size_t *col;    /* [rowptr[n]] */
  double *val;    /* [rowptr[n]] */
} dtm_csr;
/* Free m's arrays and zero it (NULL and a zeroed m are fine). */
DTM_EXPORT void dtm_csr_free(dtm_csr *m);
/* y = m x (x, y of m->n). */
DTM_EXPORT void dtm_csr_apply(const dtm_csr *m, const double *x, double *y);

/* ---- natural modes (src/spectral/modes.c, modes_compare.c) ---------------
 * The lowest natural frequencies of the pencil (K, B), B = the lumped mass
 * M + extra (a dtm_csr over the operator's unknowns; NULL: none): K x =
 * lambda B x, lambda = omega^2 (rad^2/s^2), f = omega / 2 pi (Hz). dtmap's
 * model has no supports, so a free model has rigid-body modes (6 in 3D, 3
 * in a plane, 1 along a line; more for parts not joined): they are found
 * and named, then the lowest elastic ones. Elastic operators of solids,
 * membranes and trusses; an error for shells and beams (their rotations are
 * not assembled) and for diffusion. */
#define DTM_MODES_RIGID_TOL 1e-8 /* rigid: |lambda| <= this times the largest eigenvalue computed */
#define DTM_MODES_TOL 1e-9       /* a Ritz pair converged: ||OP y - nu y||_B <= this times |nu| */
#define DTM_MODES_MAC_MIN 0.8    /* a modified mode matches a base mode at a MAC of at least this */

typedef struct {
  double lambda;   /* eigenvalue omega^2, rad^2/s^2 */
  double freq;     /* natural frequency sqrt(max(lambda, 0)) / 2 pi, Hz */
  double residual; /* ||K x - lambda B x|| / (lambda ||B x||) measured on the returned shape; a rigid
                      mode's with the largest lambda computed in the denominator */
  int rigid;       /* 1: a rigid-body mode (|lambda| <= DTM_MODES_RIGID_TOL x the largest) */
} dtm_mode;

typedef struct {
  int n;                 /* modes returned: nrigid rigid ones, then nelastic elastic ones, lambda ascending */
  int nrigid;            /* rigid-body modes found */
  int nelastic;          /* elastic modes: as many as asked unless not converged */
  dtm_mode *mode;        /* [n] (owned) */
  double *shape;         /* [n][ndof] the mode shapes, x^T B x = 1 (owned) */
  size_t ndof;           /* the operator's unknowns */
  double sigma;          /* the shift, rad^2/s^2 (negative) */
  int block;             /* the Lanczos block: start vectors (the most equal eigenvalues it separates) */
  int steps;             /* Lanczos steps (one solve each) */
  int converged;         /* every returned mode passed the test (DTM_MODES_TOL) */
  double seconds;        /* wall time (assembly, factorisation, Lanczos) */
  double factor_seconds; /* of which the assembly and factorisation */
  double sturm_at;       /* the Sturm check's s: just above the largest mode returned, rad^2/s^2 */
  long sturm;            /* the eigenvalues below sturm_at by the inertia of K - s B (LDL^T), -1: not counted */
  int counted;           /* 1: sturm equals the modes Lanczos found below sturm_at (none missed); 0: it does not
                            (a mode missed); -1: not checked (a zero pivot); -2: not checked (its factorisation
                            predicted above 1e9 flops) */
} dtm_modes;

/* The lowest n elastic modes (and the rigid ones below them) of (K, M +
 * extra) by shift-invert block Lanczos with full reorthogonalisation in the
 * B inner product on CHOLMOD's factorisation of K - sigma B; see
 * src/spectral/modes.c. extra: n x n of the operator's unknowns, symmetric
 * positive semi-definite, or NULL. out is zeroed first; dtm_modes_free. */
DTM_EXPORT int dtm_modes_lowest(const dtm_operator *op, const dtm_csr *extra, int n, dtm_modes *out);
DTM_EXPORT void dtm_modes_free(dtm_modes *m);

/* A base elastic mode against the modified model's. */
typedef struct {
  int base;     /* the base's elastic mode, 0-based among its elastic modes */
  int match;    /* the modified model's elastic mode it matches (0-based), -1: none */
  double mac;   /* the largest MAC of the base mode with any modified elastic mode (that of match when matched) */
  double shift; /* 100 (f_modified / f_base - 1), %; NaN without a match */
} dtm_mode_shift;

/* Each of base's elastic modes matched to one of mod's by the mass-weighted
 * modal assurance criterion MAC(a, b) = (a^T M b)^2 / (a^T M a  b^T M b),
 * M the operator's lumped mass (the same weight for every model compared):
 * pairs are taken greedily by descending MAC, each mode at most once, at a
 * MAC of at least DTM_MODES_MAC_MIN; out[base->nelastic]. base and mod are
 * modes of the same operator's unknowns. */
DTM_EXPORT int dtm_modes_compare(const dtm_operator *op, const dtm_modes *base, const dtm_modes *mod,
                                 dtm_mode_shift *out);

/* The diagonal matrix of point masses kg[nnodes] (kg per node, NULL: none;
 * per unit thickness in 2D) on each node's translational unknowns
 * (node * ncomp + c), zero rows elsewhere (rotations): conventional mass
 * scaling as an extra mass for dtm_modes_lowest. */
DTM_EXPORT int dtm_csr_point_masses(const dtm_operator *op, const double *kg, size_t nnodes, dtm_csr *out);
/* out = full - M (M the operator's lumped diagonal), entries that become 0
 * dropped: the added part of a whole mass matrix (M_s = M + M_add of
 * selective mass scaling), the form dtm_modes_lowest's extra takes. */
DTM_EXPORT int dtm_csr_minus_lumped(const dtm_operator *op, const dtm_csr *full, dtm_csr *out);

DTM_EXPORT size_t dtm_operator_ndof(const dtm_operator *op);
DTM_EXPORT int dtm_operator_ncomp(const dtm_operator *op);
/* DTM_OP_ELASTIC or DTM_OP_DIFFUSION, as created. */
DTM_EXPORT int dtm_operator_kind(const dtm_operator *op);
/* Lumped diagonal [ndof] (kg, or J/K ...); 0 for nodes of no element. */
DTM_EXPORT const double *dtm_operator_mass(const dtm_operator *op);
/* x[ndof] uniform in [lo, hi), each dof's value drawn from the seed and
 * its node's Gmsh tag (the mesh's node_tags; index + 1 when it has none)
 * and component: the same field whatever order the nodes are stored in
 * (dtm_mesh_reorder). */
DTM_EXPORT void dtm_operator_draw(const dtm_operator *op, unsigned long long seed, double lo, double hi, double *x);
/* x[ndof] standard normal, drawn per node tag and component like
 * dtm_operator_draw: normalised over any set of dofs, uniform on that
 * set's unit sphere. */
DTM_EXPORT void dtm_operator_draw_normal(const dtm_operator *op, unsigned long long seed, double *x);
/* y = K u ([ndof] each). */
DTM_EXPORT void dtm_operator_apply(const dtm_operator *op, const double *u, double *y);
/* y = M^-1/2 K M^-1/2 x; dofs with zero mass give 0. */
DTM_EXPORT void dtm_operator_apply_sym(const dtm_operator *op, const double *x, double *y);
/* y = C v with C = sum_e (alpha_e M_e + beta_e K_e). */
DTM_EXPORT void dtm_operator_apply_damping(const dtm_operator *op, const double *v, double *y);

typedef struct {
  double theta;             /* largest Ritz value of M^-1 K: a lower bound of lambda_max */
  double residual;          /* ||A y - theta y|| measured on the returned unit Ritz
                               vector y (one extra product): an eigenvalue lies in
                               [theta - residual, theta + residual] */
  int iterations;           /* Lanczos steps k; a call costs k products (k + 1 with
                               the Ritz vector, V_k s from the stored basis) */
  int converged;            /* invariant subspace, or residual <= tol * theta */
  double seconds;           /* wall time */
  double *mode;             /* [ndof] the top Ritz vector as a field u = M^-1/2 y,
                               normalised so that u^T M u = 1 (owned, free()) */
  double theta2;            /* the second Ritz value of the last T_k (NaN for k = 1) */
  int certified;            /* dtm_lanczos_max_certified: DTM_CERT_* */
  double tol_used;          /* the tolerance the last pass ran to */
  double cert_seconds;      /* wall time of the certificate (assembly and factorisations) */
  int deterministic;        /* DTM_CERT_* of the factorisation alone (PROVEN, TOO_DEAR, UNAVAILABLE, REFUTED;
                               NONE when not asked) */
  double eps;               /* DTM_CERT_PROBABLE: the relative gap eps_k of the Kuczynski-Wozniakowski bound
                               after the k = iterations steps, so lambda_max <= bound with probability at least
                               1 - failure; NaN otherwise */
  double failure;           /* the failure probability the bound was asked at (DTM_LANCZOS_FAILURE), or NaN */
  double bound;             /* DTM_CERT_PROBABLE: (theta + rounding) / (1 - eps), an upper bound of
                               lambda_max with probability >= 1 - failure; NaN otherwise */
  double nbound;            /* n of the bound: the dofs with mass (the start vector's sphere) */
  unsigned seed;            /* the start vector's seed */
  double cert_predicted[2]; /* the factorisation's predicted flops and bytes (NaN: not predicted; 0: not asked) */
} dtm_lanczos_result;

/* The failure probability of the probable bound: Lanczos's top Ritz value
 * from a start uniform on the sphere is below (1 - eps_k) lambda_max with
 * at most this probability. */
#define DTM_LANCZOS_FAILURE 1e-12

/* The Kuczynski-Wozniakowski bound (SIAM J. Matrix Anal. Appl. 13(4),
 * 1992) for Lanczos on a symmetric positive semi-definite matrix of order
 * n from a start uniform on the unit sphere: after k steps,
 * P((lambda_max - theta_k) / lambda_max >= eps) <= 1.648 sqrt(n)
 * exp(-sqrt(eps) (2k - 1)). The smallest eps whose bound is <= p:
 * eps_k = (ln(1.648 sqrt(n) / p) / (2k - 1))^2, 0 when the logarithm is
 * not positive, 1 (no information) when it reaches 1 or k < 1. */
DTM_EXPORT double dtm_lanczos_kw_eps(double n, int k, double p);
/* The fewest steps k whose eps_k (dtm_lanczos_kw_eps) is <= eps (0 < eps):
 * the smallest integer k >= (ln(1.648 sqrt(n) / p) / sqrt(eps) + 1) / 2,
 * at least 1. */
DTM_EXPORT int dtm_lanczos_kw_steps(double n, double eps, double p);

/* What dtm_lanczos_max_certified could say of theta + residual. */
enum {
  DTM_CERT_NONE = 0,        /* not asked for */
  DTM_CERT_PROVEN = 1,      /* sigma I - A factored positive definite at sigma = theta + residual: every
                               eigenvalue lies below it (Sylvester), whatever the gaps */
  DTM_CERT_TOO_DEAR = 2,    /* the factorisation would cost more than the budget (flops) or the memory cap:
                               not tried */
  DTM_CERT_UNAVAILABLE = 3, /* shells or beams (not assembled) */
  DTM_CERT_REFUTED = 4,     /* a factorisation found an eigenvalue above every bound tried: not converged */
  DTM_CERT_PROBABLE = 5     /* no factorisation (deterministic says why): the Kuczynski-Wozniakowski bound
                               holds lambda_max <= bound with probability >= 1 - failure */
};

/* Lanczos on M^-1/2 K M^-1/2 from a seeded random start (normal per dof
 * with mass, normalised: uniform on the unit sphere of those dofs), with
 * full reorthogonalisation against the stored basis (k vectors of ndof),
 * at most maxit products, stopping when residual <= tol * theta. */
DTM_EXPORT int dtm_lanczos_max(const dtm_operator *op, double tol, int maxit, unsigned seed, dtm_lanczos_result *r);
/* The same; with want_mode = 0 no Ritz vector is built (mode = NULL, one
 * product less) and residual is Paige's estimate |beta_k s_k|, which bounds
 * the distance from theta to an eigenvalue up to O(eps |A|). */
DTM_EXPORT int dtm_lanczos_max_ex(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode,
                                  dtm_lanczos_result *r);
/* The same, with the bound theta + residual checked: when the certificate
 * (CHOLMOD's Cholesky factorisation of sigma I - A, assembled from the
 * product) is predicted to cost at most budget flops and to fit the
 * memory cap, each converged bound is certified, and one it refutes
 * sends Lanczos on at a tolerance 100x stricter (up to three times; then
 * converged = 0). Where it is too dear or unavailable and the
 * top of T_k is clustered (theta2 within 10 tol of theta) or suspect is set
 * (point masses), Lanczos goes on to tol * 1e-4 instead: a heuristic, not
 * a proof. On success residual includes the factorisation's rounding
 * margin. */
DTM_EXPORT int dtm_lanczos_max_certified(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode,
                                         double budget, int suspect, dtm_lanczos_result *r);
/* The same, with the probable layer where the factorisation does not
 * prove the bound (too dear or unavailable): Lanczos goes on past its
 * tolerance until eps_k <= eps_target (1 - safety^2: then safety times
 * the step of theta + residual is at most the step of the probable
 * bound), or maxit steps, or an invariant subspace, and the result is
 * DTM_CERT_PROBABLE with eps, failure and bound (when eps_k < 1);
 * converged is judged at tol, whatever the heuristic's stricter pass. A
 * negative eps_target asks for no probable layer (as
 * dtm_lanczos_max_certified). */
DTM_EXPORT int dtm_lanczos_max_probable(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode,
                                        double budget, int suspect, double eps_target, dtm_lanczos_result *r);

typedef struct {
  int steps;     /* steps taken */
  double growth; /* max over the last half of the run of the energy
                    norm, divided by its initial value */
  int unstable;  /* growth > 1e6, or any non-finite value */
  double seconds;
} dtm_verify_result;

/* Integrate from u0 [ndof]: elastic by central differences with lumped mass
 * and the damping force on the lagged velocity v_{n-1/2} (starting at rest:
 * u_{-1} = u_0); diffusion by forward Euler. The energy norm is
 * sqrt(u^T K u + v^T M v) (elastic) or sqrt(u^T M u) (diffusion). */
DTM_EXPORT int dtm_verify_run(const dtm_operator *op, double dt, int steps, const double *u0, dtm_verify_result *r);

#endif
