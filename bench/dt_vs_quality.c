/* Benchmark (not a test): the element-bound dt map on about 1e6 tets against
 * Gmsh's own Plugin(AnalyseMeshQuality) on the same mesh, in the same run.
 * Usage: bench_dt_vs_quality [mesh_size] (default 0.0105 on a unit cube,
 * about 1e6 tets). Prints elements per second and the ratio. */
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
    "<meshing size=\"%g\" dim=\"3\"/>\n"
    "<material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
    "<effects><elastic formulation=\"3d\"/></effects>\n</dtmap-scene>\n";

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f) exit(3);
  fputs(text, f);
  fclose(f);
}

/* Time one AnalyseMeshQuality measure on the current model, s. */
static double time_quality(const char *measure) {
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

/* Best of 3 element loops with nthreads, s (each repetition extracts the
 * current model's mesh again and runs the whole analysis; the element loop
 * is its "effects" stage). */
static double time_dtmap(const dtm_scene *s, int nthreads) {
  double best = 1e30;
  omp_set_num_threads(nthreads);
  for (int rep = 0; rep < 3; rep++) {
    dtm_analysis *b = NULL;
    if (dtm_analysis_current(s, 3, &b)) exit(3);
    double t = dtm_analysis_timing(b, DTM_T_EFFECTS);
    if (t < best) best = t;
    dtm_analysis_destroy(&b);
  }
  return best;
}

int main(int argc, char **argv) {
  double h = argc > 1 ? atof(argv[1]) : 0.0105;
  char scene[1024];
  snprintf(scene, sizeof scene, scene_fmt, h);
  write_file("/tmp/dtmap-bench-cube.geo", geo);
  write_file("/tmp/dtmap-bench-cube.xml", scene);
  dtm_scene *s = NULL;
  dtm_analysis *a = NULL;
  if (dtm_scene_load("/tmp/dtmap-bench-cube.xml", &s) || dtm_gmsh_start(0)) return 3;
  int ierr = 0;
  gmshOptionSetNumber("Mesh.Algorithm3D", 10, &ierr); /* HXT: fast, parallel */
  double t0 = dtm_wtime();
  if (dtm_analysis_run(s, &a)) return fprintf(stderr, "%s\n", dtm_error_message()), 3;
  size_t nel = dtm_analysis_nelements(a);
  printf("mesh: %zu tets, %zu nodes (meshing %.1f s, extraction %.2f s)\n", nel, dtm_analysis_mesh(a)->nnodes,
         dtm_analysis_timing(a, DTM_T_MESH), dtm_analysis_timing(a, DTM_T_EXTRACT));
  (void)t0;
  double t1 = time_dtmap(s, 1), tn = time_dtmap(s, omp_get_num_procs());
  double qj = time_quality("JacobianDeterminant"), qi = time_quality("ICNMeasure");
  printf("dtmap element bound, 1 thread : %.3f s  (%.1f M elements/s)\n", t1, nel / t1 / 1e6);
  printf("dtmap element bound, %d threads: %.3f s  (%.1f M elements/s)\n", omp_get_num_procs(), tn, nel / tn / 1e6);
  printf("AnalyseMeshQuality J   : %.3f s  -> ratio %.1fx (1 thread), %.1fx (all)\n", qj, qj / t1, qj / tn);
  printf("AnalyseMeshQuality ICN : %.3f s  -> ratio %.1fx (1 thread), %.1fx (all)\n", qi, qi / t1, qi / tn);
  dtm_analysis_destroy(&a);
  dtm_gmsh_stop();
  dtm_scene_destroy(&s);
  return 0;
}
