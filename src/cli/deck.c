/* `dtmap deck SCENE.xml --solver S`: analyse the scene as run does (its
 * geometry meshed, or its mesh read; with --posterior the global estimate
 * as the basis), then write the solver's input deck (src/deck/) and, with
 * --report, the run's report with the deck's object. The solver is checked
 * first (exit 2 listing the solvers), the output paths before any work
 * (never an input of the scene; the deck and the report distinct), and the
 * deck is written atomically: a failure leaves an older deck whole. With
 * --target the scene's target is that step, and the deck adds the mass it
 * needs at the nodes; --max-added-mass P makes a need above P % of the
 * model's mass exit 1 with the figures, writing nothing. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/deck.h"
#include "dtmap/gmsh.h"
#include "dtmap/util.h"

static const cli_command *command(void) {
  const cli_command *c = dtm_cli_commands;
  while (strcmp(c->name, "deck")) c++;
  return c;
}

/* Usage: the solver, and --max-added-mass only with a target. */
static int check_usage(const cli_opts *o, const char **ext) {
  if (!o->solver) return dtm_cli_usage_error(command(), "needs --solver (%s)", dtm_deck_solvers());
  if (dtm_deck_solver(o->solver, ext)) return dtm_cli_usage_error(command(), "%s", dtm_error_message());
  if (o->lsdyna_step && strcmp(o->lsdyna_step, "conventional") && strcmp(o->lsdyna_step, "proven"))
    return dtm_cli_usage_error(command(), "--lsdyna-step '%s' is neither conventional nor proven", o->lsdyna_step);
  if (o->lsdyna_step && strcmp(o->solver, "lsdyna"))
    return dtm_cli_usage_error(command(), "--lsdyna-step is for --solver lsdyna, not %s", o->solver);
  if (o->selective_mass && !(o->target > 0))
    return dtm_cli_usage_error(command(), "--selective-mass scales the mass to reach a step: give --target DT");
  if (o->selective_mass && o->lsdyna_step && !strcmp(o->lsdyna_step, "proven"))
    return dtm_cli_usage_error(command(),
                               "--selective-mass takes LS-DYNA's own scaling (DT2MS < 0 with IMSCL); --lsdyna-step "
                               "proven writes dtmap's masses at the nodes instead: choose one");
  if (!isnan(o->max_added_mass) && !(o->target > 0))
    return dtm_cli_usage_error(command(), "--max-added-mass limits the mass --target DT needs: give --target");
  return DTM_OK;
}

/* The deck's path (-o, else SCENE_<solver><ext> here) and the report's,
 * checked before any work. */
static int outputs(const dtm_scene *s, const cli_opts *o, const char *ext, char *deck, size_t len) {
  char tail[64];
  snprintf(tail, sizeof tail, "_%s%s", o->solver, ext);
  if (o->out)
    snprintf(deck, len, "%s", o->out);
  else
    dtm_cli_default_out(s->path, tail, deck, len);
  DTM_CHECK(dtm_output_path_check(s, deck, NULL, o->out ? "-o" : "default output"));
  if (!o->report) return DTM_OK;
  DTM_CHECK(dtm_output_path_check(s, o->report, NULL, "--report"));
  if (!strcmp(o->report, deck))
    return DTM_ERR(DTM_ERR_INPUT, "-o %s and --report %s: two outputs with one name", deck, o->report);
  return DTM_OK;
}

/* The summary's lines on --selective-mass. */
static void print_selective(const dtm_deck_info *d, const char *M) {
  char beta[64] = "";
  printf("  selective  %s\n", d->sms_note);
  if (!d->sms_solver || !(d->sms_elements > 0)) return;
  if (!isnan(d->sms_beta_max)) snprintf(beta, sizeof beta, ", beta up to %.6g", d->sms_beta_max);
  printf("             predicted by its rule: %.6g %s at %zu elements%s (%.3g %% of the model's %.6g %s; its "
         "translational mass unchanged)\n",
         d->sms_added, M, d->sms_elements, beta, 100 * d->sms_added / d->model_mass, d->model_mass, M);
}

static void print_deck(const dtm_deck_info *d, const char *M) {
  printf("\ndeck         %s (%s): %zu nodes, %zu elements, %d element sets, %d node sets, %.2f s\n", d->path, d->title,
         d->nodes, d->elements, d->element_sets, d->node_sets, d->seconds);
  printf("  step       %.6e s, %s (dtmap's recommended step %.6e s)\n", d->step, d->basis, d->recommended);
  if (!isnan(d->own))
    printf("  %s's own estimate %.6e s (element %zu): the step is %.3fx it\n", d->title, d->own, d->own_element,
           d->step / d->own);
  if (isfinite(d->tssfac) && isfinite(d->dt2ms))
    printf("  TSSFAC     %.6g, DT2MS %.6g s (TSSFAC x |DT2MS| = the step): LS-DYNA adds %.6g %s at %zu elements "
           "(%.3g %% of the model's %.6g %s) by its rule\n",
           d->tssfac, d->dt2ms, d->solver_added, M, d->solver_added_elements, 100 * d->solver_added / d->model_mass,
           d->model_mass, M);
  else if (isfinite(d->tssfac))
    printf("  TSSFAC     %.6g (LS-DYNA's estimate x TSSFAC = the step)%s\n", d->tssfac,
           d->tssfac > 0.9 ? ": above 0.9 (--lsdyna-step proven)" : "");
  if (d->added > 0)
    printf("  added mass %.6g %s at %zu nodes (%.3g %% of the model's %.6g %s)\n", d->added, M, d->added_nodes,
           100 * d->added / d->model_mass, d->model_mass, M);
  if (d->selective) print_selective(d, M);
  printf("  the run    the step %s takes with this deck, and the hours of the scene's duration:\n", d->title);
  dtm_cli_print_solver_run(d->solver, &d->run);
  for (int i = 0; i < d->nwarnings; i++) fprintf(stderr, "dtmap: warning: %s\n", d->warnings[i]);
}

void dtm_cli_print_solver_run(const char *solver, const dtm_solver_run *r) {
  printf("  %-9s step %.4e s (%s): ", solver, r->step, r->basis);
  if (isnan(r->element_steps))
    printf("no <time duration>, no hours\n");
  else if (isnan(r->cost))
    printf("%.4g element-steps; hours %s\n", r->element_steps, r->cost_source);
  else
    printf("%.4g element-steps x %.4g ns = %.4g h (%s)\n", r->element_steps, 1e9 * r->cost, r->hours, r->cost_source);
}

/* Analyse, write the deck, then the report. */
static int analyse(const dtm_scene *s, const cli_opts *o, const char *path, double t_scene) {
  dtm_analysis *a = NULL;
  dtm_cost *cost = NULL;
  dtm_deck_info info;
  dtm_deck_opts dop = {o->solver,
                       path,
                       o->target,
                       isnan(o->max_added_mass) ? s->max_added_mass : o->max_added_mass,
                       o->lsdyna_step && !strcmp(o->lsdyna_step, "proven"),
                       o->selective_mass};
  int r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0);
  if (r == DTM_OK) r = dtm_analysis_run(s, &a);
  if (r == DTM_OK) dtm_cli_warn_flagged(a), dtm_cli_warn_curved(a), dtm_cli_warn_units(a);
  if (r == DTM_OK) dtm_analysis_set_lanczos_seed(a, (unsigned)o->seed);
  if (r == DTM_OK && (o->posterior || s->posterior))
    r = dtm_analysis_estimate_global(a, o->tol, o->lanczos_max, DTM_GLOBAL_BASIS);
  if (r == DTM_OK) r = dtm_cost_create(a, &cost);
  if (r == DTM_OK) r = dtm_deck_write(a, &dop, &info);
  if (r == DTM_OK && o->verbosity) print_deck(&info, dtm_scene_mass_unit(s, dtm_analysis_mesh(a)->dim));
  dtm_results res = {
      a,           cost, NULL, t_scene, r == DTM_OK ? info.seconds : 0.0, dtm_cli_top(o), 1, {info.solver},
      {&info.run}, NULL, NULL};
  if (r == DTM_OK && o->report) r = dtm_report_write_deck(&res, &info, o->report);
  if (r == DTM_OK && o->verbosity)
    printf("\nwrote        %s%s%s\n", path, o->report ? ", " : "", o->report ? o->report : "");
  dtm_cost_destroy(&cost);
  dtm_analysis_destroy(&a);
  dtm_gmsh_stop();
  return r;
}

int dtm_cli_deck(const cli_opts *o) {
  const char *ext = NULL;
  char path[4096], note[512];
  int r = check_usage(o, &ext);
  if (r) return r;
  if (o->threads > 0) omp_set_num_threads(o->threads);
  dtm_scene *s = NULL;
  double t0 = dtm_wtime();
  r = dtm_scene_load(o->scene, &s);
  if (r == DTM_OK && o->target > 0) s->target = o->target;
  if (r == DTM_OK) r = outputs(s, o, ext, path, sizeof path);
  if (r == DTM_OK) r = dtm_deck_adapt(s, o->solver, note, sizeof note);
  if (r == DTM_OK && o->verbosity) printf("dtmap %s: %s deck of %s\n", DTM_VERSION, o->solver, s->path);
  if (r == DTM_OK && o->verbosity > 1 && note[0]) printf("  %s\n", note);
  if (r == DTM_OK) r = analyse(s, o, path, dtm_wtime() - t0);
  dtm_scene_destroy(&s);
  return r ? dtm_cli_fail(r, o->verbosity) : 0;
}
