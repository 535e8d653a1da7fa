/* Selective mass scaling (issue 44): for a target step T each
 * element e whose own undamped step dt_e is below T gets the added mass
 * M_add^e = beta_e (W_e - w_e w_e^T / m_e) (x) I_d, beta_e = (T / dt_e)^2
 * - 1, with w_e the operator's lumped node masses of the element (m_e
 * their sum), so that the element's step grows by exactly sqrt(1 +
 * beta_e) while every rigid translation keeps its inertia. The scaled
 * mass M_s = M + sum_e M_add^e over an operator's unknowns (dtm_csr,
 * include/dtmap/operator.h), its matrix-free product, its Jacobi-
 * preconditioned conjugate-gradient solve, and the largest eigenvalue of
 * the pencil (K, M_s) by Lanczos in the M_s inner product, proven by the
 * factorisation of sigma M_s - K where affordable. Shells and beams are
 * refused (their rotations would need a form of their own). */
#ifndef DTMAP_SMS_H
#define DTMAP_SMS_H

#include "dtmap/export.h"

#include <stddef.h>

#include "dtmap/mesh.h"
#include "dtmap/operator.h"

/* beta[i] = max(0, (target / dt[i])^2 - 1) for the n element steps dt
 * (s; 0 where dt[i] is not a positive finite number: the element limits
 * nothing). The steps are undamped: damping lowers an element's step by a
 * factor that depends on its frequency, which the scaling lowers too, so
 * the damped step of a scaled element lies between the damped step at its
 * old frequency times sqrt(1 + beta) and T. */
DTM_EXPORT void dtm_sms_beta(size_t n, const double *dt, double target, double *beta);

/* The element steps of the scaled model: out[i] = dt[i] sqrt(1 + beta[i])
 * (each element's undamped step grows by exactly that factor). */
DTM_EXPORT void dtm_sms_element_steps(size_t n, const double *dt, const double *beta, double *out);

/* The added masses of one operator's elements: beta per element in the
 * mesh's global element order (block 0's elements, then block 1's ...). */
typedef struct dtm_sms dtm_sms;
/* DTM_ERR_INPUT for shells or beams. mesh is the operator's; level the
 * converged rule levels of its second-order elements that its creation
 * was given (dtm_operator_kept.level: an analysis's), or NULL (searched
 * again: the same lumped weights, slower on curved elements). */
DTM_EXPORT int dtm_sms_create(const dtm_operator *op, const dtm_mesh *mesh, const unsigned char *const *level,
                              const double *beta, dtm_sms **out);
DTM_EXPORT void dtm_sms_destroy(dtm_sms **s);
/* y = M_s x, matrix free (the lumped diagonal plus each scaled element's
 * added mass; x, y of the operator's ndof). */
DTM_EXPORT void dtm_sms_apply(const dtm_sms *s, const double *x, double *y);
/* M_s assembled into *out (both triangles, columns ascending; owned:
 * dtm_csr_free); add_only: M_add alone (no lumped diagonal; explicit
 * zeros on the diagonal of every unknown). */
DTM_EXPORT int dtm_sms_assemble(const dtm_sms *s, int add_only, dtm_csr *out);

/* What the added mass comes to. */
typedef struct {
  int ncomp;              /* directions (the operator's components) */
  size_t scaled;          /* elements with beta > 0 */
  double beta_max;        /* the largest beta */
  int beta_block;         /* its mesh block and index there (-1: none scaled) */
  size_t beta_local;      /* ... */
  double trace_add[3];    /* trace of M_add per direction (component), kg */
  double trace_mass[3];   /* trace of the lumped M per direction (point masses included), kg */
  double translational;   /* the scaled model's translational mass, kg: 1^T M_s 1 for the unit translation
                             along x, computed by the product (the lumped model's: M_add has every
                             rigid translation in its null space) */
  double translational_m; /* the same of the lumped M (point masses included), kg */
} dtm_sms_stats;
DTM_EXPORT void dtm_sms_stats_get(const dtm_sms *s, dtm_sms_stats *st);

/* Jacobi-preconditioned conjugate gradients on m x = b (m a dtm_csr of
 * M_s: symmetric positive definite on the unknowns with mass; unknowns
 * with a zero diagonal get x = 0) from x = 0, until the preconditioned
 * residual sqrt(r^T D^-1 r) is at most rtol sqrt(b^T D^-1 b) (D the
 * diagonal of m) or maxit iterations. Returns the iterations in *it
 * (maxit + 1 when not converged). */
DTM_EXPORT int dtm_sms_solve(const dtm_csr *m, const double *b, double rtol, int maxit, double *x, int *it);

/* The relative tolerance of the mass solves inside Lanczos (tight, so
 * that the Krylov space is that of exact solves up to it) and the one an
 * explicit solver would use, at which the iterations per step are
 * counted. */
#define DTM_SMS_LANCZOS_RTOL 1e-10
#define DTM_SMS_SOLVER_RTOL 1e-6

/* The largest eigenvalue of the pencil (K, M_s). */
typedef struct {
  double theta;        /* Rayleigh quotient y^T K y / y^T M_s y of the Ritz vector, exact products */
  double residual;     /* ||K y - theta M_s y||_{M^-1} / ||y||_{M_s} with M the lumped diagonal (M_s >= M): an
                          eigenvalue lies within it of theta, whatever the solves' error */
  double margin;       /* PROVEN: the factorisation's rounding margin; 0 otherwise */
  int iterations;      /* Lanczos steps */
  int converged;       /* residual <= tol theta, or an invariant subspace */
  int certified;       /* DTM_CERT_PROVEN: sigma M_s - K factored positive definite at sigma = theta + residual
                          (+ margin): every eigenvalue below; DTM_CERT_PROBABLE: the Kuczynski-Wozniakowski
                          bound (eps below); else DTM_CERT_REFUTED / NONE */
  int deterministic;   /* DTM_CERT_* of the factorisation alone (PROVEN, TOO_DEAR, UNAVAILABLE, REFUTED) */
  double eps;          /* PROBABLE: eps_k + the solves' allowance (DTM_SMS_LANCZOS_RTOL k); NaN otherwise */
  double bound;        /* PROBABLE: (theta + residual) / (1 - eps), lambda_max <= bound with probability
                          >= 1 - DTM_LANCZOS_FAILURE; PROVEN: theta + residual + margin */
  double dt;           /* 2 / sqrt(bound) (PROVEN, PROBABLE), else 2 / sqrt(theta + residual), s */
  double cg_mean;      /* mean CG iterations of the Lanczos mass solves (DTM_SMS_LANCZOS_RTOL) */
  double seconds;      /* wall time */
  double cert_seconds; /* of it the certificate's */
} dtm_sms_global;

/* Lanczos on (K, M_s) from a start whose M_s^1/2 image is uniform on the
 * sphere (one M_s solve of a normal draw through a factor of M_s), each
 * step one product with K and one PCG solve, fully reorthogonalised in
 * the M_s inner product, to residual <= tol theta (at most maxit steps);
 * then sigma M_s - K factored where the certificate's budget (flops)
 * allows (CHOLMOD, src/spectral/certify.c), a refuted sigma sending
 * Lanczos on at tol / 100 (up to three times); where it is too dear, on
 * until the Kuczynski-Wozniakowski eps_k is at most eps_target. */
DTM_EXPORT int dtm_sms_lambda_max(const dtm_operator *op, const dtm_sms *s, double tol, int maxit, unsigned seed,
                                  double budget, double eps_target, dtm_sms_global *g);

/* Central differences on (K, M_s) at step dt (s) for steps steps from u0
 * at rest, each step one K product and one PCG solve to
 * DTM_SMS_LANCZOS_RTOL; undamped; the growth of the energy norm sqrt(u^T
 * K u + v^T M_s v) as dtm_verify_run's (include/dtmap/operator.h).
 * *cg_mean (may be NULL): the mean CG iterations per step. */
DTM_EXPORT int dtm_sms_verify_run(const dtm_operator *op, const dtm_sms *s, double dt, int steps, const double *u0,
                                  dtm_verify_result *r, double *cg_mean);

#endif
