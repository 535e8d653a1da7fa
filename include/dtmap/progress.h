/* Progress of the long stages (meshing, reading and writing a mesh, the
 * Lanczos estimate, verify's time loop, each refine round). The library
 * never prints: it reports to a hook the caller installs, and the dtmap CLI
 * draws a one-line indicator from it on a terminal. Stages nest (a refine
 * round meshes); the hook is called on the thread that runs the stage,
 * never from inside a parallel region. */
#ifndef DTMAP_PROGRESS_H
#define DTMAP_PROGRESS_H

#include "dtmap/export.h"

enum { DTM_PROGRESS_BEGIN = 0, DTM_PROGRESS_UPDATE = 1, DTM_PROGRESS_END = 2 };

/* event: DTM_PROGRESS_*; stage: the innermost stage's name (valid during
 * the call); fraction: done so far in [0, 1], or -1 when unknown; depth:
 * nesting level of that stage, from 0. */
typedef void (*dtm_progress_fn)(void *user, int event, const char *stage, double fraction, int depth);

/* Install the hook (NULL: none, the default). Not thread-safe: install it
 * before the work starts. */
DTM_EXPORT void dtm_progress_set(dtm_progress_fn fn, void *user);

/* For the library's stages (and plugins'): open a stage named stage (copied),
 * report its fraction done (-1: unknown), close the innermost stage. */
DTM_EXPORT void dtm_progress_begin(const char *stage);
DTM_EXPORT void dtm_progress_update(double fraction);
DTM_EXPORT void dtm_progress_end(void);

#endif
