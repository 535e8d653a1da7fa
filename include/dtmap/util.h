/* Small services every layer of dtmap uses and the CLI needs too: a
 * monotonic clock, and output files written atomically (to a temporary
 * beside the target, renamed into place only when complete, so a failed or
 * interrupted run never leaves a partial file at the output path; what a
 * killed run left beside a target is removed by the next write of it). */
#ifndef DTMAP_UTIL_H
#define DTMAP_UTIL_H

#include <stdio.h>

#include "dtmap/export.h"

/* Monotonic wall clock, s. */
DTM_EXPORT double dtm_wtime(void);

#define DTM_PATH_MAX 4096

/* One output file being written atomically. */
typedef struct {
  char path[DTM_PATH_MAX];     /* the target */
  char tmp[DTM_PATH_MAX + 64]; /* dir/.base.tmpPID<suffix>, beside it */
  FILE *f;                     /* open stream on tmp, or NULL (a library writes tmp itself) */
  int fd;                      /* descriptor holding tmp's flock while it is written, or -1 */
} dtm_atomic;

/* Prepare w for path: remove the temporaries of path that killed writers
 * left (no lock held, PID gone), then create w->tmp and lock it. suffix
 * ends the temporary's name (".msh" when Gmsh must recognise the format;
 * "" otherwise). With stream = 1 the temporary is also opened for writing
 * in w->f; otherwise the caller writes w->tmp by name (truncating it, not
 * replacing it). DTM_ERR_INPUT naming path when it cannot be created. */
DTM_EXPORT int dtm_atomic_open(dtm_atomic *w, const char *path, const char *suffix, int stream);
/* Close the stream (if any), check that every write succeeded and rename
 * the temporary to the target. On any failure the temporary is removed and
 * DTM_ERR_INPUT names the target and the reason. */
DTM_EXPORT int dtm_atomic_commit(dtm_atomic *w);
/* Give up: close and remove the temporary. Safe to call twice. */
DTM_EXPORT void dtm_atomic_abort(dtm_atomic *w);
/* Remove the temporaries this process is writing. Async-signal-safe: for a
 * SIGINT/SIGTERM handler, which then lets the signal end the process. */
DTM_EXPORT void dtm_atomic_cleanup_signal(void);
/* Write text (plus a newline when add_newline) to path atomically. */
DTM_EXPORT int dtm_atomic_write_text(const char *path, const char *text, int add_newline);

#endif
