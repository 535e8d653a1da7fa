/* `dtmap snapshot RESULT.msh` and `dtmap run --png PREFIX`: pictures of a
 * result drawn by Gmsh's renderer (dtm_gmsh_snapshot), under a virtual
 * display when there is none: PREFIX_worst.png shows the views as the .opt
 * leaves them on opening (in 3D the faint model with the below-target
 * elements; in 2D the worst elements framed, opaque over a faint dt map), PREFIX_dt.png
 * the dt map alone, whole, with its colour bar; both with dtmap's figures.
 * Gmsh's window toolkit (FLTK) reports one X protocol error for a window
 * property the server refuses, "X_ChangeProperty: BadValue ...", which is
 * harmless (the window draws) but reads as a failure: while Gmsh draws,
 * the standard error goes through a pipe that passes every other line. */
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli-impl.h"
#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "dtmap/util.h"

#define X_NOISE "X_ChangeProperty: BadValue" /* the line FLTK prints */

typedef struct {
  const char *msh;          /* the result */
  char worst[DTM_PATH_MAX]; /* PREFIX_worst.png */
  char dt[DTM_PATH_MAX];    /* PREFIX_dt.png */
  int width, height;        /* pixels */
} pictures;

typedef struct {
  int from, to; /* the pipe's read end, the real standard error */
} passing;

/* Copy lines from the pipe to the standard error, but X_NOISE's. */
static void *pass_lines(void *arg) {
  passing *p = arg;
  char line[4096];
  size_t k = 0;
  for (;;) {
    char c;
    ssize_t n = read(p->from, &c, 1);
    if (n <= 0 || c == '\n' || k + 1 >= sizeof line) {
      if (n == 1) line[k++] = c;
      if (k && strncmp(line, X_NOISE, strlen(X_NOISE)) && write(p->to, line, k) < 0) break;
      k = 0;
      if (n <= 0) break;
    } else
      line[k++] = c;
  }
  return NULL;
}

/* draw(arg) with the standard error filtered (unfiltered when the pipe
 * cannot be made). */
static int filtered(int (*draw)(void *), void *arg) {
  int fd[2];
  passing p = {-1, -1};
  pthread_t thread;
  fflush(stderr);
  if (pipe(fd)) return draw(arg);
  p.from = fd[0], p.to = dup(2);
  fcntl(fd[0], F_SETFD, FD_CLOEXEC), fcntl(fd[1], F_SETFD, FD_CLOEXEC);
  if (p.to < 0 || dup2(fd[1], 2) < 0 || pthread_create(&thread, NULL, pass_lines, &p)) {
    if (p.to >= 0) dup2(p.to, 2), close(p.to);
    close(fd[0]), close(fd[1]);
    return draw(arg);
  }
  close(fd[1]);
  int r = draw(arg);
  fflush(stderr);
  dup2(p.to, 2); /* the pipe's last write end closes: the thread reads to its end */
  pthread_join(thread, NULL);
  close(p.to), close(fd[0]);
  return r;
}

static int draw(void *arg) {
  pictures *p = arg;
  dtm_snapshot_shot shots[2] = {{p->worst, NULL, 1}, {p->dt, "dt", 0}};
  return dtm_gmsh_snapshot(p->msh, shots, 2, p->width, p->height);
}

static int draw_filtered(void *arg) { return filtered(draw, arg); }

int dtm_cli_pictures(const char *msh, const char *prefix, int width, int height, int verbosity) {
  pictures p = {msh, "", "", width, height};
  snprintf(p.worst, sizeof p.worst, "%.4000s_worst.png", prefix);
  snprintf(p.dt, sizeof p.dt, "%.4000s_dt.png", prefix);
  DTM_CHECK(dtm_cli_with_display(draw_filtered, &p));
  if (verbosity) printf("wrote        %s, %s (%d x %d)\n", p.worst, p.dt, width, height);
  return DTM_OK;
}

/* The pictures can be written (dtm_output_path_check), before Xvfb starts. */
static int check_pictures(const char *prefix, const char *origin) {
  char path[DTM_PATH_MAX];
  static const char *const suffix[2] = {"_worst.png", "_dt.png"};
  for (int i = 0; i < 2; i++) {
    snprintf(path, sizeof path, "%.4000s%s", prefix, suffix[i]);
    DTM_CHECK(dtm_output_path_check(NULL, path, NULL, origin));
  }
  return DTM_OK;
}

int dtm_cli_snapshot(const cli_opts *o) {
  char prefix[DTM_PATH_MAX];
  size_t n = strlen(o->scene);
  if (n < 5 || strcmp(o->scene + n - 4, ".msh"))
    return dtm_cli_fail(DTM_ERR(DTM_ERR_INPUT, "%s: not a .msh result of dtmap run", o->scene), o->verbosity);
  if (access(o->scene, F_OK))
    return dtm_cli_fail(DTM_ERR(DTM_ERR_INPUT,
                                "%s: no such file (the .msh dtmap run wrote: run it first, or check the "
                                "path)",
                                o->scene),
                        o->verbosity);
  if (access(o->scene, R_OK)) return dtm_cli_fail(DTM_ERR(DTM_ERR_INPUT, "%s: cannot read it", o->scene), o->verbosity);
  snprintf(prefix, sizeof prefix, "%.*s", (int)(n - 4), o->scene);
  int r = check_pictures(o->png ? o->png : prefix, o->png ? "--png" : "default picture");
  if (r == DTM_OK) r = dtm_cli_pictures(o->scene, o->png ? o->png : prefix, o->width, o->height, o->verbosity);
  return r ? dtm_cli_fail(r, o->verbosity) : 0;
}
