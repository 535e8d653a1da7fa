/* What the accuracy measures (src/cost/accuracy.c) add to `dtmap run`:
 * the scene is meshed at the given size and analysed, then the measures
 * are computed alone (best of three) and compared with the analysis's own
 * stages: meshing, extraction, the element loop and the nodal bound.
 * Prints one line per run: elements, the stages, the measures and their
 * share of the analysis with and without the meshing.
 *
 * Usage: bench_accuracy_cost SCENE.xml SIZE [SIZE ...] (sizes in m) */
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/analysis.h"
#include "dtmap/cost.h"
#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/scene.h"
#include "dtmap/util.h"

static int one_size(dtm_scene *s, double h) {
  s->mesh_size = h;
  if (s->mesh_min_size > h) s->mesh_min_size = h;
  dtm_analysis *a = NULL;
  DTM_CHECK(dtm_analysis_run(s, &a));
  double best = 1e30, stages = 0;
  for (int k = 0; k < 3; k++) {
    dtm_measures *m = NULL;
    double t0 = dtm_wtime();
    int r = dtm_measures_compute(a, 0, NULL, &m);
    double t = dtm_wtime() - t0;
    dtm_measures_destroy(&m);
    if (r) return dtm_analysis_destroy(&a), r;
    if (t < best) best = t;
  }
  for (int t = DTM_T_EXTRACT; t <= DTM_T_NODAL; t++) stages += dtm_analysis_timing(a, t);
  double mesh = dtm_analysis_timing(a, DTM_T_MESH);
  printf("%10.4g %10zu %9.3f %9.3f %9.4f %8.2f%% %8.2f%%\n", h, dtm_analysis_nelements(a), mesh, stages, best,
         100 * best / (mesh + stages), 100 * best / stages);
  dtm_analysis_destroy(&a);
  return DTM_OK;
}

int main(int argc, char **argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: %s SCENE.xml SIZE [SIZE ...]\n", argv[0]);
    return 2;
  }
  dtm_scene *s = NULL;
  int r = dtm_scene_load(argv[1], &s);
  if (r == DTM_OK) r = dtm_gmsh_start(0);
  printf("%10s %10s %9s %9s %9s %9s %9s\n", "size (m)", "elements", "mesh (s)", "anal. (s)", "meas. (s)", "of all",
         "of anal.");
  for (int i = 2; i < argc && r == DTM_OK; i++) r = one_size(s, atof(argv[i]));
  if (r) fprintf(stderr, "%s\n", dtm_error_message());
  dtm_scene_destroy(&s);
  return r ? 1 : 0;
}
