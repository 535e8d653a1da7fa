/* The output module's interface to the distributed run's report
 * (src/parallel/report.c; internal to libdtmap, hidden): the pieces of the
 * JSON report that read only an analysis's global figures, so that the
 * serial and the distributed report write them the same way. */
#ifndef DTMAP_OUTPUT_REPORT_H
#define DTMAP_OUTPUT_REPORT_H

#include <cJSON.h>

#include "dtmap/analysis.h"

/* Into dt: min, effect (the name of effect index `effect`, the one that
 * limits the smallest step), safety, recommended, basis, nodal and global
 * where computed, target where set. */
void dtm_report_steps(cJSON *dt, const dtm_analysis *a, int effect);
/* Into o: effect k's name, index, minima (element, nodal with the Gmsh tag
 * nodal_node of its node, global), its global estimate and its safe step. */
void dtm_report_effect(cJSON *o, const dtm_analysis *a, int k, size_t nodal_node);

#endif
