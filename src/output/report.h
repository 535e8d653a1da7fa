/* The output module's interface to the distributed run's report
 * (src/parallel/report.c; internal to libdtmap, hidden): the pieces of the
 * JSON report that read only an analysis's global figures, so that the
 * serial and the distributed report write them the same way. */
#ifndef DTMAP_OUTPUT_REPORT_H
#define DTMAP_OUTPUT_REPORT_H

#include <cJSON.h>
#include <stdio.h>

#include "dtmap/analysis.h"
#include "dtmap/cost.h"
#include "dtmap/output.h"

/* Into dt: min, effect (the name of effect index `effect`, the one that
 * limits the smallest step), safety, recommended, basis, nodal and global
 * where computed, target where set. */
void dtm_report_steps(cJSON *dt, const dtm_analysis *a, int effect);
/* Into o: effect k's name, index, minima (element, nodal with the Gmsh tag
 * nodal_node of its node, global), its global estimate and its safe step. */
void dtm_report_effect(cJSON *o, const dtm_analysis *a, int k, size_t nodal_node);

#define DTM_REPORT_LISTED 100   /* under-resolved elements listed by tag */
#define DTM_REPORT_TOP_ADDED 10 /* elements listed with the most added mass */

/* The first DTM_REPORT_LISTED elements of a that are larger than their
 * accuracy bound ({element, h, hmax} each), in a's element order. */
cJSON *dtm_report_under_resolved(const dtm_analysis *a);
/* The indices of the (at most) max largest positive values of m[n], largest
 * first, into idx[max]; returns how many. */
int dtm_report_largest(const double *m, size_t n, size_t *idx, int max);
/* The DTM_REPORT_TOP_ADDED elements of a with the most added mass m[nel]
 * ({element, added} each), most first. */
cJSON *dtm_report_top_added(const dtm_analysis *a, const double *m);
/* The subcycling levels (counts per level) and speed-up of sc. */
cJSON *dtm_report_subcycling(const dtm_subcycling *sc);
/* The mass scaling ms (totals, groups of a's mesh), with most_added as its
 * list (taken over), or NULL for dtm_report_top_added(a, ms->added). */
cJSON *dtm_report_mass(const dtm_analysis *a, const dtm_mass_scaling *ms, cJSON *most_added);
/* run --selective-mass's object (selective.c); r->selective_mass set. */
cJSON *dtm_report_selective_mass(const dtm_results *r);

/* refine's rounds, stop, causes, counts and ways (src/output/
 * refine_report.c), and the point masses a's mesh carries. */
cJSON *dtm_report_refine(const dtm_results *r);
cJSON *dtm_report_point_masses(const dtm_analysis *a);
/* add o[key] = v, or null when v is not finite. */
void dtm_report_number(cJSON *o, const char *key, double v);

/* The cost c ({duration, steps, element_steps, ...}), the cohesive process
 * zone and the damping factor per material, the smallest steps of r (its
 * top, ascending), as the report writes them. */
cJSON *dtm_report_cost(const dtm_analysis *a, const dtm_cost *c);
cJSON *dtm_report_zones(const dtm_analysis *a);
/* The accuracy measures ms of a (src/output/measures.c), one object each. */
cJSON *dtm_report_measures(const dtm_analysis *a, const dtm_measures *ms);
/* One of them (a verify --accuracy report's "mesh_measure"). */
cJSON *dtm_report_measure(const dtm_analysis *a, const dtm_measure *m);
cJSON *dtm_report_damping(const dtm_analysis *a);
cJSON *dtm_report_worst(const dtm_results *r);
/* The report's unit rule (report_units.c): under mm-t-s, every field of
 * root with a unit (a length, area, mass, ...) converted from the scene's
 * units into SI, but for a top-level "model" (the scene's own units) when
 * top is set; with top, the top-level "units" object that says so. */
void dtm_report_units(cJSON *root, const dtm_analysis *a, int top);
/* The whole report of r (report.c). */
cJSON *dtm_report_json(const dtm_results *r);
/* The report's "shape_limited" (at most 100 of them) and
 * "thickness_limited" arrays of r's analysis, and the summary's lines on
 * them (summary.c), for the distributed run's advice. */
cJSON *dtm_report_shape(const dtm_results *r);
cJSON *dtm_report_layers(const dtm_results *r);
void dtm_summary_advice(const dtm_results *r, FILE *f);
/* The elements r lists as the smallest steps: r->top, or the default. */
int dtm_results_top(const dtm_results *r);

/* A target the accuracy bounds forbid, over a whole distributed mesh. */
typedef struct {
  size_t conflicts;  /* elements whose size for the target exceeds their bound */
  double dt_cap;     /* the smallest step the bounds allow there, s */
  double hmax;       /* that bound's size at its element, m */
  const char *bound; /* the bound's view name */
} dtm_report_conflict;
/* The report's warnings from the given figures rather than a's own: the
 * mass scaling ms (NULL: none), the conflict c (NULL: none), then note
 * (NULL: none), as a JSON array of sentences. */
cJSON *dtm_report_warnings_of(const dtm_analysis *a, const dtm_mass_scaling *ms, const dtm_report_conflict *c,
                              const char *note);

/* run --modes (src/output/modes_report.c): the report's "modes" object and
 * the summary's table of a's natural frequencies p. */
cJSON *dtm_report_modes(const dtm_analysis *a, const dtm_modes_price *p);
void dtm_summary_modes(const dtm_analysis *a, const dtm_modes_price *p, void *stream);
#endif
