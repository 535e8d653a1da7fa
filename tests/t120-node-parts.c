/* The ordered scatters in parallel (src/mesh/node_parts.c, used by the
 * nodal bound and the size suggestion):
 * - on a Gmsh mesh of the unit cube in locality order, for 2 to 256 parts,
 *   each part walks exactly the elements that have a node in its range,
 *   each once, in ascending order (its listed elements, then its core);
 *   the cores cover the block without overlap; up to 16 parts, the parts
 *   together list fewer than half as many elements as the block holds
 *   (the split's straddlers and the Hilbert curve's far neighbours, which
 *   are walked twice);
 * - a mesh in Gmsh's own order gets one part (the serial loop);
 * - the analysis's nodal steps, size suggestion and local steps on 3
 *   threads with 4 parts per thread are the bits of the serial loop (one
 *   part): each node's sums are added in the same order; so are the cost's
 *   subcycling levels and its phase-error measure, whose measured table
 *   smooths each element's size over the nodes around it.
 * Tolerance: none (set equality, bitwise equality). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "dtmap/cost.h"
#include "dtmap/gmsh.h"
#include "testutil.h"

static dtm_scene *scene;

/* The current model's mesh, in Gmsh's order or reordered. */
static dtm_mesh *extract(int reorder) {
  dtm_mesh *m = calloc(1, sizeof *m);
  int gm[4] = {0, 0, 0, 0};
  m->dim = 3;
  assert_int_equal(dtm_gmsh_groups(3, &m->groups, &m->ngroups), 0);
  assert_int_equal(dtm_gmsh_extract(3, gm, 0, scene, m), 0);
  if (reorder) assert_int_equal(dtm_mesh_reorder(m), 0);
  return m;
}

static int touches(const dtm_block *b, size_t e, size_t lo, size_t hi) {
  for (int k = 0; k < b->nn; k++)
    if (b->conn[e * (size_t)b->nn + (size_t)k] >= lo && b->conn[e * (size_t)b->nn + (size_t)k] < hi) return 1;
  return 0;
}

/* Part p's walk over block b against the brute force: the elements with a
 * node in [lo, hi), ascending, each once. */
static void check_part(const dtm_node_parts *np, const dtm_block *b, int bi, int p, size_t *core_total,
                       size_t *listed_total) {
  const size_t *list;
  size_t nlist, e0, e1, lo, hi, walked = 0, last = 0, want = 0;
  dtm_mesh_node_part(np, p, &lo, &hi);
  dtm_mesh_node_part_elements(np, p, bi, &list, &nlist, &e0, &e1);
  for (size_t e = 0; e < b->n; e++) want += (size_t)touches(b, e, lo, hi);
  for (size_t j = 0; j < nlist + (e1 - e0); j++) {
    size_t e = j < nlist ? list[j] : e0 + (j - nlist);
    assert_true(touches(b, e, lo, hi));
    if (j) assert_true(e > last); /* ascending: once each */
    last = e, walked++;
  }
  assert_int_equal(walked, want);
  *core_total += e1 - e0, *listed_total += nlist;
}

static void parts_cover(void **unused) {
  dtm_mesh *m = extract(1);
  const int counts[] = {1, 2, 3, 7, 16, 64, 256};
  for (size_t c = 0; c < sizeof counts / sizeof *counts; c++) {
    dtm_node_parts np;
    assert_int_equal(dtm_mesh_node_parts(m, counts[c], &np), 0);
    assert_int_equal(np.n, counts[c]);
    for (int b = 0; b < m->nblocks; b++) {
      size_t core = 0, listed = 0;
      for (int p = 0; p < np.n; p++) check_part(&np, &m->blocks[b], b, p, &core, &listed);
      assert_int_equal(core, m->blocks[b].n);
      if (counts[c] <= 16) assert_true(2 * listed < core); /* measured 7 % at 2 parts, 39 % at 16 */
    }
    dtm_mesh_node_parts_free(&np);
  }
  dtm_mesh_destroy(&m);
  (void)unused;
}

static void unordered_one_part(void **unused) {
  dtm_mesh *m = extract(0);
  dtm_node_parts np;
  assert_int_equal(dtm_mesh_node_parts(m, 8, &np), 0);
  assert_int_equal(np.n, 1);
  size_t core = 0, listed = 0;
  check_part(&np, &m->blocks[0], 0, 0, &core, &listed);
  assert_int_equal(listed, 0);
  assert_int_equal(core, m->blocks[0].n);
  dtm_mesh_node_parts_free(&np);
  dtm_mesh_destroy(&m);
  (void)unused;
}

static dtm_analysis *analyse(int parts_per_thread) {
  dtm_mesh *m = extract(1);
  dtm_effect *e = NULL;
  dtm_analysis *a = NULL;
  int ne = 0, keep = dtm_scatter_parts;
  dtm_scatter_parts = parts_per_thread;
  assert_int_equal(dtm_effects_create(scene, m, &e, &ne), 0);
  assert_int_equal(dtm_analysis_compute(scene, m, e, ne, &a), 0);
  dtm_scatter_parts = keep;
  return a;
}

static void same_bits(void **unused) {
  omp_set_num_threads(3);
  dtm_analysis *par = analyse(4), *ser = analyse(0);
  assert_int_equal(par->parts.n, 12);
  assert_int_equal(ser->parts.n, 1);
  size_t nn = par->mesh->nnodes;
  assert_memory_equal(par->nodal_node, ser->nodal_node, nn * sizeof *par->nodal_node);
  assert_memory_equal(par->size_node, ser->size_node, nn * sizeof *par->size_node);
  assert_memory_equal(par->local, ser->local, par->nel * sizeof *par->local);
  dtm_cost *cp = NULL, *cs = NULL;
  assert_int_equal(dtm_cost_create(par, &cp), 0);
  assert_int_equal(dtm_cost_create(ser, &cs), 0);
  assert_memory_equal(cp->subcycling.level, cs->subcycling.level, par->nel * sizeof *cp->subcycling.level);
  assert_int_equal(cp->measures->n, cs->measures->n);
  assert_true(cp->measures->n > 0);
  const dtm_measure *mp = &cp->measures->m[0], *ms = &cs->measures->m[0];
  assert_int_equal(mp->kind, DTM_MEASURE_PHASE);
  assert_int_equal(mp->rings, 3); /* the measured table: its sizes smoothed over the nodes */
  assert_memory_equal(&mp->worst, &ms->worst, sizeof mp->worst);
  assert_memory_equal(&mp->median, &ms->median, sizeof mp->median);
  assert_memory_equal(&mp->worst_alone, &ms->worst_alone, sizeof mp->worst_alone);
  assert_int_equal(mp->worst_element, ms->worst_element);
  dtm_cost_destroy(&cp), dtm_cost_destroy(&cs);
  dtm_analysis_destroy(&par), dtm_analysis_destroy(&ser);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  if (dtm_gmsh_start(0)) return 3;
  char path[600];
  tu_cube_geo("cube.geo", "");
  tu_steel_scene("cube", "<geometry file=\"cube.geo\"/>", "size=\"0.06\" dim=\"3\"", "");
  snprintf(path, sizeof path, "%s/cube.xml", tu_tmpdir());
  dtm_analysis *a = NULL;
  if (dtm_scene_load(path, &scene) || dtm_analysis_run(scene, &a)) return 3; /* meshes the cube once */
  dtm_analysis_destroy(&a);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(parts_cover),
      cmocka_unit_test(unordered_one_part),
      cmocka_unit_test(same_bits),
  };
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_scene_destroy(&scene);
  dtm_gmsh_stop();
  return r;
}
