/* `dtmap refine`: remesh until the recommended step reaches a target. Each
 * round turns the size suggestion (the size every element needs to reach
 * the target, clamped by accuracy bounds) into a list-based Gmsh view, uses
 * it as the background size field of a fresh mesh of the same geometry,
 * runs Gmsh's optimisers to remove the slivers that set the step, and
 * analyses again. */
#ifndef DTMAP_REFINE_H
#define DTMAP_REFINE_H

#include <stddef.h>

#include "dtmap/analysis.h"

typedef struct dtm_refine_round_s {
  size_t elements;    /* analysed elements after the round */
  double dt_min;      /* smallest element step, s */
  double recommended; /* recommended step, s */
  double seconds;     /* wall time of the round (mesh + analysis) */
} dtm_refine_round;

#define DTM_REFINE_MAX_ROUNDS 32

/* Round 0 is the scene's own mesh; then at most max_rounds remeshes. Stops
 * when recommended >= target, or when a round gains less than 1%. *out is
 * the final analysis (its scene is *scene_copy, which the caller keeps
 * alive and which carries target as its <time target>). Returns DTM_OK even
 * when the target is not met: compare (*out)->recommended with target. */
int dtm_refine(const dtm_scene *s, double target, int max_rounds, dtm_scene *scene_copy, dtm_refine_round *rounds,
               int *nrounds, dtm_analysis **out);

#endif
