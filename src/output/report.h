/* The output module's interface to the distributed run's report
 * (src/parallel/report.c; internal to libdtmap, hidden): the pieces of the
 * JSON report that read only an analysis's global figures, so that the
 * serial and the distributed report write them the same way. */
#ifndef DTMAP_OUTPUT_REPORT_H
#define DTMAP_OUTPUT_REPORT_H

#include <cJSON.h>

#include "dtmap/analysis.h"
#include "dtmap/cost.h"

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
/* The DTM_REPORT_TOP_ADDED elements of a with the most added mass m[nel]
 * ({element, added} each), most first. */
cJSON *dtm_report_top_added(const dtm_analysis *a, const double *m);
/* The subcycling levels (counts per level) and speed-up of sc. */
cJSON *dtm_report_subcycling(const dtm_subcycling *sc);
/* The mass scaling ms (totals, groups of a's mesh), with most_added as its
 * list (taken over), or NULL for dtm_report_top_added(a, ms->added). */
cJSON *dtm_report_mass(const dtm_analysis *a, const dtm_mass_scaling *ms, cJSON *most_added);

#endif
