/* What dtmap writes: the mesh with its views (and X.msh.opt), the JSON
 * report and the terminal summary. Each takes the bundle of results a
 * command produced: the analysis, and where they exist the cost, the refine
 * rounds and the caller's own stage times. Nothing here computes. */
#ifndef DTMAP_OUTPUT_H
#define DTMAP_OUTPUT_H

#include "dtmap/analysis.h"
#include "dtmap/cost.h"
#include "dtmap/deck.h"
#include "dtmap/export.h"
#include "dtmap/refine.h"
#include "dtmap/selective.h"
#include "dtmap/verify.h"

typedef struct {
  const dtm_analysis *analysis;         /* required (not owned) */
  const dtm_cost *cost;                 /* or NULL (not owned) */
  const dtm_refine_result *refine;      /* the refine rounds, or NULL (not owned) */
  double t_scene;                       /* reading the scene, s (the caller's stage) */
  double t_output;                      /* writing the mesh and views, s (the caller's stage) */
  int top;                              /* elements listed as the smallest steps ("worst"); 0: 10, < 0: none */
  int nsolvers;                         /* solvers named (run --solver-rule, deck --solver): the report's solvers[] */
  const char *solver_names[8];          /* their names (not owned) */
  const dtm_solver_run *solver_runs[8]; /* the step each takes with dtmap's deck and the hours (not owned) */
  const dtm_modes_price *modes;         /* run --modes: the natural frequencies and their shifts, or NULL (not owned) */
  const dtm_selective_mass *selective_mass; /* run --selective-mass: the summary's lines and the report's
                                               selective_mass object, or NULL (not owned) */
} dtm_results;

/* The view of the elements whose step is below the scene's target, and the
 * one written instead when there is no target: the 1 % smallest steps. */
#define DTM_VIEW_BELOW_TARGET "below target [s]"
#define DTM_VIEW_SMALLEST "smallest 1% [s]"

/* Check, before any work, that path can receive an output of scene s (s
 * may be NULL): it names a regular file or none yet (not a directory or a
 * device), its directory exists and accepts a new file, it is not the
 * scene file, its geometry or its mesh, and it ends in ext unless ext is
 * NULL (".msh"). origin says where the path came from, for the message
 * ("-o", "scene.xml:12: <output mesh>"; NULL: nothing). DTM_ERR_INPUT
 * "<origin> <path>: <reason>" otherwise. Leaves nothing behind. */
DTM_EXPORT int dtm_output_path_check(const dtm_scene *s, const char *path, const char *ext, const char *origin);
/* Write the mesh with its views to path atomically, plus path.opt.
 * Refuses to overwrite the scene's input mesh or the scene itself. */
DTM_EXPORT int dtm_output_write(const dtm_results *r, const char *path);
/* Above this many analysed elements the output .msh is binary unless the
 * caller or the scene's <output format> says otherwise. */
#define DTM_BINARY_ABOVE 100000

/* One part of a distributed run's output (src/parallel/): what its views
 * and its .opt take from the whole mesh rather than from the part. */
typedef struct {
  int part;                       /* this part's number, 1 ...: its views carry it, so Gmsh merges the
                                     parts' views; only part 1 gets the .opt (opened first) */
  double below_at;                /* without a target: the whole mesh's 1 % smallest step, s */
  size_t below;                   /* elements of the whole mesh in the below-target (or 1 %) view */
  size_t elements;                /* elements of the whole mesh */
  unsigned long long min_element; /* Gmsh tag of the element with the smallest step */
  const char *min_group;          /* its physical group */
} dtm_output_part;

/* How the output mesh is written. */
typedef struct {
  int format;                  /* DTM_MSH_AUTO (the scene's <output format>, else binary
                                  above DTM_BINARY_ABOVE elements), DTM_MSH_ASCII or
                                  DTM_MSH_BINARY */
  int views_only;              /* 1: write only the views, for Gmsh to merge on top of the
                                  scene's input .msh (needs a <mesh> scene) */
  const dtm_output_part *part; /* a distributed run's part (read when the views are written), or NULL */
  int background;              /* dtm_output_begin: Gmsh writes the mesh on a thread of its own, then
                                  releases the model (dtm_gmsh_release), while the caller computes;
                                  the caller makes no Gmsh call until finish or abort */
} dtm_output_opts;

/* dtm_output_write with options (NULL: the defaults above). */
DTM_EXPORT int dtm_output_write_ex(const dtm_results *r, const char *path, const dtm_output_opts *o);

/* The same in two steps, so that the current Gmsh model's mesh can be
 * written as soon as it is extracted and the model released before or while
 * the analysis computes (dtm_analysis_run_ex): begin checks path (as
 * dtm_output_write), opens its temporary and writes the mesh (not for
 * views_only; nelements chooses the automatic encoding), or starts writing
 * it (background); finish waits for that write, appends the views of r,
 * renames the file into place, writes path.opt (not for a distributed run's
 * parts after the first) and frees the handle; abort waits too, then
 * removes the temporary. */
typedef struct dtm_output_file dtm_output_file;
DTM_EXPORT int dtm_output_begin(const dtm_scene *s, const char *path, const dtm_output_opts *o, size_t nelements,
                                dtm_output_file **out);
DTM_EXPORT int dtm_output_finish(dtm_output_file **f, const dtm_results *r);
DTM_EXPORT void dtm_output_abort(dtm_output_file **f);
/* The solvers' own element steps (run --solver-rule) that finish writes as
 * one ElementData view "dt <solver>" each (steps[n] not owned: they must
 * live until finish). */
DTM_EXPORT void dtm_output_solver_steps(dtm_output_file *f, const dtm_deck_steps *steps, int n);

/* Add the same views to the current model of the open Gmsh session (a
 * script's), styled as X.msh.opt styles them (without its text view and its
 * mesh display options); nothing is written. tags[cap] (may be NULL)
 * receives the Gmsh view tags in order, and *n (may be NULL) the number of
 * views added. */
DTM_EXPORT int dtm_output_add_views(const dtm_results *r, int *tags, int cap, int *n);
/* Write the JSON report to path atomically. */
DTM_EXPORT int dtm_report_write(const dtm_results *r, const char *path);
/* The same with the object "deck" of a solver deck written (dtmap deck). */
DTM_EXPORT int dtm_report_write_deck(const dtm_results *r, const dtm_deck_info *d, const char *path);
/* Print the terminal summary (counts, the recommended step and its basis
 * beside the element bound, accuracy, cost, the shape-limited elements,
 * damping, the smallest steps, a histogram in octaves of the recommended step or the target, warnings) to stream
 * (a FILE *). */
DTM_EXPORT void dtm_summary_print(const dtm_results *r, void *stream);
/* Print the plausibility warnings of the analysis (a density, wave speed or
 * model size that looks like a unit error; docs/units.md), one
 * "dtmap: warning: ..." line each, to stream (a FILE *); the summary and
 * the report carry them too. */
DTM_EXPORT void dtm_output_warn_plausibility(const dtm_analysis *a, void *stream);
/* The warnings of the summary and of the report's warnings[] (the
 * plausibility ones first), one a line, into buf[len] (cut at len); returns
 * how many there are. */
DTM_EXPORT int dtm_output_warning_lines(const dtm_results *r, char *buf, size_t len);

/* The two worst figures of a phase-speed measure m (dtmap/cost.h), as
 * `run` and `verify --accuracy` print them, into buf[len]: the worst with
 * each element at the spacing averaged over its neighbourhood (m->worst),
 * and with each element alone (m->worst_alone), each with its name. */
DTM_EXPORT void dtm_summary_phase_worst(const dtm_measure *m, char *buf, size_t len);

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
/* The same for `verify --accuracy`: the step, the wave (branch, direction,
 * frequency, host material, polarisation, the window and the periods run),
 * the measured and predicted phase-speed errors, their agreement and the
 * verdict (within 20 %: "agrees"). */
DTM_EXPORT int dtm_verify_wave_report_write(const dtm_analysis *a, double dt, const dtm_wave_spec *w,
                                            const dtm_wave_result *r, const char *path);

/* What a `verify --accuracy` report says of the prediction. */
typedef struct {
  int mode;         /* the wave: 0 P, 1 S */
  double dir[3];    /* its direction (unit) */
  double f;         /* its frequency, Hz */
  double measured;  /* the measured phase-speed error, fraction */
  double predicted; /* the predicted one, fraction */
} dtm_wave_check;
/* Read the report at path (dtm_verify_wave_report_write's) into c;
 * DTM_ERR_INPUT naming the file when it cannot be read or is not one, or
 * has no measured or predicted error. */
DTM_EXPORT int dtm_verify_wave_report_read(const char *path, dtm_wave_check *c);

#endif
