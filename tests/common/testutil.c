/* Test helpers: paths from argv, temporary directories removed at exit,
 * running shell commands with captured output, JSON look-ups, and reading
 * views back through the Gmsh API. */
#include "testutil.h"

#include <cJSON.h>
#include <gmshc.h>

#include "dtmap/analysis.h"
#include <dirent.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

char *mkdtemp(char *);

static const char *src_dir = ".", *cli_path = "dtmap";
static char tmp_dir[256];

/* Every report the program wrote (the *.json of its temporary folder)
 * must follow the report schema; a violation fails the program. */
static int check_reports(void) {
  char cmd[8192];
  snprintf(cmd, sizeof cmd, "'%s' '%s/tests/common/report_schema.py' '%s/schema/dtmap-report.schema.json' '%s' >&2",
           DTM_TEST_PYTHON, src_dir, src_dir, tmp_dir);
  int st = system(cmd);
  if (st == 0) return 0;
  fprintf(stderr, "a report written by this test does not follow schema/dtmap-report.schema.json (above)\n");
  return 1;
}

static void cleanup(void) {
  if (!tmp_dir[0]) return;
  char cmd[300];
  int bad = check_reports();
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp_dir);
  if (system(cmd)) fprintf(stderr, "could not remove %s\n", tmp_dir);
  if (bad) _exit(1);
}

void tu_init(int argc, char **argv) {
  if (argc > 1) src_dir = argv[1];
  if (argc > 2) cli_path = argv[2];
}
const char *tu_src(void) { return src_dir; }
const char *tu_cli(void) { return cli_path; }

const char *tu_tmpdir(void) {
  if (!tmp_dir[0]) {
    snprintf(tmp_dir, sizeof tmp_dir, "/tmp/dtmap-test-XXXXXX");
    if (!mkdtemp(tmp_dir)) abort();
    atexit(cleanup);
  }
  return tmp_dir;
}

void tu_write(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f || fputs(text, f) < 0 || fclose(f)) {
    fprintf(stderr, "cannot write %s\n", path);
    abort();
  }
}

char *tu_slurp(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  long size = f && !fseek(f, 0, SEEK_END) ? ftell(f) : -1;
  char *buf = size >= 0 ? malloc((size_t)size + 1) : NULL;
  if (!buf || fseek(f, 0, SEEK_SET) || fread(buf, 1, (size_t)size, f) != (size_t)size) {
    fprintf(stderr, "cannot read %s\n", path);
    abort();
  }
  fclose(f);
  buf[size] = '\0';
  *n = (size_t)size;
  return buf;
}

void tu_remove_tree(const char *path) {
  DIR *d = opendir(path);
  struct dirent *e;
  while (d && (e = readdir(d))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    char child[PATH_MAX * 2];
    struct stat st;
    snprintf(child, sizeof child, "%s/%s", path, e->d_name);
    if (lstat(child, &st) == 0 && S_ISDIR(st.st_mode))
      tu_remove_tree(child);
    else
      unlink(child);
  }
  if (d) closedir(d);
  rmdir(path);
}

int tu_exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0;
}

int tu_run(char **out, const char *fmt, ...) {
  char cmd[8192];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(cmd, sizeof cmd, fmt, ap);
  va_end(ap);
  strncat(cmd, " 2>&1", sizeof cmd - strlen(cmd) - 1);
  FILE *p = popen(cmd, "r");
  if (!p) return -1;
  size_t cap = 4096, n = 0;
  char *buf = malloc(cap);
  for (size_t k; (k = fread(buf + n, 1, cap - n - 1, p)) > 0;) {
    n += k;
    if (cap - n < 2) buf = realloc(buf, cap *= 2);
  }
  buf[n] = '\0';
  int st = pclose(p);
  if (out)
    *out = buf;
  else
    free(buf);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

cJSON *tu_json_load(const char *path) {
  FILE *f = fopen(path, "r");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *buf = malloc((size_t)n + 1);
  size_t got = fread(buf, 1, (size_t)n, f);
  buf[got] = '\0';
  fclose(f);
  cJSON *j = cJSON_Parse(buf);
  free(buf);
  return j;
}

double tu_json_number(const cJSON *root, const char *dotted) {
  char key[256];
  snprintf(key, sizeof key, "%s", dotted);
  const cJSON *o = root;
  for (char *tok = strtok(key, "."); tok && o; tok = strtok(NULL, ".")) o = cJSON_GetObjectItemCaseSensitive(o, tok);
  return (o && cJSON_IsNumber(o)) ? o->valuedouble : NAN;
}

int tu_view_count(void) {
  int *tags = NULL, ierr = 0;
  size_t n = 0;
  gmshViewGetTags(&tags, &n, &ierr);
  gmshFree(tags);
  return (int)n;
}

/* Tag of the first (last: the latest) view called name, -1 when none. */
static int view_tag_named(const char *name, int last) {
  int *tags = NULL, ierr = 0, found = -1;
  size_t n = 0;
  gmshViewGetTags(&tags, &n, &ierr);
  for (size_t i = 0; i < n && (found < 0 || last); i++) {
    char opt[64], *val = NULL;
    snprintf(opt, sizeof opt, "View[%d].Name", gmshViewGetIndex(tags[i], &ierr));
    gmshOptionGetString(opt, &val, &ierr);
    if (val && strcmp(val, name) == 0) found = tags[i];
    gmshFree(val);
  }
  gmshFree(tags);
  return found;
}

static int view_read(const char *name, int last, tu_view *v) {
  int tag = view_tag_named(name, last), ierr = 0, nc = 0;
  char *type = NULL;
  double time = 0;
  memset(v, 0, sizeof *v);
  if (tag < 0) return -1;
  size_t nd = 0;
  gmshViewGetHomogeneousModelData(tag, 0, &type, &v->tags, &v->n, &v->values, &nd, &time, &nc, &ierr);
  if (type) snprintf(v->type, sizeof v->type, "%s", type);
  gmshFree(type);
  return ierr || nd != v->n ? -1 : 0;
}

int tu_view_read(const char *name, tu_view *v) { return view_read(name, 0, v); }
int tu_view_read_last(const char *name, tu_view *v) { return view_read(name, 1, v); }

void tu_view_free(tu_view *v) {
  gmshFree(v->tags);
  gmshFree(v->values);
  memset(v, 0, sizeof *v);
}

dtm_analysis *tu_analyse(const char *name, dtm_scene **s) {
  char path[600];
  dtm_analysis *a = NULL;
  snprintf(path, sizeof path, "%s/%s.xml", tu_tmpdir(), name);
  if (dtm_scene_load(path, s) || dtm_analysis_run(*s, &a)) {
    fprintf(stderr, "%s: %s\n", path, dtm_error_message());
    abort();
  }
  return a;
}

void tu_steel_scene(const char *name, const char *source, const char *meshing, const char *tail) {
  char path[600], text[4096];
  snprintf(text, sizeof text,
           "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n%s\n<meshing %s/>\n"
           "<material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
           "<effects><elastic/></effects>\n%s\n</dtmap-scene>\n",
           source, meshing, tail);
  snprintf(path, sizeof path, "%s/%s.xml", tu_tmpdir(), name);
  tu_write(path, text);
}

void tu_cube_geo(const char *file, const char *extra) {
  char path[600], text[1024];
  snprintf(path, sizeof path, "%s/%s", tu_tmpdir(), file);
  snprintf(text, sizeof text,
           "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\n"
           "Physical Volume(\"block\") = {1};\n%s",
           extra);
  tu_write(path, text);
}

void tu_gmsh_begin(void) {
  int ierr = 0;
  gmshInitialize(0, NULL, 0, &ierr);
  gmshOptionSetNumber("General.Terminal", 0, &ierr);
  gmshOptionSetNumber("General.AbortOnError", 0, &ierr);
  /* A solver socket of this process's own: Gmsh's default (~/.gmshsock)
   * is shared by every Gmsh of the user, so two suites side by side (or
   * another user's Gmsh on a shared machine) would connect dtmap to the
   * wrong session. */
  char sock[64];
  snprintf(sock, sizeof sock, ".gmshsock-dtmtest-%ld-", (long)getpid());
  gmshOptionSetString("Solver.SocketName", sock, &ierr);
}

void tu_gmsh_end(void) {
  int ierr = 0;
  gmshFinalize(&ierr);
}
