/* The CLI's progress: the library's progress hook (include/dtmap/progress.h)
 * records the open stages, and a small thread draws them every 0.2 s, on a
 * terminal (stderr), unless -q: a stage that has run for more than a second
 * shows as "  refine round 1 > meshing  4.2 s" (with a percentage when the
 * stage knows its fraction), moving even while Gmsh meshes, and erased when
 * the stage ends, before anything else is printed. DTMAP_PROGRESS_AFTER=
 * <seconds> changes the one second (tests use 0).
 *
 * The record lives in memory shared by the supervisor and its worker
 * (supervise.c): the worker's hook writes it, the supervisor's thread draws
 * it (and hands it to a relay: ONELAB progress to Gmsh), and after a crash
 * the supervisor names the stage the worker died in. A process-shared
 * robust mutex guards it, so a worker killed while holding it does not
 * stop the drawing. Without a supervisor both ends run in one process. */
#define _GNU_SOURCE /* MAP_ANONYMOUS, robust mutexes */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "cli-impl.h"
#include "dtmap/progress.h"
#include "dtmap/util.h"

#define LEVELS 8 /* nesting shown */

/* The record (shared). */
typedef struct {
  pthread_mutex_t mu;    /* guards everything below (process-shared, robust) */
  int depth;             /* open stages */
  char name[LEVELS][96]; /* their names, outermost first */
  double t0[LEVELS];     /* when each began, s (CLOCK_MONOTONIC: the same in both processes) */
  double frac;           /* the innermost stage's fraction, or -1 */
  int draw;              /* draw on the terminal (stderr, shared by both processes) */
  int drawn;             /* a line is on the terminal */
  double after;          /* draw stages older than this, s */
} record;

/* The drawing end (the process that draws). */
static struct {
  record *r;                /* the record, NULL until placed */
  pthread_t ticker;         /* the redrawing thread */
  int running;              /* 1 while the ticker runs */
  cli_progress_relay relay; /* also hand the stages to this, or NULL */
  void *user;               /* its argument */
} pg;

static void lock(record *r) {
  if (pthread_mutex_lock(&r->mu) == EOWNERDEAD) pthread_mutex_consistent(&r->mu); /* the worker died in the hook */
}

void dtm_cli_progress_place(void) {
  if (pg.r) return;
  record *r = mmap(NULL, sizeof *r, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (r == MAP_FAILED) return;
  pthread_mutexattr_t a;
  pthread_mutexattr_init(&a);
  pthread_mutexattr_setpshared(&a, PTHREAD_PROCESS_SHARED);
  pthread_mutexattr_setrobust(&a, PTHREAD_MUTEX_ROBUST);
  pthread_mutex_init(&r->mu, &a);
  pthread_mutexattr_destroy(&a);
  const char *env = getenv("DTMAP_PROGRESS_AFTER");
  r->after = env && *env ? atof(env) : 1.0;
  r->frac = -1;
  pg.r = r;
}

/* "outer > inner" of the open stages into line. */
static void path_locked(const record *r, char *line, size_t len) {
  line[0] = '\0';
  for (int i = 0; i < r->depth && i < LEVELS; i++) {
    size_t n = strlen(line);
    snprintf(line + n, len - n, "%s%s", i ? " > " : "", r->name[i]);
  }
}

static void draw_locked(record *r) {
  if (!r->draw || r->depth <= 0 || dtm_wtime() - r->t0[r->depth - 1] < r->after) return;
  char line[512] = "  ";
  path_locked(r, line + 2, sizeof line - 2);
  size_t n = strlen(line);
  if (r->frac >= 0) snprintf(line + n, sizeof line - n, " %3.0f%%", 100 * r->frac), n = strlen(line);
  snprintf(line + n, sizeof line - n, "  %.1f s", dtm_wtime() - r->t0[0]);
  fprintf(stderr, "\r%.78s\033[K", line);
  fflush(stderr);
  r->drawn = 1;
}

static void erase_locked(record *r) {
  if (r->drawn) fputs("\r\033[K", stderr), fflush(stderr);
  r->drawn = 0;
}

static void hook(void *user, int event, const char *stage, double fraction, int depth) {
  record *r = user;
  lock(r);
  if (event == DTM_PROGRESS_BEGIN && depth < LEVELS) {
    snprintf(r->name[depth], sizeof r->name[depth], "%s", stage);
    r->t0[depth] = dtm_wtime();
    r->depth = depth + 1, r->frac = -1;
  } else if (event == DTM_PROGRESS_UPDATE) {
    r->frac = fraction;
  } else if (event == DTM_PROGRESS_END) {
    erase_locked(r);
    r->depth = depth, r->frac = -1;
  }
  if (event != DTM_PROGRESS_END && r->after <= 0) draw_locked(r); /* no delay: draw every event */
  pthread_mutex_unlock(&r->mu);
}

/* The innermost open stage's path and age, for the relay. */
static void relay(record *r) {
  char line[512];
  lock(r);
  int open = r->depth > 0;
  double age = open ? dtm_wtime() - r->t0[0] : 0;
  if (open) path_locked(r, line, sizeof line);
  pthread_mutex_unlock(&r->mu);
  if (open) pg.relay(pg.user, line, age);
}

static void *tick(void *unused) {
  (void)unused;
  struct timespec ts = {0, 200000000};
  for (int n = 0;; n++) {
    lock(pg.r);
    int run = pg.running;
    if (run) draw_locked(pg.r);
    pthread_mutex_unlock(&pg.r->mu);
    if (!run) return NULL;
    if (pg.relay && n % 5 == 4) relay(pg.r); /* once a second */
    nanosleep(&ts, NULL);
  }
}

void dtm_cli_progress_hook(void) {
  if (pg.r) dtm_progress_set(hook, pg.r);
}

void dtm_cli_progress_draw(int verbosity, cli_progress_relay fn, void *user) {
  if (!pg.r) return;
  pg.r->draw = verbosity >= 1 && isatty(fileno(stderr));
  pg.relay = fn, pg.user = user;
  if (!pg.r->draw && !fn) return;
  pg.running = 1;
  if (pthread_create(&pg.ticker, NULL, tick, NULL)) pg.running = 0;
}

void dtm_cli_progress_start(int verbosity) {
  dtm_cli_progress_place();
  dtm_cli_progress_draw(verbosity, NULL, NULL);
  if (pg.running) dtm_cli_progress_hook();
}

void dtm_cli_progress_stop(void) {
  dtm_progress_set(NULL, NULL);
  if (!pg.running) return;
  lock(pg.r);
  pg.running = 0;
  erase_locked(pg.r);
  pthread_mutex_unlock(&pg.r->mu);
  pthread_join(pg.ticker, NULL);
}

int dtm_cli_progress_stage(char *buf, size_t len) {
  buf[0] = '\0';
  if (!pg.r) return 0;
  lock(pg.r);
  int depth = pg.r->depth;
  if (depth > 0) snprintf(buf, len, "%s", pg.r->name[(depth < LEVELS ? depth : LEVELS) - 1]);
  erase_locked(pg.r);
  pthread_mutex_unlock(&pg.r->mu);
  return depth;
}
