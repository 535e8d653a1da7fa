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
 * The nodes are ordered by nested dissection on breadth-first level
 * structures (the middle level of a search from a far node separates the
 * rest; the separators come last), then the factorisation is the
 * up-looking sparse Cholesky: the elimination tree, the row patterns by
 * climbing it, the column counts (whose squares estimate the flops, checked
 * against the caller's budget before any number is computed), then row by
 * row the sparse triangular solve.
 *
 * Rounding: when the factorisation succeeds in floating point, sigma I - A
 * + E is positive definite with |E| <= g |L| |L^T|, g = (c + 1) u / (1 -
 * (c + 1) u) for c the most terms of an inner product (the largest count
 * of a row or a column of L) and u the unit round-off
 * (Demmel's bound for Cholesky), so ||E||_2 <= g ||L||_F^2. That is the
 * margin returned: every eigenvalue of the assembled A is below sigma +
 * margin. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "spectral.h"
#include "dtmap/operator.h"

#define SMALL_PART 48         /* nested dissection stops below this many nodes */
#define ASSEMBLY_TOL 1e-10    /* the assembled product against the operator's, relative */
#define CERT_MAX_DOFS 30000.0 /* above this, the certificate is not attempted (its flops grow as n^2) */

/* The assembled A (upper triangle, columns in the new order) and the
 * symbolic factorisation, kept across the values of sigma. */
struct dtm_certifier {
  size_t n;           /* dofs */
  size_t *ap, *ai;    /* [n + 1], [nnz]: upper CSC of A in the new order (rows <= column) */
  double *ax;         /* [nnz] */
  size_t *parent;     /* [n] elimination tree (SIZE_MAX: root) */
  size_t *lp;         /* [n + 1] column pointers of L */
  size_t terms;       /* largest count of a row or a column of L (the terms of an inner product) */
  double flops;       /* sum of the squared column counts */
  size_t *li, *stack; /* [nnz(L)], [n] */
  size_t *next, *mark;
  double *lx, *x; /* [nnz(L)], [n] */
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

/* The entries of A in node blocks: blk[(p * nc + i) * nc + j] = A(w nc + i,
 * v nc + j) for w = ad[p], p in v's list. */
static int probe(const dtm_operator *op, size_t nn, const size_t *xa, const size_t *ad, double *blk) {
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
      dtm_operator_apply_sym(op, x, y);
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

/* ---- nested dissection on the node graph ---------------------------- */

typedef struct {
  const size_t *xa, *ad;
  size_t *region; /* [nn] the part each node belongs to */
  size_t *level;  /* [nn] breadth-first level */
  size_t *queue;  /* [nn] */
  size_t *order;  /* [nn] the new order, filled from the back */
  size_t back;    /* next free place from the back */
  size_t nregion; /* regions made so far */
} nd_state;

/* Breadth-first search from s inside region id; returns the nodes reached
 * (in queue[0 ..)) and sets level; *last is the last node reached. */
static size_t bfs(nd_state *s, size_t src, size_t id, size_t *last, size_t *depth) {
  size_t head = 0, tail = 0;
  s->queue[tail++] = src, s->level[src] = 0, s->region[src] = ~id;
  while (head < tail) {
    size_t v = s->queue[head++];
    for (size_t p = s->xa[v]; p < s->xa[v + 1]; p++) {
      size_t w = s->ad[p];
      if (s->region[w] != id) continue;
      s->region[w] = ~id, s->level[w] = s->level[v] + 1, s->queue[tail++] = w;
    }
  }
  for (size_t k = 0; k < tail; k++) s->region[s->queue[k]] = id;
  *last = s->queue[tail - 1], *depth = s->level[*last];
  return tail;
}

static void place(nd_state *s, const size_t *nodes, size_t m) {
  for (size_t k = m; k-- > 0;) s->order[--s->back] = nodes[k];
}

/* Split nodes[m] of region id at the middle level of a breadth-first
 * search from a far node (the search from nodes[0] reached them all).
 * Returns the sizes of the first half *na and the second *nb (nodes[] then
 * holds the first half, the second, and the separator, with their regions
 * ra, rb and SIZE_MAX); 0 when there is no level to cut at. */
static int split(nd_state *s, size_t *nodes, size_t m, size_t id, size_t far, size_t *na, size_t *nb) {
  size_t depth;
  bfs(s, far, id, &far, &depth);
  if (depth < 2) return 0;
  size_t *count = calloc(depth + 2, sizeof *count), *tmp = malloc((m + 1) * sizeof *tmp), mid = 0, acc = 0;
  if (!count || !tmp) return free(count), free(tmp), -1;
  for (size_t k = 0; k < m; k++) count[s->level[nodes[k]]]++;
  while (mid < depth && acc + count[mid] < m / 2) acc += count[mid++];
  if (mid == 0) mid = 1;
  size_t a = s->nregion++, b = s->nregion++, ia = 0, ib = 0, is = 0;
  for (size_t k = 0; k < m; k++) {
    size_t l = s->level[nodes[k]];
    ia += l<mid, ib += l> mid;
  }
  *na = ia, *nb = ib, is = ia + ib, ib = ia, ia = 0;
  for (size_t k = 0; k < m; k++) {
    size_t v = nodes[k], l = s->level[v];
    s->region[v] = l < mid ? a : l > mid ? b : SIZE_MAX;
    tmp[l < mid ? ia++ : l > mid ? ib++ : is++] = v;
  }
  memcpy(nodes, tmp, m * sizeof *nodes);
  free(count), free(tmp);
  return 1;
}

/* Order the m nodes in nodes[] (all of region id; nodes[] is scratch the
 * size of m). Separators are placed last, so the order fills backwards:
 * separator, then the second half, then the first; a part that is not
 * connected gives its components one after the other. */
static int dissect(nd_state *s, size_t *nodes, size_t m, size_t id) {
  while (m > SMALL_PART) {
    size_t far, depth, got = bfs(s, nodes[0], id, &far, &depth), na = 0, nb = 0;
    if (got < m) { /* the component reached goes to a region of its own, ordered now */
      size_t a = s->nregion++, rest = 0;
      for (size_t k = 0; k < got; k++) s->region[s->queue[k]] = a;
      for (size_t k = 0; k < m; k++)
        if (s->region[nodes[k]] != a) nodes[rest++] = nodes[k];
      memcpy(nodes + rest, s->queue, got * sizeof *nodes);
      DTM_CHECK(dissect(s, nodes + rest, got, a));
      m = rest;
      continue;
    }
    int r = split(s, nodes, m, id, far, &na, &nb);
    if (r < 0) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the certificate");
    if (r == 0) break;
    place(s, nodes + na + nb, m - na - nb);
    DTM_CHECK(dissect(s, nodes + na, nb, s->region[nodes[na]]));
    id = na ? s->region[nodes[0]] : id, m = na;
  }
  place(s, nodes, m);
  return DTM_OK;
}

/* order[k]: the node placed k-th. */
static int node_order(size_t nn, const size_t *xa, const size_t *ad, size_t *order) {
  nd_state s = {xa,
                ad,
                malloc((nn + 1) * sizeof(size_t)),
                malloc((nn + 1) * sizeof(size_t)),
                malloc((nn + 1) * sizeof(size_t)),
                order,
                nn,
                1};
  size_t *nodes = malloc((nn + 1) * sizeof *nodes);
  int r = s.region && s.level && s.queue && nodes ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t m = 0, lone = 0; /* nodes of no element are placed last, the others dissected */
  for (size_t v = 0; r == DTM_OK && v < nn; v++) {
    int alone = xa[v + 1] - xa[v] <= 1;
    s.region[v] = alone ? SIZE_MAX : 0;
    if (alone)
      order[nn - ++lone] = v;
    else
      nodes[m++] = v;
  }
  s.back = nn - lone;
  if (r == DTM_OK && m) r = dissect(&s, nodes, m, 0);
  free(s.region), free(s.level), free(s.queue), free(nodes);
  return r;
}

/* ---- the assembled matrix in the new order -------------------------- */

/* Upper CSC of A with dofs numbered node-major in the node order. */
static int permuted_upper(struct dtm_certifier *c, size_t nn, size_t nc, const size_t *xa, const size_t *ad,
                          const double *blk, const size_t *order) {
  size_t *inv = malloc((nn + 1) * sizeof *inv), nnz = 0;
  if (!inv) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the certificate");
  for (size_t k = 0; k < nn; k++) inv[order[k]] = k;
  if (!c->ap) c->ap = malloc((c->n + 1) * sizeof *c->ap);
  if (!c->ai) c->ai = malloc((xa[nn] * nc * nc + c->n + 1) * sizeof *c->ai);
  if (!c->ax) c->ax = malloc((xa[nn] * nc * nc + c->n + 1) * sizeof *c->ax);
  if (!c->ap || !c->ai || !c->ax) return free(inv), DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the certificate");
  for (size_t k = 0; k < nn; k++) {
    size_t v = order[k];
    for (size_t j = 0; j < nc; j++) {
      size_t col = k * nc + j, diag = 0;
      c->ap[col] = nnz;
      for (size_t p = xa[v]; p < xa[v + 1]; p++)
        for (size_t i = 0; i < nc; i++) {
          size_t row = inv[ad[p]] * nc + i;
          if (row > col) continue;
          diag |= row == col;
          c->ai[nnz] = row, c->ax[nnz++] = blk ? blk[(p * nc + i) * nc + j] : 0;
        }
      if (!diag) c->ai[nnz] = col, c->ax[nnz++] = 0; /* a node of no element */
    }
  }
  c->ap[c->n] = nnz;
  free(inv);
  return DTM_OK;
}

/* ||A x - op x|| <= ASSEMBLY_TOL ||op x|| for a random x (in the new
 * order, with dof map perm: new -> old). */
static int assembly_agrees(const dtm_operator *op, const struct dtm_certifier *c, const size_t *order, size_t nc) {
  size_t n = c->n;
  double *x = malloc((n + 1) * sizeof *x), *y = malloc((n + 1) * sizeof *y), *z = calloc(n + 1, sizeof *z);
  int ok = 0;
  if (x && y && z) {
    dtm_operator_draw(op, 777, -1, 1, x);
    dtm_operator_apply_sym(op, x, y);
    for (size_t col = 0; col < n; col++) {
      size_t oc = order[col / nc] * nc + col % nc;
      for (size_t p = c->ap[col]; p < c->ap[col + 1]; p++) {
        size_t row = c->ai[p], orow = order[row / nc] * nc + row % nc;
        z[orow] += c->ax[p] * x[oc];
        if (row != col) z[oc] += c->ax[p] * x[orow];
      }
    }
    double e = 0, s = 0;
    for (size_t i = 0; i < n; i++) e += (z[i] - y[i]) * (z[i] - y[i]), s += y[i] * y[i];
    ok = e <= ASSEMBLY_TOL * ASSEMBLY_TOL * s;
  }
  free(x), free(y), free(z);
  return ok;
}

/* ---- symbolic -------------------------------------------------------- */

static void etree(struct dtm_certifier *c, size_t *anc) {
  for (size_t k = 0; k < c->n; k++) {
    c->parent[k] = anc[k] = SIZE_MAX;
    for (size_t p = c->ap[k]; p < c->ap[k + 1]; p++)
      for (size_t i = c->ai[p]; i != SIZE_MAX && i < k;) {
        size_t up = anc[i];
        anc[i] = k;
        if (up == SIZE_MAX) c->parent[i] = k;
        i = up;
      }
  }
}

/* The pattern of row k of L (columns < k) in topological order, in
 * stack[top ..); mark[] holds k for the visited columns. */
static size_t row_pattern(const struct dtm_certifier *c, size_t k, size_t *stack, size_t *mark) {
  size_t top = c->n;
  mark[k] = k;
  for (size_t p = c->ap[k]; p < c->ap[k + 1]; p++) {
    size_t i = c->ai[p], len = 0;
    if (i >= k) continue;
    for (; mark[i] != k; i = c->parent[i]) stack[len++] = i, mark[i] = k;
    while (len > 0) stack[--top] = stack[--len];
  }
  return top;
}

/* Column counts and pointers of L; 0 when the flops exceed budget (counted
 * without finishing, against nnz cap). */
static int symbolic(struct dtm_certifier *c, double budget) {
  size_t n = c->n, *cnt = calloc(n + 1, sizeof *cnt), tot = n;
  double cap = sqrt(budget * (double)n) + (double)n;
  if (!cnt) return -1;
  for (size_t k = 0; k < n; k++) c->mark[k] = SIZE_MAX;
  c->terms = 0;
  for (size_t k = 0; k < n && (double)tot <= cap; k++) {
    size_t top = row_pattern(c, k, c->stack, c->mark);
    cnt[k]++;
    if (n - top + 1 > c->terms) c->terms = n - top + 1;
    for (size_t t = top; t < n; t++) cnt[c->stack[t]]++, tot++;
  }
  if ((double)tot > cap) return free(cnt), 0;
  c->lp[0] = 0, c->flops = 0;
  for (size_t k = 0; k < n; k++) {
    c->lp[k + 1] = c->lp[k] + cnt[k], c->flops += (double)cnt[k] * (double)cnt[k];
    if (cnt[k] > c->terms) c->terms = cnt[k];
  }
  free(cnt);
  return c->flops <= budget;
}

/* ---- numeric --------------------------------------------------------- */

/* L L^T = sigma I - A; 1 when every pivot is positive, with *frob =
 * ||L||_F^2. */
static int cholesky(struct dtm_certifier *c, double sigma, double *frob) {
  size_t n = c->n;
  double f = 0;
  for (size_t k = 0; k < n; k++) c->x[k] = 0, c->mark[k] = SIZE_MAX, c->next[k] = c->lp[k];
  for (size_t k = 0; k < n; k++) {
    size_t top = row_pattern(c, k, c->stack, c->mark);
    for (size_t p = c->ap[k]; p < c->ap[k + 1]; p++) c->x[c->ai[p]] = (c->ai[p] == k ? sigma : 0) - c->ax[p];
    double d = c->x[k];
    c->x[k] = 0;
    for (; top < n; top++) {
      size_t j = c->stack[top];
      double l = c->x[j] / c->lx[c->lp[j]];
      c->x[j] = 0;
      for (size_t p = c->lp[j] + 1; p < c->next[j]; p++) c->x[c->li[p]] -= c->lx[p] * l;
      d -= l * l, f += l * l;
      c->li[c->next[j]] = k, c->lx[c->next[j]++] = l;
    }
    if (!(d > 0)) return 0;
    c->li[c->next[k]] = k, c->lx[c->next[k]++] = sqrt(d), f += d;
  }
  *frob = f;
  return 1;
}

/* ---- the public face -------------------------------------------------- */

void dtm_certifier_destroy(dtm_certifier **cp) {
  if (!cp || !*cp) return;
  dtm_certifier *c = *cp;
  free(c->ap), free(c->ai), free(c->ax), free(c->parent), free(c->lp), free(c->li), free(c->stack);
  free(c->next), free(c->mark), free(c->lx), free(c->x), free(c);
  *cp = NULL;
}

static int certifier_alloc(dtm_certifier *c) {
  size_t n = c->n + 1;
  c->parent = malloc(n * sizeof(size_t)), c->lp = malloc((n + 1) * sizeof(size_t));
  c->stack = malloc(n * sizeof(size_t)), c->next = malloc(n * sizeof(size_t));
  c->mark = malloc(n * sizeof(size_t)), c->x = malloc(n * sizeof(double));
  return c->parent && c->lp && c->stack && c->next && c->mark && c->x ? DTM_OK
                                                                      : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
}

/* The pattern of A in the new order and its symbolic factorisation;
 * *status DTM_CERT_TOO_DEAR when over budget. */
static int pattern(dtm_certifier *c, size_t nn, size_t nc, const size_t *xa, const size_t *ad, const size_t *order,
                   double budget, int *status) {
  DTM_CHECK(permuted_upper(c, nn, nc, xa, ad, NULL, order));
  DTM_CHECK(certifier_alloc(c));
  size_t *anc = malloc((c->n + 1) * sizeof *anc);
  if (!anc) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  etree(c, anc);
  free(anc);
  int s = symbolic(c, budget);
  if (s < 0) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  *status = s ? DTM_CERT_PROVEN : DTM_CERT_TOO_DEAR;
  return DTM_OK;
}

/* The values of A by the coloured products, checked against one product. */
static int values(const dtm_operator *op, dtm_certifier *c, size_t nn, size_t nc, const size_t *xa, const size_t *ad,
                  const size_t *order, int *status) {
  double *blk = malloc((xa[nn] * nc * nc + 1) * sizeof *blk);
  int r = blk ? probe(op, nn, xa, ad, blk) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = permuted_upper(c, nn, nc, xa, ad, blk, order);
  free(blk);
  if (r == DTM_OK) *status = assembly_agrees(op, c, order, nc) ? DTM_CERT_PROVEN : DTM_CERT_UNAVAILABLE;
  if (r || *status != DTM_CERT_PROVEN) return r;
  c->li = malloc((c->lp[c->n] + 1) * sizeof *c->li), c->lx = malloc((c->lp[c->n] + 1) * sizeof *c->lx);
  return c->li && c->lx ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the factor");
}

/* Order and symbolic factorisation first (no product), then, within the
 * budget, the assembly; *status as for dtm_certifier_create. */
static int build(const dtm_operator *op, double budget, dtm_certifier *c, int *status) {
  size_t nn = 0, *xa = NULL, *ad = NULL, nc = (size_t)dtm_operator_ncomp(op);
  if (dtm_operator_node_graph(op, &nn, &xa, &ad) != DTM_OK) return *status = DTM_CERT_UNAVAILABLE, DTM_OK;
  size_t *order = malloc((nn + 1) * sizeof *order);
  int r = order ? node_order(nn, xa, ad, order) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = pattern(c, nn, nc, xa, ad, order, budget, status);
  if (r == DTM_OK && *status == DTM_CERT_PROVEN) r = values(op, c, nn, nc, xa, ad, order, status);
  free(xa), free(ad), free(order);
  return r;
}

int dtm_certifier_create(const dtm_operator *op, double budget, dtm_certifier **out, int *status) {
  *out = NULL, *status = DTM_CERT_TOO_DEAR;
  size_t n = dtm_operator_ndof(op);
  if ((double)n > CERT_MAX_DOFS) return DTM_OK;
  dtm_certifier *c = calloc(1, sizeof *c);
  if (!c) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  c->n = n;
  int r = build(op, budget, c, status);
  if (r || *status != DTM_CERT_PROVEN) return dtm_certifier_destroy(&c), r;
  *out = c;
  return DTM_OK;
}

double dtm_certifier_flops(const dtm_certifier *c) { return c ? c->flops : NAN; }

int dtm_certifier_below(dtm_certifier *c, double sigma, double *margin) {
  double frob = 0, g = (double)(c->terms + 1) * DBL_EPSILON / 2;
  if (!cholesky(c, sigma, &frob)) return *margin = NAN, 0;
  *margin = g / (1 - g) * frob;
  return 1;
}
