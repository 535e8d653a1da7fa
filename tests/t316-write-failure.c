/* A write that fails names the file the user asked for and the system's
 * reason, exits 2 (as every failed write does), leaves the older file at
 * that path byte for byte as it was and no temporary beside it.
 *
 * The failures are real ones, provoked without root: the CLI runs in a
 * child whose files may not grow past RLIMIT_FSIZE bytes, with SIGXFSZ
 * ignored, so the write that would pass the limit fails with EFBIG ("File
 * too large"). The limits are chosen so that each writer fails in turn:
 * Gmsh's writer of the mesh (which does not check its writes), dtmap's
 * writer of the views appended to it, the JSON report, sweep's CSV and the
 * PNG PLplot draws (which does not check its writes either). A full disk
 * (ENOSPC) cannot be provoked portably without root for a file in a
 * directory; /dev/full gives it to the two writers that take a stream: the
 * views writer and an atomic output whose stream is pointed at it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/util.h"
#include "testutil.h"

#define TOO_LARGE "File too large"
#define NO_SPACE "No space left on device"

static char dir[512], scene[700], mesh[700], report[700], csv[700], png[700], vreport[700];

/* The bytes of the file at path (malloc'ed) and their count; NULL when it
 * cannot be read. */
static char *slurp(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  size_t cap = 1 << 16;
  char *buf = malloc(cap);
  *n = 0;
  for (size_t k; buf && (k = fread(buf + *n, 1, cap - *n, f)) > 0;)
    if ((*n += k) == cap) buf = realloc(buf, cap *= 2);
  fclose(f);
  return buf;
}

/* An older output, kept to compare the file at its path with afterwards. */
typedef struct {
  const char *path;
  char *bytes;
  size_t n;
} older;

static older keep(const char *path) {
  older o = {path, NULL, 0};
  o.bytes = slurp(path, &o.n);
  assert_non_null(o.bytes);
  assert_true(o.n > 0);
  return o;
}

static void assert_unchanged(older *o) {
  size_t n = 0;
  char *now = slurp(o->path, &n);
  assert_non_null(now);
  if (n != o->n || memcmp(now, o->bytes, n)) fail_msg("%s was changed by the failed run", o->path);
  free(now);
  free(o->bytes);
  o->bytes = NULL;
}

/* No temporary (a name holding ".tmp") is left in the test's folder. */
static void assert_no_temporary(void) {
  DIR *d = opendir(dir);
  assert_non_null(d);
  for (struct dirent *e; (e = readdir(d));)
    if (strstr(e->d_name, ".tmp")) fail_msg("a temporary was left: %s/%s", dir, e->d_name);
  closedir(d);
}

/* Run the CLI with args (NULL-terminated, after the program name) in a
 * child whose files may hold at most limit bytes (0: no limit), SIGXFSZ
 * ignored; its stderr (through a pipe: not a file, so not limited) into
 * log. Returns its exit code, -1 when it did not exit. */
static int run_limited(long limit, char *log, size_t len, const char *const *args) {
  const char *argv[16] = {tu_cli()};
  for (int i = 0; args[i] && i < 14; i++) argv[i + 1] = args[i];
  int fds[2];
  assert_int_equal(pipe(fds), 0);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    struct rlimit rl = {(rlim_t)limit, (rlim_t)limit};
    int null = open("/dev/null", O_WRONLY);
    signal(SIGXFSZ, SIG_IGN);
    if (limit > 0 && setrlimit(RLIMIT_FSIZE, &rl)) _exit(126);
    dup2(fds[1], 2), dup2(null, 1), close(fds[0]), close(fds[1]);
    execv(tu_cli(), (char *const *)argv);
    _exit(127);
  }
  close(fds[1]);
  size_t n = 0;
  for (ssize_t k; n + 1 < len && (k = read(fds[0], log + n, len - n - 1)) > 0;) n += (size_t)k;
  log[n] = '\0';
  close(fds[0]);
  int status;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* The message names path and reason. */
static void assert_says(const char *log, const char *path, const char *reason) {
  char want[800];
  snprintf(want, sizeof want, "dtmap: error: %s: cannot write", path);
  if (!strstr(log, want) || !strstr(log, reason))
    fail_msg("expected a message naming %s and '%s', got:\n%s", path, reason, log);
}

static const char *const run_args[] = {"run", scene, "-q", "--format", "ascii", "-o", mesh, "--report", report, NULL};

static int setup(void **state) {
  (void)state;
  char log[4096];
  snprintf(dir, sizeof dir, "%s", tu_tmpdir());
  snprintf(scene, sizeof scene, "%s/geometries/box.xml", tu_src());
  snprintf(mesh, sizeof mesh, "%s/out.msh", dir);
  snprintf(report, sizeof report, "%s/out.json", dir);
  snprintf(vreport, sizeof vreport, "%s/verify.json", dir);
  snprintf(csv, sizeof csv, "%s/sweep.csv", dir);
  snprintf(png, sizeof png, "%s/sweep.png", dir);
  /* the older outputs: complete runs */
  if (run_limited(0, log, sizeof log, run_args)) return fprintf(stderr, "%s", log), -1;
  const char *const verify[] = {"verify", scene, "-q", "--steps", "20", "--report", vreport, NULL};
  if (run_limited(0, log, sizeof log, verify)) return fprintf(stderr, "%s", log), -1;
  const char *const sweep[] = {"sweep", scene, "-q", "--sizes", "0.03,0.02", "--csv", csv, "--plot", png, NULL};
  if (run_limited(0, log, sizeof log, sweep)) return fprintf(stderr, "%s", log), -1;
  return 0;
}

/* The offset of the first view in the older output: the mesh's size. */
static long mesh_bytes(void) {
  size_t n = 0;
  char *b = slurp(mesh, &n), *at = NULL;
  assert_non_null(b);
  for (size_t i = 0; i + 12 < n && !at; i++)
    if (!memcmp(b + i, "\n$ElementData", 13)) at = b + i + 1;
  assert_non_null(at);
  long off = (long)(at - b);
  free(b);
  return off;
}

/* Gmsh's writer of the mesh hits the limit: no reason from Gmsh, so dtmap
 * sees the mesh cut short and asks the system. */
static void test_mesh(void **state) {
  (void)state;
  char log[4096], opt[720];
  snprintf(opt, sizeof opt, "%s.opt", mesh);
  older m = keep(mesh), o = keep(opt), r = keep(report);
  assert_int_equal(run_limited(mesh_bytes() / 2, log, sizeof log, run_args), 2);
  assert_says(log, mesh, TOO_LARGE);
  assert_non_null(strstr(log, "the mesh"));
  assert_null(strstr(log, ".tmp")); /* the user's path, not the temporary's */
  assert_unchanged(&m), assert_unchanged(&o), assert_unchanged(&r);
  assert_no_temporary();
}

/* The mesh fits, the views appended after it do not. */
static void test_views(void **state) {
  (void)state;
  char log[4096], opt[720];
  snprintf(opt, sizeof opt, "%s.opt", mesh);
  older m = keep(mesh), o = keep(opt), r = keep(report);
  assert_int_equal(run_limited(mesh_bytes() + 4096, log, sizeof log, run_args), 2);
  assert_says(log, mesh, TOO_LARGE);
  assert_non_null(strstr(log, "view '"));
  assert_null(strstr(log, ".tmp"));
  assert_unchanged(&m), assert_unchanged(&o), assert_unchanged(&r);
  assert_no_temporary();
}

/* The JSON report (verify's: no mesh is written before it). */
static void test_report(void **state) {
  (void)state;
  char log[4096];
  older v = keep(vreport);
  const char *const args[] = {"verify", scene, "-q", "--steps", "20", "--report", vreport, NULL};
  assert_int_equal(run_limited(64, log, sizeof log, args), 2);
  assert_says(log, vreport, TOO_LARGE);
  assert_unchanged(&v);
  assert_no_temporary();
}

/* Sweep's CSV (dtmap's stream), then its PNG (PLplot's writer, with the
 * CSV under the limit). */
static void test_sweep(void **state) {
  (void)state;
  char log[4096];
  older c = keep(csv), p = keep(png);
  const char *const args[] = {"sweep", scene, "-q", "--sizes", "0.03,0.02", "--csv", csv, "--plot", png, NULL};
  assert_int_equal(run_limited(64, log, sizeof log, args), 2);
  assert_says(log, csv, TOO_LARGE);
  assert_unchanged(&c), assert_unchanged(&p);
  assert_no_temporary();
  p = keep(png);
  assert_true(p.n > 8192);
  assert_int_equal(run_limited(4096, log, sizeof log, args), 2);
  assert_says(log, png, TOO_LARGE);
  assert_unchanged(&p);
  assert_no_temporary();
}

/* ENOSPC for the views writer: /dev/full takes the views and refuses
 * them at the first flush. A view larger than stdio's buffer fails while
 * it is written; a small one only when the file is closed. */
static void test_full_views(void **state) {
  (void)state;
  if (access("/dev/full", W_OK)) skip();
  enum { N = 4000 };
  static size_t tags[N];
  static double vals[N];
  for (size_t i = 0; i < N; i++) tags[i] = i + 1, vals[i] = 1e-7 * (double)(i + 1);
  dtm_view big = {"big", 0, tags, vals, N, NULL, 0}, small = {"small", 0, tags, vals, 2, NULL, 0};
  dtm_msh_format fmt = {0, 0, 0};
  dtm_error_clear();
  assert_int_equal(dtm_gmsh_write_views("/dev/full", &big, 1, &fmt), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "/dev/full: cannot write view 'big': " NO_SPACE));
  dtm_error_clear();
  assert_int_equal(dtm_gmsh_write_views("/dev/full", &small, 1, &fmt), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "/dev/full: cannot write the views: " NO_SPACE));
  dtm_error_clear();
}

/* ENOSPC for an atomic output's stream: pointed at /dev/full, its writes
 * fail; the commit names the target, removes the temporary and leaves the
 * older file. */
static void test_full_atomic(void **state) {
  (void)state;
  if (access("/dev/full", W_OK)) skip();
  char path[700];
  snprintf(path, sizeof path, "%s/atomic.txt", dir);
  tu_write(path, "the older file\n");
  older o = keep(path);
  dtm_atomic w;
  assert_int_equal(dtm_atomic_open(&w, path, "", 1), DTM_OK);
  int full = open("/dev/full", O_WRONLY);
  assert_true(full >= 0);
  assert_true(dup2(full, fileno(w.f)) >= 0);
  close(full);
  for (int i = 0; i < 10000; i++) fprintf(w.f, "line %d of a file that does not fit\n", i);
  dtm_error_clear();
  assert_int_equal(dtm_atomic_commit(&w), DTM_ERR_INPUT);
  char want[800];
  snprintf(want, sizeof want, "%s: cannot write: " NO_SPACE, path);
  assert_string_equal(dtm_error_message(), want);
  dtm_error_clear();
  assert_unchanged(&o);
  assert_no_temporary();
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mesh),  cmocka_unit_test(test_views),      cmocka_unit_test(test_report),
      cmocka_unit_test(test_sweep), cmocka_unit_test(test_full_views), cmocka_unit_test(test_full_atomic),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
