/* What a run costs, and the two ways around a small step that do not
 * remesh: mass scaling and subcycling. Computed from an analysis's dt map
 * and its recommended step; the results are objects of their own, owned by
 * the caller. Arrays over elements follow the analysis's global element
 * order. */
#ifndef DTMAP_COST_H
#define DTMAP_COST_H

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/export.h"

/* Mass scaling to reach the target step dt_t. As explicit codes do it, mass
 * is added only to elements whose own wave step dt_e (the smallest over
 * the wave-type effects, damping included) is below dt_t: their mass grows
 * by (dt_t/dt_e)^2, since dt ~ sqrt(m). Elements limited only by
 * non-wave effects get none (mass does not change a diffusion limit). */
typedef struct dtm_mass_scaling_s {
  double target;       /* dt_t, s */
  double *added;       /* [nel] added mass, kg (per unit thickness in 2D) */
  double total_mass;   /* mass of the analysed elements, kg */
  double total_added;  /* sum of added, kg */
  size_t scaled;       /* elements that receive mass */
  int ngroups;         /* mesh groups + 1: the last slot is "no group" */
  double *group_mass;  /* [ngroups] */
  double *group_added; /* [ngroups] */
} dtm_mass_scaling;

DTM_EXPORT int dtm_mass_scaling_compute(const dtm_analysis *a, double target, dtm_mass_scaling *ms);
DTM_EXPORT void dtm_mass_scaling_free(dtm_mass_scaling *ms);

/* Subcycling levels: element e is on level k when its step lies in
 * [dt_min 2^k, dt_min 2^(k+1)), dt_min the smallest element step. The ideal
 * speed-up over one global step is N / sum_k N_k 2^-k. */
#define DTM_MAX_LEVELS 64
typedef struct dtm_subcycling_s {
  int *level;                   /* [nel] */
  int nlevels;                  /* highest level + 1 */
  size_t count[DTM_MAX_LEVELS]; /* elements per level */
  double speedup;               /* N / sum_k N_k 2^-k */
} dtm_subcycling;

DTM_EXPORT int dtm_subcycling_compute(const dtm_analysis *a, dtm_subcycling *sc);
DTM_EXPORT void dtm_subcycling_free(dtm_subcycling *sc);

/* What a run of the scene's duration costs on an analysed mesh. */
typedef struct dtm_cost {
  double duration;                /* the scene's <time duration>, s (0: none) */
  double element_steps;           /* elements x steps of the recommended step (NaN: no duration) */
  double element_steps_subcycled; /* with ideal subcycling (NaN: no duration) */
  dtm_subcycling subcycling;      /* levels of the dt map */
  dtm_mass_scaling *mass;         /* to reach the scene's target, or NULL without one */
} dtm_cost;

/* The cost of analysis a: subcycling levels always; mass scaling when the
 * scene has a target (every element's safety x step brought to it). *out is
 * owned by the caller (dtm_cost_destroy). */
DTM_EXPORT int dtm_cost_create(const dtm_analysis *a, dtm_cost **out);
DTM_EXPORT void dtm_cost_destroy(dtm_cost **c);

/* Element-steps to cover the scene's duration (NaN without one). Single
 * step: every element takes duration / recommended steps. Subcycled: the
 * elements of level k step at safety x dt_min x 2^k (dt_min the element
 * bound, which holds element by element), i.e.
 * (duration / (safety dt_min)) sum_k N_k 2^-k. */
DTM_EXPORT double dtm_cost_element_steps(const dtm_analysis *a);
DTM_EXPORT double dtm_cost_element_steps_subcycled(const dtm_analysis *a, const dtm_subcycling *sc);

#endif
