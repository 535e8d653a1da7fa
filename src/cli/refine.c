/* `dtmap refine SCENE.xml --target DT`: remesh until the recommended step
 * reaches DT, printing each round, then write the final mesh with all its
 * views and the report. Exit 1 when the target is not met. */
#include <stdio.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/refine.h"
#include "dtmap/scene.h"
#include "opts.h"

static void print_rounds(const dtm_refine_round *r, int n, double target) {
  printf("\n%5s %10s %12s %14s %9s\n", "round", "elements", "dt min (s)", "recommended", "time (s)");
  for (int i = 0; i < n; i++)
    printf("%5d %10zu %12.4e %14.4e %9.2f%s\n", i, r[i].elements, r[i].dt_min, r[i].recommended, r[i].seconds,
           r[i].recommended >= target ? "  target met" : "");
}

static int refine_scene(dtm_scene *s, const run_opts *o) {
  dtm_scene sc;
  dtm_refine_round rounds[DTM_REFINE_MAX_ROUNDS];
  dtm_analysis *a = NULL;
  int n = 0, r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0);
  if (r == DTM_OK) r = dtm_refine(s, o->target, o->max_iter, &sc, rounds, &n, &a);
  if (r == DTM_OK) {
    a->refine_rounds = rounds, a->nrefine = n;
    if (o->verbosity) print_rounds(rounds, n, o->target), printf("\n"), dtm_summary_print(a, stdout);
    r = dtm_cli_write_outputs(a, o, &a->timings[DTM_T_OUTPUT]);
    a->refine_rounds = NULL;
  }
  if (r == DTM_OK && a->recommended < o->target)
    r = DTM_ERR(DTM_ERR_TARGET, "refine: the target %.4e s was not met after %d round(s); best recommended step %.4e s",
                o->target, n - 1, a->recommended);
  dtm_analysis_destroy(&a);
  dtm_gmsh_stop();
  return r;
}

int dtm_cli_refine(int argc, char **argv) {
  run_opts o = dtm_cli_defaults();
  int r = dtm_cli_parse(argc, argv, &o);
  if (r) return r;
  if (!(o.target > 0)) return dtm_cli_usage_error("%s", "refine needs --target DT (s)");
  dtm_scene *s = NULL;
  r = dtm_scene_load(o.scene, &s);
  if (r == DTM_OK) {
    if (o.verbosity) printf("dtmap %s: refining %s to %.4e s\n", DTM_VERSION, s->path, o.target);
    r = refine_scene(s, &o);
  }
  dtm_scene_destroy(&s);
  return r ? dtm_cli_fail(r, o.verbosity) : 0;
}
