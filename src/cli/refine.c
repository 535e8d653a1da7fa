/* `dtmap refine SCENE.xml --target DT`: remesh until the recommended step
 * reaches DT, printing each round, then write the final mesh with all its
 * views and the report. Exit 1 when the target is not met. */
#include <omp.h>
#include <stdio.h>

#include "cli-impl.h"
#include "dtmap/gmsh.h"
#include "dtmap/refine.h"
#include "dtmap/scene.h"

static void print_rounds(const dtm_refine_result *rr) {
  printf("\n%5s %10s %12s %14s %9s\n", "round", "elements", "dt min (s)", "recommended", "time (s)");
  for (int i = 0; i < rr->nrounds; i++) {
    const dtm_refine_round *r = &rr->rounds[i];
    printf("%5d %10zu %12.4e %14.4e %9.2f%s\n", i, r->elements, r->dt_min, r->recommended, r->seconds,
           r->recommended >= rr->target ? "  target met" : "");
  }
}

static int report_rounds(const dtm_refine_result *rr, const cli_opts *o) {
  dtm_cost *cost = NULL;
  DTM_CHECK(dtm_cost_create(rr->analysis, &cost));
  dtm_results res = {rr->analysis, cost, rr, 0.0, 0.0};
  if (o->verbosity) print_rounds(rr), printf("\n"), dtm_summary_print(&res, stdout);
  int r = dtm_cli_write_outputs(&res, o, NULL);
  dtm_cost_destroy(&cost);
  return r;
}

static int refine_scene(const dtm_scene *s, const cli_opts *o) {
  dtm_refine_result *rr = NULL;
  int r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0);
  if (r == DTM_OK) r = dtm_refine_run(s, o->target, o->max_iter, &rr);
  if (r == DTM_OK) r = report_rounds(rr, o);
  double best = rr ? dtm_analysis_recommended(rr->analysis) : 0;
  if (r == DTM_OK && best < o->target)
    r = DTM_ERR(DTM_ERR_TARGET, "refine: the target %.4e s was not met after %d round(s); best recommended step %.4e s",
                o->target, rr->nrounds - 1, best);
  dtm_refine_destroy(&rr);
  dtm_gmsh_stop();
  return r;
}

int dtm_cli_refine(const cli_opts *o) {
  int f;
  if (!(o->target > 0)) return dtm_cli_usage_error(&dtm_cli_commands[2], "needs --target DT (s)");
  if (dtm_cli_format(&dtm_cli_commands[2], o->format, &f)) return DTM_ERR_INPUT;
  if (o->threads > 0) omp_set_num_threads(o->threads);
  dtm_scene *s = NULL;
  int r = dtm_scene_load(o->scene, &s);
  if (r == DTM_OK) {
    if (o->verbosity) printf("dtmap %s: refining %s to %.4e s\n", DTM_VERSION, s->path, o->target);
    r = refine_scene(s, o);
  }
  dtm_scene_destroy(&s);
  return r ? dtm_cli_fail(r, o->verbosity) : 0;
}
