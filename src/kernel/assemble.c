/* Element matrices of the generic path, built by quadrature in the
 * element's own frame: the lumped mass (lump.c: row sums integral(N_a)
 * for linear types, HRZ for second-order ones), the
 * scalar Laplacian K_ab = integral(grad N_a . grad N_b) and the isotropic
 * elastic stiffness K_(a i)(b j) = integral(lam g_ai g_bj + mu g_aj g_bi +
 * mu delta_ij g_a . g_b). Used by every non-simplex element and, for
 * cross-checking, by the simplices. Matrices are dense, row-major, on the
 * caller's stack: n <= DTM_K_DOF (81 for hex27: a 52 kB stiffness). */
#if defined(__GNUC__) && !defined(__clang__)
/* Let GCC vectorise the loops with a varying trip count (axpy updates of
 * the element matrices): -O2's very-cheap cost model leaves them scalar.
 * Lanes are independent, so every sum is rounded as before. */
#pragma GCC optimize("vect-cost-model=dynamic")
#endif
#include <math.h>
#include <string.h>

#include "dtmap/error.h"
#include "kernel-impl.h"
#include "assemble-impl.h"

int dtm_elem_setup(int type, const double *x, int model, dtm_elem_geom *eg) {
  if (!dtm_elem_topology(type)) return -1;
  dtm_elem_info(type, &eg->d, &eg->nn);
  eg->type = type;
  eg->bad = -1;
  eg->bad_det = 0;
  eg->level = 0, eg->settled = 1;
  if (dtm_elem_local(type, x, eg->xl)) return -1;
  eg->level = dtm_elem_rule_choose(type, eg->d, eg->nn, (const double(*)[3])eg->xl, model, &eg->q, &eg->settled);
  const dtm_ref_table *t = dtm_ref_level_table(type, eg->level);
  eg->bad = t ? dtm_map_first_bad_table(eg->d, eg->nn, (const double(*)[3])eg->xl, t, &eg->bad_det)
              : dtm_map_first_bad(type, eg->d, eg->nn, (const double(*)[3])eg->xl, &eg->q, &eg->bad_det);
  return eg->bad < 0 ? 0 : -1;
}

int dtm_elem_prepare(int type, const double *x, int model, dtm_elem_geom *eg) {
  DTM_CHECK(dtm_elem_info(type, NULL, NULL));
  if (!dtm_elem_setup(type, x, model, eg)) return DTM_OK;
  if (eg->bad < 0)
    return DTM_ERR(DTM_ERR_INPUT, "degenerate or inverted %s element: its nodes span no %s", dtm_elem_name(type),
                   eg->d == 1 ? "line" : "plane");
  return DTM_ERR(DTM_ERR_INPUT, "degenerate or inverted %s element: Jacobian determinant %g at integration point %d",
                 dtm_elem_name(type), eg->bad_det, eg->bad);
}

/* Calls visit(ctx, N, g, dv) at every quadrature point (a levelled rule's
 * shape functions from its table). */
static void each_point(const dtm_elem_geom *eg,
                       void (*visit)(void *, const dtm_elem_geom *, const double *, const double (*)[3], double),
                       void *ctx) {
  double N[DTM_K_NODES], g[DTM_K_NODES][3], dv;
  const dtm_ref_table *t = dtm_ref_level_table(eg->type, eg->level);
  for (int k = 0; k < eg->q.n; k++) {
    if (t)
      dtm_map_eval_dn(eg->d, eg->nn, (const double(*)[3])eg->xl, (const double(*)[3])t->dN[k], eg->q.w[k], g, &dv);
    else
      dtm_map_eval(eg->type, eg->d, eg->nn, (const double(*)[3])eg->xl, eg->q.p[k], eg->q.w[k], N, g, &dv);
    visit(ctx, eg, t ? t->N[k] : N, (const double(*)[3])g, dv);
  }
}

static double dot(int d, const double *a, const double *b) {
  double s = 0;
  for (int i = 0; i < d; i++) s += a[i] * b[i];
  return s;
}

static void add_laplace(void *ctx, const dtm_elem_geom *eg, const double *N, const double (*g)[3], double dv) {
  double *K = ctx;
  (void)N;
  for (int a = 0; a < eg->nn; a++)
    for (int b = 0; b < eg->nn; b++) K[a * eg->nn + b] += dot(eg->d, g[a], g[b]) * dv;
}

typedef struct {
  double lam, mu; /* Lame parameters seen by the element (bar: E, 0) */
  double *K;      /* [nn*d][nn*d] */
} elastic_ctx;

static void add_elastic(void *ctx, const dtm_elem_geom *eg, const double *N, const double (*g)[3], double dv) {
  elastic_ctx *c = ctx;
  int d = eg->d, n = eg->nn * d;
  (void)N;
  for (int a = 0; a < eg->nn; a++)
    for (int b = 0; b < eg->nn; b++) {
      double gg = c->mu * dot(d, g[a], g[b]);
      for (int i = 0; i < d; i++)
        for (int j = 0; j < d; j++)
          c->K[(a * d + i) * n + b * d + j] +=
              dv * (c->lam * g[a][i] * g[b][j] + c->mu * g[a][j] * g[b][i] + (i == j ? gg : 0));
    }
}

/* The same for second-order types, faster: only the blocks b >= a, with
 * dv folded into the moduli (so the rounding differs from add_elastic's
 * in the last bits, which is why the linear types keep add_elastic);
 * dtm_elem_stiffness mirrors the rest. g[a][i] is 0 for i >= d. */
static void add_elastic_sym(void *ctx, const dtm_elem_geom *eg, const double *N, const double (*g)[3], double dv) {
  elastic_ctx *c = ctx;
  int d = eg->d, n = eg->nn * d;
  double lam = c->lam * dv, mu = c->mu * dv;
  (void)N;
  for (int a = 0; a < eg->nn; a++) {
    double la[3], ma[3];
    for (int i = 0; i < 3; i++) la[i] = lam * g[a][i], ma[i] = mu * g[a][i];
    for (int b = a; b < eg->nn; b++) {
      const double *gb = g[b];
      double gg = ma[0] * gb[0] + ma[1] * gb[1] + ma[2] * gb[2];
      double *Kab = c->K + a * d * n + b * d;
      for (int i = 0; i < d; i++) {
        double *row = Kab + i * n;
        for (int j = 0; j < d; j++) row[j] += la[i] * gb[j] + ma[j] * gb[i];
        row[i] += gg;
      }
    }
  }
}

/* Make the nn x nn block matrix K (blocks d x d) exactly symmetric from
 * its blocks b >= a: the upper triangle of K is copied to the lower one
 * (the diagonal blocks were summed in full, but with roundings that
 * differ between (i, j) and (j, i)). */
static void mirror(int nn, int d, double *K) {
  int n = nn * d;
  for (int r = 0; r < n; r++)
    for (int c = r + 1; c < n; c++) K[c * n + r] = K[r * n + c];
}

void dtm_elem_mass(const dtm_elem_geom *eg, double *m) {
  dtm_lumped_mass(eg->type, eg->d, eg->nn, (const double(*)[3])eg->xl, &eg->q, m);
}

void dtm_elem_laplace(const dtm_elem_geom *eg, double *K) {
  memset(K, 0, sizeof(double) * (size_t)(eg->nn * eg->nn));
  each_point(eg, add_laplace, K);
}

void dtm_elem_stiffness(const dtm_elem_geom *eg, const dtm_elastic_moduli *m, double *K) {
  int n = eg->nn * eg->d;
  elastic_ctx c = {m->lam, m->mu, K};
  if (eg->d == 1) c.lam = m->modulus, c.mu = 0; /* axial stiffness only */
  memset(K, 0, sizeof(double) * (size_t)(n * n));
  if (dtm_elem_parent(eg->type) == eg->type) {
    each_point(eg, add_elastic, &c);
    return;
  }
  each_point(eg, add_elastic_sym, &c);
  mirror(eg->nn, eg->d, K);
}

/* Static, so that the clones' resolver stays inside the library (GCC
 * gives a global target_clones function a resolver symbol of default
 * visibility, which libdtmap would then export: t001). */
static DTM_KERNEL_AVX void gram_add(int nd, const double *gl, double dv, double *U) {
  for (int x = 0; x < nd; x++) {
    double gx = gl[x] * dv, *row = U + x * nd;
    for (int y = x; y < nd; y++) row[y] += gx * gl[y];
  }
}

/* gram_add of four points, one pass over U. */
static DTM_KERNEL_AVX void gram_add4(int nd, const double (*gl)[DTM_K_DOF], const double *dv, double *U) {
  const double *g0 = gl[0], *g1 = gl[1], *g2 = gl[2], *g3 = gl[3];
  for (int x = 0; x < nd; x++) {
    double a0 = g0[x] * dv[0], a1 = g1[x] * dv[1], a2 = g2[x] * dv[2], a3 = g3[x] * dv[3], *row = U + x * nd;
    for (int y = x; y < nd; y++) {
      double r = row[y];
      r += a0 * g0[y];
      r += a1 * g1[y];
      r += a2 * g2[y];
      r += a3 * g3[y];
      row[y] = r;
    }
  }
}

void dtm_elem_gram_add_points(int nd, int np, const double (*gl)[DTM_K_DOF], const double *dv, double *U) {
  if (np == 4) {
    gram_add4(nd, gl, dv, U);
    return;
  }
  for (int p = 0; p < np; p++) gram_add(nd, gl[p], dv[p], U);
}

/* Tiles of 4 rows from the diagonal rightwards, 8 columns wide but for a
 * last one of at most 4 (tet10: 576 entries for the 465 of its
 * triangle), each a chain of np multiplications and additions per entry
 * in named vector registers (GCC keeps an array of accumulators in
 * memory). */
#define TILE_ROW(r, c0, c1)                                                                                            \
  do {                                                                                                                 \
    double a_ = A[p][x0 + (r)];                                                                                        \
    c0 += a_ * g0;                                                                                                     \
    c1 += a_ * g1;                                                                                                     \
  } while (0)
static inline __attribute__((always_inline)) void
tile8(int np, const double (*A)[DTM_GRAM_W], const double (*gb)[DTM_GRAM_W], double (*Ul)[DTM_GRAM_W], int x0, int y0) {
  dtm_v4d *u0 = (dtm_v4d *)&Ul[x0][y0], *u1 = (dtm_v4d *)&Ul[x0 + 1][y0], *u2 = (dtm_v4d *)&Ul[x0 + 2][y0],
          *u3 = (dtm_v4d *)&Ul[x0 + 3][y0];
  dtm_v4d c00 = u0[0], c01 = u0[1], c10 = u1[0], c11 = u1[1], c20 = u2[0], c21 = u2[1], c30 = u3[0], c31 = u3[1];
  for (int p = 0; p < np; p++) {
    dtm_v4d g0 = *(const dtm_v4d *)&gb[p][y0], g1 = *(const dtm_v4d *)&gb[p][y0 + 4];
    TILE_ROW(0, c00, c01);
    TILE_ROW(1, c10, c11);
    TILE_ROW(2, c20, c21);
    TILE_ROW(3, c30, c31);
  }
  u0[0] = c00, u0[1] = c01, u1[0] = c10, u1[1] = c11, u2[0] = c20, u2[1] = c21, u3[0] = c30, u3[1] = c31;
}
#undef TILE_ROW

static inline __attribute__((always_inline)) void
tile4(int np, const double (*A)[DTM_GRAM_W], const double (*gb)[DTM_GRAM_W], double (*Ul)[DTM_GRAM_W], int x0, int y0) {
  dtm_v4d *u0 = (dtm_v4d *)&Ul[x0][y0], *u1 = (dtm_v4d *)&Ul[x0 + 1][y0], *u2 = (dtm_v4d *)&Ul[x0 + 2][y0],
          *u3 = (dtm_v4d *)&Ul[x0 + 3][y0];
  dtm_v4d c0 = *u0, c1 = *u1, c2 = *u2, c3 = *u3;
  for (int p = 0; p < np; p++) {
    dtm_v4d g0 = *(const dtm_v4d *)&gb[p][y0];
    c0 += A[p][x0] * g0;
    c1 += A[p][x0 + 1] * g0;
    c2 += A[p][x0 + 2] * g0;
    c3 += A[p][x0 + 3] * g0;
  }
  *u0 = c0, *u1 = c1, *u2 = c2, *u3 = c3;
}

static DTM_KERNEL_AVX void gram_tiles(int nd, int np, const double (*gb)[DTM_GRAM_W], const double *dv,
                                      double (*Ul)[DTM_GRAM_W]) {
  _Alignas(32) double A[DTM_GRAM_W][DTM_GRAM_W]; /* A[p][x] = gb[p][x] dv[p], as gram_add forms it */
  for (int p = 0; p < np; p++)
    for (int x = 0; x < DTM_GRAM_W; x++) A[p][x] = gb[p][x] * dv[p];
  for (int x0 = 0; x0 < nd; x0 += 4)
    for (int y0 = x0; y0 < nd; y0 += 8) {
      if (nd - y0 > 4)
        tile8(np, (const double(*)[DTM_GRAM_W])A, gb, Ul, x0, y0);
      else
        tile4(np, (const double(*)[DTM_GRAM_W])A, gb, Ul, x0, y0);
    }
}

void dtm_elem_gram_block(int nd, int np, const double (*gb)[DTM_GRAM_W], const double *dv, double (*Ul)[DTM_GRAM_W]) {
  gram_tiles(nd, np, gb, dv, Ul);
}

void dtm_point_walk_start(dtm_point_walk *w, const dtm_ref_table *t, int d, int nn, const double (*xl)[3]) {
  w->t = t, w->d = d, w->nn = nn, w->xl = xl, w->bad4 = -1, w->held = 0;
  w->blocked = d == 3 && nn * d <= DTM_GRAM_W, w->bl = 0, w->ul = 0;
}

/* Point k's gradients g (dv) into the block; the block summed when full. */
/* Before the block's first point: Ul and the rows' padding cleared. */
static void block_open(dtm_point_walk *w, int nd) {
  if (w->ul) return;
  memset(w->Ul, 0, sizeof w->Ul), w->ul = 1;
  for (int p = 0; p < DTM_GRAM_W; p++)
    for (int x = nd; x < DTM_GRAM_W; x++) w->gb[p][x] = 0;
}

static void walk_block_add(dtm_point_walk *w, const double (*g)[3], double dv) {
  int nd = w->nn * w->d;
  block_open(w, nd);
  double *row = w->gb[w->bl];
  if ((const double *)g != row) memcpy(row, g, sizeof(double) * (size_t)nd); /* else the map wrote it there */
  w->dvb[w->bl++] = dv;
  if (w->bl == DTM_GRAM_W) gram_tiles(nd, w->bl, (const double(*)[DTM_GRAM_W])w->gb, w->dvb, w->Ul), w->bl = 0;
}

/* Whether point k is in a full group of four (3D). */
static int grouped(const dtm_point_walk *w, int k) { return w->d == 3 && k - k % 4 + 4 <= w->t->q.n; }

const double (*dtm_point_walk_at(dtm_point_walk *w, int k, double *dv, double *dj, int *valid))[3] {
  const dtm_ref_table *t = w->t;
  if (!grouped(w, k)) {
    *valid = !dtm_map_eval_valid(w->d, w->nn, w->xl, (const double(*)[3])t->dN[k], t->q.w[k], w->g, dv, dj);
    return (const double(*)[3])w->g;
  }
  if (k % 4 == 0) { /* the next four points' maps side by side, into the block's next rows where it sums */
    for (int l = 0; l < 4; l++) w->rows[l] = w->blocked && w->bl + 4 <= DTM_GRAM_W ? w->gb[w->bl + l] : &w->g4[l][0][0];
    w->bad4 =
        dtm_map_eval_valid4(w->nn, w->xl, (const dtm_v4d(*)[3])t->dN4[k / 4], &t->q.w[k], w->rows, w->dv4, w->dj4);
  }
  *dv = w->dv4[k % 4], *dj = w->dj4[k % 4], *valid = k % 4 != w->bad4;
  return (const double(*)[3])w->rows[k % 4];
}

void dtm_point_walk_gram(dtm_point_walk *w, int k, const double (*g)[3], double dv, double *U) {
  int nd = w->nn * w->d;
  if (w->blocked) {
    walk_block_add(w, g, dv);
    return;
  }
  if (grouped(w, k)) { /* the group's rows are already flat (d = 3) */
    if (k % 4 == 3) dtm_elem_gram_add_points(nd, 4, (const double(*)[DTM_K_DOF])w->g4, w->dv4, U);
    return;
  }
  for (int a = 0; a < w->nn; a++)
    for (int i = 0; i < w->d; i++) w->gl[w->held][a * w->d + i] = g[a][i];
  w->dvl[w->held++] = dv;
  if (w->held == 4) dtm_elem_gram_add_points(nd, 4, (const double(*)[DTM_K_DOF])w->gl, w->dvl, U), w->held = 0;
}

void dtm_point_walk_gram_end(dtm_point_walk *w, double *U) {
  if (w->blocked) {
    int nd = w->nn * w->d;
    if (!w->ul) return; /* no point */
    if (w->bl) gram_tiles(nd, w->bl, (const double(*)[DTM_GRAM_W])w->gb, w->dvb, w->Ul), w->bl = 0;
    for (int x = 0; x < nd; x++)
      for (int y = x; y < nd; y++) U[x * nd + y] += w->Ul[x][y];
    return;
  }
  if (w->held) dtm_elem_gram_add_points(w->nn * w->d, w->held, (const double(*)[DTM_K_DOF])w->gl, w->dvl, U);
  w->held = 0;
}

int dtm_point_walk_gram_all(dtm_point_walk *w, double *U, double *dv, double *dj) {
  const dtm_ref_table *t = w->t;
  int n = t->q.n, nd = w->nn * w->d, bad = -1, k = 0;
  if (w->blocked && n >= 4) { /* whole groups straight into the block's rows: what the walk does, without its calls */
    block_open(w, nd);
    for (; k + 4 <= n; k += 4) {
      double *rows[4] = {w->gb[w->bl], w->gb[w->bl + 1], w->gb[w->bl + 2], w->gb[w->bl + 3]}, d4[4];
      int b4 =
          dtm_map_eval_valid4(w->nn, w->xl, (const dtm_v4d(*)[3])t->dN4[k / 4], &t->q.w[k], rows, &w->dvb[w->bl], d4);
      memcpy(dv + k, &w->dvb[w->bl], sizeof d4);
      if (b4 >= 0 && bad < 0) bad = k + b4, *dj = d4[b4];
      if ((w->bl += 4) == DTM_GRAM_W)
        gram_tiles(nd, w->bl, (const double(*)[DTM_GRAM_W])w->gb, w->dvb, w->Ul), w->bl = 0;
    }
  }
  for (; k < n; k++) {
    int valid;
    double djk;
    const double(*gp)[3] = dtm_point_walk_at(w, k, &dv[k], &djk, &valid);
    if (!valid && bad < 0) bad = k, *dj = djk;
    dtm_point_walk_gram(w, k, gp, dv[k], U);
  }
  dtm_point_walk_gram_end(w, U);
  return bad;
}

/* The elastic stiffness from the Gram tensor U (upper triangle of
 * integral g_ai g_bj), in place: K_(ai)(bj) = lam U_(ai)(bj) +
 * mu U_(aj)(bi) + delta_ij mu sum_r U_(ar)(br), mirrored. */
static void stiffness_from_gram(int nn, int d, double lam, double mu, double *U, double *K) {
  int nd = nn * d;
#define UU(x, y) ((x) <= (y) ? U[(x)*nd + (y)] : U[(y)*nd + (x)])
  for (int a = 0; a < nn; a++)
    for (int b = a; b < nn; b++) {
      double tr = 0;
      for (int r = 0; r < d; r++) tr += UU(a * d + r, b * d + r);
      for (int i = 0; i < d; i++)
        for (int j = 0; j < d; j++) {
          int x = a * d + i, y = b * d + j;
          if (y < x) continue;
          K[x * nd + y] = lam * UU(x, y) + mu * UU(a * d + j, b * d + i) + (i == j ? mu * tr : 0);
        }
    }
#undef UU
  mirror(nn, d, K);
}

/* The lumped masses per unit density m[nn] (HRZ's N_a^2 dv where hrz,
 * else N_a dv) and the measure *vol of the points' dv, as
 * dtm_lumped_mass_table sums them, point after point from zero; up to 12
 * nodes in three vectors of accumulators kept in registers through the
 * points (the table's rows are zero beyond nn: ref_table.c), so the same
 * bits without a chain through memory at every point. */
static DTM_KERNEL_AVX void masses(const dtm_ref_table *t, int nn, int hrz, const double *dv, double *m, double *vol) {
  double v = 0;
  if (nn > 12) {
    for (int a = 0; a < nn; a++) m[a] = 0;
    for (int k = 0; k < t->q.n; k++) {
      for (int a = 0; a < nn; a++) m[a] += (hrz ? t->N[k][a] * t->N[k][a] : t->N[k][a]) * dv[k];
      v += dv[k];
    }
    *vol = v;
    return;
  }
  dtm_v4d a0 = {0, 0, 0, 0}, a1 = a0, a2 = a0, n0, n1, n2;
  for (int k = 0; k < t->q.n; k++) {
    memcpy(&n0, t->N[k], sizeof n0), memcpy(&n1, t->N[k] + 4, sizeof n1), memcpy(&n2, t->N[k] + 8, sizeof n2);
    if (hrz) n0 *= n0, n1 *= n1, n2 *= n2;
    a0 += n0 * dv[k], a1 += n1 * dv[k], a2 += n2 * dv[k];
    v += dv[k];
  }
  double s[12];
  memcpy(s, &a0, sizeof a0), memcpy(s + 4, &a1, sizeof a1), memcpy(s + 8, &a2, sizeof a2);
  for (int a = 0; a < nn; a++) m[a] = s[a];
  *vol = v;
}

void dtm_elem_masses(const dtm_ref_table *t, int nn, int hrz, const double *dv, double *m, double *vol) {
  masses(t, nn, hrz, dv, m, vol);
}

int dtm_elem_gram(int type, int d, int nn, const double (*xl)[3], const dtm_ref_table *t, double *U, double *mass,
                  double *dj) {
  int nd = nn * d;
  double dv[DTM_K_QP], vol;
  if (dtm_memo_get(type, t, nn, nd, xl, U, mass, &vol)) return -1; /* the level search just integrated it */
  memset(U, 0, sizeof(double) * (size_t)(nd * nd));
  dtm_point_walk w;
  dtm_point_walk_start(&w, t, d, nn, xl);
  int bad = dtm_point_walk_gram_all(&w, U, dv, dj);
  if (bad >= 0) return bad;
  dtm_elem_masses(t, nn, 1, dv, mass, &vol);
  dtm_lumped_finish(type, nn, t->q.n, vol, mass);
  return -1;
}

int dtm_elem_assemble(int type, int d, int nn, const double (*xl)[3], const dtm_ref_table *t,
                      const dtm_elastic_moduli *m, double *K, double *mass, double *dj) {
  dtm_elem_geom eg; /* only type, d and nn: what the visitors read */
  double dv, vol = 0;
  int n = m ? nn * d : nn, hrz = dtm_elem_parent(type) != type;
  elastic_ctx c = {0, 0, K};
  void (*add)(void *, const dtm_elem_geom *, const double *, const double(*)[3], double) = add_laplace;
  if (m) {
    c.lam = d == 1 ? m->modulus : m->lam, c.mu = d == 1 ? 0 : m->mu;
    add = hrz ? add_elastic_sym : add_elastic;
  }
  if (m && hrz) {                    /* second-order elastic: the Gram tensor, half the products of add_elastic_sym */
    double U[DTM_K_DOF * DTM_K_DOF]; /* 52 kB on the stack at most, as K */
    int bad = dtm_elem_gram(type, d, nn, xl, t, U, mass, dj);
    if (bad < 0) stiffness_from_gram(nn, d, c.lam, c.mu, U, K);
    return bad;
  }
  eg.type = type, eg.d = d, eg.nn = nn;
  memset(K, 0, sizeof(double) * (size_t)(n * n));
  for (int a = 0; a < nn; a++) mass[a] = 0;
  dtm_point_walk w;
  dtm_point_walk_start(&w, t, d, nn, xl);
  for (int k = 0; k < t->q.n; k++) {
    int valid;
    const double(*gp)[3] = dtm_point_walk_at(&w, k, &dv, dj, &valid);
    if (!valid) return k;
    add(m ? (void *)&c : (void *)K, &eg, t->N[k], gp, dv);
    for (int a = 0; a < nn; a++) mass[a] += (hrz ? t->N[k][a] * t->N[k][a] : t->N[k][a]) * dv;
    vol += dv;
  }
  dtm_lumped_finish(type, nn, t->q.n, vol, mass);
  return -1;
}

double dtm_elem_gram_lane(int nn, double lam, double mu, const double *U, const double *r, int l, dtm_v4d *A) {
  enum { D = 3 };
  int nd = nn * D;
  double top[D][D] = {{0}}, z = 0; /* a maximum per entry of the blocks, not one chain through them all */
  for (int a = 0; a < nn; a++)
    for (int b = a; b < nn; b++) {
      /* stiffness_from_gram's entries (x, y) = (a d + i, b d + j), y >= x, its UU read without the test: in
       * block (a, b) the row of U_(aj)(bi) is a d + j <= b d + i but in block (a, a) below the diagonal
       * (j > i), where U_(aj)(ai) is U_(ai)(aj) */
      const double *Uab = U + a * D * nd + b * D;
      double tr = 0;
      for (int q = 0; q < D; q++) tr += Uab[q * nd + q];
#pragma GCC unroll 3
      for (int i = 0; i < D; i++)
#pragma GCC unroll 3
        for (int j = 0; j < D; j++) {
          if (a == b && j < i) continue;
          int x = a * D + i, y = b * D + j;
          double v = lam * Uab[i * nd + j] + mu * (a == b ? Uab[i * nd + j] : Uab[j * nd + i]) + (i == j ? mu * tr : 0);
          v *= r[x] * r[y]; /* lumped_scale */
          A[y * (y + 1) / 2 + x][l] = v;
          double av = fabs(v);
          top[i][j] = av > top[i][j] ? av : top[i][j], z += v * 0; /* z: NaN once an entry is not finite */
        }
    }
  double t = 0;
  for (int i = 0; i < D; i++)
    for (int j = 0; j < D; j++) t = top[i][j] > t ? top[i][j] : t;
  return z == 0 ? t : NAN;
}

int dtm_elem_matrix_at(int type, const double *x, int id, const dtm_elastic_moduli *m, double *K) {
  int d = 0, nn = 0;
  double xl[DTM_K_NODES][3], mass[DTM_K_NODES], dj = 0;
  const dtm_ref_table *t = dtm_ref_rule_table(type, id);
  if (!t || dtm_elem_info(type, &d, &nn) || d != 3 || dtm_elem_local(type, x, xl)) return -2;
  return dtm_elem_assemble(type, 3, nn, (const double(*)[3])xl, t, m, K, mass, &dj);
}
