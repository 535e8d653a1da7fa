/* The global spectral estimate: the largest eigenvalue of M^-1 K by the
 * Lanczos recurrence on the symmetric A = M^-1/2 K M^-1/2 (dofs without
 * mass stay 0), started from a vector drawn by splitmix64 from the seed.
 * Only three vectors are kept and there is no reorthogonalisation beyond
 * a second local pass against the newest vector: for the extreme
 * eigenvalue from a random start that is enough (lost orthogonality only
 * adds spurious copies of converged Ritz values). After each step the top
 * eigenvalue theta of the tridiagonal T_k is found by Sturm bisection to
 * full precision and its unit eigenvector s by inverse iteration, which
 * gives the residual estimate |beta_k s_k|. The run stops when that is
 * <= tol * theta, at maxit steps, or when beta_k vanishes (an invariant
 * subspace: theta is then exact). The Ritz vector y = V s is built by
 * running the recurrence a second time from the same start (k - 1 more
 * products, no stored basis, so the memory stays at four vectors whatever
 * k is), and one last product measures the true residual ||A y - theta y||,
 * which is what the result reports.
 * theta + residual bounds the eigenvalue nearest theta, not necessarily the
 * largest: from a start that holds little of the top mode, with the top
 * two eigenvalues closer than a few tol, Lanczos meets its tolerance on
 * the second. dtm_lanczos_max_certified then checks the bound by the
 * factorisation of certify.c and goes on from where it stopped (the
 * recurrence's three vectors are kept) at a stricter tolerance while the
 * bound is refuted; where the factorisation is too dear it goes on to tol
 * * 1e-4 when the caller suspects a cluster (point masses) or T_k shows
 * one (its second Ritz value within 10 tol of theta), which is a
 * heuristic, not a proof. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "spectral.h"
#include "dtmap/operator.h"
#include "dtmap/progress.h"

typedef struct {
  const dtm_operator *op;
  size_t n;
  unsigned seed;
  double *vp, *v, *w; /* v_{j-1}, v_j, and the next direction */
  double bprev;       /* beta_{j-1} */
} lz_state;

typedef struct {
  int k;             /* steps taken */
  double *a, *b;     /* [maxit] diagonal and off-diagonal of T */
  double *s;         /* [maxit] top eigenvector of T_k */
  double *work;      /* [5 maxit] tridiagonal solver */
  double theta, est; /* top Ritz value, |beta_k s_k| */
  int invariant;     /* beta_k vanished */
} lz_tri;

static double dot(size_t n, const double *x, const double *y) {
  double s = 0;
  for (size_t i = 0; i < n; i++) s += x[i] * y[i];
  return s;
}

/* v_0: uniform in [-1, 1) on the dofs with mass (drawn per Gmsh node tag,
 * so the start does not depend on the node order), unit norm; 0 when there
 * are none. */
static double lz_start(lz_state *z) {
  const double *m = dtm_operator_mass(z->op);
  dtm_operator_draw(z->op, z->seed, -1.0, 1.0, z->v);
  for (size_t i = 0; i < z->n; i++) {
    z->v[i] = m[i] > 0 ? z->v[i] : 0;
    z->vp[i] = 0;
  }
  double nv = sqrt(dot(z->n, z->v, z->v));
  for (size_t i = 0; i < z->n && nv > 0; i++) z->v[i] /= nv;
  z->bprev = 0;
  return nv;
}

/* w = A v_j - a v_j - beta_{j-1} v_{j-1}, with a second pass against v_j. */
static void lz_step(lz_state *z, double *a, double *b) {
  size_t n = z->n;
  dtm_operator_apply_sym(z->op, z->v, z->w);
  *a = dot(n, z->w, z->v);
  for (size_t i = 0; i < n; i++) z->w[i] -= *a * z->v[i] + z->bprev * z->vp[i];
  double c = dot(n, z->w, z->v);
  for (size_t i = 0; i < n; i++) z->w[i] -= c * z->v[i];
  *a += c;
  *b = sqrt(dot(n, z->w, z->w));
}

/* v_{j+1} = w / b; the old v_{j-1} becomes the next w. */
static void lz_advance(lz_state *z, double b) {
  double *t = z->vp;
  z->vp = z->v, z->v = z->w, z->w = t;
  for (size_t i = 0; i < z->n; i++) z->v[i] /= b;
  z->bprev = b;
}

/* ---- the tridiagonal T_k -------------------------------------------- */

/* Number of eigenvalues of T_k below x (Sturm count of T - xI = LDL^T). */
static int count_below(int k, const double *a, const double *b, double x, double piv) {
  int c = 0;
  double q = 1;
  for (int i = 0; i < k; i++) {
    q = a[i] - x - (i ? b[i - 1] * b[i - 1] / q : 0);
    if (fabs(q) < piv) q = -piv;
    c += q < 0;
  }
  return c;
}

/* The j-th largest eigenvalue of T_k (j = 1: the largest) by bisection
 * inside its Gershgorin interval. */
static double top_eig(int k, const double *a, const double *b, int j, double *norm) {
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < k; i++) {
    double r = (i ? fabs(b[i - 1]) : 0) + (i < k - 1 ? fabs(b[i]) : 0);
    lo = fmin(lo, a[i] - r), hi = fmax(hi, a[i] + r);
  }
  *norm = fmax(fabs(lo), fabs(hi));
  double piv = DBL_MIN * fmax(1, *norm * *norm);
  while (hi - lo > 2 * DBL_EPSILON * fmax(fabs(lo), fabs(hi))) {
    double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (count_below(k, a, b, mid, piv) >= k - j + 1)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

/* Forward elimination with partial pivoting of the tridiagonal (dl, d, du)
 * on x (LAPACK dgtsv); du2 receives the fill-in. Zero pivots become piv. */
static void tri_eliminate(int n, double *dl, double *d, double *du, double *du2, double *x, double piv) {
  for (int i = 0; i < n - 1; i++) {
    du2[i] = 0;
    if (fabs(d[i]) >= fabs(dl[i])) {
      if (d[i] == 0) d[i] = piv;
      double f = dl[i] / d[i];
      d[i + 1] -= f * du[i], x[i + 1] -= f * x[i];
    } else {
      double f = d[i] / dl[i], t = d[i + 1], xi = x[i];
      d[i] = dl[i], d[i + 1] = du[i] - f * t;
      if (i < n - 2) du2[i] = du[i + 1], du[i + 1] = -f * du2[i];
      du[i] = t, x[i] = x[i + 1], x[i + 1] = xi - f * x[i + 1];
    }
  }
  if (d[n - 1] == 0) d[n - 1] = piv;
}

/* Solve (T - theta I) x = x in place; w is [4k] workspace. */
static void tri_solve(int k, const double *a, const double *b, double theta, double piv, double *x, double *w) {
  double *dl = w, *d = w + k, *du = w + 2 * k, *du2 = w + 3 * k;
  for (int i = 0; i < k; i++) {
    d[i] = a[i] - theta;
    dl[i] = du[i] = i < k - 1 ? b[i] : 0;
  }
  tri_eliminate(k, dl, d, du, du2, x, piv);
  for (int i = k - 1; i >= 0; i--) {
    double r = x[i];
    if (i < k - 1) r -= du[i] * x[i + 1];
    if (i < k - 2) r -= du2[i] * x[i + 2];
    x[i] = r / d[i];
  }
}

/* Scale x[k] to unit 2-norm (via its largest entry, against overflow). */
static void unit(int k, double *x) {
  double m = 0, s = 0;
  for (int i = 0; i < k; i++) m = fmax(m, fabs(x[i]));
  for (int i = 0; i < k && m > 0; i++) x[i] /= m, s += x[i] * x[i];
  for (int i = 0; i < k && s > 0; i++) x[i] /= sqrt(s);
}

/* theta, s and the residual estimate of T_k (k = t->k). */
static void tri_update(lz_tri *t) {
  int k = t->k;
  double norm;
  t->theta = top_eig(k, t->a, t->b, 1, &norm);
  double piv = DBL_EPSILON * fmax(norm, DBL_MIN);
  uint64_t x = 12345;
  for (int i = 0; i < k; i++) t->s[i] = dtm_rng_uniform(&x, 0.5, 1.5);
  for (int it = 0; it < 3; it++) {
    tri_solve(k, t->a, t->b, t->theta, piv, t->s, t->work);
    unit(k, t->s);
  }
  t->est = fabs(t->b[k - 1] * t->s[k - 1]);
  t->invariant = t->b[k - 1] <= 1e-13 * norm;
}

/* ---- the two passes -------------------------------------------------- */

/* First pass: steps until the estimate meets tol, T_k becomes invariant
 * or maxit steps are taken. */
/* How far the residual estimate est has come down towards tol * theta,
 * on a log scale (for the progress hook). */
static double fraction_done(const lz_tri *t, double tol) {
  if (!(t->est > 0) || !(tol > 0) || !(t->theta > 0)) return -1;
  double f = log(t->theta / t->est) / log(1 / tol);
  return f < 0 ? 0 : f > 1 ? 1 : f;
}

static void first_pass(lz_state *z, lz_tri *t, double tol, int maxit) {
  if (t->k > 0) { /* go on from where an earlier pass stopped */
    if (t->invariant || t->k == maxit || t->est <= tol * t->theta) return;
    lz_advance(z, t->b[t->k - 1]);
    t->k++;
  } else
    t->k = 1;
  for (;; t->k++) {
    lz_step(z, &t->a[t->k - 1], &t->b[t->k - 1]);
    tri_update(t);
    dtm_progress_update(fraction_done(t, tol));
    if (t->est <= tol * t->theta || t->invariant || t->k == maxit) return;
    lz_advance(z, t->b[t->k - 1]);
  }
}

/* Second pass: y = V_k s (unit), then the true residual ||A y - theta y||,
 * with A y left in z->w. */
static double ritz(lz_state *z, const lz_tri *t, double *y) {
  double a, b;
  lz_start(z);
  memset(y, 0, z->n * sizeof *y);
  for (int j = 0; j < t->k; j++) {
    for (size_t i = 0; i < z->n; i++) y[i] += t->s[j] * z->v[i];
    if (j == t->k - 1) break;
    lz_step(z, &a, &b);
    lz_advance(z, b);
  }
  double ny = sqrt(dot(z->n, y, y)), r = 0;
  for (size_t i = 0; i < z->n; i++) y[i] /= ny;
  dtm_operator_apply_sym(z->op, y, z->w);
  for (size_t i = 0; i < z->n; i++) r += pow(z->w[i] - t->theta * y[i], 2);
  return sqrt(r);
}

/* The mode u = M^-1/2 y, into y (u^T M u = y^T y = 1). */
static void to_field(const dtm_operator *op, size_t n, double *y) {
  const double *m = dtm_operator_mass(op);
  for (size_t i = 0; i < n; i++) y[i] = m[i] > 0 ? y[i] / sqrt(m[i]) : 0;
}

static void lz_free(lz_state *z, lz_tri *t) {
  free(z->vp), free(z->v), free(z->w);
  free(t->a), free(t->b), free(t->s), free(t->work);
}

static int lz_alloc(lz_state *z, lz_tri *t, int maxit) {
  size_t n = z->n ? z->n : 1, k = (size_t)maxit;
  z->vp = malloc(n * sizeof(double)), z->v = malloc(n * sizeof(double));
  z->w = malloc(n * sizeof(double));
  t->a = malloc(k * sizeof(double)), t->b = malloc(k * sizeof(double));
  t->s = malloc(k * sizeof(double)), t->work = malloc(4 * k * sizeof(double));
  if (z->vp && z->v && z->w && t->a && t->b && t->s && t->work) return DTM_OK;
  lz_free(z, t);
  return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the Lanczos vectors");
}

/* The result of the steps taken so far: theta, the residual (Paige's
 * estimate, or the true one of the Ritz vector rebuilt when want_mode) and
 * whether it meets tol. */
static int finish(lz_state *z, const lz_tri *t, double tol, int want_mode, dtm_lanczos_result *r) {
  double norm;
  r->theta = t->theta;
  r->theta2 = t->k > 1 ? top_eig(t->k, t->a, t->b, 2, &norm) : NAN;
  r->iterations = t->k;
  r->tol_used = tol;
  if (!want_mode) { /* Paige: an eigenvalue lies within |beta_k s_k| (+ O(eps |A|)) of theta */
    r->residual = t->est;
    r->converged = t->invariant || t->est <= tol * t->theta;
    return DTM_OK;
  }
  double *y = malloc(z->n * sizeof *y);
  if (!y) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the Ritz vector");
  r->residual = ritz(z, t, y);
  r->converged = t->invariant || r->residual <= tol * t->theta;
  to_field(z->op, z->n, y);
  free(r->mode);
  r->mode = y;
  return DTM_OK;
}

static int run(lz_state *z, lz_tri *t, double tol, int maxit, int want_mode, dtm_lanczos_result *r) {
  if (lz_start(z) == 0) return DTM_ERR(DTM_ERR_INPUT, "the global estimate needs a mesh with mass");
  first_pass(z, t, tol, maxit);
  return finish(z, t, tol, want_mode, r);
}

/* Go on from where the last pass stopped, to tol. The Ritz vector's pass
 * replayed the recurrence up to v_k; one more step restores the next
 * direction the first pass had. */
static int go_on(lz_state *z, lz_tri *t, double tol, int maxit, int want_mode, dtm_lanczos_result *r) {
  double a, b;
  if (want_mode) lz_step(z, &a, &b);
  first_pass(z, t, tol, maxit);
  return finish(z, t, tol, want_mode, r);
}

#define CERT_TRIES 3      /* stricter passes after a refuted bound */
#define CERT_TIGHTEN 1e-2 /* the tolerance of each */
#define CLUSTER_GAP 10    /* theta2 within this many tol of theta: a clustered top */
#define STRICT 1e-4       /* the tolerance factor of the uncertified clustered case */

/* The bound theta + residual checked by the certificate c; a refuted one
 * sends Lanczos on at a stricter tolerance. */
static int certify(lz_state *z, lz_tri *t, dtm_certifier *c, double tol, int maxit, int want_mode,
                   dtm_lanczos_result *r) {
  for (int tries = 0;; tries++) {
    double margin, t0 = dtm_wtime();
    int below = dtm_certifier_below(c, r->theta + r->residual, &margin);
    r->cert_seconds += dtm_wtime() - t0;
    if (below) return r->residual += margin, r->certified = DTM_CERT_PROVEN, DTM_OK;
    r->certified = DTM_CERT_REFUTED;
    if (tries == CERT_TRIES || t->invariant || t->k == maxit) return r->converged = 0, DTM_OK;
    tol *= CERT_TIGHTEN;
    DTM_CHECK(go_on(z, t, tol, maxit, want_mode, r));
    if (!r->converged) return DTM_OK;
  }
}

static int certified_run(lz_state *z, lz_tri *t, double tol, int maxit, int want_mode, double budget, int suspect,
                         dtm_lanczos_result *r) {
  DTM_CHECK(run(z, t, tol, maxit, want_mode, r));
  if (!r->converged) return DTM_OK;
  dtm_certifier *c = NULL;
  int status = DTM_CERT_TOO_DEAR;
  double t0 = dtm_wtime();
  if (budget > 0) DTM_CHECK(dtm_certifier_create_costed(z->op, budget, &c, &status, r->cert_predicted));
  r->cert_seconds = dtm_wtime() - t0;
  if (c) {
    int e = certify(z, t, c, tol, maxit, want_mode, r);
    dtm_certifier_destroy(&c);
    return e;
  }
  r->certified = status;
  int clustered = t->k > 1 && r->theta2 >= (1 - CLUSTER_GAP * tol) * r->theta;
  if (suspect || clustered) DTM_CHECK(go_on(z, t, tol * STRICT, maxit, want_mode, r));
  return DTM_OK;
}

int dtm_lanczos_max(const dtm_operator *op, double tol, int maxit, unsigned seed, dtm_lanczos_result *r) {
  return dtm_lanczos_max_ex(op, tol, maxit, seed, 1, r);
}

static int lanczos(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode, double budget,
                   int suspect, int certified, dtm_lanczos_result *r) {
  if (!r) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_lanczos_max: no result");
  memset(r, 0, sizeof *r);
  r->theta2 = NAN;
  if (!op || maxit < 1 || !(tol >= 0))
    return DTM_ERR(DTM_ERR_INPUT,
                   "Lanczos needs an operator, maxit >= 1 (got %d) and "
                   "tol >= 0 (got %g)",
                   maxit, tol);
  double t0 = dtm_wtime();
  lz_state z = {.op = op, .n = dtm_operator_ndof(op), .seed = seed};
  lz_tri t = {0};
  DTM_CHECK(lz_alloc(&z, &t, maxit));
  dtm_progress_begin("Lanczos");
  int e = certified ? certified_run(&z, &t, tol, maxit, want_mode, budget, suspect, r)
                    : run(&z, &t, tol, maxit, want_mode, r);
  dtm_progress_end();
  lz_free(&z, &t);
  r->seconds = dtm_wtime() - t0;
  if (e) free(r->mode), r->mode = NULL;
  return e ? dtm_error_trace(e, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_lanczos_max_ex(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode,
                       dtm_lanczos_result *r) {
  return lanczos(op, tol, maxit, seed, want_mode, 0, 0, 0, r);
}

int dtm_lanczos_max_certified(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode,
                              double budget, int suspect, dtm_lanczos_result *r) {
  return lanczos(op, tol, maxit, seed, want_mode, budget, suspect, 1, r);
}
