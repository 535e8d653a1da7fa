/* The accessors of the opaque analysis handle: what other modules, the CLI
 * and library users read. Each returns a field (or a row of it) as the
 * compute stages left it; nothing here computes. */
#include <stddef.h>

#include "analysis-impl.h"

const dtm_scene *dtm_analysis_scene(const dtm_analysis *a) { return a->scene; }
const dtm_mesh *dtm_analysis_mesh(const dtm_analysis *a) { return a->mesh; }
size_t dtm_analysis_nelements(const dtm_analysis *a) { return a->nel; }
int dtm_analysis_neffects(const dtm_analysis *a) { return a->neffects; }
size_t dtm_analysis_nnodes(const dtm_analysis *a) { return a->mesh->nnodes; }
const size_t *dtm_analysis_node_tags(const dtm_analysis *a) { return a->mesh->node_tags; }

void dtm_analysis_tags(const dtm_analysis *a, size_t *tags) {
  for (int b = 0; b < a->mesh->nblocks; b++)
    for (size_t l = 0; l < a->mesh->blocks[b].n; l++) *tags++ = a->mesh->blocks[b].tags[l];
}

const dtm_effect_class *dtm_analysis_effect(const dtm_analysis *a, int k) {
  return k >= 0 && k < a->neffects ? a->effects[k].cls : NULL;
}

const double *dtm_analysis_dt(const dtm_analysis *a) { return a->dt; }
const double *dtm_analysis_length(const dtm_analysis *a) { return a->len; }
const int *dtm_analysis_limiting(const dtm_analysis *a) { return a->limiting; }
const double *dtm_analysis_size(const dtm_analysis *a) { return a->h; }
const double *dtm_analysis_measure(const dtm_analysis *a) { return a->meas; }
const double *dtm_analysis_hmax(const dtm_analysis *a) { return a->hmax; }
const int *dtm_analysis_hmax_by(const dtm_analysis *a) { return a->hmax_by; }

const double *dtm_analysis_effect_dt(const dtm_analysis *a, int k) {
  return k >= 0 && k < a->neffects ? a->dt_effect[k] : NULL;
}

const double *dtm_analysis_effect_dt_undamped(const dtm_analysis *a, int k) {
  if (k < 0 || k >= a->neffects) return NULL;
  return a->dt_bare && a->dt_bare[k] ? a->dt_bare[k] : a->dt_effect[k];
}

const double *dtm_analysis_resolution(const dtm_analysis *a, int k) {
  return k >= 0 && k < a->neffects ? a->resolution[k] : NULL;
}

const double *dtm_analysis_size_suggestion(const dtm_analysis *a) { return a->size_node; }
const double *dtm_analysis_nodal(const dtm_analysis *a) { return a->nodal_node; }

const double *dtm_analysis_effect_nodal(const dtm_analysis *a, int k) {
  return k >= 0 && k < a->neffects && a->node_dt ? a->node_dt[k] : NULL;
}

double dtm_analysis_dt_quantile(const dtm_analysis *a) { return a->dt_q1; }

const dtm_node_parts *dtm_analysis_node_parts(const dtm_analysis *a) { return &a->parts; }

double dtm_analysis_dt_min(const dtm_analysis *a, size_t *element) {
  if (element) *element = a->el_min;
  return a->dt_min;
}

double dtm_analysis_dt_nodal(const dtm_analysis *a) { return a->dt_nodal; }
double dtm_analysis_dt_global(const dtm_analysis *a) { return a->dt_global; }
double dtm_analysis_recommended(const dtm_analysis *a) { return a->recommended; }
int dtm_analysis_recommended_certified(const dtm_analysis *a) { return a->rec_certified; }
void dtm_analysis_set_lanczos_seed(dtm_analysis *a, unsigned seed) { a->lanczos_seed = seed; }
const char *dtm_analysis_basis(const dtm_analysis *a) { return a->basis; }
double dtm_analysis_basis_step(const dtm_analysis *a) { return a->best; }
const double *dtm_analysis_local_step(const dtm_analysis *a) { return a->local; }

const double *dtm_analysis_effect_hmax(const dtm_analysis *a, int k) {
  return k >= 0 && k < a->neffects ? a->hmax_effect[k] : NULL;
}

size_t dtm_analysis_below_target(const dtm_analysis *a) { return a->below; }
double dtm_analysis_advice_target(const dtm_analysis *a) { return a->advice_target; }
const dtm_geo *dtm_analysis_geo(const dtm_analysis *a) { return a->geo; }

const dtm_shape_limited *dtm_analysis_shape_limited(const dtm_analysis *a, size_t *n) {
  *n = a->nshape;
  return a->shape;
}

const dtm_effect_min *dtm_analysis_effect_min(const dtm_analysis *a, int k) {
  return k >= 0 && k < a->neffects ? &a->per_effect[k] : NULL;
}

const dtm_global_info *dtm_analysis_global(const dtm_analysis *a, int k) {
  return a->global && k >= 0 && k < a->neffects && a->global[k].done ? &a->global[k] : NULL;
}

void dtm_analysis_accuracy(const dtm_analysis *a, dtm_accuracy *out) { *out = a->accuracy; }
double dtm_analysis_timing(const dtm_analysis *a, int t) { return t >= 0 && t < DTM_T_COUNT ? a->timings[t] : 0.0; }
int dtm_analysis_threads(const dtm_analysis *a) { return a->threads; }
int dtm_analysis_space_dim(const dtm_analysis *a) { return a->mesh->space_dim; }
int dtm_analysis_planes(const dtm_analysis *a) { return a->planes; }
const dtm_mesher_info *dtm_analysis_mesher(const dtm_analysis *a) { return &a->mesher; }
