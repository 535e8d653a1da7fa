/* The gap between two model entities of the current Gmsh model near a
 * point, from the geometry itself: the closest points of the two, found by
 * projecting alternately onto each (Gmsh's getClosestPoint), from the
 * projection of the point onto the first. Two faces of a wall converge in
 * one step; a plane and a cylinder (a ligament between a hole and an edge)
 * in a few. A mesh sees a gap only between its nodes, which on a coarse
 * mesh of a curved face can lie far from the narrowest place (4.5 mm for a
 * 2.5 mm ligament), so the layers' thickness (src/analysis/layers.c) asks
 * the geometry when there is one. Projection is onto the untrimmed
 * surfaces; the caller checks the pair against the mesh. While run's
 * background writer has the model (dtm_gmsh_model_given: it writes and
 * then releases it on its own thread) the answer is NaN, under the lock
 * the writer holds, so the gap never asks a model being cleared (a crash
 * once seen under the sanitizers: t803) and does not depend on which
 * thread came first. */
#include <gmshc.h>
#include <math.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

#define GAP_ITERATIONS 40

/* The point of entity (dim, tag) closest to x, into y; 0 on success. */
static int closest(int dim, int tag, const double x[3], double y[3]) {
  double in[3] = {x[0], x[1], x[2]}, *out = NULL, *par = NULL;
  size_t nout = 0, npar = 0;
  int ierr = 0;
  gmshModelGetClosestPoint(dim, tag, in, 3, &out, &nout, &par, &npar, &ierr);
  int ok = !ierr && nout == 3 && isfinite(out[0]) && isfinite(out[1]) && isfinite(out[2]);
  for (int d = 0; ok && d < 3; d++) y[d] = out[d];
  gmshFree(out), gmshFree(par);
  return ok ? 0 : 1;
}

static double dist3(const double *p, const double *q) {
  return sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
}

static double gap(const int a[2], const int b[2], const double x0[3], double pa[3], double pb[3]) {
  if (a[0] < 1 || b[0] < 1 || closest(a[0], a[1], x0, pa)) return NAN;
  double last = INFINITY;
  for (int k = 0; k < GAP_ITERATIONS; k++) {
    if (closest(b[0], b[1], pa, pb) || closest(a[0], a[1], pb, pa)) return NAN;
    double t = dist3(pa, pb);
    if (!(t < last * (1 - 1e-12))) return t;
    last = t;
  }
  return last;
}

double dtm_gmsh_gap(const int a[2], const int b[2], const double x0[3], double pa[3], double pb[3]) {
  dtm_gmsh_lock(); /* run's writer may be writing the mesh on its thread */
  double g = dtm_gmsh_model_is_given() ? NAN : gap(a, b, x0, pa, pb);
  dtm_gmsh_unlock();
  return g;
}
