/* The analysis side of a distributed run (distributed.h): each stage that
 * needs the other parts of the mesh calls these, which go through the
 * caller's dtm_exchange when there is one and do nothing on a whole mesh. */
#include <math.h>

#include "analysis-impl.h"

int dtm_x_agree(const dtm_analysis *a, int status) {
  return a->x ? a->x->reduce(a->x->ctx, status, NULL, 0, DTM_X_MAX) : status;
}

int dtm_x_nodes(const dtm_analysis *a, int status, double *v, dtm_x_op op) {
  return a->x ? a->x->nodes(a->x->ctx, status, v, op) : status;
}

int dtm_x_reduce(const dtm_analysis *a, int status, double *v, int n, dtm_x_op op) {
  return a->x ? a->x->reduce(a->x->ctx, status, v, n, op) : status;
}

int dtm_x_at_min(const dtm_analysis *a, int status, double mine, double min, double *value) {
  double v = mine == min ? *value : INFINITY;
  int r = dtm_x_reduce(a, status, &v, 1, DTM_X_MIN);
  if (r == DTM_OK && a->x) *value = v;
  return r;
}

int dtm_analysis_is_distributed(const dtm_analysis *a) { return a->x != NULL; }

int dtm_analysis_combine_nodes(const dtm_analysis *a, int status, double *v, dtm_x_op op) {
  return dtm_x_nodes(a, status, v, op);
}
