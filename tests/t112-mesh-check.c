/* The mesh check (dtm_mesh_check) on hand-built meshes: elements inverted
 * only at a corner are kept in the flagged list with their closed-form
 * scaled Jacobian (t111 derives it: (1 - 3a)/((1-a)^2 + 2a^2)^(3/2) for a
 * unit cube whose node 0 moved to (a, a, a)); elements inverted at an
 * integration point stop the check with a message naming the mesh file,
 * the first 20 elements by tag, type, group and centroid, and how many
 * more; non-finite coordinates and missing nodes are named too. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/mesh.h"

#define MAXN 128

/* A mesh of one block on caller storage; group 0 is "rock". */
typedef struct {
  dtm_mesh m;
  dtm_block b;
  dtm_group g;
  double xyz[MAXN * 3];
  size_t ntags[MAXN], tags[MAXN], conn[MAXN * 8];
  int group[MAXN], mat[MAXN];
} fixture;

static void init(fixture *f, int type, int nn) {
  memset(f, 0, sizeof *f);
  f->g = (dtm_group){3, 1, "rock"};
  f->b = (dtm_block){type, 3, nn, 0, f->tags, f->conn, f->group, f->mat, NULL, NULL, NULL};
  f->m = (dtm_mesh){
      .dim = 3, .node_tags = f->ntags, .xyz = f->xyz, .nblocks = 1, .blocks = &f->b, .ngroups = 1, .groups = &f->g};
}

static size_t add_node(fixture *f, double x, double y, double z) {
  size_t v = f->m.nnodes++;
  f->xyz[3 * v] = x, f->xyz[3 * v + 1] = y, f->xyz[3 * v + 2] = z;
  f->ntags[v] = 1000 + v;
  return v;
}

/* Unit cube at (ox, 0, 0) with its node 0 moved by (a, a, a). */
static void add_hex(fixture *f, double ox, double a, size_t tag) {
  static const double c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                 {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  size_t e = f->b.n++;
  for (int k = 0; k < 8; k++)
    f->conn[8 * e + k] = add_node(f, ox + c[k][0] + (k ? 0 : a), c[k][1] + (k ? 0 : a), c[k][2] + (k ? 0 : a));
  f->tags[e] = tag, f->group[e] = 0;
}

static void test_flagged(void **state) {
  (void)state;
  fixture f;
  init(&f, DTM_HEX8, 8);
  add_hex(&f, 0, 0, 7);
  add_hex(&f, 2, 0.4, 8);
  add_hex(&f, 4, 0, 9);
  assert_int_equal(dtm_mesh_check(&f.m, "hex.msh"), DTM_OK);
  assert_int_equal(f.m.nflagged, 1);
  const dtm_flagged *fl = &f.m.flagged[0];
  assert_int_equal(fl->block, 0);
  assert_int_equal(fl->index, 1);
  assert_int_equal(fl->node, 0);
  double want = (1 - 3 * 0.4) / pow(0.6 * 0.6 + 2 * 0.16, 1.5);
  assert_true(fabs(fl->min_jacobian - want) <= 1e-13 * fabs(want)); /* a few roundings, see t111 */
  char place[256];
  dtm_mesh_element_place(&f.m, 0, 0, place, sizeof place);
  assert_string_equal(place, "element 7 (hex8) in group 'rock' at (0.5, 0.5, 0.5)");
  f.group[2] = -1;
  dtm_mesh_element_place(&f.m, 0, 2, place, sizeof place);
  assert_string_equal(place, "element 9 (hex8) in no physical group at (4.5, 0.5, 0.5)");
  free(f.m.flagged);
}

/* 25 inverted tets (nodes 1 and 2 swapped), tags 1..25, each shifted by
 * its index along x so their centroids differ. */
static void test_refused(void **state) {
  (void)state;
  fixture f;
  init(&f, DTM_TET4, 4);
  for (size_t e = 0; e < 25; e++) {
    double ox = (double)e;
    f.conn[4 * e] = add_node(&f, ox, 0, 0);
    f.conn[4 * e + 1] = add_node(&f, ox, 1, 0);
    f.conn[4 * e + 2] = add_node(&f, ox + 1, 0, 0);
    f.conn[4 * e + 3] = add_node(&f, ox, 0, 1);
    f.tags[e] = e + 1, f.group[e] = 0, f.b.n++;
  }
  dtm_error_clear();
  assert_int_equal(dtm_mesh_check(&f.m, "tets.msh"), DTM_ERR_INPUT);
  const char *msg = dtm_error_message();
  assert_non_null(strstr(msg, "tets.msh: 25 elements cannot be analysed"));
  assert_non_null(strstr(msg, "element 1 (tet4) in group 'rock' at (0.25, 0.25, 0.25): inverted or folded"));
  assert_non_null(strstr(msg, "element 20 (tet4) in group 'rock' at (19.25, 0.25, 0.25)"));
  assert_null(strstr(msg, "element 21 "));
  assert_non_null(strstr(msg, "... and 5 more"));
  assert_int_equal(f.m.nflagged, 0);
  dtm_error_clear();
}

static void test_nodes(void **state) {
  (void)state;
  fixture f;
  init(&f, DTM_HEX8, 8);
  add_hex(&f, 0, 0, 3);
  f.xyz[3 * 5 + 1] = NAN;
  dtm_error_clear();
  assert_int_equal(dtm_mesh_check(&f.m, "n.msh"), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "n.msh: node 1005 has coordinates (1, nan, 1)"));
  dtm_error_clear();
  f.xyz[3 * 5 + 1] = 0;
  f.conn[4] = 99;
  assert_int_equal(dtm_mesh_check(&f.m, "n.msh"), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "n.msh: element 3 (hex8) references a node that does not exist"));
  dtm_error_clear();
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_flagged),
      cmocka_unit_test(test_refused),
      cmocka_unit_test(test_nodes),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
