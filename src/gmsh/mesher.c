/* The mesher dtmap asks Gmsh for: the scene's <meshing algorithm threads>
 * when it names them, else whatever the geometry file set (Gmsh's own
 * default: Delaunay on one thread). The choice in force is remembered for
 * the remeshing of refine and reported: a mesher on more than one thread
 * may number, and even count, the elements differently from one run to the
 * next, and HXT does so even on one thread, with the process's OpenMP
 * thread count (measured: 1606 or 1608 tets for the same scene with -j 2
 * or -j 1); such a mesh is reported as not reproducible. */
#include <gmshc.h>
#include <omp.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

#define HXT 10 /* Mesh.Algorithm3D of HXT */

static dtm_mesher_info last = {0, 0, 1}; /* the current model's mesher */

/* Threads Gmsh will mesh with: General.NumThreads, 0 meaning all cores. */
static int effective_threads(void) {
  double n = 1;
  int ierr = 0;
  gmshOptionGetNumber("General.NumThreads", &n, &ierr);
  return n >= 1 ? (int)n : omp_get_num_procs();
}

void dtm_gmsh_mesher_apply(const dtm_scene *s) {
  int ierr = 0;
  if (s && s->mesh_algorithm > 0) gmshOptionSetNumber("Mesh.Algorithm3D", s->mesh_algorithm, &ierr);
  if (s && s->mesh_threads > 0) gmshOptionSetNumber("General.NumThreads", s->mesh_threads, &ierr);
  if (!s && last.threads > 0) gmshOptionSetNumber("General.NumThreads", last.threads, &ierr); /* the load's */
  double alg = 1;
  gmshOptionGetNumber("Mesh.Algorithm3D", &alg, &ierr);
  last = (dtm_mesher_info){(int)alg, effective_threads(), effective_threads() == 1 && (int)alg != HXT};
  omp_set_num_threads(last.threads);
}

void dtm_gmsh_mesher_read(void) { last = (dtm_mesher_info){0, 0, 1}; }

void dtm_gmsh_mesher_defaults(void) {
  int ierr = 0;
  gmshOptionSetNumber("Mesh.Algorithm3D", 1, &ierr); /* Gmsh's defaults: an earlier scene's choice does not leak */
  gmshOptionSetNumber("General.NumThreads", 1, &ierr);
}

void dtm_gmsh_mesher(dtm_mesher_info *out) { *out = last; }
