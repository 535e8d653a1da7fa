/* The advice on elements below the target, distributed: the same scene run
 * serially and under mpirun -n 3 (rank 0 meshes the geometry and splits
 * it with Gmsh) classifies the same elements the same way.
 *  - tunnel: the bundled tunnel lining (geometries/tunnel_lining.geo, its
 *    scene's target 5.2e-5 s): the serial run names 24 thickness-limited
 *    lining elements, 0.300 m across; the distributed run names the same
 *    elements with the same feature, model entity, size, quality, reach and
 *    remedy, and the same layer (group, count, thickness, reach, worst
 *    element, mean size), with no warning that it cannot tell; its parts'
 *    views 'thickness limited' and 'shape limited', merged in Gmsh, are
 *    the serial run's.
 *  - tunnel without a target: the layer the smallest steps lie across
 *    (at_minimum) is the same.
 *  - plate: tests/data/sharp_plate.geo (a notched block with a sliver
 *    surface along each short side) with a target 1.5e-6 s: 24 of 36
 *    elements below it shape-limited (short curves and small angles, no
 *    layer), the same in both runs (and in the view 'shape limited'); they
 *    lie in two of the parts.
 * Element tags, kinds, entities and counts compare exactly; the figures
 * within 1e-12 (the own steps rest on the nodal bound, whose node sums the
 * parts add in another order). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parts.h"

#define NP 3

static char dir[512];

static const char tunnel[] = "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n"
                             "<geometry file=\"%s/geometries/tunnel_lining.geo\"/>\n"
                             "<meshing size=\"0.5\" order=\"1\" dim=\"2\"/>\n"
                             "<material name=\"rock\" groups=\"rock\" E=\"20e9\" nu=\"0.25\" rho=\"2600\"/>\n"
                             "<material name=\"concrete\" groups=\"lining\" E=\"30e9\" nu=\"0.2\" rho=\"2400\"/>\n"
                             "<effects><elastic formulation=\"plane-strain\"/></effects>\n"
                             "<time safety=\"0.9\" %s duration=\"0.1\"/>\n</dtmap-scene>\n";

static const char plate[] = "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n"
                            "<geometry file=\"%s/tests/data/sharp_plate.geo\"/>\n"
                            "<meshing size=\"0.05\" order=\"1\" dim=\"2\"/>\n"
                            "<material name=\"steel\" default=\"true\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                            "<effects><elastic formulation=\"plane-strain\"/></effects>\n"
                            "<time %s duration=\"1e-3\"/>\n</dtmap-scene>\n";

static char par_out[3][1 << 14]; /* the distributed runs' terminal output */

/* Scene name.xml from fmt (source folder, time attributes), run serially
 * into NAME_ser.* and under mpirun into NAME_par.*. */
static int run_pair(int k, const char *name, const char *fmt, const char *time) {
  char path[1024], text[4096], *out = NULL;
  snprintf(path, sizeof path, "%s/%s.xml", dir, name);
  snprintf(text, sizeof text, fmt, tu_src(), time);
  tu_write(path, text);
  int rc =
      tu_run(&out, "cd %s && %s run %s.xml -o %s_ser.msh --report %s_ser.json -q", dir, tu_cli(), name, name, name);
  if (rc) fprintf(stderr, "%s", out);
  free(out);
  rc |= tu_mpirun(&out, NP, "sh -c 'cd %s && %s run %s.xml -o %s_par.msh --report %s_par.json'", dir, tu_cli(), name,
                  name, name);
  if (rc) fprintf(stderr, "%s", out);
  snprintf(par_out[k], sizeof par_out[k], "%s", out ? out : "");
  free(out);
  return rc;
}

static int setup(void **state) {
  (void)state;
  snprintf(dir, sizeof dir, "%s", tu_tmpdir());
  return run_pair(0, "tl", tunnel, "target=\"5.2e-5\"") | run_pair(1, "tm", tunnel, "") |
         run_pair(2, "pl", plate, "target=\"1.5e-6\"");
}

static cJSON *load(const char *name, const char *run) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s_%s.json", dir, name, run);
  cJSON *j = tu_json_load(path);
  assert_non_null(j);
  return j;
}

static double num(const cJSON *o, const char *dotted) { return tu_json_number(o, dotted); }

static void close_to(double a, double b) { assert_true(a == b || fabs(a - b) <= 1e-12 * fmax(fabs(a), fabs(b))); }

static const char *text(const cJSON *o, const char *a, const char *b) {
  const cJSON *x = cJSON_GetObjectItem(o, a);
  if (b) x = cJSON_GetObjectItem(x, b);
  assert_non_null(x);
  return x->valuestring;
}

/* The shape-limited lists, entry by entry. */
static void same_shape(const cJSON *s, const cJSON *p) {
  const cJSON *ls = cJSON_GetObjectItem(s, "shape_limited"), *lp = cJSON_GetObjectItem(p, "shape_limited");
  assert_int_equal(num(s, "below_target"), num(p, "below_target"));
  assert_int_equal(num(s, "shape_limited_count"), num(p, "shape_limited_count"));
  assert_int_equal(cJSON_GetArraySize(ls), cJSON_GetArraySize(lp));
  for (int k = 0; k < cJSON_GetArraySize(ls); k++) {
    const cJSON *a = cJSON_GetArrayItem(ls, k), *b = cJSON_GetArrayItem(lp, k);
    assert_int_equal(num(a, "element"), num(b, "element"));
    assert_string_equal(text(a, "group", NULL), text(b, "group", NULL));
    assert_string_equal(text(a, "feature", "kind"), text(b, "feature", "kind"));
    assert_int_equal(num(a, "feature.entity"), num(b, "feature.entity"));
    assert_int_equal(num(a, "feature.entity_dim"), num(b, "feature.entity_dim"));
    close_to(num(a, "feature.size"), num(b, "feature.size"));
    close_to(num(a, "quality"), num(b, "quality"));
    close_to(num(a, "reach"), num(b, "reach"));
    assert_string_equal(text(a, "remedy", "kind"), text(b, "remedy", "kind"));
  }
}

/* The layers, group by group. */
static void same_layers(const cJSON *s, const cJSON *p) {
  const cJSON *ls = cJSON_GetObjectItem(s, "thickness_limited"), *lp = cJSON_GetObjectItem(p, "thickness_limited");
  assert_int_equal(cJSON_GetArraySize(ls), cJSON_GetArraySize(lp));
  for (int k = 0; k < cJSON_GetArraySize(ls); k++) {
    const cJSON *a = cJSON_GetArrayItem(ls, k), *b = cJSON_GetArrayItem(lp, k);
    assert_string_equal(text(a, "group", NULL), text(b, "group", NULL));
    assert_int_equal(num(a, "elements"), num(b, "elements"));
    assert_int_equal(num(a, "element"), num(b, "element"));
    assert_int_equal(cJSON_IsTrue(cJSON_GetObjectItem(a, "at_minimum")),
                     cJSON_IsTrue(cJSON_GetObjectItem(b, "at_minimum")));
    close_to(num(a, "thickness"), num(b, "thickness"));
    close_to(num(a, "reach"), num(b, "reach"));
    close_to(num(a, "size"), num(b, "size"));
  }
}

/* No warning that the distributed run cannot tell. */
static void no_note(const cJSON *p) {
  const cJSON *w;
  cJSON_ArrayForEach(w, cJSON_GetObjectItem(p, "warnings")) assert_null(strstr(w->valuestring, "does not tell"));
}

/* View name of the merged parts of NAME_par against the serial output's:
 * the same elements, the same values. */
static void same_view(const char *model, const char *name) {
  char whole[1024], parts[1024];
  tu_view a, b;
  tu_view_diff d;
  snprintf(whole, sizeof whole, "%s/%s_ser.msh", dir, model);
  snprintf(parts, sizeof parts, "%s/%s_par.msh", dir, model);
  tu_gmsh_begin();
  assert_int_equal(tu_view_pair(whole, parts, NP, name, &a, &b), 0);
  tu_view_compare(&a, &b, &d);
  assert_true(a.n > 0);
  assert_int_equal(d.missing, 0);
  assert_true(d.worst <= 1e-12);
  tu_view_free(&a), tu_view_free(&b);
  tu_gmsh_end();
}

static void test_tunnel(void **state) {
  (void)state;
  cJSON *s = load("tl", "ser"), *p = load("tl", "par");
  const cJSON *ly = cJSON_GetArrayItem(cJSON_GetObjectItem(s, "thickness_limited"), 0);
  assert_non_null(ly);
  assert_string_equal(text(ly, "group", NULL), "lining");
  assert_int_equal(num(ly, "elements"), 24);
  assert_true(fabs(num(ly, "thickness") - 0.300) < 5e-4);
  assert_int_equal(num(s, "shape_limited_count"), 24);
  same_shape(s, p);
  same_layers(s, p);
  no_note(p);
  assert_non_null(strstr(par_out[0], "24 element(s), 0.3 m thick"));
  same_view("tl", "thickness limited");
  same_view("tl", "shape limited");
  cJSON_Delete(s), cJSON_Delete(p);
}

static void test_tunnel_minimum(void **state) {
  (void)state;
  cJSON *s = load("tm", "ser"), *p = load("tm", "par");
  const cJSON *ly = cJSON_GetArrayItem(cJSON_GetObjectItem(s, "thickness_limited"), 0);
  assert_non_null(ly);
  assert_true(cJSON_IsTrue(cJSON_GetObjectItem(ly, "at_minimum")));
  same_layers(s, p);
  cJSON_Delete(s), cJSON_Delete(p);
}

/* How many of the parts of NAME_par hold one of the tags. */
static int parts_holding(const char *name, const cJSON *list) {
  int n = 0, ierr = 0;
  for (int k = 1; k <= NP; k++) {
    char path[1024];
    int *types = NULL, hit = 0;
    size_t nt = 0, **tags = NULL, *ntags = NULL, ntt = 0, **nodes = NULL, *nnodes = NULL, nnt = 0;
    snprintf(path, sizeof path, "%s/%s_par_%d.msh", dir, name, k);
    gmshClear(&ierr), gmshOpen(path, &ierr);
    assert_int_equal(ierr, 0);
    gmshModelMeshGetElements(&types, &nt, &tags, &ntags, &ntt, &nodes, &nnodes, &nnt, 2, -1, &ierr);
    for (size_t t = 0; t < nt; t++) {
      for (size_t e = 0; e < ntags[t]; e++) {
        const cJSON *it;
        cJSON_ArrayForEach(it, list) hit |= (size_t)num(it, "element") == tags[t][e];
      }
      gmshFree(tags[t]), gmshFree(nodes[t]);
    }
    gmshFree(types), gmshFree(tags), gmshFree(ntags), gmshFree(nodes), gmshFree(nnodes);
    n += hit;
  }
  return n;
}

static void test_plate(void **state) {
  (void)state;
  cJSON *s = load("pl", "ser"), *p = load("pl", "par");
  assert_true(num(s, "shape_limited_count") >= 10);
  assert_true(num(s, "below_target") > num(s, "shape_limited_count"));
  same_shape(s, p);
  same_layers(s, p);
  no_note(p);
  same_view("pl", "shape limited");
  tu_gmsh_begin();
  assert_true(parts_holding("pl", cJSON_GetObjectItem(p, "shape_limited")) >= 2);
  tu_gmsh_end();
  cJSON_Delete(s), cJSON_Delete(p);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_tunnel), cmocka_unit_test(test_tunnel_minimum),
                                     cmocka_unit_test(test_plate)};
  return cmocka_run_group_tests(tests, setup, NULL);
}
