/* Lanczos on small 3D blocks against a dense eigen-solve, the parallel
 * product against serial ones, and (on request) the timing of the product
 * and of a whole Lanczos run on a large tet mesh.
 * Meshes: structured n^3 grids of cells of side h, as hex8 or split into 6
 * tet4 along the main diagonal (Kuhn; conforming), every node moved by up
 * to 15 % of h so the spectrum has no symmetry-induced multiplicities, one
 * or two materials.
 * Dense reference: A = M^-1/2 K M^-1/2 assembled from A e_j and its top
 * eigenvalue by dtm_eig_sym_max (cyclic Jacobi, every eigenvalue to a small
 * multiple of eps |A|). Lanczos runs to tol 1e-8 within 200 steps; the
 * residual bracket then holds lambda_max, and theta must agree with the
 * dense value to 1e-8 relative (Ritz values converge quadratically in the
 * residual, so the actual gap is far smaller).
 * Parallel product: the same mesh as one operator (above the size where the
 * product uses several threads) and as two operators on the two halves of
 * the element list (each small enough to run serially); K is additive over
 * elements, so the sums agree to rounding: 1e-12 of the largest element
 * force (sums of a few dozen terms of that size, added in another order).
 * Timing: set DTM_BENCH_CELLS=55 (55^3 x 6 ~ 1e6 tets) and OMP_NUM_THREADS
 * to print the time of the set-up, of one product and of Lanczos to 1e-3. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/operator.h"
#include "fixtures.h"

static void near(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s: got %.17g, want %.17g (rel %.3g, tol %g)", what, got, want, (got - want) / want, rel);
}

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct {
  dtm_mesh m;
  dtm_block b;
  double *xyz;
  size_t *conn, *tags;
  int *mat;
} grid;

static double jitter(uint64_t *s) {
  *s = *s * 6364136223846793005u + 1442695040888963407u;
  return (double)(*s >> 11) * 0x1.0p-52 - 1;
}

static size_t node_id(int n, int i, int j, int k) {
  return (size_t)i + (size_t)(n + 1) * ((size_t)j + (size_t)(n + 1) * (size_t)k);
}

static double tet_det(const double *xyz, const size_t *c) {
  double e[3][3];
  for (int a = 0; a < 3; a++)
    for (int i = 0; i < 3; i++) e[a][i] = xyz[3 * c[a + 1] + i] - xyz[3 * c[0] + i];
  return e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
         e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
}

/* The 8 corners of cell (i, j, k) in Gmsh hex order. */
static void corners(int n, int i, int j, int k, size_t *c) {
  static const int off[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int a = 0; a < 8; a++) c[a] = node_id(n, i + off[a][0], j + off[a][1], k + off[a][2]);
}

/* Kuhn split: tets (v0, v0 + e_p, v0 + e_p + e_q, v7) for the 6 axis
 * orders (p, q); bit index of a corner is x + 2y + 4z. */
static void kuhn(const double *xyz, const size_t *c8, size_t *c) {
  static const int perm[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
  static const int bit_to_gmsh[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  for (int t = 0; t < 6; t++, c += 4) {
    int b1 = 1 << perm[t][0], b2 = b1 | 1 << perm[t][1];
    c[0] = c8[0], c[1] = c8[bit_to_gmsh[b1]], c[2] = c8[bit_to_gmsh[b2]], c[3] = c8[6];
    if (tet_det(xyz, c) < 0) {
      size_t s = c[1];
      c[1] = c[2], c[2] = s;
    }
  }
}

static void grid_nodes(grid *g, int n, double h, double jit) {
  uint64_t s = 2024;
  for (int k = 0; k <= n; k++)
    for (int j = 0; j <= n; j++)
      for (int i = 0; i <= n; i++) {
        double *x = g->xyz + 3 * node_id(n, i, j, k);
        x[0] = h * (i + jit * jitter(&s));
        x[1] = h * (j + jit * jitter(&s));
        x[2] = h * (k + jit * jitter(&s));
      }
}

/* n^3 cells of side h as hex8 or 6 tet4 each; material 1 for x > n/2 when
 * two is set. */
static void grid_init(grid *g, int n, int tets, double h, int two) {
  size_t ncell = (size_t)n * (size_t)n * (size_t)n, per = tets ? 6 : 1, nn = tets ? 4 : 8;
  size_t ne = ncell * per, e = 0;
  memset(g, 0, sizeof *g);
  g->xyz = malloc(3 * node_id(n, 0, 0, n + 1) * sizeof *g->xyz);
  g->conn = malloc(ne * nn * sizeof *g->conn);
  g->tags = malloc(ne * sizeof *g->tags);
  g->mat = malloc(ne * sizeof *g->mat);
  assert_non_null(g->xyz), assert_non_null(g->conn), assert_non_null(g->mat);
  grid_nodes(g, n, h, 0.15);
  for (int k = 0; k < n; k++)
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++) {
        size_t c8[8];
        corners(n, i, j, k, c8);
        if (tets)
          kuhn(g->xyz, c8, g->conn + e * nn);
        else
          memcpy(g->conn + e * nn, c8, sizeof c8);
        for (size_t t = 0; t < per; t++, e++) g->tags[e] = e + 1, g->mat[e] = two && 2 * i >= n;
      }
  g->b = (dtm_block){.type = tets ? DTM_TET4 : DTM_HEX8,
                     .dim = 3,
                     .nn = (int)nn,
                     .n = ne,
                     .tags = g->tags,
                     .conn = g->conn,
                     .mat = g->mat};
  g->m = (dtm_mesh){.dim = 3, .nnodes = node_id(n, 0, 0, n + 1), .xyz = g->xyz, .nblocks = 1, .blocks = &g->b};
}

static void grid_free(grid *g) { free(g->xyz), free(g->conn), free(g->tags), free(g->mat); }

static void coeffs(dtm_operator_coeffs c[2]) {
  c[0] = (dtm_operator_coeffs){.kind = DTM_OP_ELASTIC, .capacity = 2700};
  c[1] = (dtm_operator_coeffs){.kind = DTM_OP_ELASTIC, .capacity = 7850};
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, 60e9, 0.25, 2700, &c[0].mod), 0);
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, 210e9, 0.45, 7850, &c[1].mod), 0);
}

static dtm_operator *make(const dtm_mesh *m) {
  dtm_operator_coeffs c[2];
  dtm_operator *op = NULL;
  coeffs(c);
  dtm_error_clear();
  if (dtm_operator_create(m, DTM_OP_ELASTIC, c, NULL, NULL, 2, &op)) fail_msg("create: %s", dtm_error_message());
  return op;
}

static double dense_top(const dtm_operator *op) {
  size_t n = dtm_operator_ndof(op);
  double *a = tu_operator_dense(op, 1);
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < i; j++) assert_true(fabs(a[i * n + j] - a[j * n + i]) <= 1e-12 * fabs(a[i * n + i]));
  double top = dtm_eig_sym_max((int)n, a);
  free(a);
  return top;
}

static void block_vs_dense(int n, int tets, int two) {
  grid g;
  grid_init(&g, n, tets, 0.01, two);
  dtm_operator *op = make(&g.m);
  double want = dense_top(op);
  dtm_lanczos_result r;
  dtm_error_clear();
  assert_int_equal(dtm_lanczos_max(op, 1e-8, 200, 3, &r), 0);
  print_message("%d^3 %s%s: %zu dofs, dense %.15g, Lanczos %.15g after %d steps, "
                "residual %.2g theta, rel diff %.2g\n",
                n, tets ? "tet" : "hex", two ? " (2 materials)" : "", dtm_operator_ndof(op), want, r.theta,
                r.iterations, r.residual / r.theta, (r.theta - want) / want);
  assert_true(r.converged);
  assert_true(r.iterations <= 200);
  assert_true(fabs(r.theta - want) <= r.residual + 1e-13 * want);
  near(r.theta, want, 1e-8, "theta vs dense");
  free(r.mode);
  dtm_operator_destroy(&op);
  grid_free(&g);
}

static void test_hex_block(void **state) {
  (void)state;
  block_vs_dense(4, 0, 0);
  block_vs_dense(4, 0, 1);
}

static void test_tet_block(void **state) {
  (void)state;
  block_vs_dense(3, 1, 0);
  block_vs_dense(4, 1, 1);
}

/* The whole mesh (parallel when threads are available) against its two
 * halves (serial), which must add up. */
static void test_parallel_sum(void **state) {
  (void)state;
  grid g;
  grid_init(&g, 16, 1, 0.01, 1); /* 24576 tets */
  dtm_operator *full = make(&g.m);
  dtm_block half = g.b;
  dtm_mesh hm = g.m;
  hm.blocks = &half;
  half.n = g.b.n / 2;
  dtm_operator *a = make(&hm);
  half.conn += half.n * 4, half.tags += half.n, half.mat += half.n;
  half.n = g.b.n - half.n;
  dtm_operator *b = make(&hm);
  size_t n = dtm_operator_ndof(full);
  double *u = malloc(n * sizeof *u), *y = malloc(n * sizeof *y), *ya = malloc(n * sizeof *ya),
         *yb = malloc(n * sizeof *yb), scale = 0;
  uint64_t s = 9;
  for (size_t i = 0; i < n; i++) u[i] = jitter(&s);
  dtm_operator_apply(full, u, y);
  dtm_operator_apply(a, u, ya);
  dtm_operator_apply(b, u, yb);
  for (size_t i = 0; i < n; i++) scale = fmax(scale, fmax(fabs(ya[i]), fabs(yb[i])));
  for (size_t i = 0; i < n; i++) {
    assert_true(fabs(y[i] - ya[i] - yb[i]) <= 1e-12 * scale);
    double m = dtm_operator_mass(a)[i] + dtm_operator_mass(b)[i];
    assert_true(fabs(dtm_operator_mass(full)[i] - m) <= 1e-14 * m);
  }
  /* the product is deterministic */
  dtm_operator_apply(full, u, ya);
  assert_memory_equal(y, ya, n * sizeof *y);
  free(u), free(y), free(ya), free(yb);
  dtm_operator_destroy(&full), dtm_operator_destroy(&a), dtm_operator_destroy(&b);
  grid_free(&g);
}

static void bench(int cells) {
  grid g;
  double t0 = now();
  grid_init(&g, cells, 1, 1e-3, 0);
  double t1 = now();
  dtm_operator *op = make(&g.m);
  double t2 = now();
  size_t n = dtm_operator_ndof(op);
  double *u = malloc(n * sizeof *u), *y = malloc(n * sizeof *y);
  uint64_t s = 5;
  for (size_t i = 0; i < n; i++) u[i] = jitter(&s);
  dtm_operator_apply(op, u, y); /* warm up */
  double t3 = now();
  for (int r = 0; r < 10; r++) dtm_operator_apply(op, u, y);
  double t4 = now();
  dtm_lanczos_result r;
  assert_int_equal(dtm_lanczos_max(op, 1e-3, 300, 1, &r), 0);
  print_message("bench: %zu tets, %zu dofs; mesh %.2f s, create %.3f s, apply %.2f ms, "
                "Lanczos tol 1e-3: %d steps (+%d for the mode), %.3f s, theta %.6g, "
                "residual %.2g theta\n",
                g.b.n, n, t1 - t0, t2 - t1, (t4 - t3) * 100, r.iterations, r.iterations, r.seconds, r.theta,
                r.residual / r.theta);
  free(u), free(y), free(r.mode);
  dtm_operator_destroy(&op);
  grid_free(&g);
}

static void test_bench(void **state) {
  (void)state;
  const char *e = getenv("DTM_BENCH_CELLS");
  if (e && atoi(e) > 0)
    bench(atoi(e));
  else
    bench(12); /* quick: 10368 tets */
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_hex_block),
      cmocka_unit_test(test_tet_block),
      cmocka_unit_test(test_parallel_sum),
      cmocka_unit_test(test_bench),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
