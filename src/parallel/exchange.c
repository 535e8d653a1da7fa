/* The dtm_exchange a part's analysis uses to reach the other parts
 * (src/analysis/distributed.h): node values combined through the ghosted
 * node Vec (reverse scatter with ADD, MIN or MAX into the owners, forward
 * scatter back to the ghosts), scalars through MPI_Allreduce, and the
 * global estimate through SLEPc (eigen.c). Each first agrees on the
 * callers' statuses. */
#include <limits.h>
#include <stdlib.h>

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

/* Every rank's count to rank 0, then its values (MPI_Gatherv counts are
 * ints: a part of more values is refused on every rank). */
static int gather_counts(dtm_par *p, size_t n, int **counts, int **displs, size_t *total) {
  double big = n > (size_t)INT_MAX ? 1.0 : 0.0;
  int mine = (int)(big ? 0 : n), r = DTM_OK;
  MPI_Allreduce(MPI_IN_PLACE, &big, 1, MPI_DOUBLE, MPI_MAX, p->comm);
  if (big) return DTM_ERR(DTM_ERR_INTERNAL, "a part holds more than %d values to gather", INT_MAX);
  *counts = p->rank == 0 ? calloc((size_t)p->size, sizeof **counts) : NULL;
  *displs = p->rank == 0 ? calloc((size_t)p->size, sizeof **displs) : NULL;
  if (p->rank == 0 && (!*counts || !*displs)) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if ((r = dtm_par_agree(p, r))) return r;
  MPI_Gather(&mine, 1, MPI_INT, *counts, 1, MPI_INT, 0, p->comm);
  *total = 0;
  for (int k = 0; p->rank == 0 && k < p->size; k++) (*displs)[k] = (int)*total, *total += (size_t)(*counts)[k];
  if (*total > (size_t)INT_MAX) r = DTM_ERR(DTM_ERR_INTERNAL, "more than %d values to gather", INT_MAX);
  return dtm_par_agree(p, r);
}

static int x_gather(void *ctx, int status, const double *mine, size_t n, double **all, size_t *nall) {
  dtm_par *p = ctx;
  int *counts = NULL, *displs = NULL, r = dtm_par_agree(p, status);
  *all = NULL, *nall = 0;
  if (r == DTM_OK) r = gather_counts(p, n, &counts, &displs, nall); /* agreed */
  if (r == DTM_OK) {
    int mem = p->rank == 0 && !(*all = malloc((*nall + 1) * sizeof **all));
    r = dtm_par_agree(p, mem ? DTM_ERR(DTM_ERR_INTERNAL, "out of memory") : DTM_OK);
  }
  if (r == DTM_OK && MPI_Gatherv(mine, (int)n, MPI_DOUBLE, *all, counts, displs, MPI_DOUBLE, 0, p->comm) != MPI_SUCCESS)
    r = DTM_ERR(DTM_ERR_INTERNAL, "MPI_Gatherv failed"); /* the caller's next agreement carries it */
  free(counts), free(displs);
  if (r) free(*all), *all = NULL;
  return r;
}

static int x_bcast(void *ctx, int status, double **v, size_t *n) {
  dtm_par *p = ctx;
  unsigned long long count = *n;
  int r = dtm_par_agree(p, status);
  if (r) return r;
  MPI_Bcast(&count, 1, MPI_UNSIGNED_LONG_LONG, 0, p->comm);
  if (count > (unsigned long long)INT_MAX) return DTM_ERR(DTM_ERR_INTERNAL, "more than %d values to share", INT_MAX);
  if (p->rank > 0) *n = (size_t)count, *v = malloc((*n + 1) * sizeof **v);
  if ((r = dtm_par_agree(p, *v || !count ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory")))) return r;
  if (MPI_Bcast(*v, (int)count, MPI_DOUBLE, 0, p->comm) != MPI_SUCCESS)
    return DTM_ERR(DTM_ERR_INTERNAL, "MPI_Bcast failed"); /* the caller's next agreement carries it */
  return DTM_OK;
}

void dtm_par_exchange_init(dtm_par *p) { p->x = (dtm_exchange){p, x_nodes, x_reduce, x_eigen, x_gather, x_bcast}; }
