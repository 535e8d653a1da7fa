/* What a run costs, and the two ways around a small step that do not
 * remesh: mass scaling and subcycling. Computed from an analysis and its
 * recommended step, the one basis of every number here; the results are
 * objects of their own, owned by the caller. Arrays over elements follow
 * the analysis's global element order. */
#ifndef DTMAP_COST_H
#define DTMAP_COST_H

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/export.h"

/* Mass scaling to reach the target step dt_t (s, compared with the
 * estimates before the safety factor: pass target / safety). Two ways,
 * one per basis:
 *  - element by element (dtm_mass_scaling_compute, the element-bound
 *    basis): as LS-DYNA's DT2MS does it, every element whose own wave step
 *    dt_e (the smallest over the wave-type effects, damping included) is
 *    below dt_t gets m_e ((dt_t/dt_e)^2 - 1), since dt ~ sqrt(m);
 *  - at the nodes (dtm_mass_scaling_nodal, the nodal-bound basis), as
 *    Radioss's nodal time step control does it: the nodal bound
 *    lambda_a = sum_e lambda_e m_ea / m_a keeps its numerator when mass is
 *    added at node a, so node a needs m_a ((dt_t/dt_a)^2 - 1) to bring its
 *    step dt_a to dt_t, and the bound stays rigorous. Non-spectral wave
 *    effects (cohesive) are scaled element by element first. Each node's
 *    mass is attributed to its elements in proportion to their share of it.
 * With damping the factor is taken as unchanged by the added mass (exact
 * for a constant xi, conservative for stiffness-proportional damping).
 * Elements limited only by non-wave effects get none (mass does not change
 * a diffusion limit). */
typedef struct dtm_mass_scaling_s {
  double target;       /* dt_t, s */
  int nodal;           /* 1: added at the nodes, 0: element by element */
  double *added;       /* [nel] added mass, kg (per unit thickness in 2D) */
  double total_mass;   /* mass of the analysed elements, kg */
  double total_added;  /* sum of added, kg */
  size_t scaled;       /* elements that receive mass */
  int ngroups;         /* mesh groups + 1: the last slot is "no group" */
  double *group_mass;  /* [ngroups] */
  double *group_added; /* [ngroups] */
} dtm_mass_scaling;

DTM_EXPORT int dtm_mass_scaling_compute(const dtm_analysis *a, double target, dtm_mass_scaling *ms);
/* At the nodes; only (NULL: every element) restricts it to the elements
 * with only[i] != 0 and their nodes. */
DTM_EXPORT int dtm_mass_scaling_nodal(const dtm_analysis *a, double target, const unsigned char *only,
                                      dtm_mass_scaling *ms);
DTM_EXPORT void dtm_mass_scaling_free(dtm_mass_scaling *ms);

/* Subcycling levels from the recommended step: element e is on level k
 * when its own safe step (dtm_analysis_local_step, the larger of its
 * element bound and the smallest nodal bound at its nodes, per effect) lies
 * in [b 2^k, b 2^(k+1)), b the basis of dt.recommended (before safety), so
 * level 0 steps at dt.recommended itself; an element below b (possible only
 * when the global estimate is the basis, which holds for the whole mesh)
 * is on level 0. Every level is >= 0, so the ideal speed-up
 * N / sum_k N_k 2^-k is >= 1. */
#define DTM_MAX_LEVELS 64
typedef struct dtm_subcycling_s {
  int *level;                   /* [nel] */
  int nlevels;                  /* highest level + 1 */
  size_t count[DTM_MAX_LEVELS]; /* elements per level */
  double speedup;               /* N / sum_k N_k 2^-k */
  double basis;                 /* the step of level 0: dt.recommended, s */
} dtm_subcycling;

DTM_EXPORT int dtm_subcycling_compute(const dtm_analysis *a, dtm_subcycling *sc);
/* The level rule on its own: own[n] steps against basis b (same units). */
DTM_EXPORT int dtm_subcycling_levels(const double *own, size_t n, double b, dtm_subcycling *sc);
DTM_EXPORT void dtm_subcycling_free(dtm_subcycling *sc);

/* What a run of the scene's duration costs on an analysed mesh, all from
 * one step: dt.recommended. */
typedef struct dtm_cost {
  double duration;                /* the scene's <time duration>, s (0: none) */
  double basis;                   /* the step used: dt.recommended, s */
  double steps;                   /* ceil(duration / basis) (NaN: no duration) */
  double element_steps;           /* elements x steps (NaN: no duration) */
  double element_steps_subcycled; /* element_steps / speedup: never above it */
  dtm_subcycling subcycling;      /* levels from the basis */
  dtm_mass_scaling *mass;         /* to reach the scene's target from the basis, or NULL */
  dtm_mass_scaling *shape_mass;   /* the mass the shape-limited elements' nodes need
                                     to reach the target, or NULL when none */
  dtm_mass_scaling *layer_mass;   /* the same for the thickness-limited ones only (per
                                     group: group_added), or NULL when none */
} dtm_cost;

/* The cost of analysis a: subcycling levels always; mass scaling when the
 * scene has a target (every step of the basis brought to target / safety,
 * at the nodes for a nodal or global basis, element by element for the
 * element bound). *out is owned by the caller (dtm_cost_destroy). */
DTM_EXPORT int dtm_cost_create(const dtm_analysis *a, dtm_cost **out);
DTM_EXPORT void dtm_cost_destroy(dtm_cost **c);

/* Element-steps to cover the scene's duration (NaN without one): every
 * element takes ceil(duration / recommended) steps. Subcycled: the same
 * divided by the ideal speed-up, (N ceil(duration / recommended)) /
 * speedup, so never above the plain cost. */
DTM_EXPORT double dtm_cost_element_steps(const dtm_analysis *a);
DTM_EXPORT double dtm_cost_element_steps_subcycled(const dtm_analysis *a, const dtm_subcycling *sc);

#endif
