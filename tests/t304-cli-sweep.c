/* `dtmap sweep` through the CLI on the bundled plate: exit 0, the CSV has a
 * header and one row per size, the PNG has the PNG signature; and bad sizes
 * exit 2 without writing anything. */
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
  const struct CMUnitTest tests[] = {cmocka_unit_test(sweep_ok), cmocka_unit_test(sweep_bad_sizes)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
