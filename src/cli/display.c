/* A display for Gmsh's renderer: with DISPLAY set, pictures are drawn
 * there; without one, dtmap starts its own virtual X server (Xvfb, from
 * Debian's xvfb package) on a free display number (Xvfb picks it and writes
 * it to a pipe: -displayfd), draws, and stops the server again. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli-impl.h"
#include "dtmap/error.h"

/* Read Xvfb's display number from fd (it writes "N\n" once it is ready). */
static int read_display(int fd, char *buf, size_t n) {
  size_t k = 0;
  while (k + 1 < n) {
    ssize_t r = read(fd, buf + k, 1);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0 || buf[k] == '\n') break;
    k++;
  }
  buf[k] = '\0';
  return k ? 0 : -1;
}

static void exec_xvfb(int fd[2]) {
  char fdtext[16];
  close(fd[0]);
  snprintf(fdtext, sizeof fdtext, "%d", fd[1]);
  int devnull = open("/dev/null", O_WRONLY);
  if (devnull >= 0) dup2(devnull, 2), dup2(devnull, 1);
  execlp("Xvfb", "Xvfb", "-displayfd", fdtext, "-screen", "0", "4096x4096x24", "-nolisten", "tcp", (char *)NULL);
  _exit(127);
}

static int start_xvfb(pid_t *pid) {
  int fd[2];
  char num[32], display[40];
  if (pipe(fd)) return DTM_ERR(DTM_ERR_INTERNAL, "cannot create a pipe for Xvfb");
  *pid = fork();
  if (*pid == 0) exec_xvfb(fd);
  close(fd[1]);
  int bad = *pid < 0 || read_display(fd[0], num, sizeof num);
  close(fd[0]);
  if (bad) {
    if (*pid > 0) kill(*pid, SIGTERM), waitpid(*pid, NULL, 0);
    return DTM_ERR(DTM_ERR_INPUT, "no display (DISPLAY is not set) and Xvfb could not be started: install the xvfb "
                                  "package (scripts/setup.sh does) or set DISPLAY");
  }
  snprintf(display, sizeof display, ":%s", num);
  setenv("DISPLAY", display, 1);
  return DTM_OK;
}

int dtm_cli_with_display(int (*draw)(void *arg), void *arg) {
  const char *d = getenv("DISPLAY");
  if (d && d[0]) return draw(arg);
  pid_t pid;
  DTM_CHECK(start_xvfb(&pid));
  int r = draw(arg);
  kill(pid, SIGTERM);
  waitpid(pid, NULL, 0);
  unsetenv("DISPLAY");
  return r;
}
