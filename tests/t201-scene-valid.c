/* Scene reader, valid input: the full scene of DESIGN.md (plus an external
 * effect) is read into the expected names, groups, properties, defaults,
 * resolved paths, effects in order with their attributes and time options;
 * a minimal scene gets the documented defaults; <mesh> sources, relative
 * scene paths and multi-line elements are handled. Fixtures are written into
 * a fresh temporary directory. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "testutil.h"
#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/scene.h"

static char dir[PATH_MAX]; /* temporary directory of the fixtures */

static void write_file(const char *name, const char *text) {
  char path[PATH_MAX * 2];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

static void make_subdir(const char *name) {
  char path[PATH_MAX * 2];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  assert_int_equal(mkdir(path, 0700), 0);
}

static int setup(void **state) {
  (void)state;
  strcpy(dir, "/tmp/dtm-t201-XXXXXX");
  if (!mkdtemp(dir)) return -1;
  dtm_error_clear();
  return 0;
}

static int teardown(void **state) {
  (void)state;
  tu_remove_tree(dir);
  return 0;
}

static dtm_scene *load(const char *name) {
  char path[PATH_MAX * 2];
  dtm_scene *s = NULL;
  snprintf(path, sizeof path, "%s/%s", dir, name);
  int rc = dtm_scene_load(path, &s);
  if (rc) fprintf(stderr, "unexpected error: %s\n", dtm_error_message());
  assert_int_equal(rc, DTM_OK);
  assert_non_null(s);
  return s;
}

static void assert_in_dir(const char *got, const char *rel) {
  char want[PATH_MAX * 2];
  snprintf(want, sizeof want, "%s/%s", dir, rel);
  assert_non_null(got);
  assert_string_equal(got, want);
}

static const char full_scene[] =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"                                        /* 1 */
    "<dtmap-scene version=\"1\">\n"                                                       /* 2 */
    "  <geometry file=\"geo/disc.geo\"/>\n"                                               /* 3 */
    "  <meshing size=\"1e-3\" min-size=\"2e-4\" order=\"2\" dim=\"2\"/>\n"                /* 4 */
    "  <material name=\"granite\" groups=\"rock\" E=\"60e9\" nu=\"0.25\" rho=\"2700\"\n"  /* 5 */
    "            conductivity=\"3\" heat-capacity=\"790\"\n"                              /* 6 */
    "            permeability=\"1e-15\" viscosity=\"1e-3\" storage=\"1e-9\"\n"            /* 7 */
    "            fracture-energy=\"50\" strength=\"10e6\"/>\n"                            /* 8 */
    "  <material name=\"steel\" groups=\"platen_top  platen_bottom\t7\" E=\"210e9\"\n"    /* 9 */
    "            nu=\"0.3\" rho=\"7850\" xi=\"0.01\" alpha=\"0\" beta=\"1e-9\"/>\n"       /* 10 */
    "  <!-- for elements in no named group -->\n"                                         /* 11 */
    "  <material name=\"filler\" default=\"true\" E=\"1e9\" nu=\"-0.5\" rho=\"1000\"/>\n" /* 12 */
    "  <effects>\n"                                                                       /* 13 */
    "    <elastic formulation=\"plane-strain\" length=\"eigen\"/>\n"                      /* 14 */
    "    <damping xi=\"0.05\"/>\n"                                                        /* 15 */
    "    <thermal/>\n"                                                                    /* 16 */
    "    <hydraulic/>\n"                                                                  /* 17 */
    "    <cohesive groups=\"rock\" elements-per-zone=\"5\" stiffness=\"1e14\"/>\n"        /* 18 */
    "    <effect name=\"creep\" library=\"lib/libcreep.so\" rate=\"1e-6\"/>\n"            /* 19 */
    "  </effects>\n"                                                                      /* 20 */
    "  <time safety=\"0.8\" target=\"2e-8\" duration=\"1e-4\" f-max=\"1e5\"\n"            /* 21 */
    "        elements-per-wavelength=\"12\"/>\n"                                          /* 22 */
    "  <output mesh=\"out/disc_dt.msh\" report=\"/abs/disc_dt.json\"/>\n"                 /* 23 */
    "</dtmap-scene>\n";                                                                   /* 24 */

static void write_full(void) {
  make_subdir("geo");
  write_file("geo/disc.geo", "// dummy\n");
  write_file("scene.xml", full_scene);
}

static void test_paths_and_meshing(void **state) {
  (void)state;
  write_full();
  dtm_scene *s = load("scene.xml");
  assert_string_equal(s->dir, dir);
  assert_in_dir(s->geometry, "geo/disc.geo");
  assert_null(s->mesh);
  assert_int_equal(s->source_line, 3);
  assert_float_equal(s->mesh_size, 1e-3, 1e-18);
  assert_float_equal(s->mesh_min_size, 2e-4, 1e-18);
  assert_int_equal(s->mesh_order, 2);
  assert_int_equal(s->mesh_dim, 2);
  assert_in_dir(s->out_mesh, "out/disc_dt.msh");
  assert_string_equal(s->out_report, "/abs/disc_dt.json");
  dtm_scene_destroy(&s);
  assert_null(s);
}

static void test_materials(void **state) {
  (void)state;
  write_full();
  dtm_scene *s = load("scene.xml");
  assert_int_equal(s->nmaterials, 3);
  const dtm_scene_material *g = &s->materials[0], *st = &s->materials[1], *f = &s->materials[2];
  assert_string_equal(g->m.name, "granite");
  assert_ptr_equal(g->m.file, s->path);
  assert_int_equal(g->m.line, 5); /* where the multi-line start tag begins */
  assert_int_equal(g->is_default, 0);
  assert_int_equal(g->ngroups, 1);
  assert_string_equal(g->groups[0], "rock");
  for (int i = 0; i < s->nprops; i++) /* all but xi alpha beta */
    assert_int_equal(dtm_material_has(&g->m, i), strcmp(s->prop_names[i], "xi") && strcmp(s->prop_names[i], "alpha") &&
                                                     strcmp(s->prop_names[i], "beta"));
  assert_float_equal(dtm_material_value(&g->m, "E"), 60e9, 1e-3);
  assert_float_equal(dtm_material_value(&g->m, "nu"), 0.25, 1e-15);
  assert_float_equal(dtm_material_value(&g->m, "permeability"), 1e-15, 1e-30);
  assert_float_equal(dtm_material_value(&g->m, "strength"), 10e6, 1e-6);
  assert_int_equal(st->m.line, 9);
  assert_int_equal(st->ngroups, 3);
  assert_string_equal(st->groups[1], "platen_bottom");
  assert_string_equal(st->groups[2], "7");
  assert_float_equal(dtm_material_value(&st->m, "beta"), 1e-9, 1e-24);
  assert_true(dtm_material_has(&st->m, dtm_scene_property_index(s, "alpha")));
  assert_false(dtm_material_has(&st->m, dtm_scene_property_index(s, "conductivity")));
  assert_int_equal(f->is_default, 1);
  assert_int_equal(f->ngroups, 0);
  assert_int_equal(f->m.line, 12);
  assert_float_equal(dtm_material_value(&f->m, "nu"), -0.5, 1e-15);
  dtm_scene_destroy(&s);
}

static void test_effects(void **state) {
  (void)state;
  static const char *const names[] = {"elastic", "damping", "thermal", "hydraulic", "cohesive", "creep"};
  write_full();
  dtm_scene *s = load("scene.xml");
  assert_int_equal(s->effects_line, 13);
  assert_int_equal(s->neffects, 6);
  for (int i = 0; i < 6; i++) {
    assert_string_equal(s->effects[i].name, names[i]);
    assert_int_equal(s->effects[i].line, 14 + i);
  }
  const dtm_scene_effect *e = s->effects;
  assert_int_equal(e[0].nattr, 2);
  assert_string_equal(e[0].keys[0], "formulation");
  assert_string_equal(e[0].values[0], "plane-strain");
  assert_string_equal(dtm_scene_effect_attr(&e[0], "length"), "eigen");
  assert_null(dtm_scene_effect_attr(&e[0], "xi"));
  assert_null(e[0].library);
  assert_string_equal(dtm_scene_effect_attr(&e[1], "xi"), "0.05");
  assert_int_equal(e[2].nattr, 0);
  assert_string_equal(dtm_scene_effect_attr(&e[4], "groups"), "rock");
  assert_string_equal(dtm_scene_effect_attr(&e[4], "stiffness"), "1e14");
  assert_int_equal(e[5].nattr, 3);
  assert_string_equal(dtm_scene_effect_attr(&e[5], "rate"), "1e-6");
  assert_string_equal(dtm_scene_effect_attr(&e[5], "name"), "creep");
  assert_in_dir(e[5].library, "lib/libcreep.so");
  dtm_scene_destroy(&s);
}

static void test_time(void **state) {
  (void)state;
  write_full();
  dtm_scene *s = load("scene.xml");
  assert_float_equal(s->safety, 0.8, 1e-15);
  assert_float_equal(s->target, 2e-8, 1e-22);
  assert_float_equal(s->duration, 1e-4, 1e-18);
  assert_float_equal(s->f_max, 1e5, 1e-9);
  assert_float_equal(s->elements_per_wavelength, 12, 1e-15);
  dtm_scene_destroy(&s);
}

/* A <mesh> source, no optional elements: every documented default. */
static void test_minimal_defaults(void **state) {
  (void)state;
  write_file("part.MSH", "");
  write_file("min.xml", "<dtmap-scene version=\"1\"><mesh file=\"part.MSH\"/>"
                        "<material name=\"m\" default=\"1\" E=\"1\" nu=\"0\" rho=\"1\" plausible=\"no-check\"/>"
                        "<effects><thermal/></effects></dtmap-scene>");
  dtm_scene *s = load("min.xml");
  assert_null(s->geometry);
  assert_in_dir(s->mesh, "part.MSH");
  assert_int_equal(s->source_line, 1);
  assert_float_equal(s->mesh_size, 0, 0);
  assert_float_equal(s->mesh_min_size, 0, 0);
  assert_int_equal(s->mesh_order, 1);
  assert_int_equal(s->mesh_dim, 0);
  assert_float_equal(s->safety, 0.9, 1e-15);
  assert_float_equal(s->target, 0, 0);
  assert_float_equal(s->duration, 0, 0);
  assert_float_equal(s->f_max, 0, 0);
  assert_float_equal(s->elements_per_wavelength, 10, 0);
  assert_null(s->out_mesh);
  assert_null(s->out_report);
  assert_int_equal(s->materials[0].is_default, 1);
  assert_int_equal(s->materials[0].no_plausible_check, 1); /* E = rho = 1: meant, not refused */
  assert_int_equal(s->neffects, 1);
  assert_string_equal(s->effects[0].name, "thermal");
  dtm_scene_destroy(&s);
}

/* A scene given by a bare file name lives in "."; paths stay relative. */
static void test_relative_scene_path(void **state) {
  (void)state;
  char cwd[PATH_MAX];
  dtm_scene *s = NULL;
  write_file("Disc.STEP", "");
  write_file("rel.xml", "<dtmap-scene version=\"1\"><geometry file=\"Disc.STEP\"/>"
                        "<material name=\"m\" E=\"70e9\" nu=\"0\" rho=\"2700\"/>"
                        "<effects><elastic/></effects></dtmap-scene>");
  assert_non_null(getcwd(cwd, sizeof cwd));
  assert_int_equal(chdir(dir), 0);
  int rc = dtm_scene_load("rel.xml", &s);
  assert_int_equal(chdir(cwd), 0);
  assert_int_equal(rc, DTM_OK);
  assert_string_equal(s->path, "rel.xml");
  assert_string_equal(s->dir, ".");
  assert_string_equal(s->geometry, "Disc.STEP");
  dtm_scene_destroy(&s);
}

/* The same scene read from memory: same paths (resolved against the
 * directory of the name given), same lines in messages; and an error names
 * the name and the line. */
static void test_from_memory(void **state) {
  (void)state;
  write_full();
  char name[PATH_MAX * 2];
  snprintf(name, sizeof name, "%s/virtual.xml", dir);
  dtm_scene *s = NULL;
  assert_int_equal(dtm_scene_load_memory(full_scene, sizeof full_scene - 1, name, &s), DTM_OK);
  assert_string_equal(s->path, name);
  assert_in_dir(s->geometry, "geo/disc.geo");
  assert_int_equal(s->source_line, 3);
  assert_int_equal(s->neffects, 6);
  assert_int_equal(s->effects[4].line, 18);
  dtm_scene_destroy(&s);
  static const char bad[] = "<dtmap-scene version=\"1\">\n  <geometry file=\"geo/disc.geo\"/>\n  <bogus/>\n";
  assert_int_equal(dtm_scene_load_memory(bad, sizeof bad - 1, name, &s), DTM_ERR_INPUT);
  assert_null(s);
  char want[PATH_MAX * 2 + 8];
  snprintf(want, sizeof want, "%s:", name);
  assert_non_null(strstr(dtm_error_message(), want));
  dtm_error_clear();
}

static void test_destroy_null(void **state) {
  (void)state;
  dtm_scene *s = NULL;
  dtm_scene_destroy(&s);
  dtm_scene_destroy(NULL);
  assert_null(dtm_scene_effect_attr(NULL, "x"));
}

int main(int argc, char **argv) {
  (void)argc;
  (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_paths_and_meshing, setup, teardown),
      cmocka_unit_test_setup_teardown(test_materials, setup, teardown),
      cmocka_unit_test_setup_teardown(test_effects, setup, teardown),
      cmocka_unit_test_setup_teardown(test_time, setup, teardown),
      cmocka_unit_test_setup_teardown(test_minimal_defaults, setup, teardown),
      cmocka_unit_test_setup_teardown(test_relative_scene_path, setup, teardown),
      cmocka_unit_test_setup_teardown(test_from_memory, setup, teardown),
      cmocka_unit_test(test_destroy_null),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
