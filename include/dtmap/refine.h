/* `dtmap refine`: remesh until the recommended step reaches a target. Each
 * round turns the size suggestion (the size every element needs to reach
 * the target, clamped by accuracy bounds) into the background size field of
 * a fresh mesh of the same geometry (dtm_gmsh_remesh), with Gmsh's
 * optimisers, and analyses again. The result is an object of its own: the
 * rounds and the final analysis. */
#ifndef DTMAP_REFINE_H
#define DTMAP_REFINE_H

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/export.h"

typedef struct dtm_refine_round_s {
  size_t elements;    /* analysed elements after the round */
  double dt_min;      /* smallest element step, s */
  double recommended; /* recommended step, s */
  double seconds;     /* wall time of the round (mesh + analysis) */
} dtm_refine_round;

#define DTM_REFINE_MAX_ROUNDS 32

typedef struct dtm_refine_result {
  double target;                                  /* the target step, s */
  dtm_scene scene;                                /* the scene with the target as its <time target>
                                                     (a shallow copy: members borrowed from the input) */
  int nrounds;                                    /* rounds run; round 0 is the scene's own mesh */
  dtm_refine_round rounds[DTM_REFINE_MAX_ROUNDS]; /* one per round */
  dtm_analysis *analysis;                         /* the final mesh's analysis (owned) */
} dtm_refine_result;

/* Round 0 is the scene's own mesh; then at most max_rounds remeshes. Stops
 * when recommended >= target, or when a round gains less than 1%. Returns
 * DTM_OK even when the target is not met: compare
 * dtm_analysis_recommended((*out)->analysis) with target. The input scene
 * must outlive *out. */
DTM_EXPORT int dtm_refine_run(const dtm_scene *s, double target, int max_rounds, dtm_refine_result **out);
DTM_EXPORT void dtm_refine_destroy(dtm_refine_result **r);

#endif
