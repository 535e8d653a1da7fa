/* dtmap's ONELAB panel keeps the base scene's system of units, driven by
 * Gmsh's own machinery as in t802 and t804 (the test process is the Gmsh
 * session; gmshOnelabRun launches `dtmap -onelab dtmap SOCKET` as the GUI's
 * Run button does), on a socket of its own. The base scene beside the model
 * is in mm-t-s: a 20 x 20 x 60 mm box (.geo in mm), mesh size 8 mm, steel
 * with E = 210000 MPa and rho = 7.85e-9 t/mm^3. Checked: the panel shows the
 * mesh size in mm and E, rho in MPa, t/mm^3 with the scene's own numbers;
 * the library's steel is shown converted into them (210e9 Pa = 210000 MPa);
 * the scene the panel writes (saved beside the model) says units="mm-t-s";
 * and the recommended step and smallest element step it computes equal
 * those of `dtmap run` on the same base scene (the same mesh: same geometry,
 * same size, same Gmsh) to 1e-12 relative (both are the same computation on
 * the same numbers; the only difference allowed is the text round trip of
 * the values through the panel, %.17g, exact). A value typed in the panel is
 * in the scene's units: E typed as 4 x 210000 (MPa) doubles the wave speed,
 * so it halves every element step of this elastic-only scene (closed form,
 * c = sqrt(E/rho) scaling; 1e-12 for rounding). Two more base scenes in
 * mm-t-s give dtmap run's steps from the panel as well: a .msh meshed in
 * metres with <mesh unit="m"> (the panel's scene keeps the unit: read in mm
 * it would be 1000x smaller), and the box with an embedded sheet, a membrane
 * 2 mm thick (the thickness field shows 2, in mm). The old panel wrote an SI
 * scene with the mm numbers (mesh size 8 m on a box of 60 m, E read as
 * 210000 Pa, rho as 7.85e-9 kg/m^3) and labelled them m, Pa, kg/m^3. */
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
#include <unistd.h>

#include "onelab.h"
#include "testutil.h"

static char dir[512], geo[600], saved[600], report[600], msh_m[600], report_m[600], sheet_geo[600], report_sheet[600];

static const char *const box_geo = "SetFactory(\"OpenCASCADE\");\n"
                                   "Box(1) = {0, 0, 0, 20, 20, 60};\n"
                                   "Physical Volume(\"block\") = {1};\n";

static const char *const box_xml = "<dtmap-scene version=\"1\" units=\"mm-t-s\">\n"
                                   "  <geometry file=\"box.geo\"/>\n"
                                   "  <meshing size=\"8\" dim=\"3\"/>\n"
                                   "  <material name=\"steel\" default=\"true\" E=\"210000\" nu=\"0.3\" "
                                   "rho=\"7.85e-9\"/>\n"
                                   "  <effects><elastic/></effects>\n"
                                   "  <time safety=\"0.9\"/>\n"
                                   "  <output mesh=\"panel_dt.msh\"/>\n"
                                   "</dtmap-scene>\n";

/* The same box drawn in metres, meshed here into a .msh (no unit of its own):
 * the base scene, in mm-t-s, declares <mesh unit="m">. */
static const char *const box_m_geo = "SetFactory(\"OpenCASCADE\");\n"
                                     "Box(1) = {0, 0, 0, 0.02, 0.02, 0.06};\n"
                                     "Physical Volume(\"block\") = {1};\n"
                                     "Mesh.MeshSizeMax = 0.008;\n";

static const char *const box_m_xml = "<dtmap-scene version=\"1\" units=\"mm-t-s\">\n"
                                     "  <mesh file=\"box_m.msh\" unit=\"m\"/>\n"
                                     "  <material name=\"steel\" default=\"true\" E=\"210000\" nu=\"0.3\" "
                                     "rho=\"7.85e-9\"/>\n"
                                     "  <effects><elastic/></effects>\n"
                                     "  <output mesh=\"box_m_dt.msh\"/>\n"
                                     "</dtmap-scene>\n";

/* The mm box with a 6 x 6 mm sheet embedded at mid-height: a membrane 2 mm
 * thick in the base scene. */
static const char *const sheet_box_geo = "SetFactory(\"OpenCASCADE\");\n"
                                         "Box(1) = {0, 0, 0, 20, 20, 60};\n"
                                         "Rectangle(100) = {2, 2, 30, 6, 6};\n"
                                         "Surface{100} In Volume{1};\n"
                                         "Physical Volume(\"block\") = {1};\n"
                                         "Physical Surface(\"sheet\") = {100};\n";

static const char *const sheet_box_xml = "<dtmap-scene version=\"1\" units=\"mm-t-s\">\n"
                                         "  <geometry file=\"sheet_box.geo\"/>\n"
                                         "  <meshing size=\"8\" dim=\"3\"/>\n"
                                         "  <material name=\"steel\" default=\"true\" E=\"210000\" nu=\"0.3\" "
                                         "rho=\"7.85e-9\" groups=\"block sheet\"/>\n"
                                         "  <section groups=\"sheet\" kind=\"membrane\" thickness=\"2\"/>\n"
                                         "  <effects><elastic/></effects>\n"
                                         "  <output mesh=\"sheet_box_dt.msh\"/>\n"
                                         "</dtmap-scene>\n";

/* Mesh the metre box into msh_m. */
static void mesh_in_metres(void) {
  char path[700];
  int ierr = 0;
  snprintf(path, sizeof path, "%s/box_m.geo", dir);
  tu_write(path, box_m_geo);
  tu_gmsh_begin();
  gmshOpen(path, &ierr);
  gmshModelMeshGenerate(3, &ierr);
  gmshWrite(msh_m, &ierr);
  tu_gmsh_end();
  assert_int_equal(ierr, 0);
}

/* `dtmap run` on the base scene xml (written into dir as name), its report to rep. */
static int cli_run(const char *name, const char *xml, const char *rep) {
  char path[700], *log = NULL;
  snprintf(path, sizeof path, "%s/%s", dir, name);
  tu_write(path, xml);
  int r = tu_run(&log, "%s run %s -q -o %s/cli_%s.msh --report %s", tu_cli(), path, dir, name, rep);
  if (r) fprintf(stderr, "%s\n", log ? log : "");
  free(log);
  return r;
}

static int setup(void **state) {
  (void)state;
  char path[700], *log = NULL;
  snprintf(dir, sizeof dir, "%s/units", tu_tmpdir());
  snprintf(geo, sizeof geo, "%s/box.geo", dir);
  snprintf(saved, sizeof saved, "%s/saved.xml", dir);
  snprintf(report, sizeof report, "%s/cli.json", dir);
  snprintf(msh_m, sizeof msh_m, "%s/box_m.msh", dir);
  snprintf(report_m, sizeof report_m, "%s/cli_m.json", dir);
  snprintf(sheet_geo, sizeof sheet_geo, "%s/sheet_box.geo", dir);
  snprintf(report_sheet, sizeof report_sheet, "%s/cli_sheet.json", dir);
  int r = tu_run(NULL, "mkdir -p %s", dir);
  tu_write(sheet_geo, sheet_box_geo);
  mesh_in_metres();
  tu_write(geo, box_geo);
  snprintf(path, sizeof path, "%s/box.xml", dir);
  tu_write(path, box_xml);
  if (!r) r = tu_run(&log, "%s run %s -q -o %s/cli_dt.msh --report %s", tu_cli(), path, dir, report);
  if (r) fprintf(stderr, "%s\n", log ? log : "");
  free(log);
  if (!r) r = cli_run("box_m.xml", box_m_xml, report_m);
  if (!r) r = cli_run("sheet_box.xml", sheet_box_xml, report_sheet);
  return r;
}

static int close_to(double a, double b, double rel) { return fabs(a - b) <= rel * fabs(b); }

/* The recommended and smallest element steps of the panel's run equal those
 * of dtmap run (report rep) to 1e-12 relative; the panel's saved scene (at
 * saved) holds want. */
static void assert_run_matches(const char *model, const char *rep, const char *want) {
  tu_onelab_session(model, "t805");
  tu_onelab_run("check");
  double rec, dmin;
  char *text = tu_onelab_compute_saved(saved, &rec, &dmin);
  if (!strstr(text, want)) fprintf(stderr, "the panel's scene (expected %s):\n%s\n", want, text);
  assert_non_null(strstr(text, want));
  free(text);
  cJSON *j = tu_json_load(rep);
  double r = tu_json_number(j, "dt.recommended"), m = tu_json_number(j, "dt.min");
  cJSON_Delete(j);
  fprintf(stderr, "%s: panel %.17g s (min %.17g s), dtmap run %.17g s (min %.17g s)\n", model, rec, dmin, r, m);
  assert_true(close_to(rec, r, 1e-12));
  assert_true(close_to(dmin, m, 1e-12));
}

/* The panel's fields carry the scene's units and numbers; the library's
 * steel is shown in MPa and t/mm^3. */
static void test_panel_units(void **state) {
  (void)state;
  tu_onelab_session(geo, "t805");
  tu_onelab_run("check");
  tu_onelab_assert_units("dtmap/3Mesh/0size", "mm");
  assert_true(tu_onelab_get_number("dtmap/3Mesh/0size") == 8);
  tu_onelab_assert_units("dtmap/4Materials/block/1E", "MPa");
  tu_onelab_assert_units("dtmap/4Materials/block/3rho", "t/mm^3");
  assert_true(tu_onelab_get_number("dtmap/4Materials/block/1E") == 210000);
  assert_true(tu_onelab_get_number("dtmap/4Materials/block/3rho") == 7.85e-9);
  tu_onelab_set_number("dtmap/4Materials/block/0material", 1); /* the library's first entry: steel */
  tu_onelab_run("check");
  assert_true(close_to(tu_onelab_get_number("dtmap/4Materials/block/1E"), 210000, 1e-15));
  assert_true(close_to(tu_onelab_get_number("dtmap/4Materials/block/3rho"), 7.85e-9, 1e-15));
  tu_gmsh_end();
}

/* The panel's run: its scene says units="mm-t-s" (with the mesh size of 8,
 * in mm: the same mesh), and its steps are those of `dtmap run` on the base
 * scene. */
static void test_same_step(void **state) {
  (void)state;
  assert_run_matches(geo, report, "<dtmap-scene version=\"1\" units=\"mm-t-s\">");
}

/* E typed in the panel is read in MPa: 4x E halves the element step. */
static void test_typed_value(void **state) {
  (void)state;
  tu_onelab_session(geo, "t805");
  tu_onelab_run("check");
  tu_onelab_set_number("dtmap/4Materials/block/0material", 0); /* custom */
  tu_onelab_run("check");
  tu_onelab_set_number("dtmap/4Materials/block/1E", 4 * 210000.0);
  tu_onelab_set_number("dtmap/4Materials/block/2nu", 0.3);
  tu_onelab_set_number("dtmap/4Materials/block/3rho", 7.85e-9);
  tu_onelab_run("compute");
  double dmin = tu_onelab_get_number("dtmap/9Results/2dt min");
  tu_gmsh_end();
  cJSON *rep = tu_json_load(report);
  double base = tu_json_number(rep, "dt.min");
  cJSON_Delete(rep);
  fprintf(stderr, "E x 4: %.17g s, base scene %.17g s\n", dmin, base);
  assert_true(close_to(dmin, base / 2, 1e-12));
}

/* A .msh in metres under a mm-t-s scene: the panel's scene keeps the
 * declared unit="m" (else the mesh is read in mm, 1000x smaller). */
static void test_mesh_unit(void **state) {
  (void)state;
  assert_run_matches(msh_m, report_m, "box_m.msh\" unit=\"m\"/>");
}

/* A membrane of a mm-t-s scene: its thickness shown in mm (2), the
 * steps those of dtmap run. */
static void test_section_units(void **state) {
  (void)state;
  tu_onelab_session(sheet_geo, "t805");
  tu_onelab_run("check");
  tu_onelab_assert_units("dtmap/4Materials/sheet/01thickness", "mm");
  assert_true(tu_onelab_get_number("dtmap/4Materials/sheet/01thickness") == 2);
  tu_gmsh_end();
  assert_run_matches(sheet_geo, report_sheet, "kind=\"membrane\" thickness=\"2\"");
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_panel_units), cmocka_unit_test(test_same_step),     cmocka_unit_test(test_typed_value),
      cmocka_unit_test(test_mesh_unit),   cmocka_unit_test(test_section_units),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
