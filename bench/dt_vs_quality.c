/* Benchmark (not a test): the element-bound dt map on about 1e6 tets against
 * Gmsh's own Plugin(AnalyseMeshQuality) on the same mesh, in the same run.
 * Usage: bench_dt_vs_quality [mesh_size] (default 0.0158 on a unit cube:
 * HXT makes about 1.0e6 tets). Each side is timed REPS times and the best
 * kept. dtmap's time is given twice: the element loop alone, and with what
 * it needs before (extracting the mesh from Gmsh's model, the locality
 * order) and after (nodal bound, size suggestion): Gmsh's plugin works on
 * its own model, so the second is the like-for-like figure. */
#include <gmshc.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/analysis.h"
#include "dtmap/gmsh.h"
#include "dtmap/util.h"

static const char geo[] =
    "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\nPhysical Volume(\"block\") = {1};\n";
static const char scene_fmt[] =
    "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n<geometry file=\"dtmap-bench-cube.geo\"/>\n"
    "<meshing size=\"%g\" dim=\"3\" algorithm=\"hxt\" threads=\"2\"/>\n"
    "<material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
    "<effects><elastic formulation=\"3d\"/></effects>\n</dtmap-scene>\n";

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f) exit(3);
  fputs(text, f);
  fclose(f);
}

#define REPS 3 /* repetitions on each side */

/* Time one AnalyseMeshQuality measure on the current model, s. */
static double quality_once(const char *measure) {
  int ierr = 0;
  gmshPluginSetNumber("AnalyseMeshQuality", "JacobianDeterminant", 0, &ierr);
  gmshPluginSetNumber("AnalyseMeshQuality", "IGEMeasure", 0, &ierr);
  gmshPluginSetNumber("AnalyseMeshQuality", "ICNMeasure", 0, &ierr);
  gmshPluginSetNumber("AnalyseMeshQuality", measure, 1, &ierr);
  gmshPluginSetNumber("AnalyseMeshQuality", "CreateView", 0, &ierr);
  gmshPluginSetNumber("AnalyseMeshQuality", "Recompute", 1, &ierr);
  gmshPluginSetNumber("AnalyseMeshQuality", "DimensionOfElements", 3, &ierr);
  double t0 = dtm_wtime();
  gmshPluginRun("AnalyseMeshQuality", &ierr);
  double t = dtm_wtime() - t0;
  if (ierr) fprintf(stderr, "AnalyseMeshQuality (%s) failed\n", measure);
  return t;
}

/* Best of REPS. */
static double time_quality(const char *measure) {
  double best = 1e30;
  for (int rep = 0; rep < REPS; rep++) {
    double t = quality_once(measure);
    if (t < best) best = t;
  }
  return best;
}

/* Best of REPS with nthreads, s: the element loop (the "effects" stage)
 * into *loop, and the whole analysis of the current model (extraction
 * included) returned. */
static double time_dtmap(const dtm_scene *s, int nthreads, double *loop) {
  double best = 1e30;
  omp_set_num_threads(nthreads);
  *loop = 1e30;
  for (int rep = 0; rep < REPS; rep++) {
    dtm_analysis *b = NULL;
    double t0 = dtm_wtime();
    if (dtm_analysis_current(s, 3, &b)) exit(3);
    double t = dtm_wtime() - t0, tl = dtm_analysis_timing(b, DTM_T_EFFECTS);
    if (t < best) best = t;
    if (tl < *loop) *loop = tl;
    dtm_analysis_destroy(&b);
  }
  return best;
}

int main(int argc, char **argv) {
  double h = argc > 1 ? atof(argv[1]) : 0.0158;
  char scene[1024];
  snprintf(scene, sizeof scene, scene_fmt, h);
  write_file("/tmp/dtmap-bench-cube.geo", geo);
  write_file("/tmp/dtmap-bench-cube.xml", scene);
  dtm_scene *s = NULL;
  dtm_analysis *a = NULL;
  if (dtm_scene_load("/tmp/dtmap-bench-cube.xml", &s) || dtm_gmsh_start(0)) return 3;
  if (dtm_analysis_run(s, &a)) return fprintf(stderr, "%s\n", dtm_error_message()), 3;
  size_t nel = dtm_analysis_nelements(a);
  printf("mesh: %zu tets, %zu nodes (meshing %.1f s, extraction %.2f s)\n", nel, dtm_analysis_mesh(a)->nnodes,
         dtm_analysis_timing(a, DTM_T_MESH), dtm_analysis_timing(a, DTM_T_EXTRACT));
  double l1, ln, t1 = time_dtmap(s, 1, &l1), tn = time_dtmap(s, omp_get_num_procs(), &ln);
  double qj = time_quality("JacobianDeterminant"), qi = time_quality("ICNMeasure");
  printf("best of %d on each side\n", REPS);
  printf("dtmap element loop, 1 thread  : %.3f s  (%.1f M elements/s)\n", l1, nel / l1 / 1e6);
  printf("dtmap element loop, %d threads : %.3f s  (%.1f M elements/s)\n", omp_get_num_procs(), ln, nel / ln / 1e6);
  printf("dtmap with extraction, 1 thread  : %.3f s\n", t1);
  printf("dtmap with extraction, %d threads : %.3f s\n", omp_get_num_procs(), tn);
  printf("AnalyseMeshQuality J   : %.3f s  -> %.1fx the loop, %.1fx with extraction (%d threads)\n", qj, qj / ln,
         qj / tn, omp_get_num_procs());
  printf("AnalyseMeshQuality ICN : %.3f s  -> %.1fx the loop, %.1fx with extraction (%d threads)\n", qi, qi / ln,
         qi / tn, omp_get_num_procs());
  dtm_analysis_destroy(&a);
  dtm_gmsh_stop();
  dtm_scene_destroy(&s);
  return 0;
}
