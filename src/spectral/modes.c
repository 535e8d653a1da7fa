/* The lowest natural frequencies and mode shapes of a model, K x = lambda B
 * x with B = M + extra (the lumped mass and, for the accuracy price of mass
 * scaling, an added mass matrix), by shift-invert Lanczos on a sparse
 * factorisation.
 *
 * K is assembled from the operator's own product by the coloured probing
 * of certify.c (dtm_operator_assemble), so every element enters as the
 * operator computes it. K - sigma B is factored once by CHOLMOD (its own
 * choice of ordering and of a simplicial LDL^T or supernodal LL^T factor:
 * the matrix is positive definite, K semi-definite and B definite on the
 * unknowns with mass). sigma = -SHIFT max_i K_ii / B_ii is a small
 * negative shift, so that the rigid-body modes of the free model (lambda =
 * 0) do not make the matrix singular; unknowns without mass (nodes of no
 * element) are decoupled with a unit diagonal and stay zero.
 *
 * OP = (K - sigma B)^-1 B is symmetric in the B inner product, with
 * eigenvalues nu = 1 / (lambda - sigma): the lowest lambda are its largest
 * nu, well separated. Lanczos runs on OP in the B inner product from a
 * block of p random start vectors (p = 6 in space, 3 in a plane, 2 on a
 * line: a single start vector cannot see more than one vector of a
 * multiple eigenvalue, and the rigid modes are a 6-fold one), as band
 * Lanczos: each step applies OP to one vector and orthogonalises the result
 * against every stored vector twice (full reorthogonalisation), which
 * keeps the basis B-orthonormal to rounding and gives H with OP Q_m =
 * Q_{m+p} H. The Ritz pairs come from the symmetric part of H's leading m
 * x m block (cyclic Jacobi); a pair (nu, y = Q_m s) has ||OP y - nu y||_B =
 * ||H_{m:m+p, :} s||, and passes the test when that is at most
 * DTM_MODES_TOL |nu| (then lambda's relative error is of order
 * DTM_MODES_TOL^2 / gap: far below the figures printed). The run stops when
 * the lowest Ritz values up to the n-th elastic one all pass, with at least
 * EXTRA more steps in the basis than modes returned, or after STEPS_PER
 * steps per wanted mode (then converged = 0). A mode is rigid when |lambda|
 * <= DTM_MODES_RIGID_TOL times the largest Ritz value of the last H (the
 * far end of the spectrum the basis sees). Each returned shape's residual
 * ||K x - lambda B x|| / (lambda ||B x||) is measured with the operator's
 * product itself.
 *
 * The Sturm check: a Krylov method may miss an eigenvalue (a multiple one
 * beyond the block, or one the start vectors hardly hold), and nothing in
 * the Ritz pairs says so. By Sylvester's law of inertia, the negative
 * pivots of K - s B = L D L^T count the eigenvalues below s exactly,
 * whatever Lanczos found; at s = (1 + STURM_GAP) times the largest mode
 * returned, that count must equal the passed Ritz values below s. The
 * factorisation is CHOLMOD's simplicial LDL^T without pivoting (K - s B is
 * indefinite there), as structural codes do it; a zero pivot leaves the
 * check undone (counted = -1). It costs one more factorisation, slower
 * than the supernodal one (no dense kernels): 15 s for the 4.5e9 flops of
 * the notched beam of geometries/ (19,000 unknowns) on this machine at load
 * 8, where its Lanczos took 6 s; so it runs only when the factorisation is
 * predicted to cost at most STURM_FLOPS (counted = -2 otherwise). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "cholmod_dl.h"
#include "spectral.h"
#include "dtmap/operator.h"
#include "dtmap/util.h"

#define SHIFT 1e-6  /* sigma = -SHIFT max K_ii / B_ii: far below the lowest elastic eigenvalue of any mesh */
#define EXTRA 4     /* Lanczos steps beyond the modes returned before the test may stop the run */
#define STEPS_PER 8 /* Lanczos steps at most per wanted mode (plus STEPS_MIN) */
#define STEPS_MIN 60
#define DEFLATE 1e-10   /* a new vector below this share of OP q_j's B-norm: an invariant subspace */
#define STURM_GAP 1e-6  /* the Sturm check's s: this far above the largest mode returned, relative */
#define STURM_FLOPS 1e9 /* the Sturm check only for factorisations predicted below this (see above) */
#define TWO_PI 6.283185307179586476925

/* The pencil and the factorisation of K - sigma B. */
typedef struct {
  const dtm_operator *op;
  const dtm_csr *extra; /* or NULL */
  size_t n;             /* unknowns */
  const double *mass;   /* [n] lumped */
  unsigned char *on;    /* [n] the unknown has mass */
  size_t non;           /* how many */
  double sigma;
  cholmod_common cm;
  cholmod_sparse *K, *B; /* upper triangles; K has a unit diagonal where no mass */
  double flops;          /* CHOLMOD's predicted flops of the factorisation */
  cholmod_factor *L;
  cholmod_dense *b; /* [n] the right-hand side */
} pencil;

/* y = B x. */
static void b_apply(const pencil *p, const double *x, double *y) {
  if (p->extra) dtm_csr_apply(p->extra, x, y);
  for (size_t i = 0; i < p->n; i++) y[i] = (p->extra ? y[i] : 0.0) + p->mass[i] * x[i];
}

/* ---- the factorisation ------------------------------------------------ */

/* B's diagonal into d[n]. */
static void b_diagonal(const pencil *p, double *d) {
  for (size_t i = 0; i < p->n; i++) {
    d[i] = p->mass[i];
    for (size_t k = p->extra ? p->extra->rowptr[i] : 0; p->extra && k < p->extra->rowptr[i + 1]; k++)
      if (p->extra->col[k] == i) d[i] += p->extra->val[k];
  }
}

static void put(cholmod_triplet *t, size_t i, size_t j, double v) {
  SuiteSparse_long *ti = t->i, *tj = t->j, k = (SuiteSparse_long)t->nnz++;
  double *tx = t->x;
  ti[k] = (SuiteSparse_long)(i < j ? i : j), tj[k] = (SuiteSparse_long)(i < j ? j : i), tx[k] = v;
}

/* The upper triangle of K's node blocks into t; K's diagonal into kd[n]. */
static void k_entries(const pencil *p, size_t nn, const size_t *xa, const size_t *ad, const double *blk,
                      cholmod_triplet *t, double *kd) {
  size_t nc = (size_t)dtm_operator_ncomp(p->op);
  for (size_t v = 0; v < nn; v++)
    for (size_t q = xa[v]; q < xa[v + 1]; q++)
      for (size_t i = 0; i < nc; i++)
        for (size_t j = 0; j < nc; j++) {
          size_t row = ad[q] * nc + i, col = v * nc + j;
          double k = blk[(q * nc + i) * nc + j];
          if (row == col) kd[row] = k;
          if (row <= col && k != 0 && p->on[row] && p->on[col]) put(t, row, col, k);
        }
}

/* B (upper triangle) into tb; a unit diagonal of K where no mass into tk. */
static void b_entries(const pencil *p, cholmod_triplet *tk, cholmod_triplet *tb) {
  for (size_t i = 0; i < p->n; i++) {
    if (!p->on[i]) put(tk, i, i, 1.0);
    if (p->on[i] && p->mass[i] != 0) put(tb, i, i, p->mass[i]);
    for (size_t k = p->extra ? p->extra->rowptr[i] : 0; p->extra && k < p->extra->rowptr[i + 1]; k++) {
      size_t j = p->extra->col[k];
      if (j >= i && p->on[i] && p->on[j] && p->extra->val[k] != 0) put(tb, i, j, p->extra->val[k]);
    }
  }
}

/* The shift from K's and B's diagonals. */
static double shift(const pencil *p, const double *kd, const double *bd) {
  double top = 0;
  for (size_t i = 0; i < p->n; i++)
    if (p->on[i]) top = fmax(top, kd[i] / bd[i]);
  return -SHIFT * (top > 0 ? top : 1.0);
}

/* K and B as CHOLMOD's triplets (upper triangles); sets on, sigma. */
static int triplets(pencil *p, cholmod_triplet **tk, cholmod_triplet **tb) {
  size_t nn = 0, *xa = NULL, *ad = NULL, nc = (size_t)dtm_operator_ncomp(p->op);
  double *blk = NULL, *kd = calloc(p->n + 1, sizeof *kd), *bd = malloc((p->n + 1) * sizeof *bd);
  int r = kd && bd ? dtm_operator_assemble(p->op, &nn, &xa, &ad, &blk) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_ERR_INPUT) { /* shells or beams */
    dtm_error_clear();
    r = DTM_ERR(DTM_ERR_INPUT, "natural modes of shells and beams are not computed yet: their rotations are not "
                               "assembled (solids, membranes and trusses only)");
  }
  size_t extra = p->extra ? p->extra->rowptr[p->n] : 0;
  if (r == DTM_OK) {
    b_diagonal(p, bd);
    for (size_t i = 0; i < p->n; i++) p->on[i] = bd[i] > 0, p->non += p->on[i];
    *tk = cholmod_l_allocate_triplet(p->n, p->n, xa[nn] * nc * nc + p->n, 1, CHOLMOD_REAL, &p->cm);
    *tb = cholmod_l_allocate_triplet(p->n, p->n, extra + p->n + 1, 1, CHOLMOD_REAL, &p->cm);
    if (!*tk || !*tb) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the modes' matrix");
  }
  if (r == DTM_OK) {
    k_entries(p, nn, xa, ad, blk, *tk, kd);
    p->sigma = shift(p, kd, bd);
    b_entries(p, *tk, *tb);
  }
  free(xa), free(ad), free(blk), free(kd), free(bd);
  return r;
}

/* K - s B (upper triangle), or NULL (out of memory). */
static cholmod_sparse *shifted(pencil *p, double s) {
  double one[2] = {1, 0}, minus_s[2] = {-s, 0};
  return cholmod_l_add(p->K, p->B, one, minus_s, 1, 1, &p->cm);
}

/* Assemble K and B, and factor K - sigma B. */
static int factor(pencil *p) {
  cholmod_triplet *tk = NULL, *tb = NULL;
  int r = triplets(p, &tk, &tb);
  if (r == DTM_OK) p->K = cholmod_l_triplet_to_sparse(tk, 0, &p->cm), p->B = cholmod_l_triplet_to_sparse(tb, 0, &p->cm);
  cholmod_l_free_triplet(&tk, &p->cm), cholmod_l_free_triplet(&tb, &p->cm);
  DTM_CHECK(r);
  cholmod_sparse *a = p->K && p->B ? shifted(p, p->sigma) : NULL;
  if (!a) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the modes' matrix");
  p->L = cholmod_l_analyze(a, &p->cm);
  p->flops = p->cm.fl;
  int ok = p->L && cholmod_l_factorize(a, p->L, &p->cm);
  cholmod_l_free_sparse(&a, &p->cm);
  if (!ok || p->cm.status != CHOLMOD_OK || p->L->minor < p->n)
    return DTM_ERR(DTM_ERR_INTERNAL, "the factorisation of K - sigma M failed (CHOLMOD status %d)", p->cm.status);
  p->b = cholmod_l_zeros(p->n, 1, CHOLMOD_REAL, &p->cm);
  return p->b ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
}

/* The eigenvalues of (K, B) below s by Sylvester's law of inertia: the
 * negative pivots of a simplicial LDL^T factorisation of K - s B (no
 * pivoting, the Sturm check of structural codes); -1 when it failed. */
static long count_below(pencil *p, double s) {
  cholmod_sparse *a = shifted(p, s);
  int simplicial = p->cm.supernodal, final_ll = p->cm.final_ll;
  p->cm.supernodal = CHOLMOD_SIMPLICIAL, p->cm.final_ll = 0;
  cholmod_factor *f = a ? cholmod_l_analyze(a, &p->cm) : NULL;
  int ok = f && cholmod_l_factorize(a, f, &p->cm) && p->cm.status == CHOLMOD_OK && f->minor == p->n && !f->is_ll;
  p->cm.supernodal = simplicial, p->cm.final_ll = final_ll;
  long neg = ok ? 0 : -1;
  const SuiteSparse_long *lp = ok ? f->p : NULL;
  const double *lx = ok ? f->x : NULL;
  for (size_t j = 0; ok && j < p->n; j++) neg += lx[lp[j]] < 0; /* D(j, j) leads column j */
  cholmod_l_free_factor(&f, &p->cm);
  cholmod_l_free_sparse(&a, &p->cm);
  return neg;
}

/* x = (K - sigma B)^-1 bx. */
static int solve(pencil *p, const double *bx, double *x) {
  memcpy(p->b->x, bx, p->n * sizeof *bx);
  cholmod_dense *s = cholmod_l_solve(CHOLMOD_A, p->L, p->b, &p->cm);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "a solve with K - sigma M failed (CHOLMOD status %d)", p->cm.status);
  memcpy(x, s->x, p->n * sizeof *x);
  cholmod_l_free_dense(&s, &p->cm);
  return DTM_OK;
}

/* ---- band Lanczos ------------------------------------------------------ */

typedef struct {
  int p, mmax, ld; /* block, most steps, rows of h (mmax + p) */
  int m, nv;       /* steps done, vectors stored */
  size_t cap;      /* most vectors: min(mmax + p, unknowns with mass) */
  size_t alloc;    /* vectors q and bq have room for (grown on demand) */
  double *q, *bq;  /* [ld][n] the basis and B times it */
  double *h;       /* [mmax][ld] column j: OP q_j in the basis */
  double *w, *bw;  /* [n] scratch */
} band;

/* Orthogonalise w against the k stored vectors, twice, adding the
 * coefficients to c[k] (may be NULL); bw = B w; returns ||w||_B. */
static double orthogonalise(const pencil *p, band *z, int k, double *c) {
  for (int pass = 0; pass < 2; pass++)
    for (int i = 0; i < k; i++) {
      double a = dtm_vec_dot(p->n, z->bq + (size_t)i * p->n, z->w);
      for (size_t r = 0; r < p->n; r++) z->w[r] -= a * z->q[(size_t)i * p->n + r];
      if (c) c[i] += a;
    }
  b_apply(p, z->w, z->bw);
  return sqrt(fmax(dtm_vec_dot(p->n, z->w, z->bw), 0.0));
}

/* Store w / norm as vector nv. */
static void keep(const pencil *p, band *z, double norm) {
  for (size_t r = 0; r < p->n; r++)
    z->q[(size_t)z->nv * p->n + r] = z->w[r] / norm, z->bq[(size_t)z->nv * p->n + r] = z->bw[r] / norm;
  z->nv++;
}

/* A random vector on the unknowns with mass, B-orthogonal to the basis,
 * as vector nv (nothing when the basis is complete). */
static void random_vector(const pencil *p, band *z, unsigned seed) {
  for (unsigned tries = 0; (size_t)z->nv < z->cap && tries < 4; tries++) {
    dtm_operator_draw_normal(p->op, seed * 7919u + tries, z->w);
    for (size_t r = 0; r < p->n; r++) z->w[r] = p->on[r] ? z->w[r] : 0.0;
    b_apply(p, z->w, z->bw);
    double before = sqrt(dtm_vec_dot(p->n, z->w, z->bw)), norm = orthogonalise(p, z, z->nv, NULL);
    if (norm > DEFLATE * before) return keep(p, z, norm);
  }
}

/* Room for k vectors in q and bq (at most cap): doubled when short. */
static int room(const pencil *p, band *z, size_t k) {
  if (k <= z->alloc || z->alloc >= z->cap) return DTM_OK;
  size_t want = 2 * z->alloc > k ? 2 * z->alloc : k;
  want = want < z->cap ? want : z->cap;
  double *q = realloc(z->q, want * p->n * sizeof *q);
  if (q) z->q = q;
  double *bq = q ? realloc(z->bq, want * p->n * sizeof *bq) : NULL;
  if (bq) z->bq = bq, z->alloc = want;
  return bq ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the modes' basis (%zu vectors)", want);
}

/* One step: OP q_m in the basis, a new vector from what remains. */
static int step(pencil *p, band *z) {
  double *c = z->h + (size_t)z->m * (size_t)z->ld;
  DTM_CHECK(room(p, z, (size_t)z->nv + 1));
  DTM_CHECK(solve(p, z->bq + (size_t)z->m * p->n, z->w));
  for (size_t r = 0; r < p->n; r++) z->w[r] = p->on[r] ? z->w[r] : 0.0;
  b_apply(p, z->w, z->bw);
  double before = sqrt(fmax(dtm_vec_dot(p->n, z->w, z->bw), 0.0)), norm = orthogonalise(p, z, z->nv, c);
  int at = z->nv;
  if ((size_t)z->nv < z->cap && norm > DEFLATE * before)
    keep(p, z, norm), c[at] = norm;
  else
    random_vector(p, z, 1000u + (unsigned)z->m); /* an invariant subspace: go on elsewhere */
  z->m++;
  return DTM_OK;
}

static int band_alloc(band *z, size_t n, int p, int mmax, size_t non) {
  z->p = p, z->mmax = mmax, z->ld = mmax + p, z->m = z->nv = 0;
  z->cap = (size_t)z->ld < non ? (size_t)z->ld : non;
  z->alloc = (size_t)(4 * p) < z->cap ? (size_t)(4 * p) : z->cap;
  z->q = malloc(z->alloc * n * sizeof *z->q + 1), z->bq = malloc(z->alloc * n * sizeof *z->bq + 1);
  z->h = calloc((size_t)z->ld * (size_t)mmax, sizeof *z->h);
  z->w = malloc((n + 1) * sizeof *z->w), z->bw = malloc((n + 1) * sizeof *z->bw);
  return z->q && z->bq && z->h && z->w && z->bw ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the modes");
}

static void band_free(band *z) { free(z->q), free(z->bq), free(z->h), free(z->w), free(z->bw); }

/* ---- Ritz pairs ------------------------------------------------------- */

/* Zero a[p][q] (row-major k x k, symmetric) by one rotation, v's columns
 * rotated alike (Rutishauser's formulas, as src/kernel/jacobi.c). */
static void rotate(int k, double *a, double *v, int p, int q) {
  double apq = a[p * k + q], theta = (a[q * k + q] - a[p * k + p]) / (2 * apq);
  double t = fabs(theta) > 1e150 ? 0.5 / theta : (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
  double c = 1 / sqrt(t * t + 1), s = t * c, tau = s / (1 + c);
  a[p * k + p] -= t * apq, a[q * k + q] += t * apq, a[p * k + q] = a[q * k + p] = 0;
  for (int r = 0; r < k; r++) {
    double g = v[r * k + p], h = v[r * k + q];
    v[r * k + p] = g - s * (h + g * tau), v[r * k + q] = h + s * (g - h * tau);
    if (r == p || r == q) continue;
    g = a[r * k + p], h = a[r * k + q];
    a[r * k + p] = a[p * k + r] = g - s * (h + g * tau);
    a[r * k + q] = a[q * k + r] = h + s * (g - h * tau);
  }
}

/* Every eigenpair of the symmetric k x k a (destroyed; eigenvalues on its
 * diagonal) by cyclic Jacobi, the vectors in v's columns. */
static void jacobi(int k, double *a, double *v) {
  double fro = 0, off;
  for (int i = 0; i < k * k; i++) fro += a[i] * a[i], v[i] = i % (k + 1) == 0;
  for (int sweep = 0; sweep < 60; sweep++) {
    off = 0;
    for (int i = 0; i < k; i++)
      for (int j = i + 1; j < k; j++) off += a[i * k + j] * a[i * k + j];
    if (off <= 0.01 * DBL_EPSILON * DBL_EPSILON * fro) return;
    for (int i = 0; i < k; i++)
      for (int j = i + 1; j < k; j++)
        if (a[i * k + j] != 0) rotate(k, a, v, i, j);
  }
}

/* The Ritz pairs of the m steps: nu[m] descending, s[m][m] (column i the
 * vector of nu[i]), res[m] = ||OP y - nu y||_B. */
typedef struct {
  int m;
  double *nu, *s, *res;
} ritz;

/* The eigenpairs of the symmetric part of H's leading m x m block (a,
 * v scratch) into rz, nu descending. */
static void ritz_sorted(const band *z, double *a, double *v, int *idx, ritz *rz) {
  int m = z->m, ld = z->ld;
  for (int i = 0; i < m; i++)
    for (int j = 0; j < m; j++) a[i * m + j] = 0.5 * (z->h[(size_t)j * ld + i] + z->h[(size_t)i * ld + j]);
  jacobi(m, a, v);
  for (int i = 0; i < m; i++) idx[i] = i;
  for (int i = 1; i < m; i++) /* insertion sort, nu descending */
    for (int j = i; j > 0 && a[idx[j] * m + idx[j]] > a[idx[j - 1] * m + idx[j - 1]]; j--) {
      int t = idx[j];
      idx[j] = idx[j - 1], idx[j - 1] = t;
    }
  for (int i = 0; i < m; i++) {
    rz->nu[i] = a[idx[i] * m + idx[i]];
    for (int r = 0; r < m; r++) rz->s[(size_t)r * m + i] = v[r * m + idx[i]];
  }
}

/* Each Ritz pair's ||OP y - nu y||_B = ||H_{m:nv, :} s||. */
static void ritz_residuals(const band *z, ritz *rz) {
  int m = z->m, ld = z->ld;
  for (int i = 0; i < m; i++) {
    double e = 0;
    for (int r = m; r < z->nv && r < ld; r++) {
      double t = 0;
      for (int c = 0; c < m; c++) t += z->h[(size_t)c * ld + r] * rz->s[(size_t)c * m + i];
      e += t * t;
    }
    rz->res[i] = sqrt(e);
  }
}

static int ritz_compute(const band *z, ritz *rz) {
  int m = z->m;
  double *a = calloc((size_t)m * m, sizeof *a),
         *v = malloc((size_t)m * m * sizeof *v); /* calloc: GCC -O1 cannot see it filled */
  int *idx = malloc((size_t)m * sizeof *idx);
  rz->m = m, rz->nu = malloc((size_t)m * sizeof *rz->nu), rz->res = malloc((size_t)m * sizeof *rz->res);
  rz->s = malloc((size_t)m * m * sizeof *rz->s);
  int r =
      a && v && idx && rz->nu && rz->s && rz->res ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the modes");
  if (r == DTM_OK) ritz_sorted(z, a, v, idx, rz), ritz_residuals(z, rz);
  free(a), free(v), free(idx);
  return r;
}

static void ritz_free(ritz *rz) { free(rz->nu), free(rz->s), free(rz->res); }

static double lambda_of(const pencil *p, double nu) { return p->sigma + 1.0 / nu; }

/* The largest Ritz value of lambda (the far end the basis sees). */
static double lambda_top(const pencil *p, const ritz *rz) {
  double top = 0;
  for (int i = 0; i < rz->m; i++)
    if (rz->nu[i] > 0) top = fmax(top, lambda_of(p, rz->nu[i]));
  return top;
}

/* The leading Ritz pairs that pass the test, *nr of them rigid. */
static int passed(const pencil *p, const ritz *rz, int *nr) {
  double top = lambda_top(p, rz);
  int k = 0;
  *nr = 0;
  while (k < rz->m && rz->nu[k] > 0 && rz->res[k] <= DTM_MODES_TOL * rz->nu[k]) {
    *nr += fabs(lambda_of(p, rz->nu[k])) <= DTM_MODES_RIGID_TOL * top;
    k++;
  }
  return k;
}

/* ---- the modes --------------------------------------------------------- */

/* Mode i of the result from Ritz pair k: shape Q s_k, its measured residual. */
static void make_mode(const pencil *p, const band *z, const ritz *rz, int k, double top, dtm_modes *out, int i) {
  double *x = out->shape + (size_t)i * p->n, lam = lambda_of(p, rz->nu[k]);
  memset(x, 0, p->n * sizeof *x);
  for (int c = 0; c < rz->m; c++) {
    double s = rz->s[(size_t)c * rz->m + k];
    for (size_t r = 0; r < p->n; r++) x[r] += s * z->q[(size_t)c * p->n + r];
  }
  dtm_operator_apply(p->op, x, z->w);
  b_apply(p, x, z->bw);
  double e = 0, bn = 0, nx = sqrt(fmax(dtm_vec_dot(p->n, x, z->bw), 0.0));
  for (size_t r = 0; r < p->n; r++)
    e += (z->w[r] - lam * z->bw[r]) * (z->w[r] - lam * z->bw[r]), bn += z->bw[r] * z->bw[r];
  for (size_t r = 0; nx > 0 && r < p->n; r++) x[r] /= nx;
  int rigid = fabs(lam) <= DTM_MODES_RIGID_TOL * top;
  out->mode[i] = (dtm_mode){lam, sqrt(fmax(lam, 0.0)) / TWO_PI, sqrt(e) / ((rigid ? top : lam) * sqrt(bn)), rigid};
}

/* The rigid modes and up to n elastic ones from the last Ritz pairs. */
static int collect(const pencil *p, const band *z, const ritz *rz, int n, dtm_modes *out) {
  double top = lambda_top(p, rz);
  int nr = 0, k = passed(p, rz, &nr), count = 0;
  for (int i = 0; i < rz->m && rz->nu[i] > 0; i++) count += fabs(lambda_of(p, rz->nu[i])) <= DTM_MODES_RIGID_TOL * top;
  int nel = 0;
  for (int i = 0; i < rz->m && rz->nu[i] > 0 && nel < n; i++)
    nel += !(fabs(lambda_of(p, rz->nu[i])) <= DTM_MODES_RIGID_TOL * top);
  out->n = count + nel, out->nrigid = count, out->nelastic = nel;
  out->converged = k >= out->n; /* every mode returned passed (fewer than n elastic ones: the model has no more) */
  out->mode = calloc((size_t)out->n + 1, sizeof *out->mode);
  out->shape = malloc(((size_t)out->n * p->n + 1) * sizeof *out->shape);
  if (!out->mode || !out->shape) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the modes");
  for (int i = 0; i < out->n; i++) make_mode(p, z, rz, i, top, out, i);
  return DTM_OK;
}

/* The Sturm check at s just above the largest mode returned: the
 * eigenvalues below s by inertia against the Ritz values below s that
 * passed the test. */
static void sturm(pencil *p, const ritz *rz, dtm_modes *out) {
  out->sturm_at = out->n ? out->mode[out->n - 1].lambda * (1 + STURM_GAP) : NAN, out->sturm = -1, out->counted = -1;
  if (!out->n) return;
  long found = 0;
  for (int i = 0; i < rz->m && rz->nu[i] > 0; i++)
    found += lambda_of(p, rz->nu[i]) < out->sturm_at && rz->res[i] <= DTM_MODES_TOL * rz->nu[i];
  if (p->flops > STURM_FLOPS) return (void)(out->counted = -2);
  out->sturm = count_below(p, out->sturm_at);
  out->counted = out->sturm < 0 ? -1 : out->sturm == found;
}

/* Steps until the test passes for the rigid modes and n elastic ones (and
 * EXTRA more steps are in the basis), or mmax steps. */
static int iterate(pencil *p, band *z, int n, ritz *rz) {
  for (unsigned i = 0; i < (unsigned)z->p; i++) random_vector(p, z, i + 1);
  int r = DTM_OK;
  while (r == DTM_OK && z->m < z->mmax && z->m < z->nv) {
    r = step(p, z);
    if (r || (z->m % z->p && z->m < z->nv && z->m < z->mmax)) continue;
    ritz_free(rz);
    r = ritz_compute(z, rz);
    int nr = 0, k = r ? 0 : passed(p, rz, &nr);
    if (r == DTM_OK && k - nr >= n && z->m >= k + EXTRA) return DTM_OK;
  }
  if (r == DTM_OK && rz->m != z->m) ritz_free(rz), r = ritz_compute(z, rz);
  return r;
}

/* The block size: the rigid modes of the space's dimension, at least 2. */
static int block_size(const dtm_operator *op) {
  int d = dtm_operator_ncomp(op);
  return d >= 3 ? 6 : d == 2 ? 3 : 2;
}

static int lowest(pencil *p, int n, dtm_modes *out) {
  double t0 = dtm_wtime();
  DTM_CHECK(factor(p));
  out->factor_seconds = dtm_wtime() - t0;
  band z = {0};
  ritz rz = {0};
  int b = block_size(p->op), mmax = STEPS_PER * (n + 2 * b + EXTRA) + STEPS_MIN;
  int r = band_alloc(&z, p->n, b, mmax, p->non);
  if (r == DTM_OK) r = iterate(p, &z, n, &rz);
  if (r == DTM_OK) r = collect(p, &z, &rz, n, out);
  if (r == DTM_OK) sturm(p, &rz, out);
  out->sigma = p->sigma, out->block = b, out->steps = z.m;
  ritz_free(&rz);
  band_free(&z);
  return r;
}

int dtm_modes_lowest(const dtm_operator *op, const dtm_csr *extra, int n, dtm_modes *out) {
  memset(out, 0, sizeof *out);
  double t0 = dtm_wtime();
  if (dtm_operator_kind(op) != DTM_OP_ELASTIC)
    return DTM_ERR(DTM_ERR_INPUT, "natural modes: the operator is not elastic (diffusion has no vibration modes)");
  if (n < 1) return DTM_ERR(DTM_ERR_INPUT, "natural modes: %d modes asked for (at least 1)", n);
  size_t nd = dtm_operator_ndof(op);
  if (extra && extra->n != nd)
    return DTM_ERR(DTM_ERR_INPUT, "natural modes: the extra mass has %zu rows, the model %zu unknowns", extra->n, nd);
  DTM_CHECK(dtm_cholmod_load());
  pencil p;
  memset(&p, 0, sizeof p);
  p.op = op, p.extra = extra, p.n = nd, p.mass = dtm_operator_mass(op), p.on = calloc(nd + 1, 1);
  if (!p.on) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  cholmod_l_start(&p.cm);
  p.cm.print = 0;
  out->ndof = nd;
  int r = lowest(&p, n, out);
  cholmod_l_free_dense(&p.b, &p.cm);
  cholmod_l_free_factor(&p.L, &p.cm);
  cholmod_l_free_sparse(&p.K, &p.cm), cholmod_l_free_sparse(&p.B, &p.cm);
  cholmod_l_finish(&p.cm);
  free(p.on);
  if (r) dtm_modes_free(out);
  out->seconds = dtm_wtime() - t0;
  return r;
}

void dtm_modes_free(dtm_modes *m) {
  if (!m) return;
  free(m->mode), free(m->shape);
  memset(m, 0, sizeof *m);
}
