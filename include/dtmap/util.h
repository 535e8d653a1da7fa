/* Small services every layer of dtmap uses and the CLI needs too: a
 * monotonic clock, and output files written atomically (to an unnamed
 * temporary beside the target, linked in and renamed into place only when
 * complete, so a failed or interrupted run never leaves a partial file at
 * the output path nor its data beside it; a name a killed run left beside
 * a target is removed by the next write of it). */
#ifndef DTMAP_UTIL_H
#define DTMAP_UTIL_H

#include <stddef.h>
#include <stdio.h>

#include "dtmap/export.h"

/* Monotonic wall clock, s. */
DTM_EXPORT double dtm_wtime(void);

/* The k-th smallest (from 0) of a[n], n > 0, a reordered in place so that
 * every value before position k is at most it and every one after at
 * least it (src/base/numbers.c). */
DTM_EXPORT double dtm_select_kth(double *a, size_t n, size_t k);

/* floor(log2(q)) for q > 0, the same integer as log2 gives, at a fraction
 * of its cost (src/base/numbers.c). */
DTM_EXPORT int dtm_octave(double q);

/* Serve large allocations from the heap, not from fresh mappings, so that
 * the per-element arrays of one stage reuse the memory earlier stages (and
 * Gmsh) freed instead of faulting in new zeroed pages (src/base/memory.c).
 * For a program's start, before anything large is allocated. */
DTM_EXPORT void dtm_memory_reuse(void);

#define DTM_PATH_MAX 4096

/* One output file being written atomically. */
typedef struct {
  char path[DTM_PATH_MAX];     /* the target */
  char tmp[DTM_PATH_MAX + 64]; /* dir/.base.tmpPID<suffix>, beside it: the name to write it by */
  FILE *f;                     /* open stream on it, or NULL (a library writes tmp itself) */
  int fd;                      /* descriptor of the file being written, or -1 */
  int unnamed;                 /* 1: the data is an unnamed file (O_TMPFILE), tmp a link to it */
} dtm_atomic;

/* Prepare w for path: remove the temporaries of path that killed writers
 * left, then create the file the output is written to: an unnamed one in
 * path's directory (nothing of it outlives the process), reached by the
 * name w->tmp (a link to it) until it is complete; or, where the file
 * system has no unnamed files, a plain file w->tmp under a lock. suffix
 * ends the name (".msh" when Gmsh must recognise the format; ""
 * otherwise). With stream = 1 the file is also opened for writing in w->f;
 * otherwise the caller writes w->tmp by name (truncating it, not replacing
 * it). DTM_ERR_INPUT naming path when it cannot be created. */
DTM_EXPORT int dtm_atomic_open(dtm_atomic *w, const char *path, const char *suffix, int stream);
/* Close the stream (if any), check that every write succeeded, link the
 * file in as w->tmp and rename it to the target. On any failure the
 * temporary is removed and DTM_ERR_INPUT names the target and the reason. */
DTM_EXPORT int dtm_atomic_commit(dtm_atomic *w);
/* Give up: close and remove the temporary. Safe to call twice. */
DTM_EXPORT void dtm_atomic_abort(dtm_atomic *w);
/* Remove the names of the temporaries this process (or, with a shared
 * list, the process sharing it) is writing. Async-signal-safe: for a
 * SIGINT/SIGTERM handler, which then lets the signal end the process. */
DTM_EXPORT void dtm_atomic_cleanup_signal(void);
/* Keep the list of those names in area (bytes long; NULL: this process's
 * own memory, the default): memory shared with a supervising process
 * (MAP_SHARED, set up before fork), so that it can remove them when this
 * one dies by a signal it cannot handle (SIGKILL). It is cleared here. */
DTM_EXPORT void dtm_atomic_share(void *area, size_t bytes);
/* A scratch file with no name (O_TMPFILE in $TMPDIR, else /tmp; or one
 * created and unlinked at once): it goes with the last descriptor, so
 * nothing of it outlives the processes that share it. Read and write,
 * close-on-exec (kept across fork); -1 with errno when none can be made. */
DTM_EXPORT int dtm_scratch_fd(void);
/* A scratch file a library writes and reads by name (Gmsh's meshes): an
 * atomic file (dtm_atomic_open) for $TMPDIR/base (else /tmp), never
 * committed; its data has no name, w->tmp is the link to write and read it
 * by; dtm_atomic_abort ends it. */
DTM_EXPORT int dtm_scratch_named(dtm_atomic *w, const char *base, const char *suffix);
/* Write text (plus a newline when add_newline) to path atomically. */
DTM_EXPORT int dtm_atomic_write_text(const char *path, const char *text, int add_newline);

#endif
