/* The analysis side of a distributed run (distributed.h): each stage that
 * needs the other parts of the mesh calls these, which go through the
 * caller's dtm_exchange when there is one and do nothing on a whole mesh. */
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
