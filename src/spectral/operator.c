/* The global operators of a spectral effect on a whole mesh, matrix free:
 * the lumped diagonal M, the stiffness K of linear elasticity or scalar
 * diffusion applied element by element, its scaling M^-1/2 K M^-1/2 and
 * the Rayleigh damping C = sum_e alpha_e M_e + beta_e K_e. At creation the
 * map of every element is evaluated once at the points of its type's full
 * rule (dtm_ref_rule, dtm_ref_eval; no type is hard-coded): per point the
 * inverse Jacobian (d x d) and dv = |det J| * weight are stored, and the
 * reference gradients once per block, so a tet4 costs 10 doubles and a
 * hex8 80, with the connectivity in 32 bits when the nodes fit. Types whose reference gradients are the same at every
 * rule point (the linear simplices) keep a single point with the summed weight, which is exact. A block of solid 3D
 * elements whose points would take more memory than their element matrices (the curved tet10 of a part at level 5 or
 * 6: 125 or 216 points, 1,250 or 2,160 doubles, against 465 for the packed 30 x 30 matrix) keeps the matrices instead,
 * assembled by the kernel (dtm_elem_matrix_at) with the material in them: the same integrals over the same points,
 * summed in another order, and a product then costs about 1,900 flops per element instead of about 60,000 or 100,000
 * (stores_matrices). The product sums the
 * element forces of each thread's contiguous share of elements into its own buffer (the first thread writes y itself)
 * and the buffers are then added in a fixed order, so results do not depend on scheduling. On 2 cores this beat element
 * colouring by 2x on a 1e6-tet mesh: a colour's elements are spread over
 * the whole mesh, so each of the ~30 colours sweeps u and y again, while
 * the extra buffer costs one zeroing and one addition of ndof values. */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "base.h"
#include "spectral.h"
#include "dtmap/error.h"
#include "dtmap/operator.h"
#include "reference.h"
#include "structural-impl.h"

typedef struct {
  int type, nn;
  int nq; /* stored points per element */
  size_t n;
  const size_t *conn, *tags; /* the mesh's (not owned) */
  uint32_t *c32;             /* [n][nn] conn in 32 bits when the nodes fit (owned), else NULL */
  const int *mat;
  double dn[DTM_K_QP][DTM_K_NODES][3]; /* reference gradients per point */
  int p1;                              /* linear simplex (line2, tri3, tet4) with the reference
                                          gradients -1 (node 0) and e_j (node j + 1): the kernels
                                          then take differences instead of products */
  double *geo;                         /* [n][nq][st]: J^-1 row-major (d x d), then dv; for a
                                          manifold block J^+ (k x d), the tangent projector (d x d), dv */
  int k;                               /* the elements' own dimension */
  int manifold;                        /* k < d: curves or surfaces in a higher-dimensional
                                          space (trusses, membranes), with tangential gradients */
  int st;                              /* doubles per stored point */
  int nmat;                            /* materials of the mesh (slot = mat + nmat (section + 1)) */
  const int *sec;                      /* [n] section of each element, or NULL (the mesh's) */
  int level;                           /* 0: the type's full rule; else the levelled rule of
                                          the curved elements of this part (parts.c) */
  int mbi;                             /* index of the mesh block the elements come from */
  const size_t *orig;                  /* [n] their index in that block, or NULL (the same) */
  double *kel;                         /* [n][npk] instead of geo (stores_matrices): each
                                          element's matrix, material included, its upper
                                          triangle packed row by row */
  double *meas;                        /* [n] with kel: each element's measure (sum of its dv) */
  int ne, npk;                         /* with kel: unknowns per element, ne (ne + 1) / 2 */
} op_block;

typedef struct {
  double lam, mu;     /* elastic: sigma = lam tr(F) I + mu (F + F^T), times the section factor */
  double cond;        /* diffusion: conductivity, times the section factor */
  double cap;         /* lumped capacity per volume, times the section factor */
  double alpha, beta; /* Rayleigh */
} op_mat;

/* What one share of the product (a contiguous range of every block's
 * elements) writes: dofs [lo, hi). Share 0 writes y itself, share s > 0
 * its own buffer buf + off, added into y afterwards. */
typedef struct {
  size_t lo, hi; /* dof range its elements touch */
  size_t off;    /* its buffer's offset in dtm_operator.buf */
} op_share;

struct dtm_operator {
  int kind, d, ncomp, nmat, nblocks; /* d: the space of the unknowns; nmat: coefficient slots */
  int nmat_base, nsec;               /* the mesh's materials and sections (slots: nmat_base (nsec + 1)) */
  size_t ndof;
  int nshares;     /* shares of the product, fixed at creation */
  op_share *share; /* [nshares] */
  double *buf;     /* the buffers of shares 1.. (allocated once: no
                      allocation per product) */
  op_block *blocks;
  op_mat *mats;
  double *mass;            /* [ndof] lumped diagonal */
  double *mass_alpha;      /* [ndof] sum_e alpha_e M_e, or NULL */
  double *dsq;             /* [ndof] M^-1/2, 0 where the mass is 0 */
  double *scaled;          /* [ndof] M^-1/2 x of a symmetric product (work, owned) */
  const size_t *node_tags; /* [nnodes] the mesh's Gmsh node tags, or NULL (not owned) */
  int has_beta;
  dtm_op_struct st;              /* shells and beams (structural.c): st.n = 0 when none */
  double *slot_alpha;            /* [nmat] Rayleigh alpha of each slot, for them */
  double *slot_beta;             /* [nmat] Rayleigh beta of each slot */
  dtm_rule_part *parts;          /* [nblocks] the parts the blocks are built on (owned) */
  const dtm_operator_kept *kept; /* what an analysis kept (creation only), or NULL */
};

enum { APPLY_K = 0, APPLY_BETA = 1 };

static int shares_setup(dtm_operator *op);

size_t dtm_operator_narrow_max = UINT32_MAX;
int dtm_operator_store = 1;

/* The element loops are specialised per dimension (and node count) by
 * inlining them with constant arguments, and their short loops unrolled;
 * at -O2 compilers need to be told to do both. */
#if defined(__GNUC__) || defined(__clang__)
#define ALWAYS_INLINE __attribute__((always_inline))
#define UNROLL _Pragma("GCC unroll 8")
#else
#define ALWAYS_INLINE
#define UNROLL
#endif

/* ---- creation: checks ---------------------------------------------- */

static const char *tag_text(const op_block *b, size_t e, char *buf, size_t n) {
  if (b->tags)
    snprintf(buf, n, "%zu", b->tags[e]);
  else
    snprintf(buf, n, "#%zu", e);
  return buf;
}

static int check_args(const dtm_mesh *m, int kind, const dtm_operator_coeffs *c, int nmat, dtm_operator **out) {
  if (!out) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_operator_create: no output");
  *out = NULL;
  if (!m || !c || nmat < 1 || (m->nblocks > 0 && !m->blocks))
    return DTM_ERR(DTM_ERR_INTERNAL, "dtm_operator_create: missing mesh or coefficients");
  if (kind != DTM_OP_ELASTIC && kind != DTM_OP_DIFFUSION)
    return DTM_ERR(DTM_ERR_INTERNAL, "dtm_operator_create: kind %d is not spectral", kind);
  if (m->dim < 1 || m->dim > 3) return DTM_ERR(DTM_ERR_INPUT, "mesh dimension %d is not 1, 2 or 3", m->dim);
  if (dtm_mesh_nelements(m) == 0) return DTM_ERR(DTM_ERR_INPUT, "the global estimate needs a mesh with elements");
  return DTM_OK;
}

static int ok_nonneg(double v) { return isfinite(v) && v >= 0; }

/* Slot (coefficient index) of element e of b: its material, offset by the
 * material count for each section index + 1. */
static int slot_of(const op_block *b, size_t e) { return b->mat[e] + (b->sec ? b->nmat * (b->sec[e] + 1) : 0); }

/* The formulation of slot i suits the elements that use it. */
static int form_check(const dtm_operator *op, int i, int form) {
  for (int ib = 0; ib < op->nblocks; ib++) {
    const op_block *b = &op->blocks[ib];
    for (size_t e = 0; e < b->n; e++)
      if (slot_of(b, e) == i) {
        DTM_CHECK(dtm_form_check(b->type, b->k, form));
        break;
      }
  }
  return DTM_OK;
}

/* Check material i's coefficients and convert them into o. */
static int material_setup(const dtm_operator *op, int i, const dtm_operator_coeffs *c, const double *alpha,
                          const double *beta, op_mat *o) {
  double f = c->section_factor > 0 ? c->section_factor : 1.0;
  o->alpha = alpha ? alpha[i] : 0, o->beta = beta ? beta[i] : 0;
  o->cap = c->capacity * f;
  op->slot_alpha[i] = o->alpha, op->slot_beta[i] = o->beta;
  if (c->kind != op->kind)
    return DTM_ERR(DTM_ERR_INTERNAL, "material %d: coefficients of kind %d, operator of kind %d", i, c->kind, op->kind);
  if (!(isfinite(c->capacity) && c->capacity > 0) || !ok_nonneg(o->alpha) || !ok_nonneg(o->beta))
    return DTM_ERR(DTM_ERR_INPUT,
                   "material %d: capacity %g, Rayleigh alpha %g, beta %g: "
                   "need capacity > 0 and finite alpha, beta >= 0",
                   i, c->capacity, o->alpha, o->beta);
  if (dtm_op_struct_is(c)) { /* shells and beams: their stored matrices alone (structural.c) */
    o->cap = 0;
    return DTM_OK;
  }
  if (op->kind == DTM_OP_DIFFUSION) {
    o->cond = c->conductivity * f;
    if (!ok_nonneg(o->cond))
      return DTM_ERR(DTM_ERR_INPUT, "material %d: conductivity %g is not finite and >= 0", i, o->cond);
    return DTM_OK;
  }
  DTM_CHECK(form_check(op, i, c->mod.form));
  int bar = c->mod.form == DTM_FORM_BAR;
  o->lam = (bar ? c->mod.modulus : c->mod.lam) * f, o->mu = (bar ? 0 : c->mod.mu) * f;
  if (!isfinite(o->lam) || !ok_nonneg(o->mu) || !(o->lam + 2 * o->mu > 0))
    return DTM_ERR(DTM_ERR_INPUT, "material %d: elastic moduli lam %g, mu %g are not admissible", i, o->lam, o->mu);
  return DTM_OK;
}

/* Which materials the elements use; DTM_ERR_INPUT for an index out of range. */
static int mark_used(const dtm_operator *op, char *used) {
  char t[32];
  for (int ib = 0; ib < op->nblocks; ib++) {
    const op_block *b = &op->blocks[ib];
    for (size_t e = 0; e < b->n; e++) {
      int m = b->mat && b->mat[e] >= 0 ? slot_of(b, e) : -1;
      if (m < 0 || m >= op->nmat)
        return DTM_ERR(DTM_ERR_INPUT, "element %s (%s) has no material (index %d of %d)", tag_text(b, e, t, sizeof t),
                       dtm_elem_name(b->type), m, op->nmat);
      used[m] = 1;
    }
  }
  return DTM_OK;
}

static int materials_setup(dtm_operator *op, const dtm_operator_coeffs *c, const double *alpha, const double *beta) {
  char *used = calloc((size_t)op->nmat, 1);
  op->mats = calloc((size_t)op->nmat, sizeof *op->mats);
  op->slot_alpha = calloc((size_t)op->nmat, sizeof *op->slot_alpha);
  op->slot_beta = calloc((size_t)op->nmat, sizeof *op->slot_beta);
  if (!used || !op->mats || !op->slot_alpha || !op->slot_beta) {
    free(used);
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  int r = mark_used(op, used);
  for (int i = 0; i < op->nmat && !r; i++) {
    if (used[i]) r = material_setup(op, i, &c[i], alpha, beta, &op->mats[i]);
    op->has_beta |= used[i] && op->mats[i].beta > 0;
  }
  free(used);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

/* ---- creation: geometry --------------------------------------------- */

/* Whether b's element is the linear simplex of its dimension with
 * reference gradients dN_0 = (-1, ..., -1), dN_(j+1) = e_j (exactly: they
 * are integers). */
static int p1_gradients(const op_block *b) {
  int d = 0, nn = 0;
  dtm_elem_info(b->type, &d, &nn);
  if (nn != d + 1) return 0;
  for (int a = 0; a < nn; a++)
    for (int j = 0; j < d; j++)
      if (b->dn[0][a][j] != (a == 0 ? -1.0 : a == j + 1 ? 1.0 : 0.0)) return 0;
  return 1;
}

/* Reference gradients at the rule points; one point with the summed weight
 * when they are the same at every point (then so is the whole map). */
static void block_rule(op_block *b, double *wq) {
  dtm_qrule q;
  double N[DTM_K_NODES];
  if (b->level == DTM_RULE_AFFINE) /* exact for the stiffness of an affine tet10: degree 2 */
    dtm_ref_rule_level(b->type, DTM_K_RULE_C3D10, &q);
  else if (b->level)
    dtm_ref_rule_level(b->type, b->level, &q);
  else
    dtm_ref_rule(b->type, &q);
  int same = 1;
  for (int k = 0; k < q.n; k++) {
    dtm_ref_eval(b->type, q.p[k], N, b->dn[k]);
    wq[k] = q.w[k];
    for (int a = 0; a < b->nn && k > 0; a++)
      for (int j = 0; j < 3; j++) same &= fabs(b->dn[k][a][j] - b->dn[0][a][j]) <= 1e-15;
  }
  b->nq = q.n;
  if (!same) return;
  for (int k = 1; k < q.n; k++) wq[0] += wq[k];
  b->nq = 1;
  b->p1 = p1_gradients(b);
}

/* inv = J^-1 packed row-major (d x d), given det J. */
static void inverse_packed(int d, const double J[3][3], double dj, double *inv) {
  double K[3][3];
  dtm_mat_inverse(d, J, dj, K);
  for (int i = 0; i < d; i++)
    for (int j = 0; j < d; j++) inv[d * i + j] = K[i][j];
}

/* Store J^-1 and dv of element e at every point; the sign of det J must be
 * positive in 3D and the same at every point in 1D and 2D (where the
 * orientation in the plane is arbitrary). Returns 0, or -1 with det J. */
static int elem_geometry(const dtm_operator *op, const op_block *b, const double *xyz, size_t e, const double *wq,
                         double *out, double *dj_bad) {
  int d = op->d, st = d * d + 1;
  const size_t *c = b->conn + e * (size_t)b->nn;
  double sign = 0;
  for (int k = 0; k < b->nq; k++) {
    double J[3][3] = {{0}}, *g = out + (size_t)k * (size_t)st;
    for (int i = 0; b->p1 && i < d; i++) /* the sum below, without its products by 0 and 1 */
      for (int j = 0; j < d; j++) J[i][j] = -xyz[3 * c[0] + i] + xyz[3 * c[j + 1] + i];
    for (int a = 0; !b->p1 && a < b->nn; a++)
      for (int i = 0; i < d; i++)
        for (int j = 0; j < d; j++) J[i][j] += xyz[3 * c[a] + i] * b->dn[k][a][j];
    double dj = dtm_mat_det(d, (const double(*)[3])J);
    if (!sign) sign = d == 3 ? 1 : dj >= 0 ? 1 : -1;
    *dj_bad = dj;
    if (!(sign * dj > 32 * DBL_EPSILON * dtm_mat_hadamard(d, (const double(*)[3])J)) || !isfinite(dj)) return -1;
    if (!b->kel) inverse_packed(d, (const double(*)[3])J, dj, g); /* a block of matrices wants dv only */
    g[d * d] = fabs(dj) * wq[k];
  }
  return 0;
}

/* One point of a manifold element (dimension k in d-space), J[d][k]: into
 * g the pseudo-inverse J^+ = (J^T J)^-1 J^T (k x d, row-major), the
 * tangent projector J J^+ (d x d) and dv = sqrt(det J^T J) w. Returns 0,
 * or -1 when the element spans no line or plane there. */
static int manifold_point(int d, int k, const double J[3][3], double w, double *g, double *meas) {
  double G[3][3] = {{0}}, Gi[3][3], norms = 1;
  for (int i = 0; i < k; i++) {
    for (int j = 0; j < k; j++)
      for (int r = 0; r < d; r++) G[i][j] += J[r][i] * J[r][j];
    norms *= sqrt(G[i][i]);
  }
  double det = dtm_mat_det(k, (const double(*)[3])G);
  *meas = sqrt(fmax(det, 0));
  if (!(*meas > 32 * DBL_EPSILON * norms) || !isfinite(det)) return -1;
  dtm_mat_inverse(k, (const double(*)[3])G, det, Gi);
  for (int i = 0; i < k; i++)
    for (int m = 0; m < d; m++) {
      g[i * d + m] = 0;
      for (int j = 0; j < k; j++) g[i * d + m] += Gi[i][j] * J[m][j];
    }
  for (int r = 0; r < d; r++)
    for (int m = 0; m < d; m++) {
      double v = 0;
      for (int i = 0; i < k; i++) v += J[r][i] * g[i * d + m];
      g[k * d + r * d + m] = v;
    }
  g[k * d + d * d] = *meas * w;
  return 0;
}

/* The same for an element of a manifold block. */
static int manifold_geometry(const dtm_operator *op, const op_block *b, const double *xyz, size_t e, const double *wq,
                             double *out, double *dj_bad) {
  int d = op->d;
  const size_t *c = b->conn + e * (size_t)b->nn;
  for (int q = 0; q < b->nq; q++) {
    double J[3][3] = {{0}}, *g = out + (size_t)q * (size_t)b->st;
    for (int a = 0; a < b->nn; a++)
      for (int i = 0; i < d; i++)
        for (int j = 0; j < b->k; j++) J[i][j] += xyz[3 * c[a] + i] * b->dn[q][a][j];
    if (manifold_point(d, b->k, (const double(*)[3])J, wq[q], g, dj_bad)) return -1;
  }
  return 0;
}

/* The points of element e into out[nq][st] (its place in geo, or a
 * scratch for a block that stores matrices, whose measure it records). */
static int any_geometry(const dtm_operator *op, op_block *b, const double *xyz, size_t e, const double *wq,
                        double *scratch, double *dj_bad) {
  double *out = b->kel ? scratch : b->geo + e * (size_t)b->nq * (size_t)b->st, meas = 0;
  int r =
      b->manifold ? manifold_geometry(op, b, xyz, e, wq, out, dj_bad) : elem_geometry(op, b, xyz, e, wq, out, dj_bad);
  if (r || !b->kel) return r;
  for (int k = 0; k < b->nq; k++) meas += out[(size_t)k * (size_t)b->st + (size_t)b->st - 1];
  b->meas[e] = meas;
  return 0;
}

/* Whether b keeps each element's matrix instead of its points: where the
 * packed matrix takes less memory than the points (the curved elements'
 * parts at a high level: a tet10 at level 6 keeps 465 doubles instead of
 * 2160, and a product then costs about 1,900 flops instead of about
 * 100,000), and only for solid 3D elements, whose matrix the kernel
 * assembles in the global axes (dtm_elem_matrix_at). dtm_operator_store:
 * 0 never, 2 wherever it may (tests). */
static int stores_matrices(const dtm_operator *op, const op_block *b) {
  int ne = b->nn * op->ncomp;
  if (!dtm_operator_store || b->manifold || b->p1 || op->d != 3 || b->k != 3) return 0;
  return dtm_operator_store == 2 || (size_t)ne * (size_t)(ne + 1) / 2 < (size_t)b->nq * (size_t)b->st;
}

/* Room for the points of each element, or for its matrix and measure. */
static int block_alloc(const dtm_operator *op, op_block *b) {
  if (!stores_matrices(op, b)) {
    b->geo = malloc(b->n * (size_t)b->nq * (size_t)b->st * sizeof *b->geo);
    return b->geo || !b->n ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  b->ne = b->nn * op->ncomp, b->npk = b->ne * (b->ne + 1) / 2;
  b->kel = malloc((b->n * (size_t)b->npk + 1) * sizeof *b->kel);
  b->meas = malloc((b->n + 1) * sizeof *b->meas);
  return b->kel && b->meas ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
}

static int block_setup(dtm_operator *op, const dtm_mesh *m, const dtm_rule_part *part, op_block *b) {
  const dtm_block *mb = &part->blk;
  int dim, nn;
  DTM_CHECK(dtm_elem_info(mb->type, &dim, &nn));
  if (dim > op->d || nn != mb->nn || nn > DTM_K_NODES)
    return DTM_ERR(DTM_ERR_INPUT,
                   "block of %s elements (dimension %d, %d nodes) in a "
                   "mesh of dimension %d",
                   dtm_elem_name(mb->type), dim, mb->nn, m->dim);
  double wq[DTM_K_QP];
  b->type = mb->type, b->nn = nn, b->n = mb->n, b->k = dim, b->manifold = dim < op->d;
  b->st = b->manifold ? dim * op->d + op->d * op->d + 1 : op->d * op->d + 1;
  b->conn = mb->conn, b->tags = mb->tags, b->mat = mb->mat;
  b->nmat = op->nmat_base, b->sec = op->nsec ? mb->section : NULL;
  b->level = part->level, b->mbi = part->block, b->orig = part->orig;
  if (m->nnodes <= dtm_operator_narrow_max) { /* 32-bit connectivity: half the index traffic of the product */
    b->c32 = malloc((b->n * (size_t)nn + 1) * sizeof *b->c32);
    if (!b->c32) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    for (size_t k = 0; k < b->n * (size_t)nn; k++) b->c32[k] = (uint32_t)b->conn[k];
  }
  block_rule(b, wq);
  if (b->manifold) b->p1 = 0;
  DTM_CHECK(block_alloc(op, b));
  size_t bad = b->n;
  double dj = 0, scratch[DTM_K_QP * 10]; /* the points of one element of a block that stores matrices (d = 3) */
#pragma omp parallel for schedule(static) reduction(min : bad)
  for (size_t e = 0; e < b->n; e++) {
    double djt, own[DTM_K_QP * 10];
    if (any_geometry(op, b, m->xyz, e, wq, own, &djt) && e < bad) bad = e;
  }
  if (bad == b->n) return DTM_OK;
  char place[256];
  any_geometry(op, b, m->xyz, bad, wq, scratch, &dj);
  if (mb->tags)
    dtm_mesh_element_place(m, b->mbi, b->orig ? b->orig[bad] : bad, place, sizeof place);
  else
    snprintf(place, sizeof place, "element #%zu (%s)", bad, dtm_elem_name(b->type));
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s is degenerate, inverted or folded "
                 "(det J = %g at an integration point): the global estimate cannot use it",
                 place, dj);
}

/* ---- creation: element matrices -------------------------------------- */

/* Element e's matrix, its material's coefficients included (the
 * conductivity scales the Laplacian), packed into b->kel. Returns 0, or -1
 * where the kernel finds det J not safely positive at a point of the rule. */
static int elem_matrix(const dtm_operator *op, const dtm_mesh *m, op_block *b, size_t e) {
  double x[DTM_K_NODES * 3], K[DTM_K_DOF * DTM_K_DOF];
  const op_mat *mt = &op->mats[slot_of(b, e)];
  const size_t *c = b->conn + e * (size_t)b->nn;
  int el = op->kind == DTM_OP_ELASTIC, ne = b->ne;
  dtm_elastic_moduli mod = {.form = DTM_FORM_3D, .lam = mt->lam, .mu = mt->mu, .modulus = mt->lam + 2 * mt->mu};
  for (int a = 0; a < b->nn; a++) memcpy(x + 3 * a, m->xyz + 3 * c[a], 3 * sizeof *x);
  if (dtm_elem_matrix_at(b->type, x, b->level == DTM_RULE_AFFINE ? 0 : b->level, el ? &mod : NULL, K) != -1) return -1;
  double f = el ? 1 : mt->cond, *k = b->kel + e * (size_t)b->npk;
  for (int r = 0; r < ne; r++)
    for (int q = r; q < ne; q++) *k++ = f * K[r * ne + q];
  return 0;
}

/* The matrices of a block that stores them, once the materials are set. */
static int block_matrices(const dtm_operator *op, const dtm_mesh *m, op_block *b) {
  size_t bad = b->n;
  if (!b->kel) return DTM_OK;
#pragma omp parallel for schedule(dynamic, 64) reduction(min : bad)
  for (size_t e = 0; e < b->n; e++)
    if (elem_matrix(op, m, b, e) && e < bad) bad = e;
  if (bad == b->n) return DTM_OK;
  char place[256];
  if (b->tags)
    dtm_mesh_element_place(m, b->mbi, b->orig ? b->orig[bad] : bad, place, sizeof place);
  else
    snprintf(place, sizeof place, "element #%zu (%s)", bad, dtm_elem_name(b->type));
  return DTM_ERR(DTM_ERR_INPUT, "%s is inverted or folded at a point of its rule: the global estimate cannot use it",
                 place);
}

/* ---- creation: lumped diagonals ------------------------------------- */

/* The converged level an analysis kept for element e of part b (level:
 * its rows per mesh block, or NULL), or -1. */
static int kept_level(const unsigned char *const *level, const op_block *b, size_t e) {
  const unsigned char *row = level ? level[b->mbi] : NULL;
  return row ? row[b->orig ? b->orig[e] : e] : -1;
}

/* Lumped node masses of element e per unit capacity, into w[nn]: the
 * kernel's weights times the measure, which is the sum of the stored dv
 * (the same rule as dtm_elem_measure, without integrating a second time). */
static void lumped_weights(const unsigned char *const *level, const dtm_mesh *m, const op_block *b, size_t e,
                           double *w) {
  double x[DTM_K_NODES * 3];
  const size_t *c = b->conn + e * (size_t)b->nn;
  if (b->p1) { /* row sums of a linear simplex (lump.c), without gathering the nodes */
    for (int a = 0; a < b->nn; a++) w[a] = 1.0 / b->nn;
    return;
  }
  for (int a = 0; a < b->nn; a++) memcpy(x + 3 * a, m->xyz + 3 * c[a], 3 * sizeof *x);
  if (b->level == DTM_K_RULE_C3D10) /* CalculiX's lumping goes with its rule (src/kernel/lump.c) */
    dtm_elem_lumped_at(b->type, x, DTM_INTEGRATION_CALCULIX, b->level, w);
  else /* the converged weights, at the level an analysis kept (else searched) */
    dtm_elem_lumped_at(b->type, x, DTM_INTEGRATION_CONVERGED, kept_level(level, b, e), w);
}

static int elem_lumped(const unsigned char *const *level, const dtm_mesh *m, const op_block *b, size_t e, double *w) {
  double meas = 0;
  size_t st = (size_t)b->st;
  const double *g = b->kel ? NULL : b->geo + e * (size_t)b->nq * st;
  for (int k = 0; g && k < b->nq; k++) meas += g[(size_t)k * st + st - 1];
  if (b->kel) meas = b->meas[e]; /* the same sum, taken at creation */
  lumped_weights(level, m, b, e, w);
  int ok = 1;
  for (int a = 0; a < b->nn; a++) {
    w[a] *= meas;
    ok &= isfinite(w[a]) && w[a] > 0;
  }
  return ok ? 0 : -1;
}

#define MASS_CHUNK 65536 /* elements whose lumped masses are computed at once */

/* Lumped masses w[e - e0][nn] of elements [e0, e1) of b, in parallel;
 * returns the first element with a bad one, or e1. */
static size_t chunk_lumped(const dtm_operator *op, const dtm_mesh *m, const op_block *b, size_t e0, size_t e1,
                           double *w) {
  size_t bad = e1;
  const unsigned char *const *level = op->kept ? op->kept->level : NULL;
#pragma omp parallel for schedule(static) reduction(min : bad)
  for (size_t e = e0; e < e1; e++)
    if (elem_lumped(level, m, b, e, w + (e - e0) * (size_t)b->nn) && e < bad) bad = e;
  return bad;
}

/* Add the lumped masses w of elements [e0, e1) of b to the diagonals. */
static void chunk_add(dtm_operator *op, const op_block *b, size_t e0, size_t e1, const double *w) {
  size_t nc = (size_t)op->ncomp, nn = (size_t)b->nn;
  for (size_t e = e0; e < e1; e++) {
    const op_mat *mt = &op->mats[slot_of(b, e)];
    for (size_t a = 0; a < nn; a++)
      for (size_t i = 0; i < nc; i++) {
        size_t k = b->conn[e * nn + a] * nc + i;
        double mk = mt->cap * w[(e - e0) * nn + a];
        op->mass[k] += mk;
        if (op->mass_alpha) op->mass_alpha[k] += mt->alpha * mk;
      }
  }
}

static int block_mass(dtm_operator *op, const dtm_mesh *m, const op_block *b, double *w) {
  for (size_t e0 = 0; e0 < b->n; e0 += MASS_CHUNK) {
    size_t e1 = b->n - e0 < MASS_CHUNK ? b->n : e0 + MASS_CHUNK;
    size_t bad = chunk_lumped(op, m, b, e0, e1, w);
    char t[32];
    if (bad < e1)
      return DTM_ERR(DTM_ERR_INPUT, "element %s (%s) has a non-positive lumped mass", tag_text(b, bad, t, sizeof t),
                     dtm_elem_name(b->type));
    chunk_add(op, b, e0, e1, w);
  }
  return DTM_OK;
}

/* The point masses the mesh carries (dtm_mesh.node_mass) on every
 * translational unknown of their node: elastic only (mass stores no heat),
 * and without mass-proportional damping (an added mass is not the
 * material's). */
static void point_masses(dtm_operator *op, const dtm_mesh *m) {
  if (!m->node_mass || op->kind != DTM_OP_ELASTIC) return;
  size_t nc = (size_t)op->ncomp;
  for (size_t v = 0; v < m->nnodes; v++)
    for (size_t i = 0; i < nc; i++) op->mass[v * nc + i] += m->node_mass[v];
}

static int mass_setup(dtm_operator *op, const dtm_mesh *m) {
  double *w = malloc((size_t)MASS_CHUNK * DTM_K_NODES * sizeof *w);
  if (!w) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = DTM_OK;
  for (int ib = 0; ib < op->nblocks && !r; ib++) r = block_mass(op, m, &op->blocks[ib], w);
  free(w);
  if (r == DTM_OK) dtm_op_struct_masses(&op->st, op->slot_alpha, op->mass, op->mass_alpha);
  if (r == DTM_OK) point_masses(op, m);
  for (size_t k = 0; k < op->ndof; k++) op->dsq[k] = op->mass[k] > 0 ? 1 / sqrt(op->mass[k]) : 0;
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

static int any_alpha(const dtm_operator *op, const double *alpha) {
  for (int i = 0; alpha && i < op->nmat; i++)
    if (op->mats[i].alpha > 0) return 1;
  return 0;
}

static int create(dtm_operator *op, const dtm_mesh *m, const dtm_operator_coeffs *c, const double *alpha,
                  const double *beta) {
  op->node_tags = m->node_tags;
  int np = 0, model = DTM_INTEGRATION_CONVERGED;
  for (int i = 0; i < op->nmat; i++) /* the elastic effect's model (one per effect) */
    if (c[i].kind == DTM_OP_ELASTIC && c[i].mod.integration != DTM_INTEGRATION_CONVERGED) model = c[i].mod.integration;
  int r = dtm_rule_parts(m, model, op->kept ? op->kept->level : NULL, &op->parts, &np);
  op->nblocks = np; /* the parts, freed by destroy */
  DTM_CHECK(r);
  op->blocks = calloc((size_t)np + 1, sizeof *op->blocks);
  if (!op->blocks) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int ib = 0; ib < np; ib++) DTM_CHECK(block_setup(op, m, &op->parts[ib], &op->blocks[ib]));
  DTM_CHECK(materials_setup(op, c, alpha, beta));
  for (int ib = 0; ib < np; ib++) DTM_CHECK(block_matrices(op, m, &op->blocks[ib]));
  DTM_CHECK(dtm_op_struct_setup(&op->st, m, c, op->nmat_base, op->kept ? op->kept->rot : NULL)); /* after
                                                                    materials_setup: it checks every slot */
  op->ndof = m->nnodes * (size_t)op->ncomp + 3 * op->st.nrot;
  op->mass = calloc(op->ndof, sizeof *op->mass);
  op->dsq = malloc(op->ndof * sizeof *op->dsq);
  op->scaled = malloc(op->ndof * sizeof *op->scaled);
  if (any_alpha(op, alpha)) op->mass_alpha = calloc(op->ndof, sizeof *op->mass_alpha);
  if (!op->mass || !op->dsq || !op->scaled || (any_alpha(op, alpha) && !op->mass_alpha))
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  DTM_CHECK(shares_setup(op));
  return mass_setup(op, m);
}

int dtm_operator_create(const dtm_mesh *mesh, int kind, const dtm_operator_coeffs *coef, const double *alpha,
                        const double *beta, int nmat, dtm_operator **out) {
  return dtm_operator_create_sections(mesh, kind, coef, alpha, beta, nmat, 0, out);
}

int dtm_operator_create_sections(const dtm_mesh *mesh, int kind, const dtm_operator_coeffs *coef, const double *alpha,
                                 const double *beta, int nmat, int nsec, dtm_operator **out) {
  return dtm_operator_create_kept(mesh, kind, coef, alpha, beta, nmat, nsec, NULL, out);
}

int dtm_operator_create_kept(const dtm_mesh *mesh, int kind, const dtm_operator_coeffs *coef, const double *alpha,
                             const double *beta, int nmat, int nsec, const dtm_operator_kept *kept,
                             dtm_operator **out) {
  DTM_CHECK(check_args(mesh, kind, coef, nmat, out));
  int d;
  DTM_CHECK(dtm_mesh_space_dim(mesh, &d));
  for (int i = 0; i < nmat * (nsec + 1); i++)
    if (dtm_op_struct_is(&coef[i])) d = 3; /* shells and beams bend out of any plane */
  dtm_operator *op = calloc(1, sizeof *op);
  if (!op) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  op->kind = kind, op->d = d, op->nmat_base = nmat, op->nsec = nsec, op->nmat = nmat * (nsec + 1);
  op->ncomp = kind == DTM_OP_ELASTIC ? d : 1;
  op->kept = kept;
  int r = create(op, mesh, coef, alpha, beta);
  op->kept = NULL; /* creation only: the caller's struct need not outlive it */
  if (r) {
    dtm_operator_destroy(&op);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = op;
  return DTM_OK;
}

void dtm_operator_destroy(dtm_operator **op) {
  if (!op || !*op) return;
  for (int ib = 0; (*op)->blocks && ib < (*op)->nblocks; ib++) {
    op_block *b = &(*op)->blocks[ib];
    free(b->geo), free(b->c32), free(b->kel), free(b->meas);
  }
  dtm_rule_parts_free((*op)->parts, (*op)->nblocks);
  free((*op)->share);
  free((*op)->buf);
  free((*op)->blocks);
  free((*op)->mats);
  free((*op)->mass);
  free((*op)->mass_alpha);
  free((*op)->dsq);
  free((*op)->scaled);
  free((*op)->slot_alpha);
  free((*op)->slot_beta);
  dtm_op_struct_free(&(*op)->st);
  free(*op);
  *op = NULL;
}

size_t dtm_operator_ndof(const dtm_operator *op) { return op->ndof; }

size_t dtm_operator_points(const dtm_operator *op) {
  size_t n = 0;
  for (int ib = 0; ib < op->nblocks; ib++) n += op->blocks[ib].kel ? 0 : op->blocks[ib].n * (size_t)op->blocks[ib].nq;
  return n;
}

size_t dtm_operator_stored(const dtm_operator *op) {
  size_t n = 0;
  for (int ib = 0; ib < op->nblocks; ib++) n += op->blocks[ib].kel ? op->blocks[ib].n : 0;
  return n;
}
int dtm_operator_ncomp(const dtm_operator *op) { return op->ncomp; }
int dtm_operator_kind(const dtm_operator *op) { return op->kind; }
const double *dtm_operator_mass(const dtm_operator *op) { return op->mass; }

void dtm_operator_draw(const dtm_operator *op, unsigned long long seed, double lo, double hi, double *x) {
  size_t nc = (size_t)op->ncomp, nt = op->ndof - 3 * op->st.nrot;
  for (size_t k = 0; k < op->ndof; k++) {
    size_t node = k < nt ? k / nc : op->st.rot_node[(k - nt) / 3];
    uint64_t tag = op->node_tags ? op->node_tags[node] : node + 1;
    /* rotations: the components after the translations' (3, 4, 5) */
    x[k] = k < nt ? dtm_rng_uniform_at(seed, tag * nc + k % nc, lo, hi)
                  : dtm_rng_uniform_at(seed ^ 0x9e3779b97f4a7c15ULL, tag * 3 + (k - nt) % 3, lo, hi);
  }
}

void dtm_operator_draw_normal(const dtm_operator *op, unsigned long long seed, double *x) {
  size_t nc = (size_t)op->ncomp, nt = op->ndof - 3 * op->st.nrot;
  for (size_t k = 0; k < op->ndof; k++) {
    size_t node = k < nt ? k / nc : op->st.rot_node[(k - nt) / 3];
    uint64_t tag = op->node_tags ? op->node_tags[node] : node + 1;
    x[k] = k < nt ? dtm_rng_normal_at(seed, tag * nc + k % nc)
                  : dtm_rng_normal_at(seed ^ 0x9e3779b97f4a7c15ULL, tag * 3 + (k - nt) % 3);
  }
}

/* ---- element kernels ------------------------------------------------- */

/* The stress s = lam tr(F) I + mu (F + F^T) of the displacement gradient
 * F = Fr J^-1, given Fr = sum_b u_b (x) dN_b and ji = J^-1 (row-major). */
static inline ALWAYS_INLINE void stress(const int d, const double fr[3][3], const double *ji, double lam, double mu,
                                        double s[3][3]) {
  double f[3][3], tr = 0;
  UNROLL
  for (int i = 0; i < d; i++) UNROLL
  for (int m = 0; m < d; m++) {
    f[i][m] = 0;
    UNROLL
    for (int j = 0; j < d; j++) f[i][m] += fr[i][j] * ji[j * d + m];
  }
  UNROLL
  for (int i = 0; i < d; i++) tr += f[i][i];
  UNROLL
  for (int i = 0; i < d; i++) UNROLL
  for (int m = 0; m < d; m++) s[i][m] = mu * (f[i][m] + f[m][i]) + (i == m ? lam * tr : 0);
}

/* Elastic forces fe[nn][d] of displacements ue[nn][d] at the element's
 * points: F = grad u = Fr J^-1 with Fr = sum_b u_b (x) dN_b, sigma, then
 * f_a += dv sigma g_a = P dN_a with P = dv sigma J^-T. d (and nn for the
 * common types) are constants after inlining, so the loops unroll. */
static inline ALWAYS_INLINE void elastic_elem(const int d, const int nn, const op_block *b, const double *geo,
                                              const double *ue, double *fe, double lam, double mu) {
  const int st = d * d + 1;
  for (int k = 0; k < b->nq; k++, geo += st) {
    const double(*dn)[3] = b->dn[k], *ji = geo, dv = geo[d * d];
    double fr[3][3] = {{0}}, s[3][3], p[3][3];
    UNROLL
    for (int a = 0; a < nn; a++) UNROLL
    for (int i = 0; i < d; i++) UNROLL
    for (int j = 0; j < d; j++) fr[i][j] += ue[a * d + i] * dn[a][j];
    stress(d, fr, ji, lam, mu, s);
    UNROLL
    for (int i = 0; i < d; i++) UNROLL
    for (int j = 0; j < d; j++) {
      p[i][j] = 0;
      UNROLL
      for (int m = 0; m < d; m++) p[i][j] += s[i][m] * ji[j * d + m];
      p[i][j] *= dv;
    }
    UNROLL
    for (int a = 0; a < nn; a++) UNROLL
    for (int i = 0; i < d; i++) UNROLL
    for (int j = 0; j < d; j++) fe[a * d + i] += p[i][j] * dn[a][j];
  }
}

/* The same on a linear simplex (one point, p1): Fr's column j is
 * u_(j+1) - u_0, and f_(j+1) = P e_j, f_0 = -sum_j P e_j, which saves the
 * two products with the reference gradients (about half the flops). */
static inline ALWAYS_INLINE void elastic_p1(const int d, const double *geo, const double *ue, double *fe, double lam,
                                            double mu) {
  const double *ji = geo, dv = geo[d * d];
  double fr[3][3], s[3][3];
  UNROLL
  for (int i = 0; i < d; i++) UNROLL
  for (int j = 0; j < d; j++) fr[i][j] = ue[(j + 1) * d + i] - ue[i];
  stress(d, fr, ji, lam, mu, s);
  UNROLL
  for (int i = 0; i < d; i++) {
    double sum = 0;
    UNROLL
    for (int j = 0; j < d; j++) {
      double pij = 0;
      UNROLL
      for (int m = 0; m < d; m++) pij += s[i][m] * ji[j * d + m];
      fe[(j + 1) * d + i] = pij * dv, sum += pij;
    }
    fe[i] = -sum * dv;
  }
}

static inline ALWAYS_INLINE void diffusion_p1(const int d, const double *geo, const double *ue, double *fe,
                                              double cond) {
  const double *ji = geo;
  double gr[3], g[3] = {0}, sum = 0;
  UNROLL
  for (int j = 0; j < d; j++) gr[j] = ue[j + 1] - ue[0];
  UNROLL
  for (int m = 0; m < d; m++) UNROLL
  for (int j = 0; j < d; j++) g[m] += gr[j] * ji[j * d + m];
  UNROLL
  for (int j = 0; j < d; j++) {
    double p = 0;
    UNROLL
    for (int m = 0; m < d; m++) p += ji[j * d + m] * g[m];
    p *= cond * geo[d * d];
    fe[j + 1] = p, sum += p;
  }
  fe[0] = -sum;
}

/* Diffusion fluxes: grad u = gr J^-1, q = dv k grad u, f_a += dN_a . J^-1 q. */
static inline ALWAYS_INLINE void diffusion_elem(const int d, const int nn, const op_block *b, const double *geo,
                                                const double *ue, double *fe, double cond) {
  const int st = d * d + 1;
  for (int k = 0; k < b->nq; k++, geo += st) {
    const double(*dn)[3] = b->dn[k], *ji = geo;
    double gr[3] = {0}, g[3] = {0}, p[3] = {0};
    UNROLL
    for (int a = 0; a < nn; a++) UNROLL
    for (int j = 0; j < d; j++) gr[j] += ue[a] * dn[a][j];
    UNROLL
    for (int m = 0; m < d; m++) UNROLL
    for (int j = 0; j < d; j++) g[m] += gr[j] * ji[j * d + m];
    UNROLL
    for (int j = 0; j < d; j++) UNROLL
    for (int m = 0; m < d; m++) p[j] += ji[j * d + m] * g[m] * cond * geo[d * d];
    UNROLL
    for (int a = 0; a < nn; a++) UNROLL
    for (int j = 0; j < d; j++) fe[a] += dn[a][j] * p[j];
  }
}

/* Elastic forces of a manifold element (dimension k in d-space): the
 * tangential gradient F = Fr J^+, the strain eps = P sym(F) P in the
 * tangent space (P the projector), sigma = lam tr(eps) P + 2 mu eps (a
 * truss: lam = E, mu = 0, so sigma = E (t.F t) t t^T; a membrane: the
 * plane-stress moduli), f_a += dv sigma grad N_a. */
static void manifold_elastic(const int d, const op_block *b, const double *geo, const double *ue, double *fe,
                             double lam, double mu) {
  const int k = b->k, nn = b->nn;
  for (int q = 0; q < b->nq; q++, geo += b->st) {
    const double(*dn)[3] = b->dn[q], *jp = geo, *P = geo + k * d, dv = geo[k * d + d * d];
    double fr[3][3] = {{0}}, F[3][3] = {{0}}, S[3][3], PS[3][3] = {{0}}, eps[3][3] = {{0}}, tr = 0;
    for (int a = 0; a < nn; a++)
      for (int i = 0; i < d; i++)
        for (int j = 0; j < k; j++) fr[i][j] += ue[a * d + i] * dn[a][j];
    for (int i = 0; i < d; i++)
      for (int m = 0; m < d; m++)
        for (int j = 0; j < k; j++) F[i][m] += fr[i][j] * jp[j * d + m];
    for (int i = 0; i < d; i++)
      for (int m = 0; m < d; m++) S[i][m] = 0.5 * (F[i][m] + F[m][i]);
    for (int i = 0; i < d; i++)
      for (int m = 0; m < d; m++)
        for (int r = 0; r < d; r++) PS[i][m] += P[i * d + r] * S[r][m];
    for (int i = 0; i < d; i++)
      for (int m = 0; m < d; m++)
        for (int r = 0; r < d; r++) eps[i][m] += PS[i][r] * P[r * d + m];
    for (int i = 0; i < d; i++) tr += eps[i][i];
    for (int i = 0; i < d; i++)
      for (int j = 0; j < k; j++) {
        double p = 0;
        for (int m = 0; m < d; m++) p += (lam * tr * P[i * d + m] + 2 * mu * eps[i][m]) * jp[j * d + m];
        for (int a = 0; a < nn; a++) fe[a * d + i] += dv * p * dn[a][j];
      }
  }
}

/* Diffusion fluxes of a manifold element: the tangential gradient
 * g = gr J^+, q = dv k g, f_a += grad N_a . q. */
static void manifold_diffusion(const int d, const op_block *b, const double *geo, const double *ue, double *fe,
                               double cond) {
  const int k = b->k;
  for (int q = 0; q < b->nq; q++, geo += b->st) {
    const double(*dn)[3] = b->dn[q], *jp = geo, dv = geo[k * d + d * d];
    double gr[3] = {0}, g[3] = {0};
    for (int a = 0; a < b->nn; a++)
      for (int j = 0; j < k; j++) gr[j] += ue[a] * dn[a][j];
    for (int m = 0; m < d; m++)
      for (int j = 0; j < k; j++) g[m] += gr[j] * jp[j * d + m];
    for (int j = 0; j < k; j++) {
      double p = 0;
      for (int m = 0; m < d; m++) p += jp[j * d + m] * g[m];
      for (int a = 0; a < b->nn; a++) fe[a] += dn[a][j] * p * cond * dv;
    }
  }
}

/* K_e D u of the manifold elements [e0, e1) of b into y (as block_range). */
static void manifold_range(const dtm_operator *op, const op_block *b, size_t e0, size_t e1, const double *u, double *y,
                           int which) {
  const int d = op->d, nc = op->ncomp, nn = b->nn, el = op->kind == DTM_OP_ELASTIC;
  double ue[DTM_K_NODES * 3], fe[DTM_K_NODES * 3];
  for (size_t e = e0; e < e1; e++) {
    const op_mat *mt = &op->mats[slot_of(b, e)];
    double s = which == APPLY_BETA ? mt->beta : 1;
    const size_t *c = b->conn + e * (size_t)nn;
    if (s == 0) continue;
    for (int a = 0; a < nn; a++)
      for (int i = 0; i < nc; i++) {
        size_t kk = c[a] * (size_t)nc + (size_t)i;
        ue[a * nc + i] = u[kk], fe[a * nc + i] = 0;
      }
    const double *geo = b->geo + e * (size_t)b->nq * (size_t)b->st;
    if (el)
      manifold_elastic(d, b, geo, ue, fe, s * mt->lam, s * mt->mu);
    else
      manifold_diffusion(d, b, geo, ue, fe, s * mt->cond);
    for (int a = 0; a < nn; a++)
      for (int i = 0; i < nc; i++) y[c[a] * nc + i] += fe[a * nc + i];
  }
}

/* Add K_e u (scaled by beta_e for APPLY_BETA) of elements [e0, e1) of b
 * into y: elastic (el = 1, d unknowns
 * per node) or diffusion (el = 0, one unknown); nnc is the node count when
 * known at compile time, else 0. */
static inline ALWAYS_INLINE void block_range(const dtm_operator *op, const op_block *b, size_t e0, size_t e1,
                                             const double *u, double *y, int which, const int d, const int el,
                                             const int nnc, const int narrow, const int p1) {
  const int nc = el ? d : 1, nn = nnc ? nnc : b->nn, st = d * d + 1;
  double ue[DTM_K_NODES * 3], fe[DTM_K_NODES * 3];
  for (size_t e = e0; e < e1; e++) {
    const op_mat *mt = &op->mats[slot_of(b, e)];
    double s = which == APPLY_BETA ? mt->beta : 1;
    size_t c[DTM_K_NODES];
    if (s == 0) continue;
    UNROLL
    for (int a = 0; a < nn; a++)
      c[a] = narrow ? b->c32[e * (size_t)nn + (size_t)a] : b->conn[e * (size_t)nn + (size_t)a];
    UNROLL
    for (int a = 0; a < nn; a++) UNROLL
    for (int i = 0; i < nc; i++) {
      size_t k = c[a] * (size_t)nc + (size_t)i;
      ue[a * nc + i] = u[k], fe[a * nc + i] = 0;
    }
    const double *geo = b->geo + e * (size_t)b->nq * (size_t)st;
    if (p1 && el)
      elastic_p1(d, geo, ue, fe, s * mt->lam, s * mt->mu);
    else if (p1)
      diffusion_p1(d, geo, ue, fe, s * mt->cond);
    else if (el)
      elastic_elem(d, nn, b, geo, ue, fe, s * mt->lam, s * mt->mu);
    else
      diffusion_elem(d, nn, b, geo, ue, fe, s * mt->cond);
    UNROLL
    for (int a = 0; a < nn; a++) UNROLL
    for (int i = 0; i < nc; i++) y[c[a] * nc + i] += fe[a * nc + i];
  }
}

/* Four linear tets at once, one per lane of a vector (GCC's and Clang's
 * vector extension: SSE2 pairs on any x86-64, AVX2 where the processor has
 * it, target_clones below): elastic_p1 (d = 3) with the same operations
 * in the same order in every lane, so each element's forces are bitwise
 * the scalar kernel's, and they are added into y element by element in
 * the same order. The element's arithmetic, about 150 flops for a dozen
 * gathered values, is what a product costs; four lanes share it. */
typedef double v4d __attribute__((vector_size(32)));

static inline ALWAYS_INLINE void elastic_p1_x4(const v4d *ji, v4d dv, const v4d *ue, v4d *fe, v4d lam, v4d mu) {
  const v4d zero = {0, 0, 0, 0};
  v4d fr[3][3], f[3][3], s[3][3], tr = zero;
  UNROLL
  for (int i = 0; i < 3; i++) UNROLL
  for (int j = 0; j < 3; j++) fr[i][j] = ue[(j + 1) * 3 + i] - ue[i];
  UNROLL
  for (int i = 0; i < 3; i++) UNROLL
  for (int m = 0; m < 3; m++) {
    f[i][m] = zero;
    UNROLL
    for (int j = 0; j < 3; j++) f[i][m] += fr[i][j] * ji[j * 3 + m];
  }
  UNROLL
  for (int i = 0; i < 3; i++) tr += f[i][i];
  UNROLL
  for (int i = 0; i < 3; i++) UNROLL
  for (int m = 0; m < 3; m++) s[i][m] = mu * (f[i][m] + f[m][i]) + (i == m ? lam * tr : zero);
  UNROLL
  for (int i = 0; i < 3; i++) {
    v4d sum = zero;
    UNROLL
    for (int j = 0; j < 3; j++) {
      v4d pij = zero;
      UNROLL
      for (int m = 0; m < 3; m++) pij += s[i][m] * ji[j * 3 + m];
      fe[(j + 1) * 3 + i] = pij * dv, sum += pij;
    }
    fe[i] = -sum * dv;
  }
}

/* Four scalars as one vector, built in registers (a vector loaded from
 * four scalars just stored would wait for the stores to drain). */
#define LANES(a, b, c, d) ((v4d){(a), (b), (c), (d)})

/* Elements [e, e + 4) of a 3D linear tet block with 32-bit connectivity. */
static inline ALWAYS_INLINE void tets_x4(const dtm_operator *op, const op_block *b, size_t e, const double *u,
                                         double *y, int which) {
  v4d ji[9] = {{0}}, ue[12] = {{0}}, fe[12]; /* zeroed: GCC 12 takes the lanes filled below for read first */
  double sc[4], lam[4], mu[4];
  const uint32_t *c = b->c32 + e * 4;
  const double *g = b->geo + e * 10;
  UNROLL
  for (int l = 0; l < 4; l++) {
    const op_mat *mt = &op->mats[slot_of(b, e + (size_t)l)];
    sc[l] = which == APPLY_BETA ? mt->beta : 1;
    lam[l] = sc[l] * mt->lam, mu[l] = sc[l] * mt->mu;
  }
  UNROLL
  for (int k = 0; k < 9; k++) ji[k] = LANES(g[k], g[10 + k], g[20 + k], g[30 + k]);
  UNROLL
  for (int a = 0; a < 4; a++) UNROLL
  for (int i = 0; i < 3; i++)
    ue[a * 3 + i] = LANES(u[c[a] * 3 + i], u[c[4 + a] * 3 + i], u[c[8 + a] * 3 + i], u[c[12 + a] * 3 + i]);
  elastic_p1_x4(ji, LANES(g[9], g[19], g[29], g[39]), ue, fe, LANES(lam[0], lam[1], lam[2], lam[3]),
                LANES(mu[0], mu[1], mu[2], mu[3]));
  UNROLL
  for (int l = 0; l < 4; l++) {
    if (sc[l] == 0) continue;
    UNROLL
    for (int a = 0; a < 4; a++) UNROLL
    for (int i = 0; i < 3; i++) y[c[4 * l + a] * 3 + i] += fe[a * 3 + i][l];
  }
}

#define RANGE(d, el, nn) block_range(op, b, e0, e1, u, y, which, d, el, nn, 1, 0)
#define RANGE_WIDE(d, el) block_range(op, b, e0, e1, u, y, which, d, el, 0, 0, 0)
/* A linear simplex (b->p1) of dimension d, 32- or 64-bit connectivity
 * (the same arithmetic either way). */
#define RANGE_P1(d, el) block_range(op, b, e0, e1, u, y, which, d, el, d + 1, 1, 1)
#define RANGE_WIDE_P1(d, el) block_range(op, b, e0, e1, u, y, which, d, el, d + 1, 0, 1)

/* Linear simplices (b->p1), with either connectivity width: the same
 * arithmetic, so a product does not depend on the width. */
#define P1_BLOCK(el)                                                                                                   \
  do {                                                                                                                 \
    if (op->d == 3)                                                                                                    \
      b->c32 ? RANGE_P1(3, el) : RANGE_WIDE_P1(3, el);                                                                 \
    else if (op->d == 2)                                                                                               \
      b->c32 ? RANGE_P1(2, el) : RANGE_WIDE_P1(2, el);                                                                 \
    else                                                                                                               \
      b->c32 ? RANGE_P1(1, el) : RANGE_WIDE_P1(1, el);                                                                 \
  } while (0)

/* The other types: 64-bit connectivity in generic loops, 32-bit
 * specialised for the node counts of the linear quadrilateral and hex. */
#define OTHER_BLOCK(el)                                                                                                \
  do {                                                                                                                 \
    int key = b->c32 ? op->d * 100 + b->nn : 0;                                                                        \
    if (key == 204)                                                                                                    \
      RANGE(2, el, 4);                                                                                                 \
    else if (key == 308)                                                                                               \
      RANGE(3, el, 8);                                                                                                 \
    else if (op->d == 3)                                                                                               \
      b->c32 ? RANGE(3, el, 0) : RANGE_WIDE(3, el);                                                                    \
    else if (op->d == 2)                                                                                               \
      b->c32 ? RANGE(2, el, 0) : RANGE_WIDE(2, el);                                                                    \
    else                                                                                                               \
      b->c32 ? RANGE(1, el, 0) : RANGE_WIDE(1, el);                                                                    \
  } while (0)

/* A 3D linear tet block with 32-bit connectivity: four at a time, then
 * the rest one by one. */
__attribute__((target_clones("avx2", "default"))) static void
tet_block(const dtm_operator *op, const op_block *b, size_t e0, size_t e1, const double *u, double *y, int which) {
  size_t e = e0;
  for (; e + 4 <= e1; e += 4) tets_x4(op, b, e, u, y, which);
  e0 = e;
  RANGE_P1(3, 1);
}

static void elastic_block(const dtm_operator *op, const op_block *b, size_t e0, size_t e1, const double *u, double *y,
                          int which) {
  if (b->p1 && op->d == 3 && b->nn == 4 && b->c32)
    tet_block(op, b, e0, e1, u, y, which);
  else if (b->p1)
    P1_BLOCK(1);
  else
    OTHER_BLOCK(1);
}

static void diffusion_block(const dtm_operator *op, const op_block *b, size_t e0, size_t e1, const double *u, double *y,
                            int which) {
  if (b->p1)
    P1_BLOCK(0);
  else
    OTHER_BLOCK(0);
}

/* Add K_e u (scaled by beta_e for APPLY_BETA) of elements [e0, e1) of a
 * block that stores their matrices: the packed upper triangle, each entry
 * used for its row and, off the diagonal, for its column. */
static void stored_range(const dtm_operator *op, const op_block *b, size_t e0, size_t e1, const double *u, double *y,
                         int which) {
  const int ne = b->ne, nc = op->ncomp, nn = b->nn;
  double ue[DTM_K_DOF], fe[DTM_K_DOF];
  for (size_t e = e0; e < e1; e++) {
    double s = which == APPLY_BETA ? op->mats[slot_of(b, e)].beta : 1;
    const double *k = b->kel + e * (size_t)b->npk;
    size_t c[DTM_K_NODES];
    if (s == 0) continue;
    for (int a = 0; a < nn; a++)
      c[a] = b->c32 ? b->c32[e * (size_t)nn + (size_t)a] : b->conn[e * (size_t)nn + (size_t)a];
    for (int a = 0; a < nn; a++)
      for (int i = 0; i < nc; i++) ue[a * nc + i] = u[c[a] * (size_t)nc + (size_t)i], fe[a * nc + i] = 0;
    for (int r = 0; r < ne; r++) { /* row r: its ne - r entries from the diagonal on */
      double acc = k[0] * ue[r], ur = ue[r];
      for (int q = r + 1; q < ne; q++) acc += k[q - r] * ue[q], fe[q] += k[q - r] * ur;
      fe[r] += acc;
      k += ne - r;
    }
    for (int a = 0; a < nn; a++)
      for (int i = 0; i < nc; i++) y[c[a] * (size_t)nc + (size_t)i] += s * fe[a * nc + i];
  }
}

static void block_apply(const dtm_operator *op, const op_block *b, size_t e0, size_t e1, const double *u, double *y,
                        int which) {
  if (b->kel)
    stored_range(op, b, e0, e1, u, y, which);
  else if (b->manifold)
    manifold_range(op, b, e0, e1, u, y, which);
  else if (op->kind == DTM_OP_ELASTIC)
    elastic_block(op, b, e0, e1, u, y, which);
  else
    diffusion_block(op, b, e0, e1, u, y, which);
}

/* ---- parallel product ------------------------------------------------ */

static int thread_id(void) {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

static int team_size(void) {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

/* How many threads pay off: work (element points x nodes) of about 80000,
 * some 20000 tets, per thread at least. */
static int threads_for(const dtm_operator *op) {
  size_t w = 0;
  for (int ib = 0; ib < op->nblocks; ib++)
    w += op->blocks[ib].n * (size_t)op->blocks[ib].nq * (size_t)op->blocks[ib].nn;
#ifdef _OPENMP
  size_t t = w / 80000 + 1, mx = (size_t)omp_get_max_threads();
  return (int)(t < mx ? t : mx);
#else
  (void)w;
  return 1;
#endif
}

/* Share t of nt: its range [e0, e1) of block b's elements. */
static void share_range(const op_block *b, int t, int nt, size_t *e0, size_t *e1) {
  *e0 = b->n * (size_t)t / (size_t)nt, *e1 = b->n * (size_t)(t + 1) / (size_t)nt;
}

/* Share t of nt: its part of every block into yt. */
static void share(const dtm_operator *op, int t, int nt, const double *u, double *yt, int which) {
  for (int ib = 0; ib < op->nblocks; ib++) {
    const op_block *b = &op->blocks[ib];
    size_t e0, e1;
    share_range(b, t, nt, &e0, &e1);
    block_apply(op, b, e0, e1, u, yt, which);
  }
}

/* The dof range [lo, hi) the elements of share t touch. With the mesh in
 * locality order (dtm_mesh_reorder) it is a slice of about ndof / nt. */
static void share_extent(const dtm_operator *op, int t, op_share *sh) {
  size_t nc = (size_t)op->ncomp;
  sh->lo = op->ndof, sh->hi = 0;
  for (int ib = 0; ib < op->nblocks; ib++) {
    const op_block *b = &op->blocks[ib];
    size_t e0, e1, nn = (size_t)b->nn;
    share_range(b, t, op->nshares, &e0, &e1);
    for (size_t k = e0 * nn; k < e1 * nn; k++) {
      size_t v = b->conn[k] * nc;
      sh->lo = v < sh->lo ? v : sh->lo, sh->hi = v + nc > sh->hi ? v + nc : sh->hi;
    }
  }
  if (sh->lo > sh->hi) sh->lo = sh->hi = 0;
}

/* The shares and their buffers, once: share s > 0 accumulates into
 * buf + (s - 1) ndof, of which it only touches its own range (the rest is
 * never written, so never backed by memory). */
static int shares_setup(dtm_operator *op) {
  op->nshares = threads_for(op);
  op->share = calloc((size_t)op->nshares, sizeof *op->share);
  if (op->nshares > 1) op->buf = malloc((size_t)(op->nshares - 1) * op->ndof * sizeof *op->buf);
  if (!op->share || (op->nshares > 1 && !op->buf)) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int t = 0; t < op->nshares; t++) share_extent(op, t, &op->share[t]);
  return DTM_OK;
}

/* y = sum_e s_e K_e u, or with dsq (M^-1/2) y = D K D u, D = diag(dsq):
 * then D u is formed once per dof (op->scaled), not at every element's
 * gather, and y scaled where it is summed, each thread over its own range
 * of dofs (the same products as scaling before and after). Shares are
 * summed in a fixed order, so the result does not depend on scheduling. */
static void apply_k(const dtm_operator *op, const double *u, double *y, int which, const double *dsq) {
  int ns = op->nshares, late = dsq && op->st.n; /* shells and beams add after the region: scale y after them */
  size_t n = op->ndof;
  const double *x = dsq ? op->scaled : u;
#pragma omp parallel num_threads(ns) if (ns > 1)
  {
    int t = thread_id(), tn = team_size();
    size_t k0 = n * (size_t)t / (size_t)tn, k1 = n * (size_t)(t + 1) / (size_t)tn;
    for (size_t k = k0; dsq && k < k1; k++) op->scaled[k] = u[k] * dsq[k];
#pragma omp barrier
    for (int s = t; s < ns; s += tn) {
      const op_share *sh = &op->share[s];
      double *ys = s ? op->buf + (size_t)(s - 1) * n : y;
      if (s)
        memset(ys + sh->lo, 0, (sh->hi - sh->lo) * sizeof *ys);
      else
        memset(y, 0, n * sizeof *y);
      share(op, s, ns, x, ys, which);
    }
#pragma omp barrier
    for (int s = 1; s < ns; s++) {
      const op_share *sh = &op->share[s];
      const double *bs = op->buf + (size_t)(s - 1) * n;
      for (size_t k = k0 > sh->lo ? k0 : sh->lo; k < k1 && k < sh->hi; k++) y[k] += bs[k];
    }
    for (size_t k = k0; dsq && !late && k < k1; k++) y[k] *= dsq[k];
  }
  if (op->st.n) dtm_op_struct_apply(&op->st, x, which == APPLY_BETA ? op->slot_beta : NULL, y);
  for (size_t k = 0; late && k < n; k++) y[k] *= dsq[k];
}

void dtm_operator_apply(const dtm_operator *op, const double *u, double *y) { apply_k(op, u, y, APPLY_K, NULL); }

void dtm_operator_apply_sym(const dtm_operator *op, const double *x, double *y) { apply_k(op, x, y, APPLY_K, op->dsq); }

void dtm_operator_apply_damping(const dtm_operator *op, const double *v, double *y) {
  if (op->has_beta)
    apply_k(op, v, y, APPLY_BETA, NULL);
  else
    memset(y, 0, op->ndof * sizeof *y);
  for (size_t k = 0; op->mass_alpha && k < op->ndof; k++) y[k] += op->mass_alpha[k] * v[k];
}

/* ---- the node graph (certify.c) -------------------------------------- */

/* Node lists of the elements incident to each node: eptr[nnodes + 1] into
 * elist (block index << 40 | element), built by counting. */
static int incidence(const dtm_operator *op, size_t nnodes, size_t **eptr, uint64_t **elist) {
  size_t *p = calloc(nnodes + 2, sizeof *p), tot = 0;
  if (!p) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int ib = 0; ib < op->nblocks; ib++)
    for (size_t k = 0; k < op->blocks[ib].n * (size_t)op->blocks[ib].nn; k++) p[op->blocks[ib].conn[k] + 2]++, tot++;
  for (size_t v = 0; v < nnodes; v++) p[v + 2] += p[v + 1];
  uint64_t *l = malloc((tot + 1) * sizeof *l);
  if (!l) return free(p), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int ib = 0; ib < op->nblocks; ib++) {
    const op_block *b = &op->blocks[ib];
    for (size_t e = 0; e < b->n; e++)
      for (int a = 0; a < b->nn; a++) l[p[b->conn[e * (size_t)b->nn + a] + 1]++] = (uint64_t)ib << 40 | e;
  }
  *eptr = p, *elist = l;
  return DTM_OK;
}

size_t dtm_operator_node_graph_floor(const dtm_operator *op) {
  if (op->st.n || op->ndof % (size_t)op->ncomp) return 0;
  size_t nn = op->ndof / (size_t)op->ncomp, used = 0, tets = 0;
  int least = INT_MAX, all_tets = op->d == 3;
  unsigned char *seen = calloc(nn + 1, 1);
  if (!seen) return 0;
  for (int ib = 0; ib < op->nblocks; ib++) {
    const op_block *b = &op->blocks[ib];
    if (b->n) least = b->nn < least ? b->nn : least;
    if (b->n) all_tets &= b->p1 && b->nn == 4, tets += b->n;
    for (size_t k = 0; k < b->n * (size_t)b->nn; k++) used += !seen[b->conn[k]], seen[b->conn[k]] = 1;
  }
  free(seen);
  if (least == INT_MAX) return 0;
  return all_tets ? 3 * used + 2 * tets : used * (size_t)least;
}

int dtm_operator_node_graph(const dtm_operator *op, size_t *nnodes, size_t **xadj, size_t **adj) {
  *xadj = NULL, *adj = NULL;
  if (op->st.n || op->ndof % (size_t)op->ncomp)
    return DTM_ERR(DTM_ERR_INPUT, "the node graph of an operator with shells or beams is not built");
  size_t nn = op->ndof / (size_t)op->ncomp, *ep = NULL, cap = 0, cnt = 0;
  uint64_t *el = NULL;
  DTM_CHECK(incidence(op, nn, &ep, &el));
  size_t *x = malloc((nn + 1) * sizeof *x), *mark = malloc((nn + 1) * sizeof *mark), *ad = NULL;
  int r = x && mark ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < nn && r == DTM_OK; v++) mark[v] = SIZE_MAX;
  for (size_t v = 0; v < nn && r == DTM_OK; v++) {
    x[v] = cnt;
    for (size_t q = ep[v]; q < ep[v + 1] && r == DTM_OK; q++) {
      const op_block *b = &op->blocks[el[q] >> 40];
      const size_t *c = b->conn + (size_t)(el[q] & ((1ULL << 40) - 1)) * (size_t)b->nn;
      for (int a = 0; a < b->nn && r == DTM_OK; a++) {
        if (mark[c[a]] == v) continue;
        if (cnt == cap) {
          size_t *t = realloc(ad, (cap = 2 * cap + 1024) * sizeof *t);
          if (!t)
            r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
          else
            ad = t;
        }
        if (r == DTM_OK) mark[c[a]] = v, ad[cnt++] = c[a];
      }
    }
  }
  if (x) x[nn] = cnt;
  free(ep), free(el), free(mark);
  if (r) return free(x), free(ad), r;
  *nnodes = nn, *xadj = x, *adj = ad;
  return DTM_OK;
}

/* ---- the elements and their lumped masses (sms.c) -------------------- */

int dtm_operator_each_element(const dtm_operator *op, const dtm_mesh *m, const unsigned char *const *level,
                              dtm_operator_elem_fn fn, void *user) {
  if (op->st.n) return DTM_ERR(DTM_ERR_INPUT, "selective mass scaling: shells and beams are not supported");
  double w[DTM_K_NODES];
  for (int ib = 0; ib < op->nblocks; ib++) {
    const op_block *b = &op->blocks[ib];
    for (size_t e = 0; e < b->n; e++) {
      if (elem_lumped(level, m, b, e, w)) return DTM_ERR(DTM_ERR_INPUT, "an element has a non-positive lumped mass");
      double cap = op->mats[slot_of(b, e)].cap;
      for (int a = 0; a < b->nn; a++) w[a] *= cap;
      int r = fn(user, b->mbi, b->orig ? b->orig[e] : e, b->nn, b->conn + e * (size_t)b->nn, w);
      if (r) return r;
    }
  }
  return DTM_OK;
}
