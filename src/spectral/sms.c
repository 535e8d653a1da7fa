/* The scaled mass of selective mass scaling (include/dtmap/sms.h): each
 * element's factor beta from a target step, the added masses of the
 * scaled elements kept element by element (their nodes, lumped node
 * masses w and beta), the matrix-free product with M_s = M + sum_e
 * beta_e (W_e - w_e w_e^T / m_e) (x) I_d, its assembly into compressed
 * rows over the operator's unknowns, and the Jacobi-preconditioned
 * conjugate-gradient solve with it. The added mass acts on each component
 * alone, so M_s couples the same component of two nodes of a scaled
 * element and nothing else. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "spectral.h"
#include "dtmap/error.h"
#include "dtmap/sms.h"

struct dtm_sms {
  size_t ndof, nnodes; /* unknowns, nodes (ndof = nnodes nc: no rotations) */
  int nc;              /* components per node */
  double *mass;        /* [ndof] the lumped diagonal (a copy) */
  size_t nel, cap;     /* scaled elements, and the room for their nodes */
  size_t *eptr;        /* [nel + 1] each element's nodes and masses from eptr[e] */
  size_t *node;        /* [eptr[nel]] node indices */
  double *w;           /* [eptr[nel]] lumped node masses, kg */
  double *beta;        /* [nel] */
  dtm_sms_stats st;
  const double *all_beta; /* creation only: beta per global element */
  size_t *offset;         /* creation only: [nblocks] first global index of each block */
};

void dtm_sms_beta(size_t n, const double *dt, double target, double *beta) {
  for (size_t i = 0; i < n; i++) {
    double r = target / dt[i];
    beta[i] = dt[i] > 0 && isfinite(dt[i]) && r > 1 ? r * r - 1 : 0;
  }
}

void dtm_sms_element_steps(size_t n, const double *dt, const double *beta, double *out) {
  for (size_t i = 0; i < n; i++) out[i] = dt[i] * sqrt(1 + beta[i]);
}

void dtm_sms_destroy(dtm_sms **sp) {
  if (!sp || !*sp) return;
  dtm_sms *s = *sp;
  free(s->mass), free(s->eptr), free(s->node), free(s->w), free(s->beta), free(s->offset);
  free(s);
  *sp = NULL;
}

/* Room for one more element of nn nodes. */
static int grow(dtm_sms *s, int nn) {
  if (s->nel % 1024 == 0) {
    size_t *p = realloc(s->eptr, (s->nel + 1025) * sizeof *p);
    double *b = realloc(s->beta, (s->nel + 1024) * sizeof *b);
    if (p) s->eptr = p;
    if (b) s->beta = b;
    if (!p || !b) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  if (s->eptr[s->nel] + (size_t)nn > s->cap) {
    s->cap = 2 * s->cap + 64 * (size_t)nn;
    size_t *q = realloc(s->node, s->cap * sizeof *q);
    double *w = realloc(s->w, s->cap * sizeof *w);
    if (q) s->node = q;
    if (w) s->w = w;
    if (!q || !w) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  return DTM_OK;
}

/* The statistics of one element: the trace of its added mass per
 * component, and the largest beta. */
static void count(dtm_sms *s, int block, size_t local, int nn, const double *w, double beta) {
  if (!(beta > 0)) return;
  double m = 0, ww = 0;
  for (int a = 0; a < nn; a++) m += w[a], ww += w[a] * w[a];
  for (int c = 0; c < s->nc; c++) s->st.trace_add[c] += beta * (m - ww / m);
  s->st.scaled++;
  if (beta > s->st.beta_max) s->st.beta_max = beta, s->st.beta_block = block, s->st.beta_local = local;
}

/* The lumped model's trace per component and the translational mass of
 * both models, measured: 1^T M_s 1 for the unit translation along x. */
static int masses(dtm_sms *s) {
  size_t nc = (size_t)s->nc;
  double *x = malloc((s->ndof + 1) * sizeof *x), *y = malloc((s->ndof + 1) * sizeof *y);
  if (!x || !y) return free(x), free(y), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t k = 0; k < s->ndof; k++) s->st.trace_mass[k % nc] += s->mass[k], x[k] = k % nc == 0;
  dtm_sms_apply(s, x, y);
  for (size_t k = 0; k < s->ndof; k += nc) s->st.translational += y[k], s->st.translational_m += s->mass[k];
  free(x), free(y);
  return DTM_OK;
}

static int collect(void *user, int block, size_t local, int nn, const size_t *nodes, const double *w) {
  dtm_sms *s = user;
  double beta = s->all_beta[s->offset[block] + local];
  count(s, block, local, nn, w, beta);
  if (!(beta > 0)) return DTM_OK;
  DTM_CHECK(grow(s, nn));
  size_t p = s->eptr[s->nel];
  for (int a = 0; a < nn; a++) s->node[p + (size_t)a] = nodes[a], s->w[p + (size_t)a] = w[a];
  s->beta[s->nel++] = beta;
  s->eptr[s->nel] = p + (size_t)nn;
  return DTM_OK;
}

static int setup(dtm_sms *s, const dtm_operator *op, const dtm_mesh *mesh, const unsigned char *const *level,
                 const double *beta) {
  s->ndof = dtm_operator_ndof(op), s->nc = dtm_operator_ncomp(op), s->nnodes = mesh->nnodes;
  if (s->ndof != s->nnodes * (size_t)s->nc)
    return DTM_ERR(DTM_ERR_INPUT, "selective mass scaling: shells and beams are not supported");
  s->mass = malloc((s->ndof + 1) * sizeof *s->mass);
  s->offset = malloc(((size_t)mesh->nblocks + 1) * sizeof *s->offset);
  s->eptr = calloc(1025, sizeof *s->eptr);
  s->beta = malloc(1024 * sizeof *s->beta);
  if (!s->mass || !s->offset || !s->eptr || !s->beta) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  memcpy(s->mass, dtm_operator_mass(op), s->ndof * sizeof *s->mass);
  for (int b = 0, i = 0; b < mesh->nblocks; i += (int)mesh->blocks[b].n, b++) s->offset[b] = (size_t)i;
  s->all_beta = beta, s->st.beta_block = -1, s->st.ncomp = s->nc;
  DTM_CHECK(dtm_operator_each_element(op, mesh, level, collect, s));
  s->all_beta = NULL;
  return masses(s);
}

int dtm_sms_create(const dtm_operator *op, const dtm_mesh *mesh, const unsigned char *const *level, const double *beta,
                   dtm_sms **out) {
  *out = NULL;
  dtm_sms *s = calloc(1, sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = setup(s, op, mesh, level, beta);
  if (r) return dtm_sms_destroy(&s), dtm_error_trace(r, __FILE__, __LINE__, __func__);
  free(s->offset), s->offset = NULL;
  *out = s;
  return DTM_OK;
}

void dtm_sms_stats_get(const dtm_sms *s, dtm_sms_stats *st) { *st = s->st; }

/* y += element e's added mass times x. */
static void add_elem(const dtm_sms *s, size_t e, const double *x, double *y) {
  size_t p0 = s->eptr[e], p1 = s->eptr[e + 1], nc = (size_t)s->nc;
  double m = 0;
  for (size_t p = p0; p < p1; p++) m += s->w[p];
  for (size_t c = 0; c < nc; c++) {
    double wx = 0;
    for (size_t p = p0; p < p1; p++) wx += s->w[p] * x[s->node[p] * nc + c];
    for (size_t p = p0; p < p1; p++) {
      size_t k = s->node[p] * nc + c;
      y[k] += s->beta[e] * s->w[p] * (x[k] - wx / m);
    }
  }
}

void dtm_sms_apply(const dtm_sms *s, const double *x, double *y) {
  for (size_t k = 0; k < s->ndof; k++) y[k] = s->mass[k] * x[k];
  for (size_t e = 0; e < s->nel; e++) add_elem(s, e, x, y);
}

/* ---- assembly ---------------------------------------------------------- */

static int cmp_size(const void *a, const void *b) {
  size_t x = *(const size_t *)a, y = *(const size_t *)b;
  return (x > y) - (x < y);
}

/* The nodes each node shares a scaled element with, itself included,
 * sorted and distinct: adj[xa[v] .. xa[v + 1]). */
static int node_lists(const dtm_sms *s, size_t **xa, size_t **adj) {
  size_t nn = s->nnodes, *x = calloc(nn + 1, sizeof *x), *fill = calloc(nn + 1, sizeof *fill), *a = NULL;
  if (!x || !fill) return free(x), free(fill), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < nn; v++) fill[v] = 1; /* itself */
  for (size_t e = 0; e < s->nel; e++)
    for (size_t p = s->eptr[e]; p < s->eptr[e + 1]; p++) fill[s->node[p]] += s->eptr[e + 1] - s->eptr[e];
  for (size_t v = 0; v < nn; v++) x[v + 1] = x[v] + fill[v], fill[v] = x[v];
  a = malloc((x[nn] + 1) * sizeof *a);
  if (!a) return free(x), free(fill), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < nn; v++) a[fill[v]++] = v;
  for (size_t e = 0; e < s->nel; e++)
    for (size_t p = s->eptr[e]; p < s->eptr[e + 1]; p++)
      for (size_t q = s->eptr[e]; q < s->eptr[e + 1]; q++) a[fill[s->node[p]]++] = s->node[q];
  free(fill);
  size_t w = 0; /* sort each list and drop repeats, in place */
  for (size_t v = 0, lo = 0; v < nn; v++) {
    size_t hi = x[v + 1];
    qsort(a + lo, hi - lo, sizeof *a, cmp_size);
    x[v] = w;
    for (size_t k = lo; k < hi; k++)
      if (k == lo || a[k] != a[k - 1]) a[w++] = a[k];
    lo = hi;
  }
  x[nn] = w;
  *xa = x, *adj = a;
  return DTM_OK;
}

/* The rows of the unknowns from the node lists: unknown v nc + c couples
 * u nc + c for u in v's list. */
static int pattern(const dtm_sms *s, const size_t *xa, const size_t *adj, dtm_csr *m) {
  size_t nc = (size_t)s->nc;
  m->n = s->ndof;
  m->rowptr = malloc((m->n + 1) * sizeof *m->rowptr);
  m->col = malloc((xa[s->nnodes] * nc + 1) * sizeof *m->col);
  m->val = calloc(xa[s->nnodes] * nc + 1, sizeof *m->val);
  if (!m->rowptr || !m->col || !m->val) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t nz = 0;
  for (size_t v = 0; v < s->nnodes; v++)
    for (size_t c = 0; c < nc; c++) {
      m->rowptr[v * nc + c] = nz;
      for (size_t p = xa[v]; p < xa[v + 1]; p++) m->col[nz++] = adj[p] * nc + c;
    }
  m->rowptr[m->n] = nz;
  return DTM_OK;
}

/* The slot of column j in row i (present by construction). */
static size_t slot(const dtm_csr *m, size_t i, size_t j) {
  size_t lo = m->rowptr[i], hi = m->rowptr[i + 1];
  while (hi - lo > 1) {
    size_t mid = lo + (hi - lo) / 2;
    if (m->col[mid] <= j)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

/* Element e's added mass into m's values. */
static void scatter(const dtm_sms *s, size_t e, dtm_csr *m) {
  size_t p0 = s->eptr[e], p1 = s->eptr[e + 1], nc = (size_t)s->nc;
  double tot = 0;
  for (size_t p = p0; p < p1; p++) tot += s->w[p];
  for (size_t p = p0; p < p1; p++)
    for (size_t q = p0; q < p1; q++) {
      double v = s->beta[e] * ((p == q ? s->w[p] : 0) - s->w[p] * s->w[q] / tot);
      for (size_t c = 0; c < nc; c++) {
        size_t i = s->node[p] * nc + c, j = s->node[q] * nc + c;
        m->val[slot(m, i, j)] += v;
      }
    }
}

int dtm_sms_assemble(const dtm_sms *s, int add_only, dtm_csr *out) {
  size_t *xa = NULL, *adj = NULL;
  memset(out, 0, sizeof *out);
  int r = node_lists(s, &xa, &adj);
  if (r == DTM_OK) r = pattern(s, xa, adj, out);
  free(xa), free(adj);
  if (r) return dtm_csr_free(out), r;
  for (size_t k = 0; k < s->ndof && !add_only; k++) out->val[slot(out, k, k)] += s->mass[k];
  for (size_t e = 0; e < s->nel; e++) scatter(s, e, out);
  return DTM_OK;
}

/* ---- Jacobi-preconditioned conjugate gradients -------------------------- */

/* The inverse of m's diagonal (0 where it is not positive). */
static void jacobi(const dtm_csr *m, double *dinv) {
  for (size_t i = 0; i < m->n; i++) {
    double d = m->val[slot(m, i, i)];
    dinv[i] = m->col[slot(m, i, i)] == i && d > 0 ? 1 / d : 0;
  }
}

/* The iterations from x = 0 with r = b; work holds dinv, r, z, p, q. */
static int pcg(const dtm_csr *m, const double *b, double rtol, int maxit, double *x, double *work) {
  size_t n = m->n;
  double *dinv = work, *r = work + n, *z = work + 2 * n, *p = work + 3 * n, *q = work + 4 * n;
  jacobi(m, dinv);
  for (size_t i = 0; i < n; i++) x[i] = 0, r[i] = b[i] * (dinv[i] > 0), z[i] = dinv[i] * r[i], p[i] = z[i];
  double rz = dtm_vec_dot(n, r, z), stop = rtol * rtol * rz;
  if (!(rz > 0)) return 0;
  for (int it = 1; it <= maxit; it++) {
    dtm_csr_apply(m, p, q);
    double alpha = rz / dtm_vec_dot(n, p, q);
    for (size_t i = 0; i < n; i++) x[i] += alpha * p[i], r[i] -= alpha * q[i], z[i] = dinv[i] * r[i];
    double rz1 = dtm_vec_dot(n, r, z);
    if (rz1 <= stop) return it;
    for (size_t i = 0; i < n; i++) p[i] = z[i] + rz1 / rz * p[i];
    rz = rz1;
  }
  return maxit + 1;
}

int dtm_sms_solve(const dtm_csr *m, const double *b, double rtol, int maxit, double *x, int *it) {
  double *work = malloc((5 * m->n + 1) * sizeof *work);
  if (!work) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  *it = pcg(m, b, rtol, maxit, x, work);
  free(work);
  return DTM_OK;
}

/* ---- a start for Lanczos ------------------------------------------------ */

void dtm_sms_factor_draw(const dtm_sms *s, const dtm_operator *op, unsigned long long seed, double *rhs) {
  size_t nc = (size_t)s->nc, key = 0;
  dtm_operator_draw_normal(op, seed, rhs);
  for (size_t k = 0; k < s->ndof; k++) rhs[k] *= sqrt(s->mass[k]);
  for (size_t e = 0; e < s->nel; e++) {
    size_t p0 = s->eptr[e], p1 = s->eptr[e + 1];
    double m = 0, b = sqrt(s->beta[e]);
    for (size_t p = p0; p < p1; p++) m += s->w[p];
    for (size_t c = 0; c < nc; c++) {
      double h[64], sum = 0; /* B_e^T h, B_e = sqrt(beta) W^1/2 (I - 1 w^T / m): M_add^e = B_e^T B_e */
      for (size_t p = p0; p < p1; p++) h[p - p0] = dtm_rng_normal_at(seed ^ 0x5bd1e995ULL, key++);
      for (size_t p = p0; p < p1; p++) sum += sqrt(s->w[p]) * h[p - p0];
      for (size_t p = p0; p < p1; p++) rhs[s->node[p] * nc + c] += b * (sqrt(s->w[p]) * h[p - p0] - s->w[p] / m * sum);
    }
  }
}
