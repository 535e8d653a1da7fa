/* The ranks of a distributed run agreeing with each other: starting MPI
 * (threads funnelled: OpenMP loops, MPI calls from the main thread only),
 * then PETSc and SLEPc (their own error printing and signal handlers off, so
 * errors come back as dtmap errors and dtmap's handlers stay in place), and
 * agreeing on a status before every collective step, so that a rank that
 * failed never leaves the others waiting. */
#include <mpi.h>
#include <petscsys.h>
#include <slepcsys.h>

#include "parallel-impl.h"

static int we_started_mpi; /* MPI_Init was ours, so MPI_Finalize is too */

int dtm_par_petsc_fail(PetscErrorCode e, const char *call, const char *file, int line, const char *func) {
  const char *text = NULL;
  PetscErrorMessage(e, &text, NULL);
  return dtm_error_raise(DTM_ERR_INTERNAL, file, line, func, "PETSc: %s failed: %s (error %d)", call,
                         text ? text : "unknown error", (int)e);
}

static int start_mpi(void) {
  int up = 0, provided = 0;
  MPI_Initialized(&up);
  if (up) return DTM_OK;
  if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    return DTM_ERR(DTM_ERR_INTERNAL, "MPI_Init failed");
  we_started_mpi = 1;
  return DTM_OK;
}

int dtm_par_init(dtm_par *p) {
  DTM_CHECK(start_mpi());
  p->comm = MPI_COMM_WORLD;
  MPI_Comm_rank(p->comm, &p->rank);
  MPI_Comm_size(p->comm, &p->size);
  PetscBool up = PETSC_FALSE;
  PAR_PETSC(SlepcInitialized(&up));
  if (up) return DTM_OK;
  PAR_PETSC(PetscOptionsSetValue(NULL, "-no_signal_handler", NULL));
  PAR_PETSC(SlepcInitialize(NULL, NULL, NULL, NULL));
  PAR_PETSC(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  return DTM_OK;
}

void dtm_par_finalize(void) {
  PetscBool up = PETSC_FALSE;
  SlepcInitialized(&up);
  if (up) SlepcFinalize();
  int done = 0;
  MPI_Finalized(&done);
  if (we_started_mpi && !done) MPI_Finalize();
}

static int agree(dtm_par *p, int status, int alike) {
  int all = status;
  if (MPI_Allreduce(&status, &all, 1, MPI_INT, MPI_MAX, p->comm) != MPI_SUCCESS) all = DTM_ERR_INTERNAL;
  if (all && !status) {
    p->quiet = 1;
    return DTM_ERR(all, "another part of the distributed run failed (its rank says why)");
  }
  if (all && alike && p->rank > 0) p->quiet = 1;
  return all;
}

int dtm_par_agree(dtm_par *p, int status) { return agree(p, status, 0); }
int dtm_par_agree_alike(dtm_par *p, int status) { return agree(p, status, 1); }
