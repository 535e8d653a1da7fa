/* Locality renumbering (dtm_mesh_reorder) changes array positions only:
 * - on a Gmsh Delaunay mesh every element keeps its tag, its node tags in
 *   the same order and their coordinates; node tags stay a permutation;
 *   consecutive elements then reference nearby nodes (the mean jump of the
 *   first node drops by more than 3x on this small mesh);
 * - the analysis (which reorders) gives every element the bit-identical
 *   step of an analysis of the Gmsh-ordered mesh, the same dt.min element
 *   tag, and nodal steps by node tag equal to round-off (1e-12: the sums
 *   over a node's elements only change order);
 * - the global estimate does not depend on the order (its start vector is
 *   drawn per node tag): theta within 1e-9, the same iteration count;
 * - the operator's 64-bit connectivity loops give the products of the
 *   32-bit ones exactly (same arithmetic). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "dtmap/gmsh.h"
#include "dtmap/operator.h"
#include "spectral.h"
#include "testutil.h"

static dtm_scene *scene;

static void setup_scene(void) {
  char path[600];
  tu_cube_geo("cube.geo", "");
  tu_steel_scene("cube", "<geometry file=\"cube.geo\"/>", "size=\"0.08\" dim=\"3\"", "");
  snprintf(path, sizeof path, "%s/cube.xml", tu_tmpdir());
  assert_int_equal(dtm_scene_load(path, &scene), 0);
}

/* The current model's mesh in Gmsh's order (no reordering). */
static dtm_mesh *extract_plain(void) {
  dtm_mesh *m = calloc(1, sizeof *m);
  int gm[4] = {0, 0, 0, 0};
  m->dim = 3;
  assert_int_equal(dtm_gmsh_groups(3, &m->groups, &m->ngroups), 0);
  assert_int_equal(dtm_gmsh_extract(3, gm, 0, scene, m), 0);
  return m;
}

static double mean_jump(const dtm_block *b) {
  double s = 0;
  for (size_t e = 1; e < b->n; e++) s += fabs((double)b->conn[e * b->nn] - (double)b->conn[(e - 1) * b->nn]);
  return s / (double)(b->n - 1);
}

/* Position of each tag in tags[n] (tags are at most max). */
static size_t *index_of(const size_t *tags, size_t n, size_t max) {
  size_t *ix = malloc((max + 1) * sizeof *ix);
  memset(ix, 0xff, (max + 1) * sizeof *ix);
  for (size_t i = 0; i < n; i++) ix[tags[i]] = i;
  return ix;
}

static size_t max_tag(const size_t *t, size_t n) {
  size_t m = 0;
  for (size_t i = 0; i < n; i++) m = t[i] > m ? t[i] : m;
  return m;
}

static void same_elements(void **unused) {
  dtm_mesh *a = extract_plain(), *b = extract_plain();
  double before = mean_jump(&b->blocks[0]);
  assert_int_equal(dtm_mesh_reorder(b), 0);
  /* measured 461 -> 104 on these 2314 nodes, 33093 -> 2042 on 201114: the gain grows with the mesh */
  assert_true(mean_jump(&b->blocks[0]) < before / 3);
  const dtm_block *ba = &a->blocks[0], *bb = &b->blocks[0];
  assert_int_equal(ba->n, bb->n);
  size_t me = max_tag(ba->tags, ba->n), *ie = index_of(ba->tags, ba->n, me);
  for (size_t e = 0; e < bb->n; e++) {
    size_t k = ie[bb->tags[e]];
    assert_true(k < ba->n); /* every tag still there, once */
    ie[bb->tags[e]] = SIZE_MAX;
    assert_int_equal(bb->mat[e], ba->mat[k]);
    for (int j = 0; j < bb->nn; j++) {
      size_t va = ba->conn[k * ba->nn + j], vb = bb->conn[e * bb->nn + j];
      assert_int_equal(a->node_tags[va], b->node_tags[vb]);
      assert_memory_equal(a->xyz + 3 * va, b->xyz + 3 * vb, 3 * sizeof(double));
    }
  }
  free(ie);
  dtm_mesh_destroy(&a), dtm_mesh_destroy(&b);
  (void)unused;
}

static void same_results(void **unused) {
  dtm_analysis *ar = NULL, *ap = NULL;
  dtm_effect *e = NULL;
  int ne = 0;
  assert_int_equal(dtm_analysis_run(scene, &ar), 0); /* reordered */
  dtm_mesh *m = extract_plain();
  assert_int_equal(dtm_effects_create(scene, m, &e, &ne), 0);
  assert_int_equal(dtm_analysis_compute(scene, m, e, ne, &ap), 0); /* Gmsh's order */
  size_t me = max_tag(ap->mesh->blocks[0].tags, ap->nel), *ie = index_of(ap->mesh->blocks[0].tags, ap->nel, me);
  for (size_t i = 0; i < ar->nel; i++) assert_true(ar->dt[i] == ap->dt[ie[ar->mesh->blocks[0].tags[i]]]);
  size_t er, ep;
  assert_true(dtm_analysis_dt_min(ar, &er) == dtm_analysis_dt_min(ap, &ep));
  assert_int_equal(dtm_analysis_tag(ar, er), dtm_analysis_tag(ap, ep));
  size_t mn = max_tag(ap->mesh->node_tags, ap->mesh->nnodes), *in = index_of(ap->mesh->node_tags, ap->mesh->nnodes, mn);
  for (size_t v = 0; v < ar->mesh->nnodes; v++) {
    double x = ar->nodal_node[v], y = ap->nodal_node[in[ar->mesh->node_tags[v]]];
    assert_true(fabs(x - y) <= 1e-12 * y); /* round-off: sums in another order */
  }
  assert_true(fabs(ar->dt_nodal - ap->dt_nodal) <= 1e-12 * ap->dt_nodal);
  dtm_operator *opr = NULL, *opp = NULL;
  dtm_lanczos_result lr, lp;
  assert_int_equal(dtm_analysis_operator(ar, 0, 0.0, &opr), 0);
  assert_int_equal(dtm_analysis_operator(ap, 0, 0.0, &opp), 0);
  assert_int_equal(dtm_lanczos_max_ex(opr, 1e-6, 400, 7, 0, &lr), 0);
  assert_int_equal(dtm_lanczos_max_ex(opp, 1e-6, 400, 7, 0, &lp), 0);
  assert_int_equal(lr.iterations, lp.iterations);
  assert_true(fabs(lr.theta - lp.theta) <= 1e-9 * lp.theta); /* the same Krylov space up to round-off */
  dtm_operator_destroy(&opr), dtm_operator_destroy(&opp);
  free(ie), free(in);
  dtm_analysis_destroy(&ar), dtm_analysis_destroy(&ap);
  (void)unused;
}

static void wide_connectivity(void **unused) {
  dtm_analysis *a = NULL;
  assert_int_equal(dtm_analysis_run(scene, &a), 0);
  dtm_operator *narrow = NULL, *wide = NULL;
  assert_int_equal(dtm_analysis_operator(a, 0, 0.0, &narrow), 0);
  dtm_operator_narrow_max = 0; /* every mesh "too large" for 32 bits */
  assert_int_equal(dtm_analysis_operator(a, 0, 0.0, &wide), 0);
  dtm_operator_narrow_max = (size_t)UINT32_MAX;
  size_t n = dtm_operator_ndof(narrow);
  double *x = malloc(n * sizeof *x), *y1 = malloc(n * sizeof *y1), *y2 = malloc(n * sizeof *y2);
  dtm_operator_draw(narrow, 3, -1, 1, x);
  dtm_operator_apply(narrow, x, y1);
  dtm_operator_apply(wide, x, y2);
  assert_memory_equal(y1, y2, n * sizeof *y1);
  free(x), free(y1), free(y2);
  dtm_operator_destroy(&narrow), dtm_operator_destroy(&wide);
  dtm_analysis_destroy(&a);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  if (dtm_gmsh_start(0)) return 3;
  setup_scene();
  int dim;
  if (dtm_gmsh_load(scene, &dim)) return 3;
  const struct CMUnitTest tests[] = {cmocka_unit_test(same_elements), cmocka_unit_test(same_results),
                                     cmocka_unit_test(wide_connectivity)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_scene_destroy(&scene);
  dtm_gmsh_stop();
  return r;
}
