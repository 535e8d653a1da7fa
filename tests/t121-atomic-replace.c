/* An output put in place over what the path held before (src/base/atomic.c,
 * dtm_atomic_commit): the exchange with an existing regular file, the
 * rename otherwise. In every case the path then holds the new content and
 * nothing else is left in the directory (no temporary, no older file under
 * the temporary's name):
 *   - no file there yet;
 *   - a regular file, several times in a row, with content of 1 byte to
 *     8 MB (the older file, swapped out, is removed each time);
 *   - a regular file with a second hard link: the other name keeps the
 *     older content, as a rename leaves it;
 *   - a symbolic link: the link itself is replaced by the new file, and the
 *     file it pointed to is untouched (a rename's behaviour; the exchange
 *     is taken for regular files only);
 *   - a directory: the write fails and the directory stays.
 * Tolerance: none (contents compared byte for byte). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/util.h"
#include "testutil.h"

static char dir[512];

static void path_of(char *buf, size_t len, const char *name) { snprintf(buf, len, "%s/%s", dir, name); }

/* The names in dir, sorted, joined by spaces. */
static void listing(char *buf, size_t len) {
  struct dirent **e = NULL;
  int n = scandir(dir, &e, NULL, alphasort);
  buf[0] = '\0';
  for (int i = 0; i < n; i++) {
    if (strcmp(e[i]->d_name, ".") && strcmp(e[i]->d_name, ".."))
      snprintf(buf + strlen(buf), len - strlen(buf), "%s%s", buf[0] ? " " : "", e[i]->d_name);
    free(e[i]);
  }
  free(e);
}

/* Write n bytes of fill through an atomic output at path. */
static int put(const char *path, size_t n, char fill) {
  dtm_atomic w;
  int r = dtm_atomic_open(&w, path, "", 1);
  if (r) return r;
  for (size_t i = 0; i < n; i++) fputc(fill + (char)(i % 7), w.f);
  return dtm_atomic_commit(&w);
}

static void holds(const char *path, size_t n, char fill) {
  size_t got;
  char *b = tu_slurp(path, &got);
  assert_int_equal(got, n);
  for (size_t i = 0; i < n; i++) assert_int_equal(b[i], fill + (char)(i % 7));
  free(b);
}

static void clean_dir(void) {
  tu_remove_tree(dir);
  assert_int_equal(mkdir(dir, 0755), 0);
}

static void new_and_replaced(void **unused) {
  char out[600], names[4096];
  clean_dir();
  path_of(out, sizeof out, "out.msh");
  const size_t sizes[] = {10, 1, 8 << 20, 4096, 0, 3};
  for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
    assert_int_equal(put(out, sizes[k], (char)('a' + k)), DTM_OK);
    holds(out, sizes[k], (char)('a' + k));
    listing(names, sizeof names);
    assert_string_equal(names, "out.msh");
  }
  (void)unused;
}

static void hard_link_keeps_older(void **unused) {
  char out[600], other[600], names[4096];
  clean_dir();
  path_of(out, sizeof out, "out.json"), path_of(other, sizeof other, "other.json");
  assert_int_equal(put(out, 100, 'A'), DTM_OK);
  assert_int_equal(link(out, other), 0);
  assert_int_equal(put(out, 50, 'k'), DTM_OK);
  holds(out, 50, 'k');
  holds(other, 100, 'A');
  listing(names, sizeof names);
  assert_string_equal(names, "other.json out.json");
  (void)unused;
}

static void symlink_replaced(void **unused) {
  char out[600], target[600], names[4096];
  struct stat st;
  clean_dir();
  path_of(out, sizeof out, "out.csv"), path_of(target, sizeof target, "target.csv");
  assert_int_equal(put(target, 20, 'T'), DTM_OK);
  assert_int_equal(symlink("target.csv", out), 0);
  assert_int_equal(put(out, 30, 'n'), DTM_OK);
  assert_int_equal(lstat(out, &st), 0);
  assert_true(S_ISREG(st.st_mode));
  holds(out, 30, 'n');
  holds(target, 20, 'T');
  listing(names, sizeof names);
  assert_string_equal(names, "out.csv target.csv");
  (void)unused;
}

static void directory_refused(void **unused) {
  char out[600], names[4096];
  struct stat st;
  clean_dir();
  path_of(out, sizeof out, "out.txt");
  assert_int_equal(mkdir(out, 0755), 0);
  assert_int_not_equal(put(out, 10, 'x'), DTM_OK);
  assert_non_null(strstr(dtm_error_message(), out));
  dtm_error_clear();
  assert_int_equal(stat(out, &st), 0);
  assert_true(S_ISDIR(st.st_mode));
  listing(names, sizeof names);
  assert_string_equal(names, "out.txt");
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  snprintf(dir, sizeof dir, "%s/replace", tu_tmpdir());
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(new_and_replaced),
      cmocka_unit_test(hard_link_keeps_older),
      cmocka_unit_test(symlink_replaced),
      cmocka_unit_test(directory_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
