/* The global step of a selectively scaled model (include/dtmap/sms.h):
 * lambda_max of the pencil (K, M_s) by Lanczos on M_s^-1 K, which is
 * self-adjoint in the M_s inner product. Each step takes one product with
 * K (dtm_operator_apply) and one solve with M_s (dtm_sms_solve, Jacobi
 * PCG to DTM_SMS_LANCZOS_RTOL), and is reorthogonalised twice against the
 * stored basis in the M_s inner product (two products with the assembled
 * M_s, which cost a fraction of one with K).
 *
 * What the solves' error does: the Ritz value's bracket does not depend
 * on it. The Ritz vector y is formed from the basis and its Rayleigh
 * quotient theta and residual r = K y - theta M_s y are computed with
 * exact products (no solve); an eigenvalue of the pencil lies within
 * ||r||_{M_s^-1} / ||y||_{M_s} of theta, and ||r||_{M_s^-1} <=
 * ||r||_{M^-1} for the lumped diagonal M <= M_s (M_add is positive
 * semi-definite), which is computed exactly. The certificate then factors
 * sigma M_s - K (as sigma D - A in the operator's scaled unknowns, D = I
 * + M^-1/2 M_add M^-1/2, A = M^-1/2 K M^-1/2 assembled by certify.c)
 * at sigma = theta + residual: positive definite proves every eigenvalue
 * below sigma + margin (Sylvester), whatever the solves did. Only the
 * probable bound rests on the Krylov space itself: the
 * Kuczynski-Wozniakowski eps_k is that of exact Lanczos on M_s^-1/2 K
 * M_s^-1/2 from a start uniform on the sphere (the start is M_s^-1 G^T g
 * for a factor M_s = G^T G and g normal, sms.c), and the inexact solves
 * perturb each basis vector by at most DTM_SMS_LANCZOS_RTOL relative in
 * the preconditioned norm; dtmap adds k DTM_SMS_LANCZOS_RTOL to eps_k as
 * a first-order allowance for the k perturbed steps (1e-8 at 100 steps
 * against an eps_k of 1e-2 or more): an allowance, not a proof. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "spectral.h"
#include "dtmap/error.h"
#include "dtmap/sms.h"
#include "dtmap/util.h"

#define CG_MAXIT 10000 /* iterations of one mass solve at most */
#define REFUTED_TRIES 3
#define CONVERGE_TRIES 4

typedef struct {
  const dtm_operator *op;
  dtm_csr ms;     /* M_s assembled */
  size_t n;       /* unknowns */
  int k, kmax;    /* steps taken, at most */
  double **V;     /* [kmax + 1][n] the basis, M_s-orthonormal */
  double *a, *b;  /* [kmax] the tridiagonal */
  double *s, *tw; /* [kmax] its top eigenvector, [4 kmax] workspace */
  double *w, *z, *mz;
  double theta, est; /* top Ritz value of T_k and Paige's estimate |b_k s_k| */
  int invariant;
  long cg_total; /* CG iterations over the solves */
  int solves;
} pz_state;

static double dot(size_t n, const double *x, const double *y) {
  double s = 0;
  for (size_t i = 0; i < n; i++) s += x[i] * y[i];
  return s;
}

static int solve(pz_state *z, const double *rhs, double *x) {
  int it = 0;
  DTM_CHECK(dtm_sms_solve(&z->ms, rhs, DTM_SMS_LANCZOS_RTOL, CG_MAXIT, x, &it));
  z->cg_total += it, z->solves++;
  return DTM_OK;
}

/* Twice: x -= V (V^T M_s x) over the k + 1 stored vectors. */
static void reorthogonalise(pz_state *z, int nv, double *x) {
  for (int pass = 0; pass < 2; pass++) {
    dtm_csr_apply(&z->ms, x, z->mz);
    for (int i = 0; i < nv; i++) {
      double h = dot(z->n, z->V[i], z->mz);
      for (size_t t = 0; t < z->n; t++) x[t] -= h * z->V[i][t];
    }
  }
}

/* ||x||_{M_s}. */
static double mnorm(pz_state *z, const double *x) {
  dtm_csr_apply(&z->ms, x, z->mz);
  return sqrt(fmax(0, dot(z->n, x, z->mz)));
}

static int start(pz_state *z, const dtm_sms *s, unsigned seed) {
  dtm_sms_factor_draw(s, z->op, seed, z->w);
  DTM_CHECK(solve(z, z->w, z->V[0]));
  double nv = mnorm(z, z->V[0]);
  if (!(nv > 0)) return DTM_ERR(DTM_ERR_INPUT, "selective mass scaling: the model has no mass");
  for (size_t t = 0; t < z->n; t++) z->V[0][t] /= nv;
  return DTM_OK;
}

/* Step k: the next column of T and, unless invariant, v_{k+1}. */
static int step(pz_state *z) {
  int j = z->k;
  double *v = z->V[j], *x = z->V[j + 1];
  dtm_operator_apply(z->op, v, z->w);
  z->a[j] = dot(z->n, v, z->w);
  DTM_CHECK(solve(z, z->w, x));
  for (size_t t = 0; t < z->n; t++) x[t] -= z->a[j] * v[t] + (j ? z->b[j - 1] * z->V[j - 1][t] : 0);
  reorthogonalise(z, j + 1, x);
  z->b[j] = mnorm(z, x);
  z->k = j + 1;
  z->theta = dtm_tridiag_top(z->k, z->a, z->b, z->s, z->tw);
  z->est = fabs(z->b[j] * z->s[j]);
  z->invariant = !(z->b[j] > 1e-13 * fabs(z->theta));
  for (size_t t = 0; !z->invariant && t < z->n; t++) x[t] /= z->b[j];
  return DTM_OK;
}

/* Steps until est <= tol theta and eps_k <= eps_target (nb: the bound's
 * n), an invariant subspace, or kmax. */
static int steps(pz_state *z, double tol, double eps_target, double nb) {
  while (!z->invariant && z->k < z->kmax) {
    if (z->k && z->est <= tol * z->theta && dtm_lanczos_kw_eps(nb, z->k, DTM_LANCZOS_FAILURE) <= eps_target) break;
    DTM_CHECK(step(z));
  }
  return DTM_OK;
}

/* theta and the residual from the Ritz vector with exact products. */
static void bracket(pz_state *z, dtm_sms_global *g) {
  double *y = z->w, *ky = z->z, *my = z->mz, r2 = 0;
  const double *ml = dtm_operator_mass(z->op);
  memset(y, 0, z->n * sizeof *y);
  for (int j = 0; j < z->k; j++)
    for (size_t t = 0; t < z->n; t++) y[t] += z->s[j] * z->V[j][t];
  dtm_operator_apply(z->op, y, ky);
  dtm_csr_apply(&z->ms, y, my);
  double ymy = dot(z->n, y, my), theta = dot(z->n, y, ky) / ymy;
  for (size_t t = 0; t < z->n; t++) {
    double r = ky[t] - theta * my[t];
    if (ml[t] > 0) r2 += r * r / ml[t];
  }
  g->theta = theta, g->residual = sqrt(r2 / ymy), g->iterations = z->k;
}

/* Steps until the bracket's residual (not Paige's estimate, which the
 * inexact solves and the M^-1 norm may put below it: up to sqrt(1 +
 * beta_max) for the norm) meets tol: the estimate's own tolerance is
 * tightened tenfold up to CONVERGE_TRIES times. */
static int converge(pz_state *z, double tol, dtm_sms_global *g) {
  double est_tol = tol;
  for (int tries = 0;; tries++, est_tol /= 10) {
    DTM_CHECK(steps(z, est_tol, INFINITY, 1));
    bracket(z, g);
    g->converged = g->residual <= tol * g->theta || z->invariant;
    if (g->converged || z->k >= z->kmax || tries == CONVERGE_TRIES) return DTM_OK;
  }
}

static void pz_free(pz_state *z) {
  for (int j = 0; z->V && j <= z->kmax; j++) free(z->V[j]);
  free(z->V), free(z->a), free(z->b), free(z->s), free(z->tw), free(z->w), free(z->z), free(z->mz);
  dtm_csr_free(&z->ms);
}

static int pz_alloc(pz_state *z, const dtm_sms *s, int maxit) {
  z->kmax = maxit, z->n = dtm_operator_ndof(z->op);
  DTM_CHECK(dtm_sms_assemble(s, 0, &z->ms));
  size_t km = (size_t)maxit + 1;
  z->V = calloc(km, sizeof *z->V), z->a = malloc(km * sizeof(double)), z->b = malloc(km * sizeof(double));
  z->s = malloc(km * sizeof(double)), z->tw = malloc(4 * km * sizeof(double));
  z->w = malloc((z->n + 1) * sizeof(double)), z->z = malloc((z->n + 1) * sizeof(double));
  z->mz = malloc((z->n + 1) * sizeof(double));
  if (!z->V || !z->a || !z->b || !z->s || !z->tw || !z->w || !z->z || !z->mz)
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t j = 0; j < km; j++)
    if (!(z->V[j] = malloc((z->n + 1) * sizeof(double)))) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  return DTM_OK;
}

/* ---- the certificate ---------------------------------------------------- */

/* dx = M^-1/2 M_add M^-1/2 (M the lumped diagonal). */
static int scaled_added(const dtm_sms *s, const dtm_operator *op, dtm_csr *dx) {
  DTM_CHECK(dtm_sms_assemble(s, 1, dx));
  const double *ml = dtm_operator_mass(op);
  for (size_t i = 0; i < dx->n; i++)
    for (size_t p = dx->rowptr[i]; p < dx->rowptr[i + 1]; p++) {
      size_t j = dx->col[p];
      dx->val[p] = ml[i] > 0 && ml[j] > 0 ? dx->val[p] / sqrt(ml[i] * ml[j]) : 0;
    }
  return DTM_OK;
}

/* Proven, refuted (Lanczos on, stricter) or no certificate. */
static int certify(pz_state *z, const dtm_sms *s, double tol, double budget, dtm_sms_global *g) {
  dtm_certifier *c = NULL;
  dtm_csr dx = {0};
  double t0 = dtm_wtime(), pred[2];
  int status = DTM_CERT_TOO_DEAR, r = dtm_certifier_create_costed(z->op, budget, &c, &status, pred);
  g->deterministic = status;
  if (r == DTM_OK && c) r = scaled_added(s, z->op, &dx);
  for (int tries = 0; r == DTM_OK && c && tries <= REFUTED_TRIES; tries++) {
    double margin, sigma = g->theta + g->residual;
    if (dtm_certifier_below_pencil(c, &dx, sigma, &margin)) {
      g->certified = g->deterministic = DTM_CERT_PROVEN, g->margin = margin, g->bound = sigma + margin;
      break;
    }
    g->certified = g->deterministic = DTM_CERT_REFUTED, g->converged = 0;
    if (tries == REFUTED_TRIES || z->invariant || z->k >= z->kmax) break;
    tol /= 100;
    r = converge(z, tol, g);
  }
  dtm_certifier_destroy(&c);
  dtm_csr_free(&dx);
  g->cert_seconds = dtm_wtime() - t0;
  return r;
}

/* Where no factorisation proves it: on until eps_k <= eps_target. */
static int probable(pz_state *z, double tol, double eps_target, dtm_sms_global *g) {
  double nb = 0;
  const double *ml = dtm_operator_mass(z->op);
  for (size_t t = 0; t < z->n; t++) nb += ml[t] > 0;
  DTM_CHECK(steps(z, tol, eps_target, nb));
  bracket(z, g);
  g->converged = g->residual <= tol * g->theta || z->invariant;
  double eps = dtm_lanczos_kw_eps(nb, z->k, DTM_LANCZOS_FAILURE) + DTM_SMS_LANCZOS_RTOL * z->k;
  if (!(eps < 1)) return DTM_OK;
  g->certified = DTM_CERT_PROBABLE, g->eps = eps, g->bound = (g->theta + g->residual) / (1 - eps);
  return DTM_OK;
}

static int run(pz_state *z, const dtm_sms *s, double tol, unsigned seed, double budget, double eps_target,
               dtm_sms_global *g) {
  DTM_CHECK(start(z, s, seed));
  DTM_CHECK(converge(z, tol, g));
  if (budget > 0) DTM_CHECK(certify(z, s, tol, budget, g));
  if (g->certified != DTM_CERT_PROVEN && g->certified != DTM_CERT_REFUTED && eps_target >= 0)
    DTM_CHECK(probable(z, tol, eps_target, g));
  return DTM_OK;
}

int dtm_sms_lambda_max(const dtm_operator *op, const dtm_sms *s, double tol, int maxit, unsigned seed, double budget,
                       double eps_target, dtm_sms_global *g) {
  double t0 = dtm_wtime();
  pz_state z = {.op = op};
  *g = (dtm_sms_global){.eps = NAN, .bound = NAN, .dt = NAN, .deterministic = DTM_CERT_NONE};
  int r = pz_alloc(&z, s, maxit < 1 ? 1 : maxit);
  if (r == DTM_OK) r = run(&z, s, tol, seed, budget, eps_target, g);
  g->cg_mean = z.solves ? (double)z.cg_total / z.solves : NAN;
  pz_free(&z);
  g->dt = 2 / sqrt(isfinite(g->bound) ? g->bound : g->theta + g->residual);
  g->seconds = dtm_wtime() - t0;
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
