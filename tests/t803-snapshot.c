/* `dtmap snapshot` draws a result with Gmsh's own renderer. The test runs
 * it with DISPLAY removed from the environment, so dtmap must start its own
 * virtual display (Xvfb), and checks both pictures: valid PNGs (libpng
 * decodes them) of exactly the requested size, and not blank: a dt map on a
 * log colour scale with text has far more than a few distinct colours. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* Decode path; *colours receives the number of distinct RGB colours (up to
 * 4096 counted). Returns 0 when libpng reads it. */
static int read_png(const char *path, unsigned *w, unsigned *h, int *colours) {
  png_image im;
  memset(&im, 0, sizeof im);
  im.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&im, path)) return -1;
  im.format = PNG_FORMAT_RGB;
  unsigned char *px = malloc(PNG_IMAGE_SIZE(im));
  if (!px || !png_image_finish_read(&im, NULL, px, 0, NULL)) return free(px), -1;
  *w = im.width, *h = im.height;
  unsigned *seen = malloc(4096 * sizeof *seen);
  int n = 0;
  for (size_t i = 0; i < (size_t)im.width * im.height && n < 4096; i++) {
    unsigned c = (unsigned)px[3 * i] << 16 | (unsigned)px[3 * i + 1] << 8 | px[3 * i + 2];
    int k = 0;
    while (k < n && seen[k] != c) k++;
    if (k == n) seen[n++] = c;
  }
  free(seen), free(px);
  *colours = n;
  return 0;
}

static void check_png(const char *path, unsigned w, unsigned h) {
  unsigned pw = 0, ph = 0;
  int colours = 0;
  assert_int_equal(read_png(path, &pw, &ph, &colours), 0);
  assert_int_equal(pw, w);
  assert_int_equal(ph, h);
  /* the dt map alone has 12 discrete colour bands besides the background
   * and the text; a blank or one-colour picture has 1 or 2 */
  assert_true(colours > 8);
}

static void test_snapshot_without_display(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  char *out = NULL;
  int r = tu_run(&out,
                 "cd %s && cp %s/geometries/brazilian_disc.geo %s/geometries/brazilian_disc.xml . && "
                 "%s run brazilian_disc.xml -q -o disc.msh && env -u DISPLAY %s snapshot disc.msh --png pic "
                 "--width 400 --height 300 -q",
                 d, tu_src(), tu_src(), tu_cli(), tu_cli());
  if (r) fprintf(stderr, "%s\n", out ? out : "");
  free(out);
  assert_int_equal(r, 0);
  char path[600];
  snprintf(path, sizeof path, "%s/pic_dt.png", d);
  check_png(path, 400, 300);
  snprintf(path, sizeof path, "%s/pic_worst.png", d);
  check_png(path, 400, 300);
}

/* A file that is not a result is bad input: exit 2, no picture. */
static void test_snapshot_bad_input(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  assert_int_equal(tu_run(NULL, "cd %s && %s snapshot missing.msh --png bad -q", d, tu_cli()), 2);
  char path[600];
  snprintf(path, sizeof path, "%s/bad_dt.png", d);
  assert_false(tu_exists(path));
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_snapshot_without_display),
      cmocka_unit_test(test_snapshot_bad_input),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
