/* Benchmark (not a test): what accuracy costs for the step estimators
 * themselves. For unit-cube tet meshes of about 1e4, 1e5 and 1e6 elements it
 * times the element bound, L_safe, the nodal bound and Lanczos at relative
 * tolerances 1e-2, 1e-3 and 1e-6 (operator set-up and the Lanczos steps
 * included; the residual is Paige's estimate, as in `run --posterior`), and gives each step's ratio to the
 * converged global step (Lanczos to 1e-10) and the number of steps a 1 ms
 * run needs. Prints a Markdown table (bench/estimators.sh writes it to
 * docs/estimators.md). Usage: bench_estimators [size ...]. */
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/analysis.h"
#include "dtmap/gmsh.h"
#include "dtmap/operator.h"
#include "dtmap/util.h"

#define DURATION 1e-3 /* s, the fixed run the step counts are for */

static const char geo[] =
    "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\nPhysical Volume(\"block\") = {1};\n";
static const char scene_fmt[] =
    "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n<geometry file=\"dtmap-est-cube.geo\"/>\n"
    "<meshing size=\"%g\" dim=\"3\" algorithm=\"hxt\" threads=\"2\"/>\n"
    "<material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
    "<effects><elastic formulation=\"3d\" length=\"%s\"/></effects>\n</dtmap-scene>\n";

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f || fputs(text, f) < 0 || fclose(f)) exit(3);
}

static dtm_scene *scene_for(double h, const char *length) {
  char text[2048], path[256];
  snprintf(text, sizeof text, scene_fmt, h, length);
  snprintf(path, sizeof path, "/tmp/dtmap-est-%s.xml", length);
  write_file(path, text);
  dtm_scene *s = NULL;
  if (dtm_scene_load(path, &s)) fprintf(stderr, "%s\n", dtm_error_message()), exit(3);
  return s;
}

/* Lanczos to tol on effect 0: step (safe side), products and time. */
static double lanczos(dtm_analysis *a, double tol, int *its, double *secs) {
  dtm_operator *op = NULL;
  dtm_lanczos_result r = {0};
  double t0 = dtm_wtime();
  if (dtm_analysis_operator(a, 0, 0.0, &op) || dtm_lanczos_max_ex(op, tol, 2000, 20261121u, 0, &r)) exit(3);
  *secs = dtm_wtime() - t0;
  *its = r.iterations;
  dtm_operator_destroy(&op);
  free(r.mode);
  return 2.0 / sqrt(r.theta + r.residual);
}

static void row(const char *name, double secs, double dt, double exact, const char *note) {
  printf("| %s | %.3f | %.4e | %.3f | %.3g | %s |\n", name, secs, dt, dt / exact, DURATION / dt, note);
}

static void one_mesh(double h) {
  dtm_scene *se = scene_for(h, "eigen"), *ss = scene_for(h, "safe");
  dtm_analysis *a = NULL, *b = NULL;
  int dim, its;
  double secs;
  if (dtm_gmsh_load(se, &dim) || dtm_analysis_current(se, dim, &a) || dtm_analysis_current(ss, dim, &b)) exit(3);
  double exact = lanczos(a, 1e-10, &its, &secs);
  printf("\n### %zu tets, %zu nodes (size %g)\n\n", dtm_analysis_nelements(a), dtm_analysis_mesh(a)->nnodes, h);
  printf("| estimator | time (s) | step (s) | step / global | steps for %g s | note |\n", DURATION);
  printf("|---|---|---|---|---|---|\n");
  row("element bound", dtm_analysis_timing(a, DTM_T_EFFECTS), dtm_analysis_dt_min(a, NULL), exact, "rigorous");
  row("L_safe", dtm_analysis_timing(b, DTM_T_EFFECTS), dtm_analysis_dt_min(b, NULL), exact,
      "rigorous on simplices (nu >= 0)");
  row("nodal bound", dtm_analysis_timing(a, DTM_T_NODAL), dtm_analysis_dt_nodal(a), exact, "rigorous");
  static const double tols[] = {1e-2, 1e-3, 1e-6};
  for (int i = 0; i < 3; i++) {
    char name[64], note[64];
    double dt = lanczos(a, tols[i], &its, &secs);
    snprintf(name, sizeof name, "Lanczos tol %g", tols[i]);
    snprintf(note, sizeof note, "%d Lanczos steps; safe side theta + residual", its);
    row(name, secs, dt, exact, note);
  }
  dtm_analysis_destroy(&a);
  dtm_analysis_destroy(&b);
  dtm_scene_destroy(&se);
  dtm_scene_destroy(&ss);
}

int main(int argc, char **argv) {
  static const double defaults[] = {0.08, 0.034, 0.0158}; /* ~1e4, 1e5, 1e6 tets */
  write_file("/tmp/dtmap-est-cube.geo", geo);
  if (dtm_gmsh_start(0)) return 3;
  printf("Steel unit cube (E = 210 GPa, nu = 0.3, rho = 7850), lumped mass, undamped.\n");
  printf("The global step is Lanczos to a relative residual of 1e-10.\n");
  for (int i = 1; i < argc; i++) one_mesh(atof(argv[i]));
  for (int i = 0; argc == 1 && i < 3; i++) one_mesh(defaults[i]);
  dtm_gmsh_stop();
  return 0;
}
