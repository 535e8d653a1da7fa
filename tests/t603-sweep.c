/* The sweep on a real Gmsh geometry written by the test (a 1 m square,
 * OpenCASCADE, one physical surface, elastic plane strain with f-max): at
 * sizes 0.2, 0.1, 0.05 m a smaller size gives more elements and smaller
 * steps; the row's derived columns follow from its own fields (hours are
 * element-steps x the cost of one element-step; the phase error is at the
 * scene's f-max, NaN only where unresolved, and smaller on a finer mesh;
 * in_band agrees with the 1 % band); the CSV
 * reads back with its header and one row per size; the PNG is a real PNG
 * with a non-zero size in its IHDR chunk. Also the error paths: a <mesh>
 * scene, bad sizes, unwritable outputs, and the plot of rows without a
 * duration; and the error plot's labels (each point of the first curve
 * named, inside the box, over no marker, label or legend) on the bundled
 * scenes' sweeps. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/scene.h"
#include "cli-impl.h"
#include "dtmap/cost.h"
#include "dtmap/sweep.h"
#include "testutil.h"

#define NS 3
static const double sizes[NS] = {0.2, 0.1, 0.05};
static const char header[] = "h_m,elements,nodes,dt_min_s,dt_recommended_s,steps,element_steps,"
                             "element_steps_subcycled,subcycling_speedup,elements_per_zone,"
                             "elements_per_wavelength,time_s,frequency_hz,phase_error,phase_error_median,"
                             "unresolved,phase_error_subcycled,phase_error_mass_scaled,"
                             "elements_per_diffusion_length,cost_per_element_step_s,run_h,run_subcycled_h,"
                             "run_mass_scaled_h,in_band,failed";
#define NCOL 24

static char path_buf[4][512];
static const char *in_tmp(int slot, const char *name) {
  snprintf(path_buf[slot], sizeof path_buf[slot], "%s/%s", tu_tmpdir(), name);
  return path_buf[slot];
}

static dtm_scene *square_scene(void) {
  tu_write(in_tmp(0, "square.geo"), "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 1, 1};\n"
                                    "MeshSize{ PointsOf{ Surface{1}; } } = 1; // the sweep's size caps this\n"
                                    "Physical Surface(\"plate\") = {1};\n");
  tu_write(in_tmp(1, "square.xml"),
           "<dtmap-scene version=\"1\">\n  <geometry file=\"square.geo\"/>\n"
           "  <meshing size=\"0.1\" min-size=\"0.08\" dim=\"2\"/>\n"
           "  <material name=\"steel\" groups=\"plate\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
           "  <effects>\n    <elastic formulation=\"plane-strain\"/>\n  </effects>\n"
           "  <time duration=\"1e-3\" f-max=\"2e4\"/>\n</dtmap-scene>\n");
  dtm_scene *s = NULL;
  assert_int_equal(dtm_scene_load(path_buf[1], &s), 0);
  return s;
}

/* Within each row: steps, costs and the wavelength indicator follow from
 * its own fields (1e-15 relative: one division or multiplication each).
 * The recommended step is never below safety (0.9) x the element bound;
 * steps are whole (the same ceil, so exact) and costs count them;
 * subcycled levels step at the recommended step x 2^k, so the subcycled
 * cost is the plain one over the speed-up (>= 1). */
static void check_row(const dtm_sweep_row *r, double h) {
  assert_true(r->h == h);
  assert_true(r->elements > 0 && r->nodes > 0);
  assert_true(r->dt_min > 0 && r->recommended >= 0.9 * r->dt_min * (1 - 1e-15));
  assert_true(r->steps == ceil(1e-3 / r->recommended) && r->steps >= 1e-3 / r->recommended);
  assert_true(fabs(r->cost - (double)r->elements * r->steps) <= 1e-15 * r->cost);
  assert_true(r->speedup >= 1.0);
  double sub = r->cost / r->speedup;
  assert_true(fabs(r->cost_subcycled - sub) <= 1e-15 * sub);
  assert_true(r->cost_subcycled <= r->cost);
  assert_true(isnan(r->per_zone));
  assert_true(r->per_wavelength > 0 && isfinite(r->per_wavelength));
  assert_true(r->seconds > 0);
  /* hours: element-steps x the cost of one; the phase error at the scene's f-max */
  assert_true(r->per_element_step > 0);
  assert_true(fabs(r->hours - r->cost * r->per_element_step / 3600) <= 1e-15 * r->hours);
  assert_true(fabs(r->hours_subcycled - r->cost_subcycled * r->per_element_step / 3600) <= 1e-15 * r->hours);
  assert_true(isnan(r->hours_mass) && isnan(r->phase_mass)); /* no target */
  assert_true(r->frequency == 2e4 && !r->frequency_default && isnan(r->per_diffusion));
  assert_true(r->unresolved ? isnan(r->phase_error) : isfinite(r->phase_error));
  assert_int_equal(r->in_band, !r->unresolved && fabs(r->phase_error) <= DTM_BAND_PHASE);
}

/* A count's cell: digits only (a whole number, no exponent). */
static int whole_cell(const char *p) {
  size_t n = strspn(p, "0123456789");
  return n > 0 && (p[n] == ',' || p[n] == '\n' || p[n] == '\0');
}

/* Parse one CSV line into v[NCOL] (NaN for empty cells); counts (elements,
 * nodes, steps, element-steps) must be written as whole numbers. */
static int parse_line(char *line, double *v) {
  static const int whole[NCOL] = {0, 1, 1, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1};
  int k = 0;
  for (char *p = line, *end; k < NCOL; p = end + 1) {
    if (whole[k] && *p != ',' && !whole_cell(p)) return -1;
    v[k++] = *p == ',' || *p == '\n' ? NAN : strtod(p, &end);
    if (isnan(v[k - 1])) end = p;
    if (*end != ',') break;
  }
  return k;
}

/* Parse the CSV back: the exact header and one row of 24 fields per size;
 * h, elements, dt_min and the speed-up agree with the rows to %.9g (5e-9
 * relative), the counts exactly (whole numbers; the subcycled element-steps
 * rounded up). */
static void check_csv(const char *path, const dtm_sweep_row *rows) {
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  char line[1024];
  assert_non_null(fgets(line, sizeof line, f));
  line[strcspn(line, "\n")] = '\0';
  assert_string_equal(line, header);
  int n = 0;
  while (fgets(line, sizeof line, f)) {
    double v[NCOL];
    assert_int_equal(parse_line(line, v), NCOL);
    assert_true(n < NS);
    const dtm_sweep_row *r = &rows[n];
    assert_true(fabs(v[0] - r->h) <= 5e-9 * r->h);
    assert_true(v[1] == (double)r->elements && v[2] == (double)r->nodes);
    assert_true(fabs(v[3] - r->dt_min) <= 5e-9 * r->dt_min);
    assert_true(v[5] == r->steps && v[6] == r->cost && v[7] == ceil(r->cost_subcycled));
    assert_true(fabs(v[8] - r->speedup) <= 5e-9 * r->speedup);
    assert_true(isnan(v[9]) && v[10] > 0);
    assert_true(v[12] == 2e4 && v[15] == (double)r->unresolved && v[23] == r->in_band);
    assert_true(r->unresolved ? isnan(v[13]) : fabs(v[13] - r->phase_error) <= 5e-9 * fabs(r->phase_error));
    assert_true(fabs(v[20] - r->hours) <= 5e-9 * r->hours && isnan(v[22]) && isnan(v[17]));
    n++;
  }
  fclose(f);
  assert_int_equal(n, NS);
}

static uint32_t be32(const unsigned char *p) {
  return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* PNG signature, then the IHDR chunk (length 13) with width and height. */
static void check_png(const char *path) {
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  unsigned char b[24];
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  assert_int_equal(fread(b, 1, 24, f), 24);
  fclose(f);
  assert_memory_equal(b, sig, 8);
  assert_int_equal(be32(b + 8), 13);
  assert_memory_equal(b + 12, "IHDR", 4);
  assert_true(be32(b + 16) > 0 && be32(b + 20) > 0);
}

static void sweep_square(void **unused) {
  dtm_scene *s = square_scene();
  dtm_sweep_row rows[NS];
  assert_int_equal(dtm_sweep_run(s, sizes, NS, rows), 0);
  for (int i = 0; i < NS; i++) check_row(&rows[i], sizes[i]);
  for (int i = 1; i < NS; i++) {
    assert_true(rows[i].elements > rows[i - 1].elements);
    assert_true(rows[i].dt_min < rows[i - 1].dt_min);
    assert_true(rows[i].recommended < rows[i - 1].recommended);
    assert_true(rows[i].per_wavelength > rows[i - 1].per_wavelength);
    /* a finer mesh at the same frequency: a smaller error, or resolved at last */
    if (!rows[i - 1].unresolved) assert_true(fabs(rows[i].phase_error) < fabs(rows[i - 1].phase_error));
  }
  assert_int_equal(rows[NS - 1].unresolved, 0);
  dtm_sweep_print(rows, NS, stdout);
  assert_int_equal(dtm_sweep_write_csv(in_tmp(2, "square_sweep.csv"), rows, NS), 0);
  check_csv(path_buf[2], rows);
  assert_int_equal(dtm_cli_sweep_plot_titled(in_tmp(3, "square_sweep.png"), "square.xml", rows, NS), 0);
  check_png(path_buf[3]);
  dtm_scene_destroy(&s);
  (void)unused;
}

static void expect_error(int r, int code, const char *text) {
  assert_int_equal(r, code);
  assert_non_null(strstr(dtm_error_message(), text));
  dtm_error_clear();
}

static void bad_input(void **unused) {
  dtm_scene *s = square_scene();
  dtm_sweep_row rows[NS];
  const double bad[2][2] = {{0.1, -0.1}, {NAN, 0.1}};
  for (int i = 0; i < 2; i++) expect_error(dtm_sweep_run(s, bad[i], 2, rows), DTM_ERR_INPUT, "positive and finite");
  dtm_scene m = *s;
  m.geometry = NULL, m.mesh = "square.msh";
  expect_error(dtm_sweep_run(&m, sizes, NS, rows), DTM_ERR_INPUT, "sweep needs a geometry, not a mesh");
  dtm_sweep_row one = {.h = 0.1,
                       .elements = 10,
                       .nodes = 8,
                       .dt_min = 1e-6,
                       .recommended = 9e-7,
                       .steps = 10,
                       .cost = 100,
                       .cost_subcycled = 50,
                       .per_zone = NAN,
                       .per_wavelength = NAN,
                       .speedup = 2};
  expect_error(dtm_sweep_write_csv("/nonexistent-dir/x.csv", &one, 1), DTM_ERR_INPUT, "cannot write");
  expect_error(dtm_cli_sweep_plot("/nonexistent-dir/x.png", &one, 1), DTM_ERR_INPUT, "cannot write");
  dtm_scene_destroy(&s);
  (void)unused;
}

/* Without a duration the CSV leaves steps and costs empty and the plot
 * falls back to cost per simulated second (x = 1/h: no indicator). */
static void no_duration(void **unused) {
  dtm_sweep_row r[2];
  for (int i = 0; i < 2; i++)
    r[i] = (dtm_sweep_row){.h = 0.1 / (i + 1),
                           .elements = 100u << (2 * i),
                           .nodes = 60u << (2 * i),
                           .dt_min = 1e-6 / (i + 1),
                           .recommended = 0.9e-6 / (i + 1),
                           .steps = NAN,
                           .cost = NAN,
                           .cost_subcycled = NAN,
                           .per_zone = NAN,
                           .per_wavelength = NAN,
                           .seconds = 0.01,
                           .speedup = 1.5};
  assert_int_equal(dtm_sweep_write_csv(in_tmp(2, "nodur.csv"), r, 2), 0);
  FILE *f = fopen(path_buf[2], "r");
  char line[1024];
  assert_non_null(fgets(line, sizeof line, f));
  assert_non_null(fgets(line, sizeof line, f));
  fclose(f);
  assert_non_null(strstr(line, "9e-07,,,,1.5,,,0.01"));
  assert_int_equal(dtm_cli_sweep_plot(in_tmp(3, "nodur.png"), r, 2), 0);
  check_png(path_buf[3]);
  (void)unused;
}

/* A row of the error plot: size, elements, recommended step, run hours
 * (global, subcycled, mass scaled), phase errors (global, subcycled, mass
 * scaled; NaN: none), elements per zone, in band. */
static dtm_sweep_row error_row(double h, size_t n, double rec, const double t[3], const double e[3], double zone,
                               int band) {
  return (dtm_sweep_row){.h = h,
                         .elements = n,
                         .recommended = rec,
                         .hours = t[0],
                         .hours_subcycled = t[1],
                         .hours_mass = t[2],
                         .phase_error = e[0],
                         .phase_subcycled = e[1],
                         .phase_mass = e[2],
                         .per_zone = zone,
                         .per_diffusion = NAN,
                         .per_wavelength = NAN,
                         .frequency = 1e4,
                         .frequency_default = 1,
                         .speedup = t[0] / t[1],
                         .in_band = band};
}

static int boxes_meet(const dtm_plot_box *a, const dtm_plot_box *b) {
  return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

/* Every label of every panel inside the frame, clear of every marker, the
 * legend and the other labels; one label per point of the first curve
 * (npoints[p]), the cheapest size's first and named so, when best. */
static void check_layout(const int *npoints, int best) {
  const dtm_plot_layout *l = dtm_cli_sweep_plot_layout();
  for (int p = 0; p < l->npanels; p++) {
    const dtm_plot_panel *pl = &l->panel[p];
    assert_int_equal(pl->nlabels, npoints[p]);
    if (best) assert_non_null(strstr(pl->text[0], "cheapest in band: h = "));
    for (int i = 0; i < pl->nlabels; i++) {
      const dtm_plot_box *b = &pl->label[i];
      assert_true(b->x0 >= pl->frame.x0 && b->x1 <= pl->frame.x1 && b->y0 >= pl->frame.y0 && b->y1 <= pl->frame.y1);
      assert_false(boxes_meet(b, &pl->legend));
      for (int k = 0; k < pl->npoints; k++) assert_false(boxes_meet(b, &pl->point[k]));
      for (int k = 0; k < i; k++) assert_false(boxes_meet(b, &pl->label[k]));
    }
  }
}

/* The labels of the error plot on the bundled scenes' sweeps
 * (bench/accuracy_sweeps.sh, the figures of its CSVs, to 3 digits): the
 * Brazilian disc, whose cheapest size in band sat on the band line under
 * the legend and whose finest size's label hid under its point, and the
 * notched beam with a cohesive zone, whose two coarsest sizes fall on one
 * point in both panels. */
static void plot_labels(void **unused) {
  const double disc_h[5] = {4e-3, 2e-3, 1e-3, 7e-4, 5e-4},
               disc_e[5] = {-9.88e-3, -3.04e-3, -8.76e-4, -4.23e-4, -2.11e-4};
  const double disc_t[5][3] = {{4.09e-3, 2.04e-3, 2.01e-3},
                               {5.93e-3, 2.62e-3, 3.05e-3},
                               {1.79e-2, 9.50e-3, 8.56e-3},
                               {3.73e-2, 2.19e-2, 1.66e-2},
                               {6.32e-2, 6.32e-2, 3.19e-2}};
  dtm_sweep_row r[5];
  for (int i = 0; i < 5; i++)
    r[i] = error_row(disc_h[i], 1000u << i, 4e-8, disc_t[i], (const double[3]){disc_e[i], 0.95 * disc_e[i], -0.46}, NAN,
                     1);
  assert_int_equal(dtm_cli_sweep_plot_titled(in_tmp(3, "labels_disc.png"), "brazilian_disc.xml", r, 5), 0);
  check_layout((const int[2]){5, 0}, 1);
  assert_non_null(strstr(dtm_cli_sweep_plot_layout()->panel[0].text[4], "h = 0.0005 m"));
  const double beam_h[4] = {16e-3, 12e-3, 8e-3, 6e-3}, beam_e[4] = {-1.35e-2, -1.23e-2, -6.96e-3, -3.93e-3};
  const double beam_z[4] = {7.18, 7.61, 10.3, 13.6};
  const double beam_t[4][3] = {{5.00, 1.34, 0.0703}, {5.02, 1.34, 0.0706}, {5.04, 1.36, 0.0734}, {6.67, 1.42, 0.0813}};
  for (int i = 0; i < 4; i++)
    r[i] = error_row(beam_h[i], 30000 + 1000u * i, 2e-9, beam_t[i],
                     (const double[3]){beam_e[i], beam_e[i], i < 2 ? -0.99 : NAN}, beam_z[i], i >= 2);
  assert_int_equal(dtm_cli_sweep_plot_titled(in_tmp(3, "labels_beam.png"), "notched_beam.xml", r, 4), 0);
  assert_int_equal(dtm_cli_sweep_plot_layout()->npanels, 2);
  check_layout((const int[2]){4, 4}, 1);
  (void)unused;
}

/* Labels never hidden: sweeps of 2 to 6 sizes with errors and run times
 * drawn at random (seeded: the same cases each run), mass-scaled errors far
 * outside the band as in issue 37 (-12.8 %, -51.7 %), the cheapest size in
 * the band anywhere in the list or none; every layout is checked as above
 * (each label inside the box, over no marker, legend or other label). */
static void plot_labels_random(void **unused) {
  unsigned seed = 12345;
  int failures = 0;
  for (int trial = 0; trial < 60; trial++) {
    dtm_sweep_row r[6];
    int n = 2 + trial % 5, best = trial % 7 - 1; /* -1: none in band */
    double t = 1e-3, e = 0.02;
    for (int i = 0; i < n; i++) {
      seed = seed * 1103515245u + 12345u;
      double u = (double)(seed >> 8 & 0xffff) / 65536.0;
      t *= 1.3 + 3 * u, e *= 0.25 + 0.6 * u;
      double times[3] = {t, 0.6 * t, 0.3 * t}, errs[3] = {-e, -0.9 * e, i % 2 ? -0.128 : -0.517};
      r[i] = error_row(0.01 / (1 << i), 1000u << (2 * i), 1e-7, times, errs, NAN, i == best);
    }
    assert_int_equal(dtm_cli_sweep_plot_titled(in_tmp(3, "labels_random.png"), "random.xml", r, n), 0);
    const dtm_plot_panel *pl = &dtm_cli_sweep_plot_layout()->panel[0];
    for (int i = 0; i < pl->nlabels; i++) {
      const dtm_plot_box *b = &pl->label[i];
      int bad = !(b->x0 >= pl->frame.x0 && b->x1 <= pl->frame.x1 && b->y0 >= pl->frame.y0 && b->y1 <= pl->frame.y1);
      bad |= boxes_meet(b, &pl->legend);
      for (int k = 0; k < pl->npoints; k++) bad |= boxes_meet(b, &pl->point[k]);
      for (int k = 0; k < i; k++) bad |= boxes_meet(b, &pl->label[k]);
      if (bad) fprintf(stderr, "trial %d (n %d, best %d): label %d '%s' hidden\n", trial, n, best, i, pl->text[i]);
      failures += bad;
    }
  }
  assert_int_equal(failures, 0);
  (void)unused;
}

/* LeakSanitizer (the DTM_SANITIZE build): the plot goes through PLplot,
 * which loads its cairo driver with libltdl and keeps it, and pango, whose
 * fontconfig caches live for the process. Both are third-party
 * process-lifetime allocations, like Gmsh's in tests/lsan.supp; dtmap's own
 * allocations stay checked. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libfontconfig\nleak:libltdl\n"; }

static int setup(void **state) {
  (void)state;
  return dtm_gmsh_start(0);
}

static int teardown(void **state) {
  (void)state;
  dtm_gmsh_stop();
  return 0;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(sweep_square), cmocka_unit_test(bad_input),
                                     cmocka_unit_test(no_duration), cmocka_unit_test(plot_labels),
                                     cmocka_unit_test(plot_labels_random)};
  return cmocka_run_group_tests(tests, setup, teardown);
}
