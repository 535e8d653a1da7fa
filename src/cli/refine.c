/* `dtmap refine SCENE.xml [--target DT]`: remesh until the recommended step
 * reaches DT (default: the scene's <time target>) without raising the
 * cost, printing each round (elements, recommended step, element-steps and
 * their change), then write the kept mesh with all its views and the
 * report (by default SCENE_refined.msh, never run's SCENE_dt.msh), with the
 * causes when the target is not met (each with the lines to paste into the
 * .geo where there are any). Exit 1 when the target is not met, also when
 * Gmsh refused or crashed in a remesh (the kept mesh is written). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/gmsh.h"
#include "dtmap/refine.h"
#include "dtmap/scene.h"

/* The worst phase error of a round in percent, or why there is none. */
static const char *phase_text(const dtm_refine_round *r, char *buf, size_t len) {
  if (r->unresolved)
    snprintf(buf, len, "unres.");
  else if (isnan(r->phase_error))
    snprintf(buf, len, "-");
  else
    snprintf(buf, len, "%+.3g%%", 100 * r->phase_error);
  return buf;
}

static void print_round(const dtm_refine_result *rr, int i) {
  const dtm_refine_round *r = &rr->rounds[i];
  double c = dtm_refine_cost(r), c0 = i ? dtm_refine_cost(&rr->rounds[i - 1]) : c;
  char ph[32];
  printf("%5d %10zu %12.4e %12.4e %12.4e %+9.1f%% %9zu %9zu %9s %5s %9.2f%s%s\n", i, r->elements, r->dt_min,
         r->recommended, c, 100.0 * (c / c0 - 1.0), r->below, r->shape_limited, phase_text(r, ph, sizeof ph),
         r->in_band ? "yes" : "no", r->seconds, r->recommended >= rr->target ? "  target met" : "",
         i == rr->best ? "  (kept)" : "");
}

/* What the kept mesh and its step do to the accuracy of the input: on
 * stdout the phase error before and after, on stderr (even with -q) a
 * warning when the kept mesh leaves a band the input was inside. */
static void print_accuracy_change(const dtm_refine_result *rr, int verbose) {
  const dtm_refine_round *r0 = &rr->rounds[0], *rb = &rr->rounds[rr->best];
  char a[32], b[32];
  if (verbose && rr->frequency > 0)
    printf("accuracy: worst phase-speed error at %.4g Hz %s on the input, %s on the kept mesh at its step\n",
           rr->frequency, phase_text(r0, a, sizeof a), phase_text(rb, b, sizeof b));
  if (r0->in_band && !rb->in_band)
    fprintf(stderr,
            "dtmap: warning: the kept mesh at its larger step leaves the accuracy band the input was inside "
            "(worst phase-speed error %s -> %s; see 'accuracy at the recommended step' in the summary)\n",
            phase_text(r0, a, sizeof a), phase_text(rb, b, sizeof b));
}

/* The causes, each with its fix indented (lines to paste into the .geo). */
static void print_causes(const dtm_refine_result *rr) {
  if (rr->ncauses) printf("causes:\n");
  for (int i = 0; i < rr->ncauses; i++) {
    const dtm_cause *c = &rr->causes[i];
    printf("  [%s] %s\n", c->kind, c->text);
    if (!c->fix[0]) continue;
    printf("    paste into the .geo:\n");
    for (const char *p = c->fix; *p;) {
      size_t len = strcspn(p, "\n");
      printf("      %.*s\n", (int)len, p);
      p += len + (p[len] == '\n');
    }
  }
}

static void print_rounds(const dtm_refine_result *rr) {
  int rate = isnan(rr->rounds[0].element_steps);
  printf("\n%5s %10s %12s %12s %12s %10s %9s %9s %9s %5s %9s\n", "round", "elements", "elem. bound", "recommended",
         rate ? "elem-steps/s" : "element-steps", "change", "below", "shape-lim", "phase", "band", "time (s)");
  for (int i = 0; i < rr->nrounds; i++) print_round(rr, i);
  printf("stopped: %s; kept round %d\n", dtm_refine_stop_text(rr->stop), rr->best);
  if (rr->forced_by && rr->forced >= 0.5)
    printf("accuracy: the bound '%s' asks for about %.0f more elements than the input's sizes give (%.4g "
           "element-steps at the kept step)\n",
           rr->forced_by, rr->forced,
           rr->forced * dtm_refine_cost(&rr->rounds[rr->best]) / rr->rounds[rr->best].elements);
  if (rr->stop == DTM_REFINE_THICKNESS)
    printf("no round was run: elements below the target are limited by the thickness of their layer, which no\n"
           "size suggestion changes; the layers and their remedies follow\n");
  if (rr->stop == DTM_REFINE_ONLY_SHAPE)
    printf("only shape-limited elements remain below the target: no larger size lifts them; their remedies and\n"
           "the mass-scaling alternative for exactly these elements follow\n");
  print_causes(rr);
}

static int report_rounds(const dtm_refine_result *rr, const cli_opts *o) {
  dtm_cost *cost = NULL;
  DTM_CHECK(dtm_cost_create(rr->analysis, &cost));
  dtm_results res = {rr->analysis, cost, rr, 0.0, 0.0, o->top};
  dtm_cli_warn_flagged(rr->analysis);
  if (o->verbosity) print_rounds(rr);
  print_accuracy_change(rr, o->verbosity);
  if (o->verbosity) printf("\n"), dtm_summary_print(&res, stdout);
  int r = dtm_cli_write_outputs(&res, o, "_refined", NULL);
  dtm_cost_destroy(&cost);
  return r;
}

static int refine_scene(const dtm_scene *s, double target, const cli_opts *o) {
  dtm_refine_result *rr = NULL;
  int r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0);
  if (r == DTM_OK) r = dtm_refine_run(s, target, o->max_iter, &rr);
  if (r == DTM_OK) r = report_rounds(rr, o);
  double best = rr ? dtm_analysis_recommended(rr->analysis) : 0;
  if (r == DTM_OK && best < target)
    r = DTM_ERR(DTM_ERR_TARGET,
                "refine: the target %.4e s was not met after %d round(s) (%s); best recommended step %.4e s%s%s",
                target, rr->nrounds - 1, dtm_refine_stop_text(rr->stop), best, rr->ncauses ? "; cause: " : "",
                rr->ncauses ? rr->causes[0].text : "");
  dtm_refine_destroy(&rr);
  dtm_gmsh_stop();
  return r;
}

int dtm_cli_refine(const cli_opts *o) {
  int f;
  if (dtm_cli_format(&dtm_cli_commands[2], o->format, &f)) return DTM_ERR_INPUT;
  if (o->threads > 0) omp_set_num_threads(o->threads);
  dtm_scene *s = NULL;
  int r = dtm_scene_load(o->scene, &s);
  double target = o->target > 0 ? o->target : s ? s->target : 0;
  if (r == DTM_OK && !(target > 0)) {
    dtm_scene_destroy(&s);
    return dtm_cli_usage_error(&dtm_cli_commands[2], "needs --target DT (s), or a <time target> in the scene");
  }
  if (r == DTM_OK) {
    cli_outputs out;
    dtm_cli_output_names(s, o, "_refined", &out);
    r = dtm_cli_check_outputs(s, &out);
  }
  if (r == DTM_OK) r = dtm_cli_verified(s, o);
  if (r == DTM_OK) {
    if (o->verbosity) printf("dtmap %s: refining %s to %.4e s\n", DTM_VERSION, s->path, target);
    r = refine_scene(s, target, o);
  }
  dtm_scene_destroy(&s);
  return r ? dtm_cli_fail(r, o->verbosity) : 0;
}
