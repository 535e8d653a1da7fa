/* The global spectral estimate: the largest eigenvalue of M^-1 K by the
 * Lanczos recurrence on the symmetric A = M^-1/2 K M^-1/2 (dofs without
 * mass stay 0), started from a vector uniform on the unit sphere of the
 * dofs with mass: a standard normal value per dof, drawn by splitmix64 from
 * the seed and the node's Gmsh tag (Box-Muller), normalised.
 * The basis V_k is kept semi-orthogonal by Simon's partial
 * reorthogonalisation (1984): the omega recurrence estimates every
 * v_{j+1} . v_i from T_k alone (no pass over the basis), and a new
 * direction is reorthogonalised against the whole stored basis (classical
 * Gram-Schmidt, a second pass where the first took much off) only when an
 * estimate exceeds sqrt(eps / k), and then at the next step too. What
 * finite precision changes, and why this is enough for the bound: with
 * |V_k^T V_k - I| <= sqrt(eps / k), T_k equals Q^T A Q for an orthonormal
 * basis Q of span(V_k) up to O(eps |A|) (Simon's semi-orthogonality
 * result), so theta, the top eigenvalue of T_k, is the largest Rayleigh
 * quotient of A over the computed Krylov space to working precision, as
 * with full reorthogonalisation at every step (tests/t931: the same top
 * Ritz value to 1e-12 on a Gmsh cube, the measured |V^T V - I| below
 * sqrt(eps / k) where plain Lanczos reaches 0.1-0.2), and it never
 * exceeds lambda_max beyond that rounding whatever k is. Without any
 * reorthogonalisation lost orthogonality brings spurious copies of
 * converged Ritz values and T_k is no longer a projection of A. Full
 * reorthogonalisation at every step (2-4 passes over k vectors of n) took
 * as much CPU as the products in a profile of run --posterior at 1.2e6
 * tets (41 steps, 6e5 unknowns: 16 % each); the partial one
 * reorthogonalised 6 of those 41 steps (docs/performance.md). The
 * basis costs k ndof doubles, and gives the Ritz vector y = V_k s
 * directly. Its vectors are stored unnormalised with their scales, and
 * every pass over them is lzvec.c's (in chunks, on the run's threads,
 * with the same bits on any thread count).
 * After each step theta is found by Sturm bisection to full precision and
 * its unit eigenvector s by inverse iteration, which gives the residual
 * estimate |beta_k s_k|. The run stops when that is <= tol * theta, at
 * maxit steps, or when beta_k vanishes (an invariant subspace: theta is
 * then exact). One last product measures the true residual
 * ||A y - theta y||, which is what the result reports.
 * theta + residual bounds the eigenvalue nearest theta, not necessarily the
 * largest: from a start that holds little of the top mode, with the top
 * two eigenvalues closer than a few tol, Lanczos meets its tolerance on
 * the second. dtm_lanczos_max_certified then checks the bound by the
 * factorisation of certify.c and goes on from where it stopped at a
 * stricter tolerance while the bound is refuted; where the factorisation
 * is too dear it goes on to tol * 1e-4 when the caller suspects a cluster
 * (point masses) or T_k shows one (its second Ritz value within 10 tol of
 * theta), which is a heuristic, not a proof.
 * dtm_lanczos_max_probable adds the probable layer there: by Kuczynski and
 * Wozniakowski (SIAM J. Matrix Anal. Appl. 13(4), 1992), for any symmetric
 * positive semi-definite A of order n (here the dofs with mass) and a start
 * uniform on the unit sphere, P((lambda_max - theta_k) / lambda_max >= eps)
 * <= 1.648 sqrt(n) exp(-sqrt(eps) (2k - 1)) in exact arithmetic, whatever
 * the spectrum and its gaps. With eps_k the smallest eps whose bound is
 * <= DTM_LANCZOS_FAILURE, lambda_max <= theta_k / (1 - eps_k) but for that
 * probability; theta_k is raised by 10 k eps |T_k| first for the rounding
 * of the semi-orthogonal recurrence. Lanczos goes on past its tolerance
 * until eps_k meets the caller's target; converged is then judged at the
 * caller's tolerance (the heuristic's stricter one may run out of steps,
 * and the probable bound caps the step instead). The seed is the caller's (the
 * report gives it); the bound is over the draw of the start, so it holds
 * for a seed chosen without looking at the matrix. */
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
  const double *vp; /* V_{j-1} (NULL for j = 0): the basis's vector */
  const double *v;  /* V_j: the basis's last vector */
  double sp, sv;    /* their scales: v_{j-1} = sp V_{j-1}, v_j = sv V_j */
  double *w;        /* the next direction (owned; it becomes V_{j+1}) */
  double bprev;     /* beta_{j-1} */
  double **V;       /* [maxit][n] the basis, unnormalised: v_i = sc[i] V_i (each owned) */
  double *sc;       /* [maxit] the scales */
  int nv;           /* vectors stored */
  double *c;        /* [maxit] Gram-Schmidt coefficients */
  double *part;     /* [chunks * (maxit + 2)] the chunks' partial sums (lzvec.c) */
  double nmass;     /* dofs with mass: the order of the bound */
  int mode;         /* DTM_REORTH_*: partial (dtmap's), full or none (the white-box test's references) */
  double *om[3];    /* [maxit + 2] omega rows j - 1, j, j + 1: estimates of v_j . v_i */
  int again;        /* the next direction is reorthogonalised too (in pairs) */
  int nreorth;      /* steps that reorthogonalised */
  double tnorm;     /* |T_k| so far (Gershgorin): the scale of the rounding */
} lz_state;

typedef struct {
  int k;             /* steps taken */
  double *a, *b;     /* [maxit] diagonal and off-diagonal of T */
  double *s;         /* [maxit] top eigenvector of T_k */
  double *work;      /* [5 maxit] tridiagonal solver */
  double theta, est; /* top Ritz value, |beta_k s_k| */
  int invariant;     /* beta_k vanished */
  int kmax;          /* maxit, or fewer when the basis could not grow */
} lz_tri;

/* A vector of the basis (n doubles, at least one). Huge pages
 * (posix_memalign to 2 MiB and madvise MADV_HUGEPAGE) were tried: with
 * Debian's defrag setting each 2 MiB fault zeroed and compacted
 * synchronously, and the global estimate at 1.2e6 tets took 1.8 s instead
 * of 1.0-1.2 s. */
static double *vec_alloc(size_t n) { return malloc((n ? n : 1) * sizeof(double)); }

/* |x|, by a pass that leaves x as it is. */
static double norm2(lz_state *z, double *x) {
  double d[2];
  dtm_vstep(z->n, x, 1, 0, x, x, z->part, d);
  return sqrt(d[1]);
}

/* v_0: standard normal on the dofs with mass (drawn per Gmsh node tag, so
 * the start does not depend on the node order), of unit norm through its
 * scale: uniform on the unit sphere of those dofs; 0 when there are none. */
static double lz_start(lz_state *z) {
  const double *m = dtm_operator_mass(z->op);
  double *v = vec_alloc(z->n);
  if (!v) return 0;
  z->V[z->nv++] = v;
  dtm_operator_draw_normal(z->op, z->seed, v);
  z->nmass = 0;
  for (size_t i = 0; i < z->n; i++) {
    v[i] = m[i] > 0 ? v[i] : 0;
    z->nmass += m[i] > 0;
  }
  double nv = norm2(z, v);
  z->sc[0] = nv > 0 ? 1 / nv : 0;
  z->v = v, z->sv = z->sc[0], z->vp = NULL, z->sp = 0, z->bprev = 0;
  z->om[1][0] = 1; /* v_0 . v_0 */
  return nv;
}

/* One classical Gram-Schmidt pass of w against the basis (lzvec.c: by
 * chunks of w that stay in cache while the basis streams past, on the
 * run's threads); returns the coefficient of the newest vector and w's
 * squared length after. */
static double orthogonalise(lz_state *z, double *ww) {
  dtm_vproject(z->n, z->w, z->V, z->sc, z->nv, z->part, z->c);
  *ww = dtm_vsubtract(z->n, z->w, z->V, z->sc, z->c, z->nv, z->part);
  return z->c[z->nv - 1];
}

/* w reorthogonalised against v_0 .. v_j, a second time when the first
 * pass left less than 1/sqrt(2) of w's length (Daniel, Gragg, Kaufman and
 * Stewart's criterion: one pass that removes little leaves w orthogonal to
 * working precision, and after one that removes much the second restores
 * it); *a takes the coefficients of v_j, *b (w's length before) becomes
 * its length after. */
static void reorthogonalise(lz_state *z, double *a, double *b) {
  double before = *b, ww;
  *a += orthogonalise(z, &ww);
  *b = sqrt(ww);
  if (*b < 0.7071067811865476 * before) { /* 1/sqrt(2) */
    *a += orthogonalise(z, &ww);
    *b = sqrt(ww);
  }
  z->nreorth++;
}

/* The rounding floor of the omega estimates: a dot of n terms and a
 * product, relative to |T_k| (the square root of n: rounding errors of
 * random sign). */
static double om_floor(const lz_state *z) { return DBL_EPSILON * sqrt((double)z->n); }

/* Simon's omega recurrence: from om[0] (row j - 1) and om[1] (row j) the
 * estimates om[2] of v_{j+1} . v_i, i <= j, before v_{j+1} = w / bj is
 * formed, from the recurrence both vectors obey (A v_i = beta_i v_{i+1} +
 * alpha_i v_i + beta_{i-1} v_{i-1} + rounding): beta_j om_{j+1,i} =
 * beta_i om_{j,i+1} + (alpha_i - alpha_j) om_{j,i} + beta_{i-1}
 * om_{j,i-1} - beta_{j-1} om_{j-1,i} + the rounding of both products,
 * taken at its bound om_floor |T_k| with the sign that makes |om| larger.
 * Returns the largest |om_{j+1,i}|, i < j (v_j itself is kept orthogonal
 * locally). */
static double om_update(lz_state *z, const double *al, const double *be, int j, double bj) {
  const double *op = z->om[0], *oc = z->om[1];
  double *on = z->om[2], noise = om_floor(z) * z->tnorm, worst = 0;
  for (int i = 0; i < j; i++) {
    double x = be[i] * oc[i + 1] + (al[i] - al[j]) * oc[i] - be[j - 1] * op[i] + (i > 0 ? be[i - 1] * oc[i - 1] : 0);
    on[i] = (x + copysign(noise, x)) / bj;
    worst = fmax(worst, fabs(on[i]));
  }
  on[j] = noise / bj; /* the local orthogonality of v_{j+1} to v_j */
  on[j + 1] = 1;
  return worst;
}

/* After a reorthogonalisation v_{j+1} is orthogonal to the basis to the
 * rounding floor. */
static void om_reset(lz_state *z, int j, double bj) {
  for (int i = 0; i < j; i++) z->om[2][i] = om_floor(z);
  z->om[2][j] = om_floor(z) * z->tnorm / bj;
}

/* Semi-orthogonality: the level of |v_i . v_j| the omega estimates are
 * kept under, sqrt(eps / k) (Simon's condition for T_k to be the
 * projection of A on an orthonormal basis of span(V_k) up to O(eps |A|)). */
static double om_limit(int k) { return sqrt(DBL_EPSILON / k); }

/* w = A v_j - a v_j - beta_{j-1} v_{j-1} for j = t->k - 1, into a_j and
 * b_j. Full mode: reorthogonalised against v_0 .. v_j at every step.
 * Partial (Simon, 1984): the omega recurrence estimates w's loss of
 * orthogonality to the older vectors from T_k alone, and w is
 * reorthogonalised against the whole basis only when an estimate exceeds
 * om_limit, and then at the next step too (the next direction inherits
 * v_j's loss through the recurrence). Locally, w . v_j after the
 * subtraction of a v_j is measured in the same pass; a second projection
 * on v_j follows only where it exceeds the rounding of a itself (4 eps
 * |T_k|: below that it changes neither a nor v_{j+1} . v_j beyond what
 * om_update already allows for). So the vector work is two passes over
 * n, each update fused with the dots that follow it. */
static void lz_step(lz_state *z, lz_tri *t) {
  size_t n = z->n;
  int j = t->k - 1;
  double *a = &t->a[j], *b = &t->b[j], d[2];
  const double *vp = z->vp ? z->vp : z->v;
  dtm_operator_apply_sym(z->op, z->v, z->w);
  dtm_vstep(n, z->w, z->sv, z->vp ? z->bprev * z->sp : 0, vp, z->v, z->part, d); /* w = A v_j - beta_{j-1} v_{j-1} */
  *a = z->sv * d[0];
  dtm_vstep(n, z->w, 1, *a * z->sv, z->v, z->v, z->part, d); /* w -= alpha_j v_j; w . v_j, |w|^2 */
  double c = z->sv * d[0], bb = d[1], scale = fmax(z->tnorm, fabs(*a) + sqrt(bb) + z->bprev);
  if (z->mode == DTM_REORTH_FULL) {
    *b = sqrt(bb);
    reorthogonalise(z, a, b);
    return;
  }
  if (fabs(c) > 4 * DBL_EPSILON * scale) { /* the local correction */
    dtm_vstep(n, z->w, 1, c * z->sv, z->v, z->v, z->part, d);
    *a += c, bb = d[1];
  }
  *b = sqrt(bb);
  z->tnorm = fmax(z->tnorm, fabs(*a) + *b + z->bprev);
  double worst = *b > 0 ? om_update(z, t->a, t->b, j, *b) : 0;
  if (z->mode == DTM_REORTH_PARTIAL && *b > 0 && (z->again || worst > om_limit(t->k + 1))) {
    z->again = !z->again;
    reorthogonalise(z, a, b);
    if (*b > 0) om_reset(z, j, *b);
  }
}

/* v_{j+1} = w / b: w itself joins the basis with the scale 1 / b, and a
 * new w is taken for the next product. 0 when the basis cannot grow. */
static int lz_advance(lz_state *z, double b) {
  double *q = vec_alloc(z->n), *o = z->om[0];
  if (!q) return 0;
  z->V[z->nv] = z->w, z->sc[z->nv] = 1 / b, z->w = q;
  z->vp = z->v, z->sp = z->sv, z->v = z->V[z->nv], z->sv = z->sc[z->nv], z->bprev = b;
  z->nv++;
  z->om[0] = z->om[1], z->om[1] = z->om[2], z->om[2] = o;
  return 1;
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

double dtm_tridiag_top(int k, const double *a, const double *b, double *s, double *w) {
  double norm, theta = top_eig(k, a, b, 1, &norm), piv = DBL_EPSILON * fmax(norm, DBL_MIN);
  uint64_t x = 12345;
  for (int i = 0; i < k; i++) s[i] = dtm_rng_uniform(&x, 0.5, 1.5);
  for (int it = 0; it < 3; it++) {
    tri_solve(k, a, b, theta, piv, s, w);
    unit(k, s);
  }
  return theta;
}

/* ---- the two passes -------------------------------------------------- */

/* How far the residual estimate est has come down towards tol * theta,
 * on a log scale (for the progress hook). */
static double fraction_done(const lz_tri *t, double tol) {
  if (!(t->est > 0) || !(tol > 0) || !(t->theta > 0)) return -1;
  double f = log(t->theta / t->est) / log(1 / tol);
  return f < 0 ? 0 : f > 1 ? 1 : f;
}

/* Done when the estimate meets tol and eps_k meets eps_target (INFINITY:
 * no probable layer), T_k became invariant, or no step is left. */
static int done(const lz_state *z, const lz_tri *t, double tol, double eps_target) {
  if (t->invariant || t->k >= t->kmax) return 1;
  return t->est <= tol * t->theta && dtm_lanczos_kw_eps(z->nmass, t->k, DTM_LANCZOS_FAILURE) <= eps_target;
}

/* Steps until done; goes on from where an earlier pass stopped. */
static void first_pass(lz_state *z, lz_tri *t, double tol, double eps_target) {
  if (t->k > 0) {
    if (done(z, t, tol, eps_target)) return;
    if (!lz_advance(z, t->b[t->k - 1])) {
      t->kmax = t->k;
      return;
    }
    t->k++;
  } else
    t->k = 1;
  for (;; t->k++) {
    lz_step(z, t);
    tri_update(t);
    dtm_progress_update(fraction_done(t, tol));
    if (done(z, t, tol, eps_target)) return;
    if (!lz_advance(z, t->b[t->k - 1])) {
      t->kmax = t->k;
      return;
    }
  }
}

/* y = V_k s (unit), then the true residual ||A y - theta y|| (ay: [n]
 * workspace). */
static double ritz(lz_state *z, const lz_tri *t, double *y, double *ay) {
  double d[2];
  dtm_vcombine(z->n, y, z->V, z->sc, t->s, t->k);
  double ny = norm2(z, y);
  for (size_t i = 0; i < z->n; i++) y[i] /= ny;
  dtm_operator_apply_sym(z->op, y, ay);
  dtm_vstep(z->n, ay, 1, t->theta, y, y, z->part, d); /* ay - theta y, its length */
  return sqrt(d[1]);
}

/* The mode u = M^-1/2 y, into y (u^T M u = y^T y = 1). */
static void to_field(const dtm_operator *op, size_t n, double *y) {
  const double *m = dtm_operator_mass(op);
  for (size_t i = 0; i < n; i++) y[i] = m[i] > 0 ? y[i] / sqrt(m[i]) : 0;
}

static void lz_free(lz_state *z, lz_tri *t) {
  for (int j = 0; z->V && j < z->nv; j++) free(z->V[j]);
  free(z->V), free(z->c), free(z->sc), free(z->part);
  free(z->om[0]), free(z->om[1]), free(z->om[2]);
  free(z->w);
  free(t->a), free(t->b), free(t->s), free(t->work);
}

static int lz_alloc(lz_state *z, lz_tri *t, int maxit) {
  size_t n = z->n ? z->n : 1, k = (size_t)maxit;
  z->w = vec_alloc(n);
  t->a = malloc(k * sizeof(double)), t->b = malloc(k * sizeof(double));
  t->s = malloc(k * sizeof(double)), t->work = malloc(4 * k * sizeof(double));
  z->V = calloc(k, sizeof *z->V), z->c = malloc(k * sizeof(double)), z->sc = malloc(k * sizeof(double));
  z->part = malloc(dtm_vchunks(n) * (k + 2) * sizeof(double));
  for (int i = 0; i < 3; i++) z->om[i] = calloc(k + 2, sizeof(double));
  t->kmax = maxit;
  if (z->w && t->a && t->b && t->s && t->work && z->V && z->c && z->sc && z->part && z->om[0] && z->om[1] && z->om[2])
    return DTM_OK;
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
  double *y = malloc(z->n * sizeof *y), *ay = malloc(z->n * sizeof *ay);
  if (!y || !ay) return free(y), free(ay), DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the Ritz vector");
  r->residual = ritz(z, t, y, ay);
  free(ay);
  r->converged = t->invariant || r->residual <= tol * t->theta;
  to_field(z->op, z->n, y);
  free(r->mode);
  r->mode = y;
  return DTM_OK;
}

static int run(lz_state *z, lz_tri *t, double tol, int want_mode, dtm_lanczos_result *r) {
  if (lz_start(z) == 0) return DTM_ERR(DTM_ERR_INPUT, "the global estimate needs a mesh with mass");
  first_pass(z, t, tol, INFINITY);
  return finish(z, t, tol, want_mode, r);
}

/* Go on from where the last pass stopped, to tol and eps_target. */
static int go_on(lz_state *z, lz_tri *t, double tol, double eps_target, int want_mode, dtm_lanczos_result *r) {
  first_pass(z, t, tol, eps_target);
  return finish(z, t, tol, want_mode, r);
}

#define CERT_TRIES 3      /* stricter passes after a refuted bound */
#define CERT_TIGHTEN 1e-2 /* the tolerance of each */
#define CLUSTER_GAP 10    /* theta2 within this many tol of theta: a clustered top */
#define STRICT 1e-4       /* the tolerance factor of the uncertified clustered case */
#define KW_C 1.648        /* the constant of the Kuczynski-Wozniakowski bound */
#define ROUND_K 10        /* theta's rounding allowance: ROUND_K k eps |T_k| */

double dtm_lanczos_kw_eps(double n, int k, double p) {
  if (k < 1 || !(n >= 1) || !(p > 0)) return 1;
  double l = log(KW_C * sqrt(n) / p);
  if (l <= 0) return 0;
  double q = l / (2.0 * k - 1);
  return q >= 1 ? 1 : q * q;
}

int dtm_lanczos_kw_steps(double n, double eps, double p) {
  double l = n >= 1 && p > 0 ? log(KW_C * sqrt(n) / p) : INFINITY;
  if (l <= 0) return 1;
  double k = ceil(0.5 * (l / sqrt(eps) + 1));
  return k < 1 ? 1 : k > INT32_MAX ? INT32_MAX : (int)k;
}

/* The bound theta + residual checked by the certificate c; a refuted one
 * sends Lanczos on at a stricter tolerance. */
static int certify(lz_state *z, lz_tri *t, dtm_certifier *c, double tol, int want_mode, dtm_lanczos_result *r) {
  for (int tries = 0;; tries++) {
    double margin, t0 = dtm_wtime();
    int below = dtm_certifier_below(c, r->theta + r->residual, &margin);
    r->cert_seconds += dtm_wtime() - t0;
    if (below) return r->residual += margin, r->certified = DTM_CERT_PROVEN, DTM_OK;
    r->certified = DTM_CERT_REFUTED;
    if (tries == CERT_TRIES || t->invariant || t->k >= t->kmax) return r->converged = 0, DTM_OK;
    tol *= CERT_TIGHTEN;
    DTM_CHECK(go_on(z, t, tol, INFINITY, want_mode, r));
    if (!r->converged) return DTM_OK;
  }
}

/* The probable layer: on to eps_target, then the bound of the k steps
 * taken (none when eps_k reaches 1: too few steps to say anything). */
static int probable(lz_state *z, lz_tri *t, double eps_target, int want_mode, dtm_lanczos_result *r) {
  DTM_CHECK(go_on(z, t, r->tol_used, eps_target, want_mode, r));
  double eps = dtm_lanczos_kw_eps(z->nmass, t->k, DTM_LANCZOS_FAILURE), norm;
  top_eig(t->k, t->a, t->b, 1, &norm);
  r->nbound = z->nmass;
  if (!(eps < 1)) return DTM_OK;
  r->eps = eps, r->failure = DTM_LANCZOS_FAILURE;
  r->bound = (t->theta + ROUND_K * t->k * DBL_EPSILON * norm) / (1 - eps);
  r->certified = DTM_CERT_PROBABLE;
  return DTM_OK;
}

static int certified_run(lz_state *z, lz_tri *t, double tol, int want_mode, double budget, int suspect,
                         double eps_target, dtm_lanczos_result *r) {
  DTM_CHECK(run(z, t, tol, want_mode, r));
  if (!r->converged) return DTM_OK;
  dtm_certifier *c = NULL;
  int status = DTM_CERT_TOO_DEAR;
  double t0 = dtm_wtime();
  if (budget > 0) DTM_CHECK(dtm_certifier_create_costed(z->op, budget, &c, &status, r->cert_predicted));
  r->cert_seconds = dtm_wtime() - t0;
  if (c) {
    int e = certify(z, t, c, tol, want_mode, r);
    dtm_certifier_destroy(&c);
    r->deterministic = r->certified;
    return e;
  }
  r->certified = r->deterministic = status;
  int clustered = t->k > 1 && r->theta2 >= (1 - CLUSTER_GAP * tol) * r->theta;
  if (suspect || clustered) DTM_CHECK(go_on(z, t, tol * STRICT, INFINITY, want_mode, r));
  if (eps_target < 0) return DTM_OK;
  DTM_CHECK(probable(z, t, eps_target, want_mode, r));
  /* the estimate meets the caller's tolerance even where the heuristic's
     stricter one ran out of steps: the probable bound now caps the step */
  r->converged = t->invariant || r->residual <= tol * r->theta;
  return DTM_OK;
}

int dtm_lanczos_max(const dtm_operator *op, double tol, int maxit, unsigned seed, dtm_lanczos_result *r) {
  return dtm_lanczos_max_ex(op, tol, maxit, seed, 1, r);
}

typedef struct {
  double budget;     /* the certificate's flops (0: none) */
  int suspect;       /* the caller expects a clustered top */
  int certified;     /* run the certified layers at all */
  double eps_target; /* the probable layer's eps (negative: none) */
} lz_layers;

static int lanczos(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode, const lz_layers *l,
                   dtm_lanczos_result *r) {
  if (!r) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_lanczos_max: no result");
  memset(r, 0, sizeof *r);
  r->theta2 = r->eps = r->failure = r->bound = NAN;
  r->seed = seed;
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
  int e = l->certified ? certified_run(&z, &t, tol, want_mode, l->budget, l->suspect, l->eps_target, r)
                       : run(&z, &t, tol, want_mode, r);
  dtm_progress_end();
  lz_free(&z, &t);
  r->seconds = dtm_wtime() - t0;
  if (e) free(r->mode), r->mode = NULL;
  return e ? dtm_error_trace(e, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_lanczos_max_ex(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode,
                       dtm_lanczos_result *r) {
  lz_layers l = {0, 0, 0, -1};
  return lanczos(op, tol, maxit, seed, want_mode, &l, r);
}

int dtm_lanczos_max_certified(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode,
                              double budget, int suspect, dtm_lanczos_result *r) {
  lz_layers l = {budget, suspect, 1, -1};
  return lanczos(op, tol, maxit, seed, want_mode, &l, r);
}

int dtm_lanczos_max_probable(const dtm_operator *op, double tol, int maxit, unsigned seed, int want_mode, double budget,
                             int suspect, double eps_target, dtm_lanczos_result *r) {
  lz_layers l = {budget, suspect, 1, eps_target};
  return lanczos(op, tol, maxit, seed, want_mode, &l, r);
}

/* The largest |v_i . v_j - delta_ij| over the basis. */
static double basis_deviation(const lz_state *z) {
  double worst = 0;
  for (int i = 0; i < z->nv; i++) {
    dtm_vproject(z->n, z->V[i], z->V, z->sc, i + 1, z->part, z->c);
    for (int j = 0; j <= i; j++) worst = fmax(worst, fabs(z->sc[i] * z->c[j] - (i == j)));
  }
  return worst;
}

int dtm_lanczos_basis_check(const dtm_operator *op, int steps, unsigned seed, int mode, double *theta,
                            double *deviation, int *nreorth) {
  if (!op || steps < 1) return DTM_ERR(DTM_ERR_INPUT, "dtm_lanczos_basis_check: an operator and steps >= 1");
  lz_state z = {.op = op, .n = dtm_operator_ndof(op), .seed = seed, .mode = mode};
  lz_tri t = {0};
  DTM_CHECK(lz_alloc(&z, &t, steps));
  int e = lz_start(&z) > 0 ? DTM_OK : DTM_ERR(DTM_ERR_INPUT, "the basis check needs a mesh with mass");
  if (e == DTM_OK) first_pass(&z, &t, 0, INFINITY); /* tol 0: every step, or an invariant subspace */
  *theta = t.theta, *deviation = basis_deviation(&z), *nreorth = z.nreorth;
  lz_free(&z, &t);
  return e;
}
