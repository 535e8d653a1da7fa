/* The bad-input corpus: every directory of tests/data/bad/ is one bad
 * input, run through the dtmap CLI in a fresh copy of the directory. Each
 * must exit 2, name the place in its message, and leave the directory
 * exactly as it was: no output, no temporary, every input unchanged (names,
 * sizes and contents compared before and after).
 *
 * A case directory holds its inputs, `args` (the command line after
 * `dtmap`, one line, shell syntax, run in the copy) and `expect` (fragments
 * the output must contain, one per line; the first is the place: file:line,
 * the Gmsh file and line, the element tag and group, or the option and the
 * command). A file named X.in is copied as X, so that inputs whose names
 * the repository ignores (*.msh) can be kept. README.md lists the cases. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <dirent.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "testutil.h"

#define MAX_FILES 64
#define MIN_CASES 60 /* the corpus the issue asked for */

/* One file of a directory tree: relative path, size and content hash. */
typedef struct {
  char path[512];
  long long size;
  uint64_t hash; /* FNV-1a 64 of the contents */
} entry;

typedef struct {
  int n;
  entry e[MAX_FILES];
} snapshot;

static uint64_t hash_file(const char *path, long long *size) {
  uint64_t h = 1469598103934665603ull;
  FILE *f = fopen(path, "rb");
  *size = 0;
  for (int c; f && (c = fgetc(f)) != EOF; ++*size) h = (h ^ (uint64_t)c) * 1099511628211ull;
  if (f) fclose(f);
  return h;
}

/* Every file under dir/rel (hidden ones too) into s. */
static void take(const char *dir, const char *rel, snapshot *s) {
  char path[PATH_MAX];
  snprintf(path, sizeof path, "%s%s%s", dir, rel[0] ? "/" : "", rel);
  DIR *d = opendir(path);
  assert_non_null(d);
  for (struct dirent *e; (e = readdir(d));) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    char sub[512], full[PATH_MAX + 512];
    struct stat st;
    snprintf(sub, sizeof sub, "%s%s%s", rel, rel[0] ? "/" : "", e->d_name);
    snprintf(full, sizeof full, "%s/%s", dir, sub);
    assert_int_equal(lstat(full, &st), 0);
    if (S_ISDIR(st.st_mode)) {
      take(dir, sub, s);
      continue;
    }
    assert_true(s->n < MAX_FILES);
    entry *en = &s->e[s->n++];
    snprintf(en->path, sizeof en->path, "%s", sub);
    en->hash = hash_file(full, &en->size);
  }
  closedir(d);
}

static int by_path(const void *a, const void *b) { return strcmp(((const entry *)a)->path, ((const entry *)b)->path); }

static void snap(const char *dir, snapshot *s) {
  s->n = 0;
  take(dir, "", s);
  qsort(s->e, (size_t)s->n, sizeof *s->e, by_path);
}

/* The differences between two snapshots, printed; their number. */
static int differences(const char *name, const snapshot *a, const snapshot *b) {
  int bad = a->n != b->n;
  for (int i = 0; i < a->n && i < b->n; i++)
    bad += strcmp(a->e[i].path, b->e[i].path) || a->e[i].size != b->e[i].size || a->e[i].hash != b->e[i].hash;
  if (bad) {
    fprintf(stderr, "[%s] the directory changed: before", name);
    for (int i = 0; i < a->n; i++) fprintf(stderr, " %s", a->e[i].path);
    fprintf(stderr, "; after");
    for (int i = 0; i < b->n; i++) fprintf(stderr, " %s(%lld)", b->e[i].path, b->e[i].size);
    fprintf(stderr, "\n");
  }
  return bad;
}

/* Copy the case directory src into dst (X.in becomes X), not args/expect. */
static void copy_case(const char *src, const char *dst) {
  char *log = NULL;
  assert_int_equal(tu_run(&log,
                          "cp -R '%s'/. '%s'/ && cd '%s' && rm -f args expect && "
                          "for f in $(find . -name '*.in'); do mv \"$f\" \"${f%%.in}\"; done",
                          src, dst, dst),
                   0);
  free(log);
}

static char *read_text(const char *path) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  char *b = calloc(1, 1 << 16);
  size_t n = fread(b, 1, (1 << 16) - 1, f);
  fclose(f);
  b[n] = '\0';
  return b;
}

/* Run one case; returns the number of failed checks (printed). */
static int run_case(const char *corpus, const char *name) {
  char src[PATH_MAX], work[PATH_MAX], path[PATH_MAX + 16], *log = NULL;
  snprintf(src, sizeof src, "%s/%s", corpus, name);
  snprintf(work, sizeof work, "%s/%s", tu_tmpdir(), name);
  assert_int_equal(mkdir(work, 0755), 0);
  copy_case(src, work);
  snprintf(path, sizeof path, "%s/args", src);
  char *args = read_text(path);
  args[strcspn(args, "\n")] = '\0';
  snprintf(path, sizeof path, "%s/expect", src);
  char *expect = read_text(path);
  snapshot before, after;
  snap(work, &before);
  int code = tu_run(&log, "cd '%s' && '%s' %s", work, tu_cli(), args), fails = 0;
  snap(work, &after);
  if (code != 2) fprintf(stderr, "[%s] exit %d, not 2\n", name, code), fails++;
  int lines = 0;
  for (char *line = strtok(expect, "\n"); line; line = strtok(NULL, "\n"), lines++)
    if (!strstr(log, line)) fprintf(stderr, "[%s] the output does not say '%s'\n", name, line), fails++;
  if (!lines) fprintf(stderr, "[%s] expect names no place\n", name), fails++;
  fails += differences(name, &before, &after);
  if (fails) fprintf(stderr, "[%s] dtmap %s\n%s\n", name, args, log);
  free(log), free(args), free(expect);
  tu_remove_tree(work);
  return fails;
}

static int by_name(const struct dirent **a, const struct dirent **b) { return strcmp((*a)->d_name, (*b)->d_name); }

static int is_case(const struct dirent *e) { return e->d_name[0] != '.' && !strchr(e->d_name, '.'); }

static void test_corpus(void **state) {
  char corpus[PATH_MAX];
  struct dirent **list = NULL;
  snprintf(corpus, sizeof corpus, "%s/tests/data/bad", tu_src());
  int n = scandir(corpus, &list, is_case, by_name), fails = 0, failed_cases = 0;
  assert_true(n >= MIN_CASES);
  for (int i = 0; i < n; i++) {
    int f = run_case(corpus, list[i]->d_name);
    fails += f, failed_cases += f > 0;
    free(list[i]);
  }
  free(list);
  printf("bad-input corpus: %d cases, %d failed\n", n, failed_cases);
  assert_int_equal(fails, 0);
  (void)state;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_corpus)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
