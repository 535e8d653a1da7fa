/* What dtmap writes: the mesh with its views (and X.msh.opt), the JSON
 * report and the terminal summary. Each takes the bundle of results a
 * command produced: the analysis, and where they exist the cost, the refine
 * rounds and the caller's own stage times. Nothing here computes. */
#ifndef DTMAP_OUTPUT_H
#define DTMAP_OUTPUT_H

#include "dtmap/analysis.h"
#include "dtmap/cost.h"
#include "dtmap/export.h"
#include "dtmap/refine.h"
#include "dtmap/verify.h"

typedef struct {
  const dtm_analysis *analysis;    /* required (not owned) */
  const dtm_cost *cost;            /* or NULL (not owned) */
  const dtm_refine_result *refine; /* the refine rounds, or NULL (not owned) */
  double t_scene;                  /* reading the scene, s (the caller's stage) */
  double t_output;                 /* writing the mesh and views, s (the caller's stage) */
  int top;                         /* elements listed as the smallest steps ("worst"); 0: 10 */
} dtm_results;

/* The view of the elements whose step is below the scene's target, and the
 * one written instead when there is no target: the 1 % smallest steps. */
#define DTM_VIEW_BELOW_TARGET "below target [s]"
#define DTM_VIEW_SMALLEST "smallest 1% [s]"

/* Write the mesh with its views to path atomically, plus path.opt.
 * Refuses to overwrite the scene's input mesh or the scene itself. */
DTM_EXPORT int dtm_output_write(const dtm_results *r, const char *path);
/* Write the JSON report to path atomically. */
DTM_EXPORT int dtm_report_write(const dtm_results *r, const char *path);
/* Print the terminal summary (counts, the recommended step and its basis
 * beside the element bound, accuracy, cost, the shape-limited elements,
 * damping, the smallest steps, a histogram by decade, warnings) to stream
 * (a FILE *). */
DTM_EXPORT void dtm_summary_print(const dtm_results *r, void *stream);

/* `dtmap verify`: the step checked and what the simulation found. */
typedef struct {
  double step;                     /* the step verified, s */
  double factor;                   /* step / dt.recommended */
  int steps;                       /* time steps run */
  const dtm_verify_effect *effect; /* [neffects] per effect (dtmap/verify.h) */
} dtm_verify_report;

/* Write the verify report (scene, dt.recommended and its basis, the step,
 * the steps run, each effect's growth and verdict, the overall verdict) to
 * path atomically. */
DTM_EXPORT int dtm_verify_report_write(const dtm_analysis *a, const dtm_verify_report *v, const char *path);

#endif
