/* Shape-limited elements on real Gmsh meshes of geometries written here.
 *  - flat: a 2 x 1 block with a sliver surface below it, the triangle
 *    (0,0), (1,-0.0437), (2,0) with one segment per side, so Gmsh meshes it
 *    as one triangle holding the whole 180 - 2 atan(0.0437) = 174.9952 deg
 *    angle at the model point (1,-0.0437). No size lifts it (the angle
 *    stays in one element); the report lists it with the feature "flat
 *    angle", that angle (1e-9 relative: one triangle, straight sides), the
 *    model point, and the remedy "split the angle"; the view "shape
 *    limited" marks it with 1 (DTM_FEATURE_FLAT_ANGLE).
 *  - thin: a strip 1 m x 5 mm meshed at 2 cm, whose triangles span it from
 *    one long side to the other (the sides do not touch): with a target
 *    twice the recommended step some are listed as "thin", with the gap
 *    (the distance of their corners across it) between 5 mm and the mesh
 *    size, and the remedy "mass" (the gap cannot grow).
 *  - platen: a Brazilian disc (R = 25 mm) whose platens meet it on 1 mm
 *    flats, so the contact corners are shallow and the flats short; with a
 *    target twice the recommended step refine either meets it, or exits 1
 *    with the corner elements (within 3 mm of a flat's end) in
 *    shape_limited, each with a remedy, and the kept mesh no dearer than
 *    the input. */
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

#include "testutil.h"

static char buf[4][600];

static const char *in_tmp(int slot, const char *name) {
  snprintf(buf[slot], sizeof buf[slot], "%s/%s", tu_tmpdir(), name);
  return buf[slot];
}

static const char flat_geo[] =
    "Point(1) = {0, 0, 0}; Point(2) = {2, 0, 0}; Point(3) = {2, 1, 0}; Point(4) = {0, 1, 0};\n"
    "Point(5) = {1, -0.0437, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1}; Line(5) = {1, 5}; Line(6) = {5, 2};\n"
    "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
    "Curve Loop(2) = {5, 6, -1}; Plane Surface(2) = {2};\n"
    "Transfinite Curve {1, 5, 6} = 2;\n"
    "Physical Surface(\"block\") = {1};\nPhysical Surface(\"sliver\") = {2};\n";

static const char flat_xml[] =
    "<dtmap-scene version=\"1\">\n  <geometry file=\"flat.geo\"/>\n"
    "  <meshing size=\"2.5\" dim=\"2\"/>\n"
    "  <material name=\"steel\" groups=\"block sliver\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
    "  <effects>\n    <elastic formulation=\"plane-strain\"/>\n  </effects>\n"
    "  <time target=\"1.2e-5\" duration=\"1e-2\"/>\n</dtmap-scene>\n";

/* The entry of shape_limited in group g, or NULL. */
static const cJSON *entry_in(const cJSON *list, const char *g) {
  const cJSON *e;
  cJSON_ArrayForEach(e, list) {
    const cJSON *grp = cJSON_GetObjectItem(e, "group");
    if (cJSON_IsString(grp) && !strcmp(grp->valuestring, g)) return e;
  }
  return NULL;
}

static void view_marks(const char *msh, double tag, double want) {
  int ierr = 0;
  tu_view v;
  gmshOpen(msh, &ierr);
  assert_int_equal(ierr, 0);
  assert_int_equal(tu_view_read("shape limited", &v), 0);
  int found = 0;
  for (size_t i = 0; i < v.n; i++)
    if ((double)v.tags[i] == tag) found = 1, assert_true(v.values[i] == want);
  assert_true(found);
  tu_view_free(&v);
  gmshClear(&ierr);
}

static void flat(void **unused) {
  char *log = NULL;
  tu_write(in_tmp(0, "flat.geo"), flat_geo);
  tu_write(in_tmp(1, "flat.xml"), flat_xml);
  int code = tu_run(&log, "%s run %s -o %s --report %s", tu_cli(), buf[1], in_tmp(2, "flat_dt.msh"),
                    in_tmp(3, "flat_dt.json"));
  fprintf(stderr, "%s\n", log);
  free(log);
  assert_int_equal(code, 0);
  cJSON *j = tu_json_load(buf[3]);
  const cJSON *s = entry_in(cJSON_GetObjectItem(j, "shape_limited"), "sliver");
  assert_non_null(s);
  const double want = 180.0 - 2.0 * atan(0.0437) * 45.0 / atan(1.0);
  assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(s, "feature"), "kind")->valuestring, "flat angle");
  assert_true(fabs(tu_json_number(s, "feature.angle") - want) <= 1e-9 * want);
  assert_true(tu_json_number(s, "feature.entity_dim") == 0 && tu_json_number(s, "feature.entity") == 5);
  assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(s, "remedy"), "kind")->valuestring, "split the angle");
  assert_true(tu_json_number(s, "reach") < 1.2e-5);
  view_marks(buf[2], tu_json_number(s, "element"), 1.0);
  cJSON_Delete(j);
  (void)unused;
}

/* The strip's scene, with a target (0: none). */
static void strip_scene(double target) {
  char text[1024], t[64] = "";
  if (target > 0) snprintf(t, sizeof t, "target=\"%.17g\" ", target);
  snprintf(text, sizeof text,
           "<dtmap-scene version=\"1\">\n  <geometry file=\"strip.geo\"/>\n"
           "  <meshing size=\"0.02\" dim=\"2\"/>\n"
           "  <material name=\"steel\" groups=\"strip\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
           "  <effects>\n    <elastic formulation=\"plane-stress\"/>\n  </effects>\n"
           "  <time %sduration=\"1e-3\"/>\n</dtmap-scene>\n",
           t);
  tu_write(in_tmp(1, "strip.xml"), text);
}

static cJSON *strip_run(void) {
  char *log = NULL;
  int code = tu_run(&log, "%s run %s -o %s --report %s -q", tu_cli(), buf[1], in_tmp(2, "strip_dt.msh"),
                    in_tmp(3, "strip_dt.json"));
  if (code) fprintf(stderr, "%s\n", log); /* a failed run's own words */
  free(log);
  assert_int_equal(code, 0);
  return tu_json_load(buf[3]);
}

static void thin(void **unused) {
  tu_write(in_tmp(0, "strip.geo"), "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 1, 0.005};\n"
                                   "Physical Surface(\"strip\") = {1};\n");
  strip_scene(0);
  cJSON *j = strip_run();
  double target = 2.0 * tu_json_number(j, "dt.recommended");
  cJSON_Delete(j);
  strip_scene(target);
  j = strip_run();
  const cJSON *e;
  int n = 0;
  cJSON_ArrayForEach(e, cJSON_GetObjectItem(j, "shape_limited")) {
    const cJSON *f = cJSON_GetObjectItem(e, "feature");
    if (strcmp(cJSON_GetObjectItem(f, "kind")->valuestring, "thin")) continue;
    double gap = tu_json_number(f, "size");
    assert_true(gap >= 0.005 * (1 - 1e-12) && gap <= 0.02);
    assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(e, "remedy"), "kind")->valuestring, "mass");
    n++;
  }
  assert_true(n > 0);
  cJSON_Delete(j);
  (void)unused;
}

static const char platen_geo[] =
    "SetFactory(\"OpenCASCADE\");\n"
    "R = 0.025; a = 0.0005; W = 0.060; T = 0.010; yc = Sqrt(R^2 - a^2); eps = 1e-6;\n"
    "Disk(1) = {0, 0, 0, R};\nRectangle(2) = {-R - 1e-3, -yc, 0, 2 * R + 2e-3, 2 * yc};\n"
    "BooleanIntersection(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };\n"
    "Rectangle(4) = {-W / 2,  yc, 0, W, T};\nRectangle(5) = {-W / 2, -yc - T, 0, W, T};\n"
    "BooleanFragments{ Surface{3, 4, 5}; Delete; }{}\n"
    "rock[] = Surface In BoundingBox{-R - eps, -yc - eps, -eps, R + eps, yc + eps, eps};\n"
    "ptop[] = Surface In BoundingBox{-W/2 - eps, yc - eps, -eps, W/2 + eps, yc + T + eps, eps};\n"
    "pbot[] = Surface In BoundingBox{-W/2 - eps, -yc - T - eps, -eps, W/2 + eps, -yc + eps, eps};\n"
    "Physical Surface(\"rock\") = {rock[]};\nPhysical Surface(\"platen_top\") = {ptop[]};\n"
    "Physical Surface(\"platen_bottom\") = {pbot[]};\n";

static const char platen_xml[] =
    "<dtmap-scene version=\"1\">\n  <geometry file=\"platen.geo\"/>\n"
    "  <meshing size=\"3e-3\" min-size=\"1e-3\" dim=\"2\"/>\n"
    "  <material name=\"granite\" groups=\"rock\" E=\"60e9\" nu=\"0.25\" rho=\"2700\"/>\n"
    "  <material name=\"steel\" groups=\"platen_top platen_bottom\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
    "  <effects>\n    <elastic formulation=\"plane-strain\"/>\n  </effects>\n"
    "  <time duration=\"1e-4\"/>\n</dtmap-scene>\n";

/* Distance from (x, y) to the nearest end of a flat, (+-a, +-yc). */
static double to_corner(double x, double y) {
  const double a = 5e-4, yc = sqrt(0.025 * 0.025 - a * a);
  return hypot(fabs(x) - a, fabs(y) - yc);
}

static void check_corners(const cJSON *list) {
  const cJSON *e;
  int near = 0;
  assert_true(cJSON_GetArraySize(list) > 0);
  cJSON_ArrayForEach(e, list) {
    const cJSON *c = cJSON_GetObjectItem(e, "centroid");
    near += to_corner(cJSON_GetArrayItem(c, 0)->valuedouble, cJSON_GetArrayItem(c, 1)->valuedouble) < 3e-3;
    assert_non_null(cJSON_GetObjectItem(cJSON_GetObjectItem(e, "remedy"), "text"));
  }
  assert_true(near > 0);
}

static void platen(void **unused) {
  char *log = NULL;
  tu_write(in_tmp(0, "platen.geo"), platen_geo);
  tu_write(in_tmp(1, "platen.xml"), platen_xml);
  int code = tu_run(&log, "%s run %s -o %s --report %s -q", tu_cli(), buf[1], in_tmp(2, "platen_dt.msh"),
                    in_tmp(3, "platen_dt.json"));
  if (code) fprintf(stderr, "%s\n", log);
  free(log);
  assert_int_equal(code, 0);
  cJSON *j = tu_json_load(buf[3]);
  double target = 2.0 * tu_json_number(j, "dt.recommended");
  cJSON_Delete(j);
  code = tu_run(&log, "%s refine %s --target %.17g -o %s --report %s", tu_cli(), buf[1], target,
                in_tmp(2, "platen_refined.msh"), in_tmp(3, "platen_refined.json"));
  fprintf(stderr, "%s\n", log);
  free(log);
  j = tu_json_load(buf[3]);
  assert_non_null(j);
  const cJSON *rounds = cJSON_GetObjectItem(cJSON_GetObjectItem(j, "refine"), "rounds");
  double input = cJSON_GetObjectItem(cJSON_GetArrayItem(rounds, 0), "element_steps")->valuedouble;
  assert_true(tu_json_number(j, "cost.element_steps") <= input);
  if (code == 0)
    assert_true(tu_json_number(j, "dt.recommended") >= target);
  else
    assert_int_equal(code, 1), check_corners(cJSON_GetObjectItem(j, "shape_limited"));
  cJSON_Delete(j);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(flat), cmocka_unit_test(thin), cmocka_unit_test(platen)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  tu_gmsh_end();
  return r;
}
