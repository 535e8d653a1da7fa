/* Outputs survive a killed run. dtmap writes every output to a locked
 * temporary beside the target and renames it into place when complete
 * (src/base/atomic.c). Here a run on a large mesh (a structured cube of
 * 6 x 40^3 tetrahedra, written by this test; its output .msh is about 55
 * MB) is killed while it writes:
 *  - SIGKILL: the older output at the path stays intact, and the killed
 *    run's temporary is left; a second killed run removes the first one's,
 *    so they never accumulate; a complete run then replaces the output and
 *    leaves no temporary.
 *  - SIGTERM: the signal handler removes the temporary; the older output
 *    stays.
 *  - A temporary whose PID still runs (this test's own) is not touched; one
 *    whose PID is gone and that nobody locks is removed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "testutil.h"

#define N 40                    /* cubes per side */
#define OLD "an older output\n" /* what the output path holds before */
#define BIG_ENOUGH (4L << 20)   /* bytes of the temporary when killed: mid-write */
static char dir[512], scene[600], out[600];

static void write_cube(const char *path) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  int n1 = N + 1;
  fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"rock\"\n$EndPhysicalNames\n");
  fprintf(f, "$Nodes\n%d\n", n1 * n1 * n1);
  for (int k = 0, id = 1; k < n1; k++)
    for (int j = 0; j < n1; j++)
      for (int i = 0; i < n1; i++) fprintf(f, "%d %g %g %g\n", id++, (double)i / N, (double)j / N, (double)k / N);
  fprintf(f, "$EndNodes\n$Elements\n%d\n", 6 * N * N * N);
  static const int split[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  for (int k = 0, t = 1; k < N; k++)
    for (int j = 0; j < N; j++)
      for (int i = 0; i < N; i++) {
        int c[8], d[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
        for (int v = 0; v < 8; v++) c[v] = 1 + (i + d[v][0]) + n1 * ((j + d[v][1]) + n1 * (k + d[v][2]));
        for (int s = 0; s < 6; s++)
          fprintf(f, "%d 4 2 1 1 %d %d %d %d\n", t++, c[split[s][0]], c[split[s][1]], c[split[s][2]], c[split[s][3]]);
      }
  fprintf(f, "$EndElements\n");
  assert_int_equal(fclose(f), 0);
}

static int setup(void **state) {
  char msh[600];
  (void)state;
  snprintf(dir, sizeof dir, "%s", tu_tmpdir());
  snprintf(msh, sizeof msh, "%s/cube.msh", dir);
  snprintf(scene, sizeof scene, "%s/cube.xml", dir);
  snprintf(out, sizeof out, "%s/out.msh", dir);
  write_cube(msh);
  tu_write(scene, "<dtmap-scene version=\"1\">\n  <mesh file=\"cube.msh\"/>\n"
                  "  <material name=\"steel\" groups=\"rock\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                  "  <effects><elastic/></effects>\n</dtmap-scene>\n");
  return 0;
}

static pid_t start_run(void) {
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    execl(tu_cli(), tu_cli(), "run", scene, "-q", "-o", out, (char *)NULL);
    _exit(127);
  }
  return pid;
}

/* Size of the file at path, -1 when absent. */
static long size_of(const char *path) {
  struct stat st;
  return stat(path, &st) ? -1 : (long)st.st_size;
}

/* Run dtmap and send sig once its temporary output holds BIG_ENOUGH bytes
 * (polled every millisecond); returns 0, or -1 when the run ended first. */
static int kill_mid_write(int sig, char *tmp, size_t len) {
  pid_t pid = start_run();
  snprintf(tmp, len, "%s/.out.msh.tmp%ld.msh", dir, (long)pid);
  int status;
  while (size_of(tmp) < BIG_ENOUGH) {
    if (waitpid(pid, &status, WNOHANG) == pid) return -1;
    nanosleep(&(struct timespec){0, 1000000}, NULL);
  }
  kill(pid, sig);
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == sig);
  return 0;
}

/* Files in dir whose names start with ".out.msh.tmp". */
static int temporaries(void) {
  DIR *d = opendir(dir);
  int n = 0;
  for (struct dirent *e; (e = readdir(d));) n += !strncmp(e->d_name, ".out.msh.tmp", 12);
  closedir(d);
  return n;
}

static void assert_old_output(void) {
  FILE *f = fopen(out, "r");
  char line[64] = "";
  assert_non_null(f);
  assert_non_null(fgets(line, sizeof line, f));
  fclose(f);
  assert_string_equal(line, OLD);
}

static void test_sigkill(void **state) {
  (void)state;
  char first[700], second[700];
  tu_write(out, OLD);
  assert_int_equal(kill_mid_write(SIGKILL, first, sizeof first), 0);
  assert_old_output();
  assert_true(size_of(first) >= BIG_ENOUGH); /* what a killed run leaves ... */
  assert_int_equal(kill_mid_write(SIGKILL, second, sizeof second), 0);
  assert_old_output();
  assert_int_equal(size_of(first), -1); /* ... the next run removes */
  assert_int_equal(temporaries(), 1);
  char *log = NULL;
  assert_int_equal(tu_run(&log, "%s run %s -q -o %s", tu_cli(), scene, out), 0);
  free(log);
  assert_int_equal(temporaries(), 0);
  assert_true(size_of(out) > BIG_ENOUGH);
}

static void test_sigterm(void **state) {
  (void)state;
  char tmp[700];
  tu_write(out, OLD);
  assert_int_equal(kill_mid_write(SIGTERM, tmp, sizeof tmp), 0);
  assert_old_output();
  assert_int_equal(temporaries(), 0);
}

/* A live writer's temporary stays; a dead, unlocked one goes. */
static void test_live_and_dead(void **state) {
  (void)state;
  char live[700], dead[700], *log = NULL;
  pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, NULL, 0); /* its PID is now gone */
  snprintf(live, sizeof live, "%s/.out.msh.tmp%ld.msh", dir, (long)getpid());
  snprintf(dead, sizeof dead, "%s/.out.msh.tmp%ld.msh", dir, (long)child);
  tu_write(live, "being written\n");
  tu_write(dead, "left by a killed run\n");
  assert_int_equal(tu_run(&log, "%s run %s -q -o %s", tu_cli(), scene, out), 0);
  free(log);
  assert_true(size_of(live) > 0);
  assert_int_equal(size_of(dead), -1);
  unlink(live);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sigkill),
      cmocka_unit_test(test_sigterm),
      cmocka_unit_test(test_live_and_dead),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
