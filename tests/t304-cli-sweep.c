/* `dtmap sweep` through the CLI on the bundled plate: exit 0, the CSV has a
 * header and one row per size, the PNG has the PNG signature; and bad sizes
 * exit 2 without writing anything. A size whose mesh is refused (1e-9 m:
 * far more memory than any machine has) is a row with its reason, the other
 * sizes are written, exit 1; when every size is refused, exit 2 and no
 * output (issue 35). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static int count_lines(const char *path) {
  FILE *f = fopen(path, "r");
  int n = 0;
  for (int c; f && (c = fgetc(f)) != EOF;) n += c == '\n';
  if (f) fclose(f);
  return n;
}

static void sweep_ok(void **unused) {
  char csv[512], png[512], *log = NULL;
  snprintf(csv, sizeof csv, "%s/plate.csv", tu_tmpdir());
  snprintf(png, sizeof png, "%s/plate.png", tu_tmpdir());
  int code = tu_run(&log, "%s sweep %s/geometries/plate_with_hole.xml --sizes 1e-2,5e-3 --csv %s --plot %s -q",
                    tu_cli(), tu_src(), csv, png);
  if (code) fprintf(stderr, "%s\n", log);
  free(log);
  assert_int_equal(code, 0);
  assert_int_equal(count_lines(csv), 3);
  unsigned char sig[8] = {0};
  FILE *f = fopen(png, "rb");
  assert_non_null(f);
  assert_int_equal(fread(sig, 1, 8, f), 8);
  fclose(f);
  assert_memory_equal(sig, "\x89PNG\r\n\x1a\n", 8);
  (void)unused;
}

/* The whole text of a file (malloc'ed), or NULL. */
static char *slurp(const char *path) {
  FILE *f = fopen(path, "r");
  if (!f) return NULL;
  char *t = calloc(1, 1 << 16);
  if (t) t[fread(t, 1, (1 << 16) - 1, f)] = '\0';
  fclose(f);
  return t;
}

static void sweep_keeps_what_it_can(void **unused) {
  char csv[512], png[512], *log = NULL;
  snprintf(csv, sizeof csv, "%s/kept.csv", tu_tmpdir());
  snprintf(png, sizeof png, "%s/kept.png", tu_tmpdir());
  int code = tu_run(&log, "%s sweep %s/geometries/plate_with_hole.xml --sizes 1e-2,1e-9,5e-3 --csv %s --plot %s",
                    tu_cli(), tu_src(), csv, png);
  if (code != 1) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, 1);
  assert_non_null(strstr(log, "dtmap: error: sweep at size 1e-09 m:"));
  assert_non_null(strstr(log, "1e-09  FAILED: "));
  assert_non_null(strstr(log, "1 of 3 sizes FAILED"));
  /* the band column says it judges the one global step (issue 37) */
  assert_non_null(strstr(log, " 1stp "));
  assert_non_null(strstr(log, "band (1stp): every measure's worst inside its band with one global step"));
  free(log);
  assert_int_equal(count_lines(csv), 4);
  char *t = slurp(csv);
  assert_non_null(t);
  assert_non_null(strstr(t, ",failed\n"));
  char *row = strstr(t, "\n1e-09,");
  assert_non_null(row);
  assert_non_null(strstr(row, "memory")); /* the reason, in the failed column */
  assert_non_null(strstr(t, "\n0.005,")); /* the size after it was written */
  char *good = strstr(t, "\n0.01,"), *eol = good ? strchr(good + 1, '\n') : NULL;
  assert_true(eol && eol[-1] == ','); /* a row with figures: its failed cell is empty */
  free(t);
  FILE *f = fopen(png, "rb");
  assert_non_null(f);
  fclose(f);
  /* every size refused: exit 2, nothing written */
  snprintf(csv, sizeof csv, "%s/none.csv", tu_tmpdir());
  code =
      tu_run(&log, "%s sweep %s/geometries/plate_with_hole.xml --sizes 1e-9,2e-9 --csv %s -q", tu_cli(), tu_src(), csv);
  assert_int_equal(code, 2);
  assert_non_null(strstr(log, "no size gave figures"));
  free(log);
  assert_null(fopen(csv, "r"));
  (void)unused;
}

static void sweep_bad_sizes(void **unused) {
  char csv[512], *log = NULL;
  snprintf(csv, sizeof csv, "%s/bad.csv", tu_tmpdir());
  int code =
      tu_run(&log, "%s sweep %s/geometries/plate_with_hole.xml --sizes 1e-2,-3 --csv %s -q", tu_cli(), tu_src(), csv);
  assert_int_equal(code, 2);
  assert_false(tu_exists(csv));
  free(log);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(sweep_ok), cmocka_unit_test(sweep_keeps_what_it_can),
                                     cmocka_unit_test(sweep_bad_sizes)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
