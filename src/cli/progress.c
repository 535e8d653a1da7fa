/* The CLI's one-line progress indicator, drawn from the library's progress
 * hook (include/dtmap/progress.h): on a terminal (stderr), unless -q, a
 * stage that has run for more than a second shows as
 * "  refine round 1 > meshing  4.2 s" (with a percentage when the stage
 * knows its fraction), redrawn every 0.2 s by a small thread so that it
 * moves even while Gmsh meshes, and erased when the stage ends, before
 * anything else is printed. DTMAP_PROGRESS_AFTER=<seconds> changes the one
 * second (tests use 0). */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli-impl.h"
#include "dtmap/progress.h"
#include "dtmap/util.h"

#define LEVELS 8 /* nesting shown */

static struct {
  pthread_mutex_t mu;    /* guards everything below */
  pthread_t ticker;      /* the redrawing thread */
  int running;           /* 1 while the ticker runs */
  int depth;             /* open stages */
  char name[LEVELS][96]; /* their names, outermost first */
  double t0[LEVELS];     /* when each began, s */
  double frac;           /* the innermost stage's fraction, or -1 */
  int drawn;             /* a line is on the terminal */
  double after;          /* draw stages older than this, s */
} pg = {.mu = PTHREAD_MUTEX_INITIALIZER};

static void draw_locked(void) {
  if (pg.depth <= 0 || dtm_wtime() - pg.t0[pg.depth - 1] < pg.after) return;
  char line[512] = "";
  for (int i = 0; i < pg.depth && i < LEVELS; i++) {
    size_t n = strlen(line);
    snprintf(line + n, sizeof line - n, "%s%s", i ? " > " : "  ", pg.name[i]);
  }
  size_t n = strlen(line);
  if (pg.frac >= 0) snprintf(line + n, sizeof line - n, " %3.0f%%", 100 * pg.frac), n = strlen(line);
  snprintf(line + n, sizeof line - n, "  %.1f s", dtm_wtime() - pg.t0[0]);
  fprintf(stderr, "\r%.78s\033[K", line);
  fflush(stderr);
  pg.drawn = 1;
}

static void erase_locked(void) {
  if (pg.drawn) fputs("\r\033[K", stderr), fflush(stderr);
  pg.drawn = 0;
}

static void hook(void *user, int event, const char *stage, double fraction, int depth) {
  (void)user;
  pthread_mutex_lock(&pg.mu);
  if (event == DTM_PROGRESS_BEGIN && depth < LEVELS) {
    snprintf(pg.name[depth], sizeof pg.name[depth], "%s", stage);
    pg.t0[depth] = dtm_wtime();
    pg.depth = depth + 1, pg.frac = -1;
  } else if (event == DTM_PROGRESS_UPDATE) {
    pg.frac = fraction;
  } else if (event == DTM_PROGRESS_END) {
    erase_locked();
    pg.depth = depth, pg.frac = -1;
  }
  if (event != DTM_PROGRESS_END && pg.after <= 0) draw_locked(); /* no delay: draw every event */
  pthread_mutex_unlock(&pg.mu);
}

static void *tick(void *unused) {
  (void)unused;
  struct timespec ts = {0, 200000000};
  for (;;) {
    pthread_mutex_lock(&pg.mu);
    int run = pg.running;
    if (run) draw_locked();
    pthread_mutex_unlock(&pg.mu);
    if (!run) return NULL;
    nanosleep(&ts, NULL);
  }
}

void dtm_cli_progress_start(int verbosity) {
  if (verbosity < 1 || !isatty(fileno(stderr))) return;
  const char *env = getenv("DTMAP_PROGRESS_AFTER");
  pg.after = env && *env ? atof(env) : 1.0;
  pg.running = 1;
  if (pthread_create(&pg.ticker, NULL, tick, NULL)) {
    pg.running = 0;
    return;
  }
  dtm_progress_set(hook, NULL);
}

void dtm_cli_progress_stop(void) {
  if (!pg.running) return;
  dtm_progress_set(NULL, NULL);
  pthread_mutex_lock(&pg.mu);
  pg.running = 0;
  erase_locked();
  pthread_mutex_unlock(&pg.mu);
  pthread_join(pg.ticker, NULL);
}
