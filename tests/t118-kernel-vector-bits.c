/* The vector paths of a curved element's integration give the scalar
 * paths' bits (src/kernel/map.c, assemble.c, ref_table.c):
 *   - the map at four points side by side (dtm_map_eval_valid4, from the
 *     table's lane-by-lane gradients dN4) against dtm_map_eval_valid at
 *     each point of every group of tet10's levelled tables 5 to 8, on
 *     curved elements and on one inverted near a node: gradients, dv, det J
 *     and the first lane that fails, all equal bit for bit; also on flat
 *     elements about the validity threshold, where the map at four points
 *     takes its shortcut or not;
 *   - det J alone (dtm_map_dv_dn4) against dtm_map_dv_dn, and det J with
 *     its Hadamard bound (dtm_map_det_dn4, the Bezier bound's root
 *     lattice) against dtm_map_det_dn;
 *   - the blocked Gram sum (dtm_elem_gram_block, register tiles over up
 *     to 32 points) against the plain loop that adds each point's product
 *     (g_x dv) g_y to each entry in the points' order, for nd from 1 to 32
 *     and 1 to 100 points over several blocks, with random gradients of
 *     very different sizes (so that a different order of additions would
 *     round differently: checked by summing in reverse);
 *   - a whole walk (dtm_point_walk over a levelled table, point by point
 *     and in one call, dtm_point_walk_gram_all, as the level search and the
 *     element assembly take it) against the scalar map and the plain loop
 *     at every point; in one call also over the full rule (groups of four
 *     and points alone) and on an element inverted in part (the first
 *     point that fails and its det J).
 * Tolerance: none, bitwise: each lane does the scalar operations in the
 * scalar order, and the tiles keep each entry's additions in order. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "assemble-impl.h"
#include "kernel-impl.h"

/* A tet10 with its mid-edge nodes moved by bend (curved) in its frame. */
static void curved_tet10(double bend, double phase, double (*xl)[3]) {
  double x[30];
  assert_int_equal(dtm_elem_regular(DTM_TET10, 1.0, x), DTM_OK);
  for (int a = 0; a < 10; a++) {
    double *p = x + 3 * a, y = p[1], z = p[2];
    p[0] += 0.3 * y + 0.1 * z + 1.5, p[1] += 0.2 * z - 0.7, p[2] += 2.0;
    if (a >= 4)
      p[0] += bend * sin(1.3 * a + phase), p[1] += bend * cos(0.7 * a + phase), p[2] += bend * sin(2.1 * a + 0.4);
  }
  assert_int_equal(dtm_elem_local(DTM_TET10, x, xl), 0);
}

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static double uniform(void) { /* in [0, 1) */
  rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
  return (double)(rng >> 11) / 9007199254740992.0;
}

/* The map at every full group of four points of table t, both ways;
 * returns how many groups had a lane that fails. */
static int compare_map(const dtm_ref_table *t, const double (*xl)[3]) {
  int failing = 0;
  for (int k = 0; k + 4 <= t->q.n; k += 4) {
    double g4[4][32], *rows[4] = {g4[0], g4[1], g4[2], g4[3]}, dv4[4], dj4[4], dvs[4], det4[4], had4[4];
    int bad = dtm_map_eval_valid4(10, xl, (const dtm_v4d(*)[3])t->dN4[k / 4], &t->q.w[k], rows, dv4, dj4);
    dtm_map_dv_dn4(10, xl, (const dtm_v4d(*)[3])t->dN4[k / 4], &t->q.w[k], dvs);
    dtm_map_det_dn4(10, xl, (const dtm_v4d(*)[3])t->dN4[k / 4], det4, had4);
    int first = -1;
    for (int l = 0; l < 4; l++) {
      double g[DTM_K_NODES][3], dv, dj, dv1;
      int r = dtm_map_eval_valid(3, 10, xl, (const double(*)[3])t->dN[k + l], t->q.w[k + l], g, &dv, &dj);
      if (r && first < 0) first = l;
      assert_memory_equal(&dv, &dv4[l], sizeof dv);
      assert_memory_equal(&dj, &dj4[l], sizeof dj);
      for (int a = 0; a < 10; a++) assert_memory_equal(g[a], &g4[l][3 * a], 3 * sizeof(double));
      dtm_map_dv_dn(3, 10, xl, (const double(*)[3])t->dN[k + l], t->q.w[k + l], &dv1);
      assert_memory_equal(&dv1, &dvs[l], sizeof dv1);
      double had, det = dtm_map_det_dn(3, 10, xl, (const double(*)[3])t->dN[k + l], &had);
      assert_memory_equal(&det, &det4[l], sizeof det);
      assert_memory_equal(&had, &had4[l], sizeof had);
    }
    assert_int_equal(bad, first);
    failing += bad >= 0;
  }
  return failing;
}

static void test_map_four_points(void **state) {
  (void)state;
  double xl[10][3];
  for (int level = 5; level <= DTM_K_LEVEL_MAX; level++) {
    const dtm_ref_table *t = dtm_ref_level_table(DTM_TET10, level);
    assert_non_null(t);
    for (int e = 0; e < 6; e++) {
      curved_tet10(0.02 + 0.03 * e, 0.5 * e, xl);
      assert_int_equal(compare_map(t, (const double(*)[3])xl), 0);
    }
    curved_tet10(0.9, 0.0, xl); /* inverted in part: some lanes fail */
    assert_true(compare_map(t, (const double(*)[3])xl) > 0);
  }
}

/* Near the validity threshold: flat tet10 whose det J at the points is
 * c 32 eps times the Hadamard bound, c from 0.3 to 9 (the corners' height
 * s; the mid-edge nodes moved by up to 0.4 s across, so that det J differs
 * from point to point and from lane to lane). The map at four points
 * skips the square roots where every lane clears the threshold by a
 * factor of 2: about c = 1 the scalar test decides, about c = 2 the
 * shortcut's own test; both are crossed, and every group's first failing
 * lane must be the scalar path's. Also scaled by 2^-170 and 2^170, where
 * the shortcut stands aside (its products would leave the normal range). */
static void test_map_threshold(void **state) {
  (void)state;
  static const double scales[] = {1, 0x1p-170, 0x1p170};
  static const double corner[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
  static const int edge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}}; /* Gmsh's tet10 order */
  int failing = 0, groups = 0;
  for (int sc = 0; sc < 3; sc++)
    for (double c = 0.3; c < 9; c *= 1.07) {
      double s = c * 32 * DBL_EPSILON * sqrt(0.5), xl[10][3];
      for (int a = 0; a < 10; a++)
        for (int i = 0; i < 3; i++) {
          double v = a < 4 ? corner[a][i] : 0.5 * (corner[edge[a - 4][0]][i] + corner[edge[a - 4][1]][i]);
          xl[a][i] = scales[sc] * (i == 2 ? s * (v + (a >= 4 ? 0.4 * sin(1.7 * a + c) : 0)) : v);
        }
      for (int level = 5; level <= DTM_K_LEVEL_MAX; level++) {
        const dtm_ref_table *t = dtm_ref_level_table(DTM_TET10, level);
        assert_non_null(t);
        failing += compare_map(t, (const double(*)[3])xl), groups += t->q.n / 4;
      }
    }
  assert_true(failing > 0 && failing < groups); /* both sides of the threshold were seen */
}

/* U += (g_x dv) g_y, point after point: the order the scalar path adds. */
static void plain_sum(int nd, int np, const double (*g)[DTM_GRAM_W], const double *dv, double *U, int reverse) {
  for (int q = 0; q < np; q++) {
    int p = reverse ? np - 1 - q : q;
    for (int x = 0; x < nd; x++) {
      double gx = g[p][x] * dv[p];
      for (int y = x; y < nd; y++) U[x * nd + y] += gx * g[p][y];
    }
  }
}

static void test_gram_block(void **state) {
  (void)state;
  static double g[100][DTM_GRAM_W], dv[100], U[32 * 32], R[32 * 32];
  static double Ul[DTM_GRAM_W][DTM_GRAM_W] __attribute__((aligned(32)));
  static double gb[DTM_GRAM_W][DTM_GRAM_W] __attribute__((aligned(32)));
  int order_shows = 0;
  for (int nd = 1; nd <= DTM_GRAM_W; nd++)
    for (int np = 1; np <= 100; np += nd % 3 ? 37 : 13) {
      for (int p = 0; p < np; p++) {
        for (int x = 0; x < DTM_GRAM_W; x++) g[p][x] = x < nd ? (uniform() - 0.5) * pow(10, 8 * uniform() - 4) : 0;
        dv[p] = uniform() * pow(10, 4 * uniform() - 2);
      }
      memset(Ul, 0, sizeof Ul);
      for (int p0 = 0; p0 < np; p0 += DTM_GRAM_W) { /* blocks of at most 32 points, as the walk hands them */
        int bl = np - p0 < DTM_GRAM_W ? np - p0 : DTM_GRAM_W;
        for (int p = 0; p < bl; p++) memcpy(gb[p], g[p0 + p], sizeof gb[p]);
        dtm_elem_gram_block(nd, bl, (const double(*)[DTM_GRAM_W])gb, dv + p0, Ul);
      }
      memset(U, 0, sizeof U), memset(R, 0, sizeof R);
      plain_sum(nd, np, (const double(*)[DTM_GRAM_W])g, dv, U, 0);
      for (int x = 0; x < nd; x++)
        for (int y = x; y < nd; y++) assert_memory_equal(&U[x * nd + y], &Ul[x][y], sizeof(double));
      plain_sum(nd, np, (const double(*)[DTM_GRAM_W])g, dv, R, 1);
      order_shows |= memcmp(U, R, sizeof U) != 0;
    }
  assert_true(order_shows); /* the data tell one order of additions from another */
}

/* A walk over tet10's levelled tables against the scalar map and the
 * plain sum at every point (the tail outside the groups included: 125 is
 * not a multiple of 4). */
/* dtm_point_walk_gram_all over table t against the scalar map and the
 * plain sum at every point (want: that sum, when the caller has it): U
 * and every dv bitwise, and the first point where det J is not safely
 * positive with its det J. */
static void whole_walk(const dtm_ref_table *t, const double (*xl)[3], const double *want) {
  static double U[30 * 30], R[30 * 30], dv[DTM_K_QP];
  static dtm_point_walk w;
  double dj = 0, dj_first = 0;
  int first = -1;
  memset(U, 0, sizeof U), memset(R, 0, sizeof R);
  dtm_point_walk_start(&w, t, 3, 10, xl);
  int bad = dtm_point_walk_gram_all(&w, U, dv, &dj);
  for (int k = 0; k < t->q.n; k++) {
    double g[DTM_K_NODES][3], dvs, djs, row[1][DTM_GRAM_W] = {{0}};
    if (dtm_map_eval_valid(3, 10, xl, (const double(*)[3])t->dN[k], t->q.w[k], g, &dvs, &djs) && first < 0)
      first = k, dj_first = djs;
    assert_memory_equal(&dv[k], &dvs, sizeof dvs);
    memcpy(row[0], g, 30 * sizeof(double));
    plain_sum(30, 1, (const double(*)[DTM_GRAM_W])row, &dvs, R, 0);
  }
  assert_int_equal(bad, first);
  if (first >= 0) assert_memory_equal(&dj, &dj_first, sizeof dj);
  assert_memory_equal(U, R, sizeof U);
  if (want) assert_memory_equal(U, want, sizeof U);
}

static void test_walk(void **state) {
  (void)state;
  double xl[10][3];
  for (int level = 5; level <= DTM_K_LEVEL_MAX; level++) {
    const dtm_ref_table *t = dtm_ref_level_table(DTM_TET10, level);
    curved_tet10(0.05, 1.0, xl);
    static double U[30 * 30], R[30 * 30];
    static dtm_point_walk w;
    memset(U, 0, sizeof U), memset(R, 0, sizeof R);
    dtm_point_walk_start(&w, t, 3, 10, (const double(*)[3])xl);
    for (int k = 0; k < t->q.n; k++) {
      double dv, dj, g[DTM_K_NODES][3], dvs, djs, row[1][DTM_GRAM_W] = {{0}};
      int valid;
      const double(*gp)[3] = dtm_point_walk_at(&w, k, &dv, &dj, &valid);
      assert_true(valid);
      assert_int_equal(
          dtm_map_eval_valid(3, 10, (const double(*)[3])xl, (const double(*)[3])t->dN[k], t->q.w[k], g, &dvs, &djs), 0);
      assert_memory_equal(&dv, &dvs, sizeof dv);
      for (int a = 0; a < 10; a++) assert_memory_equal(gp[a], g[a], sizeof g[a]);
      dtm_point_walk_gram(&w, k, gp, dv, U);
      memcpy(row[0], g, 30 * sizeof(double));
      plain_sum(30, 1, (const double(*)[DTM_GRAM_W])row, &dvs, R, 0);
    }
    dtm_point_walk_gram_end(&w, U);
    assert_memory_equal(U, R, sizeof U);
    whole_walk(t, (const double(*)[3])xl, R);
  }
  const dtm_ref_table *full = dtm_ref_rule_table(DTM_TET10, 0); /* 14 points: three groups and two alone */
  assert_non_null(full);
  curved_tet10(0.05, 1.0, xl);
  whole_walk(full, (const double(*)[3])xl, NULL);
  for (int level = 5; level <= DTM_K_LEVEL_MAX; level++) { /* inverted in part: the first point that fails */
    curved_tet10(0.9, 0.0, xl);
    whole_walk(dtm_ref_level_table(DTM_TET10, level), (const double(*)[3])xl, NULL);
  }
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_map_four_points),
      cmocka_unit_test(test_map_threshold),
      cmocka_unit_test(test_gram_block),
      cmocka_unit_test(test_walk),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
