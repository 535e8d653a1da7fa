/* Outputs survive a killed run. dtmap writes every output to a file
 * without a name beside the target, reached by a link .out.msh.tmpPID.msh
 * while it is written, and links it in and renames it into place when
 * complete (src/base/atomic.c); the command runs in a supervised worker
 * (src/cli/supervise.c). Here a run on a large mesh (a structured cube of
 * 6 x 40^3 tetrahedra, written by this test; its output .msh is about 55
 * MB) is killed while it writes:
 *  - the command killed by SIGKILL, SIGTERM or SIGINT: the older output at
 *    the path stays intact and no temporary is left (the worker, told by
 *    the signal passed on or by its parent's death, removes the link);
 *  - the worker killed by SIGKILL (what the OOM killer does): the command
 *    exits 3 naming the stage and the signal, removes the worker's link,
 *    and the older output stays;
 *  - both killed by SIGKILL at once (the process group): the link is left,
 *    dangling (no data outlives them); the next run removes it, replaces
 *    the output and leaves no temporary;
 *  - a temporary whose PID still runs (this test's own) is not touched; a
 *    plain one whose PID is gone and that nobody locks is removed, and so
 *    is a dangling link of a PID that is gone;
 *  - a link left by a writer that ended but is not reaped yet (a zombie:
 *    its PID still answers, as a worker's does until its new parent reaps
 *    it after both were killed) is removed by the next run. */
#define _GNU_SOURCE /* O_TMPFILE */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <dirent.h>
#include <fcntl.h>
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
    setpgid(0, 0); /* its own group: the test can kill the command and its worker at once */
    execl(tu_cli(), tu_cli(), "run", scene, "-q", "-o", out, (char *)NULL);
    _exit(127);
  }
  return pid;
}

/* Size of the file at path (through a link), -1 when absent. */
static long size_of(const char *path) {
  struct stat st;
  return stat(path, &st) ? -1 : (long)st.st_size;
}

/* The names in dir that start with ".out.msh.tmp"; the last into last. */
static int temporaries(char *last, size_t len) {
  DIR *d = opendir(dir);
  int n = 0;
  for (struct dirent *e; (e = readdir(d));)
    if (!strncmp(e->d_name, ".out.msh.tmp", 12)) {
      n++;
      if (last) snprintf(last, len, "%s/%s", dir, e->d_name);
    }
  closedir(d);
  return n;
}

/* Whether no temporary is left within 3 s (the worker may still be
 * running its handler when the command is gone). */
static int none_left(void) {
  for (int i = 0; i < 300 && temporaries(NULL, 0); i++) nanosleep(&(struct timespec){0, 10000000}, NULL);
  return temporaries(NULL, 0) == 0;
}

/* Run dtmap and, once its temporary output holds BIG_ENOUGH bytes (polled
 * every millisecond), send sig to the command (whom: 0), to its worker
 * (whom: 1, the PID in the temporary's name) or to both (whom: 2); returns
 * the command's wait status, or -1 when the run ended first. */
static int kill_mid_write(int sig, int whom) {
  pid_t pid = start_run();
  char tmp[1024] = "";
  int status;
  while (!temporaries(tmp, sizeof tmp) || size_of(tmp) < BIG_ENOUGH) {
    if (waitpid(pid, &status, WNOHANG) == pid) return -1;
    nanosleep(&(struct timespec){0, 1000000}, NULL);
  }
  pid_t worker = (pid_t)atol(strstr(tmp, ".tmp") + 4);
  assert_true(worker > 0 && worker != pid);
  if (whom == 2) kill(-pid, sig);
  kill(whom == 1 ? worker : pid, sig);
  assert_int_equal(waitpid(pid, &status, 0), pid);
  return status;
}

static void assert_old_output(void) {
  FILE *f = fopen(out, "r");
  char line[64] = "";
  assert_non_null(f);
  assert_non_null(fgets(line, sizeof line, f));
  fclose(f);
  assert_string_equal(line, OLD);
}

static void command_killed(int sig) {
  tu_write(out, OLD);
  int status = kill_mid_write(sig, 0);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == sig);
  assert_old_output();
  assert_true(none_left());
}

static void test_sigkill(void **state) {
  (void)state;
  command_killed(SIGKILL);
}

static void test_sigterm(void **state) {
  (void)state;
  command_killed(SIGTERM);
}

static void test_sigint(void **state) {
  (void)state;
  command_killed(SIGINT);
}

static void test_worker_killed(void **state) {
  (void)state;
  tu_write(out, OLD);
  int status = kill_mid_write(SIGKILL, 1);
  assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 3);
  assert_old_output();
  assert_int_equal(temporaries(NULL, 0), 0); /* the command removed it before it ended */
}

static void test_both_killed(void **state) {
  (void)state;
  char link[1024], *log = NULL;
  struct stat st;
  tu_write(out, OLD);
  int status = kill_mid_write(SIGKILL, 2);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  assert_old_output();
  assert_int_equal(temporaries(link, sizeof link), 1); /* what both killed leave ... */
  assert_int_equal(lstat(link, &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  for (int i = 0; i < 300 && size_of(link) >= 0; i++) /* ... a link to nothing, once the worker is gone */
    nanosleep(&(struct timespec){0, 10000000}, NULL);
  assert_int_equal(size_of(link), -1);
  assert_int_equal(tu_run(&log, "%s run %s -q -o %s", tu_cli(), scene, out), 0);
  free(log);
  assert_int_equal(temporaries(NULL, 0), 0); /* the next run removed it */
  assert_true(size_of(out) > BIG_ENOUGH);
}

/* A live writer's temporary stays; a dead, unlocked one goes, and so does
 * a dead one's link. */
static void test_live_and_dead(void **state) {
  (void)state;
  char live[700], dead[700], link[1024], *log = NULL;
  struct stat st;
  pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, NULL, 0); /* its PID is now gone */
  snprintf(live, sizeof live, "%s/.out.msh.tmp%ld.msh", dir, (long)getpid());
  snprintf(dead, sizeof dead, "%s/.out.msh.tmp%ld.msh", dir, (long)child);
  snprintf(link, sizeof link, "%s/.out.msh.tmp%ld", dir, (long)child);
  tu_write(live, "being written\n");
  tu_write(dead, "left by a killed run\n");
  assert_int_equal(symlink("/proc/1/fd/999", link), 0);
  assert_int_equal(tu_run(&log, "%s run %s -q -o %s", tu_cli(), scene, out), 0);
  free(log);
  assert_true(size_of(live) > 0);
  assert_int_equal(size_of(dead), -1);
  assert_int_equal(lstat(link, &st), -1);
  unlink(live);
}

/* A writer that ended but was not reaped yet (a zombie, whose PID still
 * answers kill(pid, 0): what a run killed with its worker leaves until the
 * worker's new parent reaps it) left a link to its closed descriptor: the
 * next run removes it. */
static void test_zombie_writer(void **state) {
  (void)state;
  char link[1024], *log = NULL;
  struct stat st;
  int go[2];
  assert_int_equal(pipe(go), 0);
  pid_t child = fork();
  if (child == 0) { /* a writer: an unnamed file, its link, then killed before the rename */
    char name[1024];
    int fd = open(dir, O_TMPFILE | O_WRONLY, 0644);
    snprintf(name, sizeof name, "/proc/%ld/fd/%d", (long)getpid(), fd);
    snprintf(link, sizeof link, "%s/.out.msh.tmp%ld.msh", dir, (long)getpid());
    char ok = fd >= 0 && symlink(name, link) == 0;
    if (write(go[1], &ok, 1) != 1) _exit(1);
    _exit(0);
  }
  char ok = 0;
  close(go[1]);
  assert_int_equal(read(go[0], &ok, 1), 1);
  close(go[0]);
  assert_true(ok);
  snprintf(link, sizeof link, "%s/.out.msh.tmp%ld.msh", dir, (long)child);
  siginfo_t si;
  assert_int_equal(waitid(P_PID, (id_t)child, &si, WEXITED | WNOWAIT), 0); /* ended, not reaped */
  assert_int_equal(kill(child, 0), 0);
  assert_int_equal(lstat(link, &st), 0);
  assert_int_equal(tu_run(&log, "%s run %s -q -o %s", tu_cli(), scene, out), 0);
  free(log);
  assert_int_equal(lstat(link, &st), -1);
  waitpid(child, NULL, 0);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sigkill),       cmocka_unit_test(test_sigterm),     cmocka_unit_test(test_sigint),
      cmocka_unit_test(test_worker_killed), cmocka_unit_test(test_both_killed), cmocka_unit_test(test_live_and_dead),
      cmocka_unit_test(test_zombie_writer),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
