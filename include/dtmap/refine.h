/* `dtmap refine`: remesh until the recommended step reaches a target,
 * without making the run more expensive. Each round turns the size
 * suggestion (the current size where a node already meets the target, the
 * larger size that reaches it elsewhere, clamped by accuracy bounds) into
 * the background size field of a fresh mesh of the same geometry
 * (dtm_gmsh_remesh), with the node counts of transfinite curves set from
 * it and Gmsh's optimisers, and analyses again, on the basis the caller
 * chose: the nodal bound, or the global estimate (run --posterior). The
 * loop keeps the best mesh and stops as soon as the target is met (by the
 * input itself, without a remesh, when it already meets it), a round makes
 * the run more expensive than the input without meeting it, or nothing a
 * remesh changes limits the step any more. Where no mesh meets the target,
 * point masses at the nodes that need them may make up the rest, up to a
 * share of the model's mass the caller allows. The result is an object of
 * its own: the rounds, the kept mesh's analysis and the masses. */
#ifndef DTMAP_REFINE_H
#define DTMAP_REFINE_H

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/export.h"
#include "dtmap/gmsh.h"

/* What a round is. */
enum {
  DTM_ROUND_INPUT = 0, /* the scene's own mesh */
  DTM_ROUND_MESH = 1,  /* a remesh */
  DTM_ROUND_MASS = 2   /* the kept mesh with point masses at the nodes that need them */
};

typedef struct dtm_refine_round_s {
  int kind;             /* DTM_ROUND_* */
  const char *basis;    /* what its recommended step rests on ("nodal bound", "global estimate", ...) */
  double gap;           /* target / recommended - 1: how far short (<= 0: met) */
  double calibration;   /* the size field's calibration, the margin aimed past the target (NaN: none) */
  int counts;           /* transfinite curves whose node count refine set for it */
  unsigned optimise;    /* DTM_OPTIMISE_* passes run */
  double added_mass;    /* kg at the nodes (a mass round; 0 otherwise; per unit thickness in 2D) */
  double added_percent; /* that, in % of the mass of the analysed elements */
  size_t mass_nodes;    /* nodes that carry it */
  size_t elements;      /* analysed elements after the round */
  double dt_min;        /* element bound (the map's own minimum), s */
  double recommended;   /* recommended step, s */
  double element_steps; /* elements x ceil(duration / recommended) (NaN without a duration) */
  double rate;          /* elements / recommended: element-steps per simulated second, 1/s */
  size_t below;         /* elements below the target */
  size_t shape_limited; /* the shape-limited ones among them */
  double seconds;       /* wall time of the round (mesh + analysis) */
  double mesh_seconds;  /* of which Gmsh's remesh (in its child, optimisers included) */
  double phase_error;   /* worst phase-speed error at the recommended step and the frequency
                           of round 0 (dtm_measures; NaN: unresolved or no elastic effect) */
  size_t unresolved;    /* elements with fewer than 2 lattice cells per wavelength */
  int in_band;          /* 1: every accuracy measure inside its band */
} dtm_refine_round;

#define DTM_REFINE_MAX_ROUNDS 32

/* Why the loop stopped. */
enum {
  DTM_REFINE_MET = 1,          /* the target is met */
                               /* 2: unused (a round dearer than the input no longer ends
                                  the loop: it is not kept, and the next aims from the best) */
  DTM_REFINE_ONLY_SHAPE = 3,   /* only shape-limited elements remain below it */
  DTM_REFINE_BUDGET = 4,       /* the round budget is spent */
  DTM_REFINE_SHAPE_CAP = 5,    /* shape-limited elements cap the step, and a round
                                  around them did not beat the kept mesh */
  DTM_REFINE_THICKNESS = 6,    /* elements the thickness of their layer caps are below the
                                  target: they are all that is below it, or a remesh did not
                                  beat the kept mesh */
  DTM_REFINE_GMSH_REFUSED = 7, /* Gmsh refused a remesh (its reason is the first cause) */
  DTM_REFINE_GMSH_CRASH = 8,   /* Gmsh crashed in a remesh (signal and last messages in
                                  the first cause) */
  DTM_REFINE_LAYERS = 9,       /* elements below the target lie where the model fixes the
                                  node counts (an extrusion's Layers{}, or transfinite curves
                                  with keep_counts), which no remesh changes (checked before
                                  any remesh) */
  DTM_REFINE_STALLED = 10      /* a remesh left the step where it was, or two in a row did
                                  not beat the kept mesh: the same elements limit it
                                  whatever the size field */
};

/* What the caller asks of refine. */
typedef struct dtm_refine_options_s {
  double target;         /* the target recommended step, s */
  int max_rounds;        /* remeshes at most */
  int global;            /* 1: on the global estimate (as run --posterior), 0: on the nodal bound */
  double tol;            /* the global estimate's relative residual (0: 1e-4) */
  int lanczos_max;       /* its Lanczos steps at most (0: 400) */
  double max_added_mass; /* point masses refine may add where no mesh meets the target, in % of
                            the mass of the analysed elements (NaN or 0: none) */
  int keep_counts;       /* 1: leave the model's transfinite node counts as they are */
  unsigned optimise;     /* Gmsh's optimiser passes after each remesh (DTM_OPTIMISE_* bits; 0:
                            DTM_REFINE_OPTIMISE) */
} dtm_refine_options;

/* The optimiser passes refine runs by default (bench/refine_optimisers.sh
 * measures what each pays). */
#define DTM_REFINE_OPTIMISE (DTM_OPTIMISE_GMSH | DTM_OPTIMISE_NETGEN)

#define DTM_REFINE_MAX_CAUSES 12

typedef struct dtm_refine_result {
  double target;                                  /* the target step, s */
  dtm_scene scene;                                /* the scene with the target as its <time target>
                                                     (a shallow copy: members borrowed from the input) */
  int nrounds;                                    /* rounds run; round 0 is the scene's own mesh */
  dtm_refine_round rounds[DTM_REFINE_MAX_ROUNDS]; /* one per round */
  int best;                                       /* the round whose mesh is kept */
  int stop;                                       /* DTM_REFINE_*: why the loop stopped */
  double forced;                                  /* elements the input's accuracy bounds add at its
                                                     size suggestion (dtm_accuracy.forced) */
  const char *forced_by;                          /* that bound's view name, or NULL */
  double frequency;                               /* the phase errors' frequency, Hz: the scene's
                                                     f-max, else round 0's mesh default (0: none) */
  dtm_analysis *analysis;                         /* the kept mesh's analysis (owned); the current
                                                     Gmsh model holds that mesh */
  int ncauses;                                    /* causes named */
  dtm_cause causes[DTM_REFINE_MAX_CAUSES];        /* why the target was not met (what ended the
                                                     loop first, then what the model holds), and the
                                                     size options refine lifted, even when met */
  dtm_refine_options options;                     /* what was asked */
  int ncounts;                                    /* transfinite curves whose count refine set */
  dtm_count_change *counts;                       /* [ncounts] for the kept mesh (owned) */
  double mass_needed;                             /* % of the mass a mass round needed when that
                                                     was beyond the limit (NaN: none needed or
                                                     none asked for) */
  double element_bound;                           /* safety x the kept mesh's element bound, s: about
                                                     what an element-by-element solver estimate
                                                     gives it (the step must be fixed above it) */
} dtm_refine_result;

/* Round 0 is the scene's own mesh; then at most o->max_rounds remeshes,
 * and a mass round when o->max_added_mass allows one. Returns DTM_OK even
 * when the target is not met: compare dtm_analysis_recommended((*out)->
 * analysis) with the target. The input scene must outlive *out. The best
 * mesh is the met round of least cost, else the round of the largest
 * recommended step among those costing no more than round 0. With
 * point masses, the kept analysis carries them (dtm_analysis_point_masses).
 * DTM_ERR_INPUT for a bad target or mass limit, or o->global on a scene
 * none of whose effects has a global estimate. */
DTM_EXPORT int dtm_refine_run(const dtm_scene *s, const dtm_refine_options *o, dtm_refine_result **out);
DTM_EXPORT void dtm_refine_destroy(dtm_refine_result **r);
/* A sentence for a DTM_REFINE_* code. */
DTM_EXPORT const char *dtm_refine_stop_text(int stop);
/* The cost a round is judged by: its element-steps, or its rate without a
 * duration. */
DTM_EXPORT double dtm_refine_cost(const dtm_refine_round *r);

#endif
