/* dtmap as Gmsh's ONELAB solver, driven by Gmsh's own machinery: the test
 * process is the Gmsh session (C API), opens the bundled box.geo with
 * box.xml beside it, and gmshOnelabRun launches `dtmap -onelab dtmap
 * SOCKET` against its in-process ONELAB server, exactly as the GUI's Run
 * button does. Checked: the contract views arrive in this session with the
 * element and node counts and the values of a plain `dtmap run`; a ONELAB
 * parameter set before the run (the safety factor) changes the result as it
 * must; after two results both dt views are on a log scale and only the
 * latest result's intended views are visible; with the analysed .msh
 * itself open, only the views are sent and land on that model; and Gmsh's
 * Stop, pressed while dtmap runs, stops it with nothing written. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <gmshc.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "gmsh-impl.h"
#include "testutil.h"

static char dir[512], plain[600], report[600];

/* Copy geometries/box.{geo,xml} into the temporary directory and run the
 * plain `dtmap run` on it once. */
static int setup(void **state) {
  (void)state;
  snprintf(dir, sizeof dir, "%s/box", tu_tmpdir());
  snprintf(plain, sizeof plain, "%s/plain.msh", dir);
  snprintf(report, sizeof report, "%s/plain.json", dir);
  char *out = NULL;
  int r = tu_run(
      &out,
      "mkdir -p %s && cp %s/geometries/box.geo %s/geometries/box.xml %s/ && %s run %s/box.xml -q -o %s --report %s",
      dir, tu_src(), tu_src(), dir, tu_cli(), dir, plain, report);
  if (r) fprintf(stderr, "%s\n", out ? out : "");
  free(out);
  return r;
}

/* A fresh Gmsh session with an empty ONELAB database. */
static void session(void) {
  int ierr = 0;
  tu_gmsh_begin();
  gmshOnelabClear("", &ierr);
}

static void run_dtmap(void) {
  int ierr = 0;
  gmshOnelabRun("dtmap", tu_cli(), &ierr);
  assert_int_equal(ierr, 0);
}

static char *view_name(int index) {
  char opt[64], *v = NULL;
  int ierr = 0;
  snprintf(opt, sizeof opt, "View[%d].Name", index);
  gmshOptionGetString(opt, &v, &ierr);
  return v;
}

static double view_number(int index, const char *what) {
  char opt[96];
  double v = NAN;
  int ierr = 0;
  snprintf(opt, sizeof opt, "View[%d].%s", index, what);
  gmshOptionGetNumber(opt, &v, &ierr);
  return v;
}

/* The contract views of the plain run, read in a session of their own. */
static const char *const contract[] = {"dt", "characteristic length", "limiting effect", "size suggestion"};

static void read_plain(tu_view out[4]) {
  int ierr = 0;
  tu_gmsh_begin();
  gmshOpen(plain, &ierr);
  assert_int_equal(ierr, 0);
  for (int i = 0; i < 4; i++) assert_int_equal(tu_view_read_last(contract[i], &out[i]), 0);
  tu_gmsh_end();
}

/* Same tags, same values. Tolerance: both files are written by the same
 * writer from the same computation (dtmap meshes on one thread, so the
 * element numbering repeats), hence equal to the last printed digit; 1e-12
 * relative leaves room only for the text round trip. */
static void assert_same_view(const tu_view *a, const tu_view *b) {
  assert_string_equal(a->type, b->type);
  assert_int_equal(a->n, b->n);
  for (size_t k = 0; k < a->n; k++) {
    assert_int_equal(a->tags[k], b->tags[k]);
    assert_true(fabs(a->values[k] - b->values[k]) <= 1e-12 * fabs(b->values[k]));
  }
}

static void open_box(void) {
  char geo[700];
  int ierr = 0;
  snprintf(geo, sizeof geo, "%s/box.geo", dir);
  gmshOpen(geo, &ierr);
  assert_int_equal(ierr, 0);
}

static void test_views_arrive(void **state) {
  (void)state;
  tu_view ref[4], got;
  read_plain(ref);
  cJSON *rep = tu_json_load(report);
  assert_non_null(rep);
  session();
  open_box();
  run_dtmap();
  int ierr = 0;
  for (int i = 0; i < 4; i++) {
    assert_int_equal(tu_view_read_last(contract[i], &got), 0);
    assert_int_equal(got.n, (size_t)tu_json_number(rep, i == 3 ? "mesh.nodes" : "mesh.elements"));
    assert_same_view(&got, &ref[i]);
    tu_view_free(&got), tu_view_free(&ref[i]);
  }
  double *rec = NULL;
  size_t n = 0;
  gmshOnelabGetNumber("dtmap/9Results/0recommended", &rec, &n, &ierr);
  assert_int_equal(n, 1);
  /* the published figure is the report's, printed with 16 digits */
  assert_true(fabs(rec[0] - tu_json_number(rep, "dt.recommended")) <= 1e-14 * rec[0]);
  gmshFree(rec);
  cJSON_Delete(rep);
  tu_gmsh_end();
}

static void set_safety(double s) {
  int ierr = 0;
  gmshOnelabSetNumber("dtmap/2Time/0safety", &s, 1, &ierr);
  assert_int_equal(ierr, 0);
}

static double recommended(void) {
  double *v = NULL, r = NAN;
  size_t n = 0;
  int ierr = 0;
  gmshOnelabGetNumber("dtmap/9Results/0recommended", &v, &n, &ierr);
  if (n == 1) r = v[0];
  gmshFree(v);
  return r;
}

/* The safety factor set in the panel before the run scales the recommended
 * step (safety x the nodal bound) and leaves the dt map alone. Tolerance
 * 1e-12 relative: the same nodal bound times 0.5 against the plain run's
 * 0.9, through 16- and 17-digit text. */
static void test_safety_parameter(void **state) {
  (void)state;
  cJSON *rep = tu_json_load(report);
  assert_non_null(rep);
  session();
  open_box();
  set_safety(0.5);
  run_dtmap();
  double expect = tu_json_number(rep, "dt.recommended") * 0.5 / 0.9;
  assert_true(fabs(recommended() - expect) <= 1e-12 * expect);
  tu_view v;
  assert_int_equal(tu_view_read_last("dt", &v), 0);
  double dmin = INFINITY;
  for (size_t k = 0; k < v.n; k++) dmin = fmin(dmin, v.values[k]);
  assert_true(fabs(dmin - tu_json_number(rep, "dt.min")) <= 1e-12 * dmin);
  tu_view_free(&v);
  cJSON_Delete(rep);
  tu_gmsh_end();
}

static int intended(const char *name) { return !strcmp(name, "dt") || !strcmp(name, "below target [s]"); }

/* Two results merged one after the other: every dt view is on a log scale,
 * and the visible views are exactly the latest result's dt and below-target
 * views (dtmap's figures are printed, not a view: a list-based view makes
 * gmsh.view.getModelData abort). */
static void test_two_results(void **state) {
  (void)state;
  session();
  open_box();
  run_dtmap();
  int first = tu_view_count();
  set_safety(0.8);
  run_dtmap();
  int all = tu_view_count(), ndt = 0, nvisible = 0;
  assert_int_equal(all, 2 * first);
  for (int i = 0; i < all; i++) {
    char *name = view_name(i);
    assert_non_null(name);
    if (!strcmp(name, "dt")) ndt++, assert_true(view_number(i, "ScaleType") == 2);
    if (view_number(i, "Visible") != 0) {
      nvisible++;
      assert_true(i >= first);
      assert_true(intended(name));
    }
    gmshFree(name);
  }
  assert_int_equal(ndt, 2);
  assert_int_equal(nvisible, 2);
  tu_gmsh_end();
}

/* With the analysed .msh open in Gmsh (its scene beside it names it), only
 * the views are sent: no second model appears, and dt covers this model's
 * elements. */
static void test_views_only_on_open_mesh(void **state) {
  (void)state;
  char sub[700], msh[760], xml[760];
  snprintf(sub, sizeof sub, "%s/open", dir);
  snprintf(msh, sizeof msh, "%s/model.msh", sub);
  snprintf(xml, sizeof xml, "%s/model.xml", sub);
  assert_int_equal(tu_run(NULL, "mkdir -p %s && cp %s %s", sub, plain, msh), 0);
  tu_write(xml, "<dtmap-scene version=\"1\"><mesh file=\"model.msh\"/>"
                "<material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>"
                "<effects><elastic formulation=\"3d\"/></effects><time target=\"4e-7\"/></dtmap-scene>\n");
  tu_view ref[4], got;
  read_plain(ref);
  session();
  int ierr = 0;
  gmshOpen(msh, &ierr);
  assert_int_equal(ierr, 0);
  int before = tu_view_count(), models = dtm_gmsh_model_count();
  run_dtmap();
  assert_int_equal(dtm_gmsh_model_count(), models);
  assert_true(tu_view_count() > before);
  assert_int_equal(tu_view_read_last("dt", &got), 0);
  assert_same_view(&got, &ref[0]);
  tu_view_free(&got);
  for (int i = 0; i < 4; i++) tu_view_free(&ref[i]);
  tu_gmsh_end();
}

/* The user, on a second thread: wait until dtmap has declared its panel
 * (the safety parameter appears, just before the analysis starts), then
 * press Stop as Gmsh's GUI does, by setting dtmap/Action to "stop" (ONELAB's
 * parameter space is locked for such concurrent use). */
static void *press_stop(void *pressed) {
  for (int i = 0; i < 60000 && !*(int *)pressed; i++) {
    double *v = NULL;
    size_t n = 0;
    int ierr = 0;
    gmshOnelabGetNumber("dtmap/2Time/0safety", &v, &n, &ierr);
    gmshFree(v);
    char *stop[] = {"stop"};
    if (n) gmshOnelabSetString("dtmap/Action", stop, 1, &ierr), *(int *)pressed = 1;
    nanosleep(&(struct timespec){0, 500000}, NULL);
  }
  return NULL;
}

/* Stop between stages: dtmap says so in Gmsh's console and sends, writes
 * and merges nothing. Which boundary it stops at depends on when the
 * "user" presses it (before the analysis, or before writing): either way no
 * result. */
static void test_stop(void **state) {
  (void)state;
  char out[700], **log = NULL;
  size_t nlog = 0;
  int ierr = 0, pressed = 0;
  snprintf(out, sizeof out, "%s/box_dt.msh", dir);
  unlink(out);
  session();
  open_box();
  gmshLoggerStart(&ierr);
  pthread_t user;
  assert_int_equal(pthread_create(&user, NULL, press_stop, &pressed), 0);
  run_dtmap();
  pthread_join(user, NULL);
  assert_true(pressed);
  gmshLoggerGet(&log, &nlog, &ierr);
  int said = 0;
  for (size_t i = 0; i < nlog; i++) {
    if (strstr(log[i], "stopped from Gmsh before")) said = 1, fprintf(stderr, "%s\n", log[i]);
    gmshFree(log[i]);
  }
  gmshFree(log);
  gmshLoggerStop(&ierr);
  assert_true(said);
  double nviews = -1;
  gmshOptionGetNumber("PostProcessing.NbViews", &nviews, &ierr);
  assert_true(nviews == 0);
  assert_false(tu_exists(out));
  tu_gmsh_end();
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_views_arrive), cmocka_unit_test(test_safety_parameter),
      cmocka_unit_test(test_two_results),  cmocka_unit_test(test_views_only_on_open_mesh),
      cmocka_unit_test(test_stop),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
