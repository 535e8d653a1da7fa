/* The dtm_exchange a part's analysis uses to reach the other parts
 * (src/analysis/distributed.h): node values combined through the ghosted
 * node Vec (reverse scatter with ADD, MIN or MAX into the owners, forward
 * scatter back to the ghosts), scalars through MPI_Allreduce, and the
 * global estimate through SLEPc (eigen.c). Each first agrees on the
 * callers' statuses. */
#include "parallel-impl.h"

static int x_nodes(void *ctx, int status, double *v, dtm_x_op op) {
  dtm_par *p = ctx;
  int r = dtm_par_agree(p, status);
  if (r) return r;
  InsertMode mode = op == DTM_X_SUM ? ADD_VALUES : op == DTM_X_MIN ? MIN_VALUES : MAX_VALUES;
  return dtm_par_agree(p, dtm_par_combine(p->node, v, p->mesh->nnodes, mode));
}

static int x_reduce(void *ctx, int status, double *v, int n, dtm_x_op op) {
  dtm_par *p = ctx;
  int r = dtm_par_agree(p, status);
  if (r || n == 0) return r;
  MPI_Op mop = op == DTM_X_SUM ? MPI_SUM : op == DTM_X_MIN ? MPI_MIN : MPI_MAX;
  if (MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, mop, p->comm) != MPI_SUCCESS)
    return DTM_ERR(DTM_ERR_INTERNAL, "MPI_Allreduce failed");
  return DTM_OK;
}

static int x_eigen(void *ctx, int status, const dtm_operator *op, double tol, int maxit, unsigned seed,
                   dtm_lanczos_result *res) {
  dtm_par *p = ctx;
  int r = dtm_par_agree(p, status);
  if (r) return r;
  return dtm_par_agree(p, dtm_par_eigen(p, op, tol, maxit, seed, res));
}

void dtm_par_exchange_init(dtm_par *p) { p->x = (dtm_exchange){p, x_nodes, x_reduce, x_eigen}; }
