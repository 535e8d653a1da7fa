/* Scene reader robustness: a valid scene is mutated 400 times by a seeded
 * generator (byte flips, truncations, duplicated and deleted slices and
 * lines, inserted XML tokens, replaced attribute values, changed letters)
 * and each result is loaded. The reader must return
 * either success or DTM_ERR_INPUT with a non-empty message, never crash,
 * leak or hang (the sanitizer and valgrind builds run this too). Then the
 * hand-made corpus in tests/data/scenes/fuzz/ (entity loops, external
 * entities, XInclude, ...) is replayed the same way, as are generated
 * inputs too big to keep there (deep nesting, huge attributes). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/scene.h"

#define NMUTATIONS 400
#define MAXLEN 8192

static char dir[PATH_MAX];     /* temporary directory of the fixtures */
static const char *source_dir; /* argv[1]: the source tree, for the corpus */

static const char seed_scene[] =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<!-- a scene to mutate -->\n"
    "<dtmap-scene version=\"1\">\n"
    "  <geometry file=\"disc.geo\"/>\n"
    "  <meshing size=\"1e-3\" min-size=\"2e-4\" order=\"1\" dim=\"2\"/>\n"
    "  <material name=\"granite\" groups=\"rock\" E=\"60e9\" nu=\"0.25\" rho=\"2700\"\n"
    "            conductivity=\"3\" heat-capacity=\"790\" permeability=\"1e-15\"\n"
    "            viscosity=\"1e-3\" storage=\"1e-9\" fracture-energy=\"50\" strength=\"10e6\"/>\n"
    "  <material name=\"steel\" groups=\"platen_top platen_bottom\" E=\"210e9\" nu=\"0.3\" "
    "rho=\"7850\"/>\n"
    "  <material name=\"filler\" default=\"true\" E=\"1e9\" nu=\"0.3\" rho=\"1000\"/>\n"
    "  <effects>\n"
    "    <elastic formulation=\"plane-strain\" length=\"eigen\"/>\n"
    "    <damping xi=\"0.05\"/>\n"
    "    <thermal/>\n"
    "    <hydraulic/>\n"
    "    <cohesive groups=\"rock\" elements-per-zone=\"5\"/>\n"
    "    <effect name=\"creep\" library=\"libcreep.so\" rate=\"1e-6\"/>\n"
    "  </effects>\n"
    "  <time safety=\"0.9\" target=\"2e-8\" duration=\"1e-4\"/>\n"
    "  <output mesh=\"disc_dt.msh\" report=\"disc_dt.json\"/>\n"
    "</dtmap-scene>\n";

static const char *const tokens[] = {
    "<",
    ">",
    "\"",
    "'",
    "&",
    "/>",
    "</",
    "<!--",
    "-->",
    "]]>",
    "<![CDATA[x]]>",
    "&amp;",
    "&#0;",
    "&#x110000;",
    "&undefined;",
    "\xff\xfe",
    "\xc3",
    "nan",
    "-1",
    "1e999",
    "0x1p3",
    " default=\"true\"",
    " groups=\"rock\"",
    "<material name=\"z\"/>",
    "<thermal/>",
    "<!DOCTYPE dtmap-scene [<!ENTITY e \"0.5\">]>",
    "&e;",
    "\n\n\n",
    "\t",
};

static uint64_t rng = 0x9e3779b97f4a7c15ull; /* fixed seed: the run is reproducible */

static uint64_t next(void) {
  rng ^= rng << 13;
  rng ^= rng >> 7;
  rng ^= rng << 17;
  return rng;
}

static size_t below(size_t n) { return n ? (size_t)(next() % n) : 0; }

static size_t flip_bytes(char *b, size_t n) {
  for (int k = 1 + (int)below(4); k > 0 && n; k--) b[below(n)] ^= (char)(1 + below(255));
  return n;
}

static size_t truncate_at(char *b, size_t n) {
  (void)b;
  return below(n + 1);
}

static size_t insert(char *b, size_t n, size_t at, const char *src, size_t len) {
  if (n + len > MAXLEN) return n;
  memmove(b + at + len, b + at, n - at);
  memcpy(b + at, src, len);
  return n + len;
}

static size_t duplicate_slice(char *b, size_t n) {
  char copy[MAXLEN];
  size_t from = below(n), len = below(n - from + 1) % 256, at = below(n + 1);
  memcpy(copy, b + from, len);
  return insert(b, n, at, copy, len);
}

static size_t delete_slice(char *b, size_t n) {
  size_t from = below(n), len = below(n - from + 1) % 128;
  memmove(b + from, b + from + len, n - from - len);
  return n - len;
}

static size_t insert_token(char *b, size_t n) {
  const char *t = tokens[below(sizeof tokens / sizeof *tokens)];
  size_t len = strlen(t) + (t[0] == '&' && t[1] == '#' && below(2)); /* sometimes a NUL */
  return insert(b, n, below(n + 1), t, len);
}

static const char *const values[] = {
    "",
    "0",
    "-1",
    "0.5",
    "-0",
    "nan",
    "NaN",
    "INF",
    "-INF",
    "1e999",
    "1e-400",
    " 7 ",
    "true",
    "false",
    "rock",
    "a b a",
    "x.msh",
    "x.geo",
    "/nonexistent/a.geo",
    "3d",
    "eigen",
};

/* Bounds [*from, *to) of a random attribute value (between double quotes). */
static int pick_value(const char *b, size_t n, size_t *from, size_t *to) {
  size_t at = below(n);
  while (at < n && b[at] != '=') at++;
  if (at + 1 >= n || b[at + 1] != '"') return 0;
  *from = at + 2;
  for (*to = *from; *to < n && b[*to] != '"'; ++*to) {
  }
  return *to < n;
}

static size_t replace_value(char *b, size_t n) {
  size_t from, to;
  if (!pick_value(b, n, &from, &to)) return n;
  const char *v = values[below(sizeof values / sizeof *values)];
  memmove(b + from, b + to, n - to);
  return insert(b, n - (to - from), from, v, strlen(v));
}

/* Bounds [*from, *to) of a random whole line, newline included. */
static void pick_line(const char *b, size_t n, size_t *from, size_t *to) {
  *from = below(n);
  while (*from > 0 && b[*from - 1] != '\n') --*from;
  for (*to = *from; *to < n && b[*to] != '\n'; ++*to) {
  }
  if (*to < n) ++*to;
}

static size_t duplicate_line(char *b, size_t n) {
  char copy[MAXLEN];
  size_t from, to;
  pick_line(b, n, &from, &to);
  memcpy(copy, b + from, to - from);
  return insert(b, n, to, copy, to - from);
}

static size_t delete_line(char *b, size_t n) {
  size_t from, to;
  pick_line(b, n, &from, &to);
  memmove(b + from, b + to, n - to);
  return n - (to - from);
}

/* Change one letter or digit into another: the XML mostly stays well formed. */
static size_t swap_alnum(char *b, size_t n) {
  static const char alnum[] = "0123456789.-+eEabcdefghijklmnopqrstuvwxyz";
  for (int tries = 0; tries < 64 && n; tries++) {
    size_t at = below(n);
    if (!strchr(alnum, b[at]) || !b[at]) continue;
    b[at] = alnum[below(sizeof alnum - 1)];
    break;
  }
  return n;
}

static size_t mutate(int i, char *b, size_t n) {
  switch (i % 9) {
  case 0: return flip_bytes(b, n);
  case 1: return truncate_at(b, n);
  case 2: return duplicate_slice(b, n);
  case 3: return delete_slice(b, n);
  case 4: return insert_token(b, n);
  case 5: return replace_value(b, n);
  case 6: return duplicate_line(b, n);
  case 7: return delete_line(b, n);
  default: return swap_alnum(b, n);
  }
}

/* Load path: success, or DTM_ERR_INPUT with a message. Returns rc. */
static int load_once(const char *path) {
  dtm_scene *s = NULL;
  dtm_error_clear();
  int rc = dtm_scene_load(path, &s);
  if (getenv("DTM_TEST_VERBOSE")) fprintf(stderr, "%d %s\n", rc, dtm_error_message());
  if (rc != DTM_OK && rc != DTM_ERR_INPUT) fprintf(stderr, "%s: rc %d: %s\n", path, rc, dtm_error_message());
  assert_true(rc == DTM_OK || rc == DTM_ERR_INPUT);
  if (rc == DTM_OK)
    assert_non_null(s);
  else
    assert_true(dtm_error_message()[0] != '\0');
  if (rc != DTM_OK) assert_null(s);
  dtm_scene_destroy(&s);
  return rc;
}

static void write_bytes(const char *path, const char *b, size_t n) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(b, 1, n, f), n);
  fclose(f);
}

static void test_mutations(void **state) {
  (void)state;
  char path[PATH_MAX * 2], buf[MAXLEN];
  int nok = 0, nerr = 0;
  snprintf(path, sizeof path, "%s/fuzz.xml", dir);
  write_bytes(path, seed_scene, sizeof seed_scene - 1);
  assert_int_equal(load_once(path), DTM_OK);
  for (int i = 0; i < NMUTATIONS; i++) {
    size_t n = sizeof seed_scene - 1;
    memcpy(buf, seed_scene, n);
    for (int k = 0, rounds = 1 + (int)below(2); k < rounds; k++) n = mutate(i + 4 * k, buf, n);
    write_bytes(path, buf, n);
    if (load_once(path) == DTM_OK)
      nok++;
    else
      nerr++;
  }
  printf("mutations: %d loaded, %d rejected\n", nok, nerr);
  assert_true(nok > 0 && nerr > NMUTATIONS / 2);
}

/* Inputs too big to keep in the corpus: deep nesting, huge attributes. */
static void test_generated(void **state) {
  (void)state;
  char path[PATH_MAX * 2];
  size_t cap = 1 << 20, n = 0;
  char *b = malloc(cap);
  assert_non_null(b);
  snprintf(path, sizeof path, "%s/fuzz.xml", dir);
  n += (size_t)sprintf(b + n, "<dtmap-scene version=\"1\">");
  for (int i = 0; i < 5000; i++) n += (size_t)sprintf(b + n, "<effects>");
  for (int i = 0; i < 5000; i++) n += (size_t)sprintf(b + n, "</effects>");
  n += (size_t)sprintf(b + n, "</dtmap-scene>\n");
  write_bytes(path, b, n);
  assert_int_equal(load_once(path), DTM_ERR_INPUT);
  n = (size_t)sprintf(b, "<dtmap-scene version=\"1\">\n<geometry file=\"");
  for (int i = 0; i < 20000; i++) n += (size_t)sprintf(b + n, "a/");
  n += (size_t)sprintf(b + n, "disc.geo\"/>\n<material name=\"");
  memset(b + n, 'm', 100000);
  n += 100000;
  n += (size_t)sprintf(b + n, "\" E=\"1\"/>\n<effects><thermal/></effects>\n</dtmap-scene>\n");
  write_bytes(path, b, n);
  assert_int_equal(load_once(path), DTM_ERR_INPUT);
  free(b);
}

static void test_corpus(void **state) {
  (void)state;
  char corpus[PATH_MAX], path[PATH_MAX * 2];
  int n = 0;
  snprintf(corpus, sizeof corpus, "%s/tests/data/scenes/fuzz", source_dir);
  DIR *d = opendir(corpus);
  if (!d) skip();
  for (struct dirent *e; (e = readdir(d));) {
    size_t len = strlen(e->d_name);
    if (e->d_name[0] == '.' || len < 4 || strcmp(e->d_name + len - 4, ".xml")) continue;
    snprintf(path, sizeof path, "%s/%s", corpus, e->d_name);
    load_once(path);
    n++;
  }
  closedir(d);
  printf("corpus: %d files replayed\n", n);
  assert_true(n > 0);
}

static int setup(void **state) {
  char path[PATH_MAX * 2];
  (void)state;
  strcpy(dir, "/tmp/dtm-t203-XXXXXX");
  if (!mkdtemp(dir)) return -1;
  snprintf(path, sizeof path, "%s/disc.geo", dir);
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fclose(f);
  return 0;
}

static int teardown(void **state) {
  char path[PATH_MAX * 2];
  (void)state;
  snprintf(path, sizeof path, "%s/disc.geo", dir);
  unlink(path);
  snprintf(path, sizeof path, "%s/fuzz.xml", dir);
  unlink(path);
  return rmdir(dir);
}

int main(int argc, char **argv) {
  source_dir = argc > 1 ? argv[1] : ".";
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mutations),
      cmocka_unit_test(test_generated),
      cmocka_unit_test(test_corpus),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
