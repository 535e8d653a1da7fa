/* A certificate that no eigenvalue of A = M^-1/2 K M^-1/2 lies at or above
 * sigma: the Cholesky factorisation of sigma I - A. By Sylvester's law of
 * inertia, sigma I - A = L L^T with a real L exists exactly when every
 * eigenvalue of A is below sigma, whatever the gaps between them; Lanczos's
 * Ritz value plus residual only bounds the eigenvalue nearest to it, which
 * is not the largest when the top of the spectrum is clustered.
 *
 * A is assembled from the matrix-free product itself (so every element the
 * operator knows enters as it computes it): the nodes are coloured so that
 * two nodes of a colour share no neighbour, and one product per colour and
 * component gives a column of A at every node of the colour. One product
 * of the assembled matrix against the operator on a random vector checks
 * the assembly; shells and beams (rotations) are not assembled.
 *
 * The factorisation is SuiteSparse's CHOLMOD, supernodal. The ordering
 * is found on the node graph, nc times smaller than the dofs' (each
 * node's dofs then follow one another): first AMD alone, whose predicted
 * flops (times nc^3 for the dofs) refuse a mesh far too large at the cost
 * of one AMD ordering, then, where AMD's prediction is within METIS_GAIN
 * budgets, CHOLMOD's own choice (AMD, and METIS where AMD's fill is high).
 * Within the caller's flop budget the dofs' pattern is analysed in that
 * order, once per certifier, for the factor's predicted flops and entries.
 * Nothing is assembled when a prediction exceeds the budget or the memory
 * cap (CERT_MEMORY of the memory this process may use), and a node graph
 * too large for its ordering to be a small share of the budget
 * (ORDER_SHARE) is not even ordered. Each sigma is then one
 * cholmod_factorize_p of -A + sigma I with the symbolic factor reused;
 * CHOLMOD stops at the first column whose pivot is not positive (status
 * CHOLMOD_NOT_POSDEF, L->minor < n): an eigenvalue lies at or above sigma,
 * up to rounding. Nearly all of a large certificate's time is the
 * supernodal kernels, that is the BLAS under CHOLMOD: scripts/setup.sh
 * installs Debian's single-threaded OpenBLAS (libopenblas0-serial), which
 * factors a box of 105,912 unknowns (1.96e11 flops) in 12 s where the
 * reference BLAS took 81 s (docs/certificate.md). An OpenMP BLAS, where
 * one is installed instead, is held to one thread: its many small
 * parallel regions, one per supernode's kernels, took 18x longer than one
 * thread on a shared two-core machine (load 5: 14.1 s against 0.78 s for
 * a box of 14,229 unknowns).
 *
 * Rounding: when the factorisation succeeds in floating point, P (sigma I
 * - A) P^T + E is positive definite with |E| <= g |L| |L^T|, g = (c + 1) u
 * / (1 - (c + 1) u) for c the most terms of an inner product and u the
 * unit round-off (Demmel's bound for Cholesky; it holds for any order of
 * the sums, so for the blocked BLAS kernels of a supernodal factor too;
 * the explicit zeros a supernode stores add nothing). The terms of an
 * inner product are bounded by the largest count of a row or a column of
 * the supernodal L, counted from its pattern, which holds every entry of
 * the exact L, so ||E||_2 <= g || |L| ||_2^2 <= g ||L||_F^2, with
 * ||L||_F^2 summed over the factor's stored lower triangle. The diagonal
 * sigma - a_ii is itself rounded, by at most u (sigma + max |a_ii|). The
 * sum of the two is the margin returned: every eigenvalue of the
 * assembled A is below sigma + margin. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "base.h"
#include "cholmod_dl.h"
#include "spectral.h"
#include "dtmap/operator.h"

#define ASSEMBLY_TOL 1e-10 /* the assembled product against the operator's, relative */
#define CERT_MEMORY 0.125  /* the factor's predicted bytes at most this share of the memory limit */
#define ORDER_SHARE 1e-4   /* the node graph is ordered when its entries are at most this share of the budget */
#define METIS_GAIN 8.0     /* METIS is tried when AMD's predicted flops are at most this many budgets */

/* The assembled -A (upper triangle, dofs node-major as the operator's),
 * CHOLMOD's workspace and its symbolic (then numeric) factor. */
struct dtm_certifier {
  size_t n;            /* dofs */
  cholmod_common cm;   /* started in dtm_certifier_create */
  cholmod_sparse *neg; /* -A, upper triangle (stype 1) */
  cholmod_factor *L;   /* the analysis, reused for every sigma */
  double flops;        /* CHOLMOD's predicted flops of one factorisation */
  double bytes;        /* its predicted memory (factor and matrix) */
  double diag;         /* max |a_ii| */
};

/* ---- assembly by coloured products ---------------------------------- */

/* Greedy colouring at distance 2: colour[v] differs from that of every
 * node within two edges. Returns the number of colours. */
static int colour_nodes(size_t nn, const size_t *xa, const size_t *ad, int *colour, int *seen) {
  int nc = 0;
  for (size_t v = 0; v < nn; v++) colour[v] = -1;
  for (size_t v = 0; v < nn; v++) {
    for (size_t p = xa[v]; p < xa[v + 1]; p++)
      for (size_t q = xa[ad[p]]; q < xa[ad[p] + 1]; q++)
        if (colour[ad[q]] >= 0) seen[colour[ad[q]]] = (int)v + 1;
    int c = 0;
    while (c < nc && seen[c] == (int)v + 1) c++;
    colour[v] = c;
    if (c == nc) seen[nc++] = 0;
  }
  return nc;
}

/* The entries of the matrix of apply (A, or K for dtm_operator_assemble)
 * in node blocks: blk[(p * nc + i) * nc + j] = A(w nc + i, v nc + j) for
 * w = ad[p], p in v's list. */
static int probe(const dtm_operator *op, void (*apply)(const dtm_operator *, const double *, double *), size_t nn,
                 const size_t *xa, const size_t *ad, double *blk) {
  size_t n = dtm_operator_ndof(op), nc = (size_t)dtm_operator_ncomp(op);
  int *colour = malloc((nn + 1) * sizeof *colour), *seen = malloc((nn + 1) * sizeof *seen);
  double *x = calloc(n + 1, sizeof *x), *y = malloc((n + 1) * sizeof *y);
  if (!colour || !seen || !x || !y) {
    free(colour), free(seen), free(x), free(y);
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the certificate");
  }
  int ncol = colour_nodes(nn, xa, ad, colour, seen);
  for (int c = 0; c < ncol; c++)
    for (size_t j = 0; j < nc; j++) {
      for (size_t v = 0; v < nn; v++) x[v * nc + j] = colour[v] == c;
      apply(op, x, y);
      for (size_t v = 0; v < nn; v++) {
        if (colour[v] != c) continue;
        x[v * nc + j] = 0;
        for (size_t p = xa[v]; p < xa[v + 1]; p++)
          for (size_t i = 0; i < nc; i++) blk[(p * nc + i) * nc + j] = y[ad[p] * nc + i];
      }
    }
  free(colour), free(seen), free(x), free(y);
  return DTM_OK;
}

/* K itself by the same coloured products (src/spectral/modes.c). */
int dtm_operator_assemble(const dtm_operator *op, size_t *nn, size_t **xadj, size_t **adj, double **blk) {
  size_t nc = (size_t)dtm_operator_ncomp(op);
  *blk = NULL;
  DTM_CHECK(dtm_operator_node_graph(op, nn, xadj, adj));
  *blk = malloc(((*xadj)[*nn] * nc * nc + 1) * sizeof **blk);
  int r = *blk ? probe(op, dtm_operator_apply, *nn, *xadj, *adj, *blk) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r) free(*xadj), free(*adj), free(*blk), *xadj = *adj = NULL, *blk = NULL;
  return r;
}

/* ---- the assembled matrix ------------------------------------------- */

/* The upper triangle of A's pattern (blk NULL: values 0) or of -A into
 * c->neg, allocated on the first call; a node of no element gets its
 * diagonal. Columns are sorted by cholmod_sort. */
static int upper(dtm_certifier *c, size_t nn, size_t nc, const size_t *xa, const size_t *ad, const double *blk) {
  if (!c->neg) c->neg = cholmod_l_allocate_sparse(c->n, c->n, xa[nn] * nc * nc + c->n, 0, 1, 1, CHOLMOD_REAL, &c->cm);
  if (!c->neg) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the certificate");
  SuiteSparse_long *ap = c->neg->p, *ai = c->neg->i, nnz = 0;
  double *ax = c->neg->x;
  c->diag = 0;
  for (size_t v = 0; v < nn; v++)
    for (size_t j = 0; j < nc; j++) {
      size_t col = v * nc + j, diag = 0;
      ap[col] = nnz;
      for (size_t p = xa[v]; p < xa[v + 1]; p++)
        for (size_t i = 0; i < nc; i++) {
          size_t row = ad[p] * nc + i;
          if (row > col) continue;
          double a = blk ? blk[(p * nc + i) * nc + j] : 0;
          if (row == col) diag = 1, c->diag = fmax(c->diag, fabs(a));
          ai[nnz] = (SuiteSparse_long)row, ax[nnz++] = -a;
        }
      if (!diag) ai[nnz] = (SuiteSparse_long)col, ax[nnz++] = 0;
    }
  ap[c->n] = nnz;
  c->neg->sorted = 0;
  if (!cholmod_l_sort(c->neg, &c->cm)) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the certificate");
  return DTM_OK;
}

/* ||A x - op x|| <= ASSEMBLY_TOL ||op x|| for a random x. */
static int assembly_agrees(const dtm_operator *op, const dtm_certifier *c) {
  size_t n = c->n;
  const SuiteSparse_long *ap = c->neg->p, *ai = c->neg->i;
  const double *ax = c->neg->x;
  double *x = malloc((n + 1) * sizeof *x), *y = malloc((n + 1) * sizeof *y), *z = calloc(n + 1, sizeof *z);
  int ok = 0;
  if (x && y && z) {
    dtm_operator_draw(op, 777, -1, 1, x);
    dtm_operator_apply_sym(op, x, y);
    for (size_t col = 0; col < n; col++)
      for (SuiteSparse_long p = ap[col]; p < ap[col + 1]; p++) {
        size_t row = (size_t)ai[p];
        z[row] -= ax[p] * x[col];
        if (row != col) z[col] -= ax[p] * x[row];
      }
    double e = 0, s = 0;
    for (size_t i = 0; i < n; i++) e += (z[i] - y[i]) * (z[i] - y[i]), s += y[i] * y[i];
    ok = e <= ASSEMBLY_TOL * ASSEMBLY_TOL * s;
  }
  free(x), free(y), free(z);
  return ok;
}

/* ---- the public face -------------------------------------------------- */

void dtm_certifier_destroy(dtm_certifier **cp) {
  if (!cp || !*cp) return;
  dtm_certifier *c = *cp;
  cholmod_l_free_factor(&c->L, &c->cm);
  cholmod_l_free_sparse(&c->neg, &c->cm);
  cholmod_l_finish(&c->cm);
  free(c);
  *cp = NULL;
}

/* The upper triangle of the node graph's pattern (nn x nn). */
static cholmod_sparse *node_pattern(size_t nn, const size_t *xa, const size_t *ad, cholmod_common *cm) {
  cholmod_sparse *g = cholmod_l_allocate_sparse(nn, nn, xa[nn] + nn, 0, 1, 1, CHOLMOD_PATTERN, cm);
  if (!g) return NULL;
  SuiteSparse_long *gp = g->p, *gi = g->i, nnz = 0;
  for (size_t v = 0; v < nn; v++) {
    gp[v] = nnz, gi[nnz++] = (SuiteSparse_long)v;
    for (size_t p = xa[v]; p < xa[v + 1]; p++)
      if (ad[p] < v) gi[nnz++] = (SuiteSparse_long)ad[p];
  }
  gp[nn] = nnz;
  return g;
}

/* An ordering of the node graph g in perm[nn]: AMD alone (quick) or
 * CHOLMOD's choice (AMD, and METIS where AMD's fill is high); *fl and *lnz
 * its predicted flops and entries of the node-level factor. */
static int node_order(cholmod_sparse *g, int quick, cholmod_common *cm, SuiteSparse_long *perm, double *fl,
                      double *lnz) {
  cm->nmethods = quick, cm->method[0].ordering = CHOLMOD_AMD;
  cholmod_factor *f = cholmod_l_analyze(g, cm);
  if (!f) return DTM_ERR(DTM_ERR_INTERNAL, "the certificate's ordering failed (CHOLMOD status %d)", cm->status);
  memcpy(perm, f->Perm, g->nrow * sizeof *perm);
  *fl = cm->fl, *lnz = cm->lnz;
  cholmod_l_free_factor(&f, cm);
  return DTM_OK;
}

/* The dofs' predicted flops and bytes from the node level's: nc^3 and nc^2
 * times, with the assembled matrix. */
static void node_prediction(dtm_certifier *c, size_t nc, double fl, double lnz, double entries) {
  c->flops = (double)(nc * nc * nc) * fl;
  c->bytes = 8.0 * (double)(nc * nc) * lnz + 16.0 * entries;
}

/* The node graph ordered by CHOLMOD's choice in perm[nn], with the
 * prediction in c; AMD alone first, and no more when even METIS_GAIN
 * times fewer flops than AMD's would exceed the budget. */
static int order(dtm_certifier *c, size_t nn, size_t nc, const size_t *xa, const size_t *ad, double budget,
                 SuiteSparse_long *perm) {
  double fl, lnz, entries = (double)(xa[nn] * nc * nc);
  cholmod_sparse *g = node_pattern(nn, xa, ad, &c->cm);
  if (!g) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the certificate");
  int r = node_order(g, 1, &c->cm, perm, &fl, &lnz);
  if (r == DTM_OK) node_prediction(c, nc, fl, lnz, entries);
  if (r == DTM_OK && c->flops <= METIS_GAIN * budget) {
    r = node_order(g, 0, &c->cm, perm, &fl, &lnz);
    if (r == DTM_OK) node_prediction(c, nc, fl, lnz, entries);
  }
  cholmod_l_free_sparse(&g, &c->cm);
  return r;
}

static int too_dear(const dtm_certifier *c, double budget) {
  return !(c->bytes <= CERT_MEMORY * dtm_memory_limit()) || c->flops > budget;
}

/* The ordering (on the node graph, each node's dofs kept together) and the
 * symbolic factor of the dofs' pattern; *status DTM_CERT_TOO_DEAR when the
 * predicted flops exceed budget or the predicted bytes the memory cap. The
 * node-level prediction, times nc^3 flops and nc^2 entries, refuses first,
 * before the dofs' pattern is built; a node graph of more than
 * ORDER_SHARE * budget entries is not even ordered. */
static int analyse(dtm_certifier *c, size_t nn, size_t nc, const size_t *xa, const size_t *ad, double budget,
                   int *status) {
  *status = DTM_CERT_TOO_DEAR;
  c->flops = NAN, c->bytes = 16.0 * (double)(xa[nn] * nc * nc);                      /* the assembled matrix alone */
  if ((double)xa[nn] > ORDER_SHARE * budget || too_dear(c, INFINITY)) return DTM_OK; /* flops NaN: not compared */
  SuiteSparse_long *perm = malloc((c->n + 1) * sizeof *perm);
  if (!perm) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the certificate");
  int r = order(c, nn, nc, xa, ad, budget, perm);
  if (r || too_dear(c, budget)) return free(perm), r;
  for (size_t k = nn; k-- > 0;) {
    SuiteSparse_long v = perm[k]; /* read before the dofs of k overwrite it */
    for (size_t j = 0; j < nc; j++) perm[k * nc + j] = v * (SuiteSparse_long)nc + (SuiteSparse_long)j;
  }
  r = upper(c, nn, nc, xa, ad, NULL);
  c->cm.nmethods = 1, c->cm.method[0].ordering = CHOLMOD_GIVEN;
  if (r == DTM_OK) c->L = cholmod_l_analyze_p(c->neg, perm, NULL, 0, &c->cm);
  free(perm);
  if (r) return r;
  if (!c->L) return DTM_ERR(DTM_ERR_INTERNAL, "the certificate's analysis failed (CHOLMOD status %d)", c->cm.status);
  c->flops = c->cm.fl;
  c->bytes = 8.0 * (fmax(c->cm.lnz, (double)c->L->xsize) + (double)c->L->ssize) + 16.0 * (double)c->neg->nzmax;
  *status = too_dear(c, budget) ? DTM_CERT_TOO_DEAR : DTM_CERT_PROVEN;
  return DTM_OK;
}

/* The values of A by the coloured products, checked against one product. */
static int values(const dtm_operator *op, dtm_certifier *c, size_t nn, size_t nc, const size_t *xa, const size_t *ad,
                  int *status) {
  double *blk = malloc((xa[nn] * nc * nc + 1) * sizeof *blk);
  int r = blk ? probe(op, dtm_operator_apply_sym, nn, xa, ad, blk) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = upper(c, nn, nc, xa, ad, blk);
  free(blk);
  if (r == DTM_OK) *status = assembly_agrees(op, c) ? DTM_CERT_PROVEN : DTM_CERT_UNAVAILABLE;
  return r;
}

/* The analysis first (no product), then, within the budget, the assembly;
 * *status as for dtm_certifier_create. A node graph whose lower bound of
 * entries already exceeds ORDER_SHARE of the budget is not built. */
static int build(const dtm_operator *op, double budget, dtm_certifier *c, int *status) {
  size_t nn = 0, *xa = NULL, *ad = NULL, nc = (size_t)dtm_operator_ncomp(op);
  if ((double)dtm_operator_node_graph_floor(op) > ORDER_SHARE * budget)
    return *status = DTM_CERT_TOO_DEAR, DTM_OK; /* not even built (at 1.2e6 tets it took 2 % of the run's CPU) */
  if (dtm_operator_node_graph(op, &nn, &xa, &ad) != DTM_OK) return *status = DTM_CERT_UNAVAILABLE, DTM_OK;
  int r = analyse(c, nn, nc, xa, ad, budget, status);
  if (r == DTM_OK && *status == DTM_CERT_PROVEN) r = values(op, c, nn, nc, xa, ad, status);
  free(xa), free(ad);
  return r;
}

int dtm_certifier_create_costed(const dtm_operator *op, double budget, dtm_certifier **out, int *status,
                                double predicted[2]) {
  *out = NULL, *status = DTM_CERT_TOO_DEAR;
  if (predicted) predicted[0] = predicted[1] = NAN;
  DTM_CHECK(dtm_cholmod_load());
  dtm_certifier *c = calloc(1, sizeof *c);
  if (!c) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  c->n = dtm_operator_ndof(op), c->flops = c->bytes = NAN;
  cholmod_l_start(&c->cm);
  c->cm.print = 0;                       /* a refused pivot is an answer, not a message */
  c->cm.supernodal = CHOLMOD_SUPERNODAL; /* one layout of L to read the margin from */
  c->cm.quick_return_if_not_posdef = 1;  /* nothing past the first refused pivot is needed */
  int r = build(op, budget, c, status);
  if (r == DTM_OK && predicted) predicted[0] = c->flops, predicted[1] = c->bytes;
  if (r || *status != DTM_CERT_PROVEN) return dtm_certifier_destroy(&c), r;
  *out = c;
  return DTM_OK;
}

int dtm_certifier_create(const dtm_operator *op, double budget, dtm_certifier **out, int *status) {
  return dtm_certifier_create_costed(op, budget, out, status, NULL);
}

double dtm_certifier_flops(const dtm_certifier *c) { return c ? c->flops : NAN; }

/* ||L||_F^2 over the supernodal factor's lower triangle and the most
 * entries of a row or a column of its pattern. */
static double frobenius(const cholmod_factor *L, size_t *terms, SuiteSparse_long *rows) {
  const SuiteSparse_long *super = L->super, *pi = L->pi, *px = L->px, *ls = L->s;
  const double *lx = L->x;
  double f = 0;
  size_t most = 0;
  memset(rows, 0, L->n * sizeof *rows);
  for (size_t s = 0; s < L->nsuper; s++) {
    SuiteSparse_long ncol = super[s + 1] - super[s], nrow = pi[s + 1] - pi[s];
    if ((size_t)nrow > most) most = (size_t)nrow;
    for (SuiteSparse_long j = 0; j < ncol; j++)
      for (SuiteSparse_long i = j; i < nrow; i++) {
        double l = lx[px[s] + i + j * nrow];
        f += l * l, rows[ls[pi[s] + i]]++;
      }
  }
  for (size_t k = 0; k < L->n; k++)
    if ((size_t)rows[k] > most) most = (size_t)rows[k];
  *terms = most;
  return f;
}

int dtm_certifier_below(dtm_certifier *c, double sigma, double *margin) {
  double beta[2] = {sigma, 0};
  *margin = NAN;
  int threads = omp_get_max_threads(), done;
  omp_set_num_threads(1); /* an OpenMP BLAS on one thread: see the purpose paragraph */
  done = cholmod_l_factorize_p(c->neg, beta, NULL, 0, c->L, &c->cm);
  omp_set_num_threads(threads);
  if (!done || c->cm.status == CHOLMOD_NOT_POSDEF || c->L->minor < c->n) return 0;
  SuiteSparse_long *rows = malloc((c->n + 1) * sizeof *rows);
  if (!rows) return 0; /* no margin to vouch for: not proven */
  size_t terms = 0;
  double frob = frobenius(c->L, &terms, rows), g = (double)(terms + 1) * DBL_EPSILON / 2;
  free(rows);
  *margin = g / (1 - g) * frob + DBL_EPSILON / 2 * (fabs(sigma) + c->diag);
  return 1;
}

/* ---- a pencil (sms.c) ------------------------------------------------- */

/* The values of dx in the slots of c->neg's pattern (upper triangle,
 * columns sorted) into out[nzmax]; 0 when an entry of dx has no slot. */
static int pencil_values(const dtm_certifier *c, const dtm_csr *dx, double *out) {
  const SuiteSparse_long *ap = c->neg->p, *ai = c->neg->i;
  for (size_t j = 0; j < c->n; j++) {
    SuiteSparse_long p = ap[j];
    for (size_t k = dx->rowptr[j]; k < dx->rowptr[j + 1] && dx->col[k] <= j; k++) {
      while (p < ap[j + 1] && (size_t)ai[p] < dx->col[k]) out[p++] = 0;
      if (p == ap[j + 1] || (size_t)ai[p] != dx->col[k]) return 0;
      out[p++] = dx->val[k];
    }
    while (p < ap[j + 1]) out[p++] = 0;
  }
  return 1;
}

/* The largest row sum of |x| over the symmetric matrix whose upper
 * triangle has c->neg's pattern. */
static double row_sum_max(const dtm_certifier *c, const double *x, double *rows) {
  const SuiteSparse_long *ap = c->neg->p, *ai = c->neg->i;
  double most = 0;
  memset(rows, 0, c->n * sizeof *rows);
  for (size_t j = 0; j < c->n; j++)
    for (SuiteSparse_long p = ap[j]; p < ap[j + 1]; p++) {
      rows[ai[p]] += fabs(x[p]);
      if ((size_t)ai[p] != j) rows[j] += fabs(x[p]);
    }
  for (size_t j = 0; j < c->n; j++) most = fmax(most, rows[j]);
  return most;
}

int dtm_certifier_below_pencil(dtm_certifier *c, const dtm_csr *dx, double sigma, double *margin) {
  size_t nz = (size_t)c->neg->nzmax;
  double *keep = malloc((nz + 1) * sizeof *keep), *d = malloc((nz + 1) * sizeof *d);
  double *rows = malloc((c->n + 1) * sizeof *rows), *ax = c->neg->x;
  int ok = 0;
  *margin = NAN;
  if (keep && d && rows && dx->n == c->n && pencil_values(c, dx, d)) {
    double na = row_sum_max(c, ax, rows), nd = row_sum_max(c, d, rows), diag = c->diag;
    memcpy(keep, ax, nz * sizeof *ax);
    for (size_t p = 0; p < nz; p++) ax[p] += sigma * d[p]; /* sigma dx - A: sigma I is added by CHOLMOD */
    for (size_t p = 0; p < nz; p++) c->diag = fmax(c->diag, fabs(ax[p]));
    ok = dtm_certifier_below(c, sigma, margin);
    memcpy(ax, keep, nz * sizeof *ax);
    c->diag = diag;
    /* forming sigma dx - A rounds each entry by at most u (|a| + sigma |dx|): a symmetric perturbation of
       2-norm at most its largest row sum */
    if (ok) *margin += DBL_EPSILON / 2 * (na + sigma * nd) * 2;
  }
  free(keep), free(d), free(rows);
  return ok;
}
