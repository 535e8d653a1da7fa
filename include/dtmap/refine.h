/* `dtmap refine`: remesh until the recommended step reaches a target,
 * without making the run more expensive. Each round turns the size
 * suggestion (the current size where a node already meets the target, the
 * larger size that reaches it elsewhere, clamped by accuracy bounds) into
 * the background size field of a fresh mesh of the same geometry
 * (dtm_gmsh_remesh), with the node counts of transfinite curves set from
 * it and Gmsh's optimisers, and analyses again, on the basis the caller
 * chose: the nodal bound, or the global estimate (run --posterior). While
 * the target is not met it tries strategies from a table (the size field,
 * the input's sizes scaled, a uniform size, variants of the field: see
 * src/study/refine.c), keeps the best mesh (the cheapest that meets the
 * target), and decides why it stopped from the meshes it tried; it stops
 * before any remesh only when extrusions' Layers{} hold every element
 * below the target. Where no mesh meets the target,
 * point masses at the nodes that need them may make up the rest, up to a
 * share of the model's mass the caller allows. The result is an object of
 * its own: the rounds, the kept mesh's analysis and the masses. */
#ifndef DTMAP_REFINE_H
#define DTMAP_REFINE_H

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/cost.h"
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
  const char *strategy; /* mesh rounds: the strategy that made it ("field", "scaled", "uniform", "field-floored",
                           "field-uncapped", "uniform-curvature"); "input" for round 0; NULL for mass */
  double uniform;       /* mesh rounds of a uniform strategy: its size, m; field-floored: the floor (NaN: none) */
  size_t layers;        /* groups whose thin layers cap elements below the target */
  const char *basis;    /* what its recommended step rests on ("nodal bound", "global estimate", ...) */
  double gap;           /* target / recommended - 1: how far short (<= 0: met) */
  double calibration;   /* the size field's calibration, the margin aimed past the target; scaled: the
                           factor on the input's sizes (NaN: none) */
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

/* Why the search stopped. Each code is one case, shown by a mesh tried. */
enum {
  DTM_REFINE_MET = 1,          /* the target is met */
                               /* 2: unused */
  DTM_REFINE_ONLY_SHAPE = 3,   /* a uniform mesh at the target's size still keeps shape-limited
                                  elements below the target, and only them */
  DTM_REFINE_BUDGET = 4,       /* the size-field rounds (--max-iter) are spent while still rising,
                                  and no other strategy met the target */
  DTM_REFINE_SHAPE_CAP = 5,    /* unused (shape-limited elements are judged on a coarser mesh) */
  DTM_REFINE_THICKNESS = 6,    /* a uniform mesh at the target's size still keeps elements across
                                  thin layers below the target, and only shape-limited ones */
  DTM_REFINE_GMSH_REFUSED = 7, /* Gmsh refused every remesh tried (its reason is a cause) */
  DTM_REFINE_GMSH_CRASH = 8,   /* Gmsh crashed in every remesh tried */
  DTM_REFINE_LAYERS = 9,       /* every element below the target lies where an extrusion's
                                  Layers{} fix the node counts (or transfinite curves with
                                  keep_counts), which no remesh changes (checked before any remesh) */
  DTM_REFINE_STALLED = 10,     /* no strategy met the target: the size field and uniform sizes
                                  up to the one the target implies left elements below it */
  DTM_REFINE_ACCURACY = 11     /* the uniform size that meets the target is above what the scene's
                                  accuracy bounds allow, and no mesh within them met it */
};

/* What the caller asks of refine. */
typedef struct dtm_refine_options_s {
  double target;         /* the target recommended step, s */
  int max_rounds;        /* remeshes of the size field at most (--max-iter); the other strategies add at most 11 */
  int global;            /* 1: on the global estimate (as run --posterior), 0: on the nodal bound */
  double tol;            /* the global estimate's relative residual (0: 1e-4) */
  int lanczos_max;       /* its Lanczos steps at most (0: 400) */
  double max_added_mass; /* point masses refine may add where no mesh meets the target, in % of
                            the mass of the analysed elements (NaN or 0: none) */
  int keep_counts;       /* 1: leave the model's transfinite node counts as they are */
  unsigned optimise;     /* Gmsh's optimiser passes after each remesh (DTM_OPTIMISE_* bits; 0:
                            DTM_REFINE_OPTIMISE) */
  int selective_mass;    /* 1: where no mesh meets the target, the kept mesh scaled selectively to it
                            (dtm_analysis_selective_mass), beside point masses (the way mesh + selective mass) */
  int modes;             /* with selective_mass: the lowest modes elastic frequencies of the kept mesh and their
                            shifts under point masses and under the selective mass (0: none) */
} dtm_refine_options;

/* The way mesh + selective mass (dtm_refine_options.selective_mass). */
enum {
  DTM_REFINE_SMS_NOT_ASKED = 0,  /* selective_mass was 0 */
  DTM_REFINE_SMS_NOT_NEEDED = 1, /* a mesh met the target */
  DTM_REFINE_SMS_REFUSED = 2,    /* the scene has shells or beams, or no elastic effect (sms_why says which) */
  DTM_REFINE_SMS_DONE = 3        /* computed: sms, sms_conventional, modes */
};
typedef struct {
  int state;                   /* DTM_REFINE_SMS_* */
  char why[320];               /* REFUSED: dtm_analysis_selective_mass's reason */
  int round;                   /* DONE: the round whose mesh is scaled (the kept mesh before any mass round) */
  double lumped;               /* DONE: that mesh's recommended step without added mass, s */
  dtm_selective_mass sms;      /* DONE: the scaled model (the options' tol and Lanczos steps, the analysis's seed) */
  double conventional_added;   /* DONE: point masses by deck --target's rule (every nodal bound lifted to target /
                                  safety, dtm_mass_scaling_nodal), kg (per unit thickness in 2D) */
  double conventional_percent; /* ... their share of the mass of the analysed elements, % (NaN: no nodal bound) */
  size_t conventional_nodes;   /* ... the nodes that get some */
  dtm_modes_price *modes; /* DONE with options.modes: the frequencies and their shifts under both (owned), or NULL */
} dtm_refine_selective;

/* The optimiser passes refine runs by default: none, since none paid in
 * Debian's Gmsh 4.8 (bench/refine_optimisers.sh, docs/refine-survey.md: in
 * 3D every pass left the worst element where it was, the mesher having
 * optimised already and Netgen not being built in; in 2D Relocate2D and
 * Laplace2D moved the step by -3 % to +4 %, median +0.1 % and +0.5 %). */
#define DTM_REFINE_OPTIMISE DTM_OPTIMISE_NONE

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
  int mass_least;                                 /* 1: mass_needed is the least share a search found (the
                                                     rule's masses scaled, the global estimate confirming
                                                     it); 0: what dtmap's mass rule adds */
  double uniform;                                 /* the largest uniform size tried, m (0: none) */
  int uniform_rounds;                             /* uniform remeshes run */
  double element_bound;                           /* safety x the kept mesh's element bound, s: about
                                                     what an element-by-element solver estimate
                                                     gives it (the step must be fixed above it) */
  dtm_refine_selective selective;                 /* the way mesh + selective mass */
} dtm_refine_result;

/* Round 0 is the scene's own mesh; then the strategies while the target
 * is not met: at most o->max_rounds remeshes of the size field, then at
 * most 3 of the input's sizes scaled, 5 of uniform sizes and one of each
 * variant (at most 11 remeshes beyond o->max_rounds), and a mass round when
 * o->max_added_mass allows one. Returns DTM_OK even
 * when the target is not met: compare dtm_analysis_recommended((*out)->
 * analysis) with the target. The input scene must outlive *out. The best
 * mesh is the met round of least cost, else the round of the largest
 * recommended step among those costing no more than round 0. With
 * point masses, the kept analysis carries them (dtm_analysis_point_masses).
 * With o->selective_mass, where no mesh meets the target, the kept mesh
 * (before any point masses) is scaled selectively to the target
 * (rr->selective; shells, beams or no elastic effect: REFUSED with the
 * reason, not an error). DTM_ERR_INPUT for a bad target or mass limit, or o->global on a scene
 * none of whose effects has a global estimate. */
DTM_EXPORT int dtm_refine_run(const dtm_scene *s, const dtm_refine_options *o, dtm_refine_result **out);
DTM_EXPORT void dtm_refine_destroy(dtm_refine_result **r);
/* A sentence for a DTM_REFINE_* code. */
DTM_EXPORT const char *dtm_refine_stop_text(int stop);
/* The cost a round is judged by: its element-steps, or its rate without a
 * duration. */
DTM_EXPORT double dtm_refine_cost(const dtm_refine_round *r);
/* The cost of the way mesh + selective mass (rr->selective DONE; NaN
 * otherwise), judged as dtm_refine_cost judges a round: the scaled mesh's
 * element-steps at the scaled recommended step (its rate without a
 * duration), times the runtime factor of the mass solves. */
DTM_EXPORT double dtm_refine_selective_cost(const dtm_refine_result *rr);
/* The uniform strategy's next size past its list of sizes, m, from the
 * rounds run so far: while the target is not met, the largest uniform size
 * tried is also the uniform round of the largest step, judged on refine's
 * own basis (rounds[].recommended: the global estimate with --posterior),
 * that size times ((target / its step) x 1.05)^(1/exponent) (exponent: the
 * step's power of the size, 1 for waves), clamped to [1.1, 2]; NaN to stop
 * (met, no uniform round, or a coarser size already did not raise the
 * step). */
DTM_EXPORT double dtm_refine_uniform_next(const dtm_refine_result *rr, double exponent);

#endif
