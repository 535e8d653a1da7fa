/* Selective mass scaling of an analysed model at a target step (issue
 * 44): each element of the elastic effect scaled so that its own
 * undamped step reaches the target over the scene's safety factor, the
 * scaled model's global step (proven or probable), what the added mass
 * comes to, and the cost of the mass solves an explicit solver then makes
 * every step (src/analysis/selective.c; the mass itself:
 * include/dtmap/sms.h). Steps in s, masses in the scene's units. */
#ifndef DTMAP_SELECTIVE_H
#define DTMAP_SELECTIVE_H

#include "dtmap/export.h"

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/sms.h"

typedef struct {
  double target;         /* the recommended step asked for, s */
  double element_target; /* target / safety: the own undamped step every element is scaled to, s */
  int effect;            /* the elastic effect scaled (scene order) */
  double dt_input;       /* the smallest undamped element step of that effect before scaling, s */
  double element_min;    /* the smallest element step of the scaled model, min_e dt_e sqrt(1 + beta_e), s */
  dtm_sms_stats stats;   /* counts, beta_max, traces and translational mass (scene units) */
  size_t beta_element;   /* global element index of the largest beta ((size_t)-1: none scaled) */
  dtm_sms_global global; /* the scaled model's lambda_max and global step (undamped) */
  double recommended;    /* safety x global.dt, s */
  int target_met;        /* recommended >= target, on a proven or probable bound */
  double cg_iterations;  /* mean PCG iterations of M_s a = K u at DTM_SMS_SOLVER_RTOL (random u) */
  double product_ratio;  /* measured wall time of an M_s product (assembled) over a K product on this mesh */
  double runtime_factor; /* 1 + cg_iterations x product_ratio: an explicit solver's time per step against
                            the lumped model's (one K product per step) */
  double seconds;        /* wall time of all of it */
} dtm_selective_mass;

/* Everything above for analysis a at target (s, > 0); tol, maxit and the
 * Lanczos seed as the global estimate's (0: dtmap's defaults).
 * DTM_ERR_INPUT for a scene with no elastic effect (diffusion only), or
 * with shells or beams. */
DTM_EXPORT int dtm_analysis_selective_mass(const dtm_analysis *a, double target, double tol, int maxit,
                                           dtm_selective_mass *out);

/* `dtmap verify --selective-mass`: central differences on the scaled
 * model m of a (made by dtm_analysis_selective_mass) at step dt (s) for
 * steps steps, from a field uniform in [-1, 1] per unknown drawn from the
 * Lanczos seed, at rest (dtm_sms_verify_run); *cg_mean (may be NULL) the
 * mean CG iterations per step. */
/* The added mass M_add of the scaled model m of a (made by
 * dtm_analysis_selective_mass) assembled into *out over the unknowns of
 * the effect's undamped operator (dtm_analysis_operator; owned:
 * dtm_csr_free), kg: for the natural frequencies it moves
 * (dtm_modes_price_add). */
DTM_EXPORT int dtm_analysis_selective_added(const dtm_analysis *a, const dtm_selective_mass *m, dtm_csr *out);
DTM_EXPORT int dtm_analysis_selective_verify(const dtm_analysis *a, const dtm_selective_mass *m, double dt, int steps,
                                             dtm_verify_result *vr, double *cg_mean);

#endif
