/* Progress of the long stages:
 * - the library reports meshing, Lanczos and verify to the installed hook,
 *   balanced (every stage that begins ends, at the depth it began),
 *   fractions in [0, 1] or -1, Lanczos' and verify's reaching 1 or close;
 *   it prints nothing itself (no hook: nothing to see);
 * - the CLI draws the line only on a terminal: under a pseudo-terminal
 *   (script) with DTMAP_PROGRESS_AFTER=0 its output carries "\r  meshing";
 *   with -q, or through a pipe, no carriage return at all. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/analysis.h"
#include "dtmap/gmsh.h"
#include "dtmap/progress.h"
#include "dtmap/verify.h"
#include "testutil.h"

typedef struct {
  int begins, ends, depth, bad; /* counts; open depth; inconsistencies */
  int saw_meshing, saw_lanczos, saw_verify;
  double last_lanczos, last_verify; /* last fraction reported */
} record;

static void hook(void *user, int event, const char *stage, double f, int depth) {
  record *r = user;
  if (event == DTM_PROGRESS_BEGIN) r->bad += depth != r->depth, r->depth++, r->begins++;
  if (event == DTM_PROGRESS_END) r->depth--, r->bad += depth != r->depth, r->ends++;
  if (event == DTM_PROGRESS_UPDATE) r->bad += depth != r->depth - 1 || !(f == -1 || (f >= 0 && f <= 1));
  r->saw_meshing |= !strcmp(stage, "meshing");
  r->saw_lanczos |= !strcmp(stage, "Lanczos");
  r->saw_verify |= !strcmp(stage, "verify");
  if (event == DTM_PROGRESS_UPDATE && !strcmp(stage, "Lanczos")) r->last_lanczos = f;
  if (event == DTM_PROGRESS_UPDATE && !strcmp(stage, "verify")) r->last_verify = f;
}

static char scene[600];

static void library_hook(void **unused) {
  record rec = {0};
  dtm_scene *s = NULL;
  dtm_analysis *a = NULL;
  dtm_progress_set(hook, &rec);
  assert_int_equal(dtm_scene_load(scene, &s), 0);
  assert_int_equal(dtm_analysis_run(s, &a), 0);
  assert_int_equal(dtm_analysis_estimate_global(a, 1e-4, 400, DTM_GLOBAL_MODES), 0);
  dtm_verify_effect v[1];
  assert_int_equal(dtm_verify(a, dtm_analysis_recommended(a), 200, v), 0);
  dtm_progress_set(NULL, NULL);
  assert_int_equal(rec.bad, 0);
  assert_int_equal(rec.depth, 0);
  assert_int_equal(rec.begins, rec.ends);
  assert_true(rec.saw_meshing && rec.saw_lanczos && rec.saw_verify);
  assert_true(rec.last_lanczos > 0.5); /* log-scale progress to the tolerance, near 1 at the end */
  assert_true(rec.last_verify >= 0.9); /* updated every 16 of 200 steps: the last at 192/200 */
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
  (void)unused;
}

static void cli_terminal_only(void **unused) {
  char *log = NULL;
  int r = tu_run(&log, "cd %s && DTMAP_PROGRESS_AFTER=0 script -qec '%s run %s -o p.msh' /dev/null", tu_tmpdir(),
                 tu_cli(), scene);
  assert_int_equal(r, 0);
  assert_non_null(strstr(log, "\r  meshing"));
  free(log);
  r = tu_run(&log, "cd %s && DTMAP_PROGRESS_AFTER=0 script -qec '%s run %s -q -o p.msh' /dev/null", tu_tmpdir(),
             tu_cli(), scene);
  assert_int_equal(r, 0);
  assert_null(strstr(log, "meshing"));
  free(log);
  r = tu_run(&log, "cd %s && DTMAP_PROGRESS_AFTER=0 %s run %s -o p.msh", tu_tmpdir(), tu_cli(), scene);
  assert_int_equal(r, 0);
  assert_null(strchr(log, '\r')); /* a pipe is not a terminal */
  free(log);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_cube_geo("cube.geo", "");
  tu_steel_scene("cube", "<geometry file=\"cube.geo\"/>", "size=\"0.2\" dim=\"3\"", "");
  snprintf(scene, sizeof scene, "%s/cube.xml", tu_tmpdir());
  if (dtm_gmsh_start(0)) return 3;
  const struct CMUnitTest tests[] = {cmocka_unit_test(library_hook), cmocka_unit_test(cli_terminal_only)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_gmsh_stop();
  return r;
}
