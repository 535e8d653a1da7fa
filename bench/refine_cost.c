/* What `dtmap refine` does to the cost of a run: for the bundled scenes and
 * a 1e5-element notched beam (the bundled geometry meshed at 3 mm, 1 mm at
 * the notch tip), the element-steps of the scene's duration before and
 * after refine, the elements, the rounds, whether the target is met, and
 * refine's wall time (meshing and analysis of every round included; the
 * analysis that finds the input's recommended step is not), and what one
 * remesh round costs against a run: round 0 (loading or meshing the input
 * and analysing it, which is what `dtmap run` does), the mean remesh round
 * and Gmsh's share of it (the remesh in its child, optimisers included),
 * so that a round costs no more than Gmsh's remesh plus a run when the
 * last column is at most 1. Targets: 1.3 x
 * the input's recommended step (the test) and each scene's own
 * <time target>. Prints a Markdown table. Usage: bench_refine_cost SRCDIR
 * [MAX_ROUNDS]. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/analysis.h"
#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/refine.h"
#include "dtmap/scene.h"
#include "dtmap/util.h"

static int fail(const char *what) {
  fprintf(stderr, "bench_refine_cost: %s: %s\n", what, dtm_error_message());
  return 1;
}

/* The input's recommended step (its own analysis, not timed). */
static int input_step(const dtm_scene *s, double *rec) {
  dtm_scene sc = *s;
  sc.target = 0;
  dtm_analysis *a = NULL;
  if (dtm_analysis_run(&sc, &a)) return fail(s->path);
  *rec = dtm_analysis_recommended(a);
  dtm_analysis_destroy(&a);
  return 0;
}

static int row(const char *name, const dtm_scene *s, double target, const char *label, int rounds) {
  dtm_refine_result *rr = NULL;
  double t0 = dtm_wtime();
  dtm_refine_options o = {.target = target, .max_rounds = rounds, .max_added_mass = NAN};
  if (dtm_refine_run(s, &o, &rr)) return fail(name);
  double t = dtm_wtime() - t0;
  const dtm_refine_round *in = &rr->rounds[0], *out = &rr->rounds[rr->best];
  double round = 0, gmsh = 0;
  int n = 0;
  for (int i = 1; i < rr->nrounds; i++)
    if (rr->rounds[i].kind == DTM_ROUND_MESH) round += rr->rounds[i].seconds, gmsh += rr->rounds[i].mesh_seconds, n++;
  printf("| %s | %s = %.3e | %zu | %.4g | %zu | %.4g | %.3f | %d | %s | %.2f | %.2f | %.2f | %.2f | %.2f |\n", name,
         label, target, in->elements, in->element_steps, out->elements, out->element_steps,
         out->element_steps / in->element_steps, rr->nrounds - 1, out->recommended >= target ? "yes" : "no", t,
         in->seconds, n ? round / n : NAN, n ? gmsh / n : NAN, n ? round / n / (gmsh / n + in->seconds) : NAN);
  fflush(stdout);
  dtm_refine_destroy(&rr);
  return 0;
}

/* Each scene in a fresh Gmsh session: a .geo file's Mesh options stay set
 * for the next file otherwise, and the meshes would differ from the CLI's. */
static int bench_scene(const char *name, const char *path, int rounds) {
  dtm_scene *s = NULL;
  double rec = 0;
  dtm_gmsh_stop();
  if (dtm_gmsh_start(0)) return fail("gmsh");
  if (dtm_scene_load(path, &s)) return fail(path);
  int r = input_step(s, &rec);
  if (!r) r = row(name, s, 1.3 * rec, "1.3 x rec.", rounds);
  if (!r && s->target > 0) r = row(name, s, s->target, "scene", rounds);
  dtm_scene_destroy(&s);
  return r;
}

/* The 1e5-element case: the notched beam at 3 mm (1 mm at the tip). */
static int write_large(const char *src, char *path, size_t len) {
  snprintf(path, len, "%s/dtmap-bench-beam-%d.xml", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid());
  FILE *f = fopen(path, "w");
  if (!f) return fprintf(stderr, "bench_refine_cost: cannot write %s\n", path), 1;
  fprintf(f,
          "<dtmap-scene version=\"1\">\n  <geometry file=\"%s/geometries/notched_beam.geo\"/>\n"
          "  <meshing size=\"3e-3\" min-size=\"1e-3\" order=\"1\" dim=\"3\"/>\n"
          "  <material name=\"concrete\" groups=\"beam\" E=\"30e9\" nu=\"0.2\" rho=\"2400\"/>\n"
          "  <effects>\n    <elastic formulation=\"3d\"/>\n  </effects>\n"
          "  <time safety=\"0.9\" duration=\"1e-3\"/>\n</dtmap-scene>\n",
          src);
  return fclose(f) != 0;
}

int main(int argc, char **argv) {
  static const char *const scenes[] = {"plate_with_hole", "brazilian_disc", "box", "notched_beam"};
  if (argc < 2) return fprintf(stderr, "usage: bench_refine_cost SRCDIR [MAX_ROUNDS]\n"), 2;
  int rounds = argc > 2 ? atoi(argv[2]) : 3, r = 0;
  char path[4096];
  if (dtm_gmsh_start(0)) return fail("gmsh");
  printf("| scene | target (s) | elements before | element-steps before | elements after | element-steps after | "
         "after / before | rounds | met | refine time (s) | round 0, a run (s) | remesh round (s) | of which Gmsh "
         "(s) | round / (Gmsh + run) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int i = 0; i < 4 && !r; i++) {
    snprintf(path, sizeof path, "%s/geometries/%s.xml", argv[1], scenes[i]);
    r = bench_scene(scenes[i], path, rounds);
  }
  if (!r) r = write_large(argv[1], path, sizeof path);
  if (!r) r = bench_scene("notched_beam, 1e5 tets", path, rounds), remove(path);
  dtm_gmsh_stop();
  return r;
}
