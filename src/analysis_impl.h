/* Private pieces of the analysis shared between its source files. */
#ifndef DTM_ANALYSIS_IMPL_H
#define DTM_ANALYSIS_IMPL_H

#include "dtmap/analysis.h"

/* Fill a->size_node from the per-element steps (src/size.c). */
int dtm_size_suggest(dtm_analysis *a);
/* Nodal bounds of the spectral effects (src/nodal.c). */
int dtm_nodal_bounds(dtm_analysis *a);
/* Fill per-effect safe steps, dt_nodal, dt_global and recommended. */
void dtm_recommend(dtm_analysis *a);
/* Create a file's atomic-write temporary name: dir/.base.tmpPID<suffix>. */
void dtm_tmp_path(const char *path, const char *suffix, char *out, size_t len);

#endif
