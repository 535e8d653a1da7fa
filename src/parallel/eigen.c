/* The global estimate of a distributed run: lambda_max of the whole mesh's
 * lumped-mass problem K u = lambda M u, as the largest eigenvalue of the
 * symmetric A = M^-1/2 K M^-1/2, by SLEPc's Krylov-Schur (EPS, Hermitian)
 * on a PETSc shell matrix. Each rank's shell applies its part's
 * matrix-free operator (src/spectral/operator.c): the owned entries of x,
 * scaled by M^-1/2, go to the ghosts (forward scatter), the part's K acts
 * on its nodes, the ghosts' partial forces are added into their owners
 * (reverse scatter), and the owners scale by M^-1/2. M is the sum of the
 * parts' lumped masses, combined the same way once. The start vector is
 * drawn per Gmsh node tag, so it does not depend on the partition.
 * The safe side is the serial Lanczos's: the converged Ritz value theta
 * approaches lambda_max from below, and for the unit Ritz vector y an
 * eigenvalue lies within ||A y - theta y|| of theta (SLEPc's
 * EPSComputeError, one more product), so the step is taken at
 * theta + residual; an unconverged estimate is reported and not used. */
#include <math.h>
#include <slepceps.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base.h"
#include "parallel-impl.h"

#define KS_PRODUCTS_PER_RESTART 8 /* Krylov-Schur with one wanted pair: ncv 16, half kept */

typedef struct {
  const dtm_operator *op; /* this part's operator (not owned) */
  Vec xg, yg;             /* ghosted, ncomp values per node */
  double *dsq;            /* [local dofs] M^-1/2 of the whole mesh, 0 where no mass */
  PetscInt nown;          /* owned dofs */
  dtm_par *p;             /* counts the products, their CPU and exchange times */
} shell;

/* CPU time of the calling thread, s: the part's own work, whatever else
 * runs on its core. */
static double cpu_now(void) {
  struct timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static PetscErrorCode ghost_update(shell *s, Vec v, InsertMode mode, ScatterMode dir) {
  double t0 = dtm_wtime();
  PetscFunctionBeginUser;
  PetscCall(VecGhostUpdateBegin(v, mode, dir));
  PetscCall(VecGhostUpdateEnd(v, mode, dir));
  s->p->exchange += dtm_wtime() - t0;
  PetscFunctionReturn(0);
}

/* y = M^-1/2 K M^-1/2 x over the whole mesh. */
static PetscErrorCode shell_mult(Mat A, Vec x, Vec y) {
  shell *s;
  const PetscScalar *in, *lx, *ly;
  PetscScalar *out, *ky;
  Vec lxv, lyv;
  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &s));
  PetscCall(VecGetArrayRead(x, &in));
  PetscCall(VecGetArray(s->xg, &out));
  for (PetscInt i = 0; i < s->nown; i++) out[i] = in[i] * s->dsq[i];
  PetscCall(VecRestoreArray(s->xg, &out));
  PetscCall(VecRestoreArrayRead(x, &in));
  PetscCall(ghost_update(s, s->xg, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(s->xg, &lxv));
  PetscCall(VecGhostGetLocalForm(s->yg, &lyv));
  PetscCall(VecGetArrayRead(lxv, &lx));
  PetscCall(VecGetArray(lyv, &ky));
  double c0 = cpu_now();
  dtm_operator_apply(s->op, lx, ky);
  s->p->product_cpu += cpu_now() - c0;
  PetscCall(VecRestoreArray(lyv, &ky));
  PetscCall(VecRestoreArrayRead(lxv, &lx));
  PetscCall(VecGhostRestoreLocalForm(s->yg, &lyv));
  PetscCall(VecGhostRestoreLocalForm(s->xg, &lxv));
  PetscCall(ghost_update(s, s->yg, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecGetArrayRead(s->yg, &ly));
  PetscCall(VecGetArray(y, &out));
  for (PetscInt i = 0; i < s->nown; i++) out[i] = ly[i] * s->dsq[i];
  PetscCall(VecRestoreArray(y, &out));
  PetscCall(VecRestoreArrayRead(s->yg, &ly));
  s->p->products++;
  PetscFunctionReturn(0);
}

/* The whole mesh's lumped mass at the part's dofs, then M^-1/2. */
static int global_mass(shell *s, size_t n) {
  memcpy(s->dsq, dtm_operator_mass(s->op), n * sizeof *s->dsq);
  DTM_CHECK(dtm_par_combine(s->yg, s->dsq, n, ADD_VALUES));
  for (size_t i = 0; i < n; i++) s->dsq[i] = s->dsq[i] > 0 ? 1.0 / sqrt(s->dsq[i]) : 0.0;
  return DTM_OK;
}

/* Uniform in [-1, 1) at (seed, index): splitmix64 from a per-index state. */
static double draw(unsigned seed, unsigned long long index) {
  uint64_t x = (uint64_t)seed ^ (index * 0x9E3779B97F4A7C15ull);
  return dtm_rng_uniform(&x, -1.0, 1.0);
}

/* Start vector: per Gmsh node tag and component, 0 on dofs without mass. */
static int start_vector(const dtm_par *p, const shell *s, unsigned seed, Vec v) {
  PetscScalar *a;
  int nc = dtm_operator_ncomp(s->op);
  PAR_PETSC(VecGetArray(v, &a));
  for (PetscInt i = 0; i < s->nown; i++) {
    unsigned long long tag = p->mesh->node_tags[i / nc];
    a[i] = s->dsq[i] > 0 ? draw(seed, tag * (unsigned long long)nc + (unsigned long long)(i % nc)) : 0.0;
  }
  PAR_PETSC(VecRestoreArray(v, &a));
  return DTM_OK;
}

static int eps_setup(EPS eps, Mat A, Vec v0, double tol, int maxit) {
  PAR_PETSC(EPSSetOperators(eps, A, NULL));
  PAR_PETSC(EPSSetProblemType(eps, EPS_HEP));
  PAR_PETSC(EPSSetType(eps, EPSKRYLOVSCHUR));
  PAR_PETSC(EPSSetWhichEigenpairs(eps, EPS_LARGEST_REAL));
  PAR_PETSC(EPSSetDimensions(eps, 1, PETSC_DEFAULT, PETSC_DEFAULT));
  PAR_PETSC(EPSSetTolerances(eps, tol, maxit / KS_PRODUCTS_PER_RESTART + 1));
  PAR_PETSC(EPSSetInitialSpace(eps, 1, &v0));
  PAR_PETSC(EPSSetFromOptions(eps)); /* -eps_* options through PETSC_OPTIONS */
  return DTM_OK;
}

/* Solve; theta and the true residual of the top converged pair. */
static int eps_solve(EPS eps, Mat A, dtm_lanczos_result *res) {
  PetscInt nconv = 0;
  PAR_PETSC(EPSSolve(eps));
  PAR_PETSC(EPSGetConverged(eps, &nconv));
  res->converged = nconv > 0;
  res->theta = res->residual = NAN;
  if (!nconv) return DTM_OK;
  Vec y;
  PetscScalar theta;
  PetscReal err;
  PAR_PETSC(MatCreateVecs(A, &y, NULL));
  PAR_PETSC(EPSGetEigenpair(eps, 0, &theta, NULL, y, NULL));
  PAR_PETSC(EPSComputeError(eps, 0, EPS_ERROR_ABSOLUTE, &err));
  PAR_PETSC(VecDestroy(&y));
  res->theta = theta, res->residual = err;
  return DTM_OK;
}

static int run_eps(dtm_par *p, shell *s, double tol, int maxit, unsigned seed, dtm_lanczos_result *res) {
  Mat A;
  Vec v0;
  EPS eps;
  PAR_PETSC(MatCreateShell(p->comm, s->nown, s->nown, PETSC_DETERMINE, PETSC_DETERMINE, s, &A));
  PAR_PETSC(MatShellSetOperation(A, MATOP_MULT, (void (*)(void))shell_mult));
  PAR_PETSC(MatCreateVecs(A, &v0, NULL));
  PAR_PETSC(EPSCreate(p->comm, &eps));
  int r = start_vector(p, s, seed, v0);
  if (r == DTM_OK) r = eps_setup(eps, A, v0, tol, maxit);
  if (r == DTM_OK) r = eps_solve(eps, A, res);
  EPSDestroy(&eps);
  VecDestroy(&v0);
  MatDestroy(&A);
  return r;
}

int dtm_par_eigen(dtm_par *p, const dtm_operator *op, double tol, int maxit, unsigned seed, dtm_lanczos_result *res) {
  double t0 = dtm_wtime();
  int nc = dtm_operator_ncomp(op);
  size_t n = dtm_operator_ndof(op);
  shell s = {op, NULL, NULL, malloc((n + 1) * sizeof(double)), (PetscInt)p->nowned * nc, p};
  memset(res, 0, sizeof *res);
  p->products = 0, p->product_cpu = p->exchange = 0;
  int r = s.dsq ? dtm_par_vec(p, nc, &s.xg) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = dtm_par_vec(p, nc, &s.yg);
  if (r == DTM_OK) r = global_mass(&s, n);
  if (r == DTM_OK) r = run_eps(p, &s, tol, maxit, seed, res);
  if (s.xg) VecDestroy(&s.xg);
  if (s.yg) VecDestroy(&s.yg);
  free(s.dsq);
  res->iterations = (int)p->products;
  res->seconds = dtm_wtime() - t0;
  return r;
}
