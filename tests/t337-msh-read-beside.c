/* dtmap's own reading of a .msh beside Gmsh's (src/gmsh/msh_read.c,
 * msh_beside.c) gives extraction exactly what Gmsh's C API listing gives:
 * for meshes Gmsh wrote (ASCII and binary; linear and second-order tets,
 * with and without parametric coordinates;
 * hexahedra and prisms in two volumes with quadrangles, triangles and
 * lines extracted as sections) and a hand-written ASCII file (sparse node
 * tags, CRLF line ends, ragged spaces, a parametric node block), the
 * extracted mesh is bit for bit the same with the reading on and off:
 * node tags, coordinates, every block's type, tags, connectivity, groups,
 * materials, entities and sections. Equality is exact (no tolerance):
 * both come from the same bytes, and ASCII numbers go through the same
 * strtod. Each case also asserts which way it took: the reading is taken
 * on every MSH 4.1 file above, and not on an MSH 2.2 file, a file whose
 * node blocks are out of Gmsh's entity order or one with a 200-character
 * number (then Gmsh lists, with the same result), so the comparison
 * cannot pass by comparing Gmsh with itself. dtm_msh_parse refuses a file
 * cut inside $Elements and one whose volume has a tet4 and a tet10 block
 * (reading the same blocks in two volumes). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/mesh.h"
#include "dtmap/scene.h"
#include "gmsh-impl.h"
#include "testutil.h"

static dtm_scene *scene;

static const char *tmp(const char *name) {
  static char path[4][600];
  static int k;
  k = (k + 1) % 4;
  snprintf(path[k], sizeof path[k], "%s/%s", tu_tmpdir(), name);
  return path[k];
}

/* Mesh geometry file geo (dimension dim, order) and write it as out in
 * MSH version (4.1 or 2.2), binary or not. */
static void mesh_to(const char *geo, int dim, int order, double version, int binary, const char *out) {
  int ierr = 0;
  gmshClear(&ierr);
  gmshOpen(tmp(geo), &ierr);
  assert_int_equal(ierr, 0);
  gmshModelMeshGenerate(dim, &ierr);
  if (order > 1) gmshModelMeshSetOrder(order, &ierr);
  assert_int_equal(ierr, 0);
  gmshOptionSetNumber("Mesh.MshFileVersion", version, &ierr);
  gmshOptionSetNumber("Mesh.Binary", binary, &ierr);
  gmshWrite(tmp(out), &ierr);
  assert_int_equal(ierr, 0);
  gmshOptionSetNumber("Mesh.MshFileVersion", 4.1, &ierr);
  gmshOptionSetNumber("Mesh.Binary", 0, &ierr);
}

/* Open msh and extract dimension dim with every group of dimension
 * lowest to dim - 1 as a section (its curves or surfaces extracted too),
 * the reading beside Gmsh on or off; *taken: whether it was taken. */
static dtm_mesh *extract(const char *msh, int dim, int lowest, int beside, int *taken) {
  dtm_mesh *m = calloc(1, sizeof *m);
  int d, before = dtm_gmsh_parsed_enable(beside);
  assert_int_equal(dtm_gmsh_open(tmp(msh), &d), 0);
  assert_int_equal(d, dim);
  m->dim = dim;
  for (int k = dim; k >= lowest; k--) {
    dtm_group *g = NULL;
    int ng = 0;
    assert_int_equal(dtm_gmsh_groups(k, &g, &ng), 0);
    m->groups = realloc(m->groups, ((size_t)m->ngroups + (size_t)ng + 1) * sizeof *m->groups);
    memcpy(m->groups + m->ngroups, g, (size_t)ng * sizeof *g);
    m->ngroups += ng;
    free(g);
  }
  int *mat = calloc((size_t)m->ngroups + 1, sizeof *mat), *sec = calloc((size_t)m->ngroups + 1, sizeof *sec);
  for (int g = 0; g < m->ngroups; g++) sec[g] = m->groups[g].dim < dim ? 0 : -1;
  dtm_group_map map = {mat, 0, sec, -1};
  int rc = dtm_gmsh_extract_map(dim, &map, scene, m);
  if (rc) fprintf(stderr, "%s\n", dtm_error_message());
  assert_int_equal(rc, 0);
  *taken = dtm_gmsh_parsed_enable(1) > before;
  free(mat), free(sec);
  return m;
}

static void same_array(const void *a, const void *b, size_t bytes) {
  assert_true((a == NULL) == (b == NULL));
  if (a) assert_memory_equal(a, b, bytes);
}

static void same_mesh(const dtm_mesh *a, const dtm_mesh *b) {
  assert_int_equal(a->nnodes, b->nnodes);
  same_array(a->node_tags, b->node_tags, a->nnodes * sizeof *a->node_tags);
  same_array(a->xyz, b->xyz, 3 * a->nnodes * sizeof *a->xyz);
  assert_int_equal(a->nblocks, b->nblocks);
  for (int k = 0; k < a->nblocks; k++) {
    const dtm_block *x = &a->blocks[k], *y = &b->blocks[k];
    assert_int_equal(x->type, y->type);
    assert_int_equal(x->n, y->n);
    assert_true(x->n > 0);
    same_array(x->tags, y->tags, x->n * sizeof *x->tags);
    same_array(x->conn, y->conn, x->n * (size_t)x->nn * sizeof *x->conn);
    same_array(x->group, y->group, x->n * sizeof *x->group);
    same_array(x->mat, y->mat, x->n * sizeof *x->mat);
    same_array(x->gmask, y->gmask, x->n * sizeof *x->gmask);
    same_array(x->entity, y->entity, x->n * sizeof *x->entity);
    same_array(x->section, y->section, x->n * sizeof *x->section);
  }
}

/* Extract msh both ways: the same mesh; the reading taken as expected;
 * returns the mesh's number of blocks. */
static int both_ways(const char *msh, int dim, int lowest, int expect_taken) {
  int on, off;
  dtm_mesh *a = extract(msh, dim, lowest, 1, &on), *b = extract(msh, dim, lowest, 0, &off);
  assert_int_equal(on, expect_taken);
  assert_int_equal(off, 0);
  same_mesh(a, b);
  int nb = a->nblocks;
  dtm_mesh_destroy(&a);
  dtm_mesh_destroy(&b);
  return nb;
}

static void tets_gmsh_wrote(void **unused) {
  (void)unused;
  tu_cube_geo("cube.geo", "Mesh.MeshSizeMax = 0.15;\n");
  mesh_to("cube.geo", 3, 1, 4.1, 0, "tet4_ascii.msh");
  mesh_to("cube.geo", 3, 1, 4.1, 1, "tet4_binary.msh");
  mesh_to("cube.geo", 3, 2, 4.1, 1, "tet10_binary.msh");
  mesh_to("cube.geo", 3, 2, 4.1, 0, "tet10_ascii.msh");
  assert_int_equal(both_ways("tet4_ascii.msh", 3, 1, 1), 1);
  assert_int_equal(both_ways("tet4_binary.msh", 3, 1, 1), 1);
  assert_int_equal(both_ways("tet10_binary.msh", 3, 1, 1), 1);
  assert_int_equal(both_ways("tet10_ascii.msh", 3, 1, 1), 1);
  int ierr = 0; /* nodes on curves and surfaces with their parametric coordinates */
  gmshOptionSetNumber("Mesh.SaveParametric", 1, &ierr);
  mesh_to("cube.geo", 3, 1, 4.1, 1, "tet4_param_binary.msh");
  mesh_to("cube.geo", 3, 1, 4.1, 0, "tet4_param_ascii.msh");
  gmshOptionSetNumber("Mesh.SaveParametric", 0, &ierr);
  assert_int_equal(both_ways("tet4_param_binary.msh", 3, 1, 1), 1);
  assert_int_equal(both_ways("tet4_param_ascii.msh", 3, 1, 1), 1);
}

/* Two extruded volumes (hexahedra over quadrangles, prisms over
 * triangles), their faces and the bottom's edges in groups of their own. */
static const char *mixed_geo = "Point(1) = {0, 0, 0, 0.25}; Point(2) = {1, 0, 0, 0.25}; Point(3) = {1, 1, 0, 0.25};\n"
                               "Point(4) = {0, 1, 0, 0.25}; Point(5) = {2, 0, 0, 0.25}; Point(6) = {2, 1, 0, 0.25};\n"
                               "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
                               "Line(5) = {2, 5}; Line(6) = {5, 6}; Line(7) = {6, 3};\n"
                               "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
                               "Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};\n"
                               "Transfinite Curve{1, 2, 3, 4} = 5; Transfinite Surface{1}; Recombine Surface{1};\n"
                               "a[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{3}; Recombine; };\n"
                               "b[] = Extrude {0, 0, 0.5} { Surface{2}; Layers{3}; Recombine; };\n"
                               "Physical Volume(\"hex\") = {a[1]}; Physical Volume(\"prism\") = {b[1]};\n"
                               "Physical Surface(\"floor\") = {1, 2}; Physical Surface(\"tops\") = {a[0], b[0]};\n"
                               "Physical Curve(\"edges\") = {1, 5, 6};\n";

static void hexes_prisms_sections(void **unused) {
  (void)unused;
  tu_write(tmp("mixed.geo"), mixed_geo);
  /* hexahedra, prisms, quadrangles, triangles and lines; second order
   * without the lines (dtmap takes no 3-node line) */
  static const struct {
    const char *msh;
    int order, binary, lowest, blocks;
  } cases[] = {{"mixed_ascii.msh", 1, 0, 1, 5}, {"mixed_binary.msh", 1, 1, 1, 5}, {"mixed2_binary.msh", 2, 1, 2, 4}};
  for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
    mesh_to("mixed.geo", 3, cases[i].order, 4.1, cases[i].binary, cases[i].msh);
    assert_int_equal(both_ways(cases[i].msh, 3, cases[i].lowest, 1), cases[i].blocks);
  }
}

/* Node tags 10..50 (sparse), CRLF, ragged spaces; the volume's node block
 * parametric: its u, v, w are skipped. */
static const char *hand_msh =
    "$MeshFormat\r\n4.1 0 8\r\n$EndMeshFormat\r\n"
    "$PhysicalNames\r\n1\r\n3 1 \"block\"\r\n$EndPhysicalNames\r\n"
    "$Entities\r\n1 0 0 1\r\n7 0 0 0 0\r\n1 0 0 0 1 1 1 1 1 0\r\n$EndEntities\r\n"
    "$Nodes\r\n2 5 10 50\r\n"
    "0 7 0 1\r\n10\r\n0 0 0\r\n"
    "3 1 1 4\r\n20\r\n30\r\n 40\r\n50\r\n1 0 0 .1 .2 .3\r\n0 1.5e0 0 4 5 6\r\n0 0   1 7 8 9\r\n1 1 1 0 0 0\r\n"
    "$EndNodes\r\n"
    "$Elements\r\n1 2 7 9\r\n3 1 4 2\r\n7 10 20 30 40\r\n9  20 30 40  50 \r\n$EndElements\r\n";

/* The same nodes with the volume's block before the point's. */
static const char *unordered_msh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                   "$PhysicalNames\n1\n3 1 \"block\"\n$EndPhysicalNames\n"
                                   "$Entities\n1 0 0 1\n7 0 0 0 0\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n"
                                   "$Nodes\n2 5 10 50\n"
                                   "3 1 0 4\n20\n30\n40\n50\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n"
                                   "0 7 0 1\n10\n0 0 0\n$EndNodes\n"
                                   "$Elements\n1 2 7 9\n3 1 4 2\n7 10 20 30 40\n9 20 30 40 50\n$EndElements\n";

static void hand_written(void **unused) {
  (void)unused;
  tu_write(tmp("hand.msh"), hand_msh);
  tu_write(tmp("unordered.msh"), unordered_msh);
  assert_int_equal(both_ways("hand.msh", 3, 1, 1), 1);
  assert_int_equal(both_ways("unordered.msh", 3, 1, 0), 1);
  /* a coordinate of 200 characters: longer than the reader takes (Gmsh reads it) */
  char digits[201], *text = malloc(strlen(hand_msh) + sizeof digits);
  memset(digits, '0', 200), digits[0] = '1', digits[1] = '.', digits[199] = '3', digits[200] = '\0';
  const char *at = strstr(hand_msh, "1.5e0");
  snprintf(text, strlen(hand_msh) + sizeof digits, "%.*s%s%s", (int)(at - hand_msh), hand_msh, digits, at + 5);
  tu_write(tmp("long.msh"), text);
  free(text);
  assert_int_equal(both_ways("long.msh", 3, 1, 0), 1);
  dtm_msh_parsed p;
  assert_int_equal(dtm_msh_parse(tmp("hand.msh"), &p), 0);
  assert_int_equal(p.nnodes, 5);
  assert_int_equal(p.node_tags[2], 30);
  assert_true(p.xyz[3 * 2 + 1] == 1.5); /* exact: "1.5e0" names a double */
  assert_int_equal(p.nblocks, 1);
  assert_int_equal(p.blocks[0].conn[4], 20);
  dtm_msh_parsed_free(&p);
  /* one volume with a tet4 block and a tet10 block, a hexahedron's block
   * between them in type order: Gmsh keeps the tets in one list and would
   * list both as tet4, so the reader declines the file (and keeps nothing) */
  char mixed[2048];
  snprintf(mixed, sizeof mixed,
           "%.*s$Elements\n3 3 1 3\n3 1 4 1\n1 10 20 30 40\n3 1 5 1\n2 10 20 30 40 50 10 20 30\n"
           "3 1 11 1\n3 10 20 30 40 50 10 20 30 40 50\n$EndElements\n",
           (int)(strstr(hand_msh, "$Elements") - hand_msh), hand_msh);
  tu_write(tmp("two_tets.msh"), mixed);
  assert_int_equal(dtm_msh_parse(tmp("two_tets.msh"), &p), -1);
  assert_int_equal(p.nblocks, 0);
  memcpy(strstr(mixed, "3 1 11 1"), "3 2", 3); /* the tet10 in a volume of its own: read */
  tu_write(tmp("two_volumes.msh"), mixed);
  assert_int_equal(dtm_msh_parse(tmp("two_volumes.msh"), &p), 0);
  assert_int_equal(p.nblocks, 3);
  dtm_msh_parsed_free(&p);
}

static void left_to_gmsh(void **unused) {
  (void)unused;
  mesh_to("cube.geo", 3, 1, 2.2, 0, "tet4_v22.msh");
  assert_int_equal(both_ways("tet4_v22.msh", 3, 1, 0), 1);
  /* cut inside $Elements: not read */
  FILE *f = fopen(tmp("tet4_binary.msh"), "rb");
  assert_non_null(f);
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  rewind(f);
  char *buf = malloc((size_t)n);
  assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
  fclose(f);
  f = fopen(tmp("cut.msh"), "wb");
  fwrite(buf, 1, (size_t)(n - 4000), f);
  fclose(f);
  free(buf);
  dtm_msh_parsed p;
  assert_int_equal(dtm_msh_parse(tmp("cut.msh"), &p), -1);
  assert_int_equal(p.nnodes, 0);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  if (dtm_gmsh_start(0)) return 3;
  tu_cube_geo("cube.geo", "");
  tu_steel_scene("cube", "<geometry file=\"cube.geo\"/>", "dim=\"3\"", "");
  if (dtm_scene_load(tmp("cube.xml"), &scene)) return 3;
  const struct CMUnitTest tests[] = {cmocka_unit_test(tets_gmsh_wrote), cmocka_unit_test(hexes_prisms_sections),
                                     cmocka_unit_test(hand_written), cmocka_unit_test(left_to_gmsh)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_scene_destroy(&scene);
  dtm_gmsh_stop();
  return r;
}
