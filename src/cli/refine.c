/* `dtmap refine SCENE.xml [--target DT]`: remesh until the recommended step
 * reaches DT (default: the scene's <time target>) without raising the
 * cost, printing each round (what it was, its basis, elements, steps, how
 * far short, element-steps and their change, what was applied), then write
 * the kept mesh with all its views and the report (by default
 * SCENE_refined.msh, never run's SCENE_dt.msh), with the causes when the
 * mesh alone does not meet the target (each with the lines to paste into
 * the .geo where there are any), and the ways found: mesh only, mesh and
 * point masses, subcycling. On the global basis it says that a solver must
 * then run at that fixed step, beside the element bound an element-by-
 * element estimate of the solver's own would not exceed. Exit 1 when the
 * target is not met, also when Gmsh refused or crashed in a remesh (the
 * kept mesh is written). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/cost.h"
#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/refine.h"
#include "dtmap/scene.h"
#include "dtmap/units.h"

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

/* Gmsh's optimiser passes by name, in the order they run, and why one may
 * not run. */
static const struct {
  unsigned bit;
  const char *name, *why;
} optimisers[] = {
    {DTM_OPTIMISE_GMSH, "gmsh", "it optimises tetrahedra: 3D meshes only"},
    {DTM_OPTIMISE_NETGEN, "netgen", "Netgen is not built into this Gmsh (General.BuildOptions), or the mesh is not 3D"},
    {DTM_OPTIMISE_RELOCATE, "relocate", "2D and 3D meshes only"},
    {DTM_OPTIMISE_LAPLACE2D, "laplace", "it smooths 2D meshes only"}};

/* What was applied in a round: the calibration (the margin aimed past the
 * target), the transfinite counts set, the optimisers, the masses. */
static const char *applied_text(const dtm_refine_round *r, const char *units, char *buf, size_t len) {
  buf[0] = '\0';
  if (r->kind == DTM_ROUND_INPUT) return snprintf(buf, len, "input"), buf;
  if (r->kind == DTM_ROUND_MASS)
    return snprintf(buf, len, "+%.3g%% mass at %zu nodes", r->added_percent, r->mass_nodes), buf;
  if (r->strategy && strcmp(r->strategy, "field") && isfinite(r->uniform))
    snprintf(buf, len, "%s %.3g %s", r->strategy, r->uniform, dtm_units_name(units, DTM_UNIT_LENGTH));
  else if (r->strategy && strcmp(r->strategy, "field"))
    snprintf(buf, len, "%s x%.3f", r->strategy, r->calibration);
  else
    snprintf(buf, len, "x%.3f", r->calibration);
  if (r->counts) snprintf(buf + strlen(buf), len - strlen(buf), ", %d counts", r->counts);
  for (size_t k = 0; k < sizeof optimisers / sizeof optimisers[0]; k++)
    if (r->optimise & optimisers[k].bit) snprintf(buf + strlen(buf), len - strlen(buf), ", %s", optimisers[k].name);
  return buf;
}

/* --optimise passes asked for that ran in no remesh: said under the table
 * (a pass of another dimension, or one this Gmsh lacks, changes nothing). */
static void print_unused_optimisers(const dtm_refine_result *rr) {
  unsigned ran = 0, asked = rr->options.optimise & ~(unsigned)DTM_OPTIMISE_NONE;
  int remeshes = 0;
  for (int i = 1; i < rr->nrounds; i++)
    if (rr->rounds[i].kind == DTM_ROUND_MESH) ran |= rr->rounds[i].optimise, remeshes++;
  for (size_t k = 0; remeshes && k < sizeof optimisers / sizeof optimisers[0]; k++)
    if ((asked & optimisers[k].bit) && !(ran & optimisers[k].bit))
      printf("--optimise %s: changed nothing, it ran in no remesh (%s)\n", optimisers[k].name, optimisers[k].why);
}

/* x rounded to the one decimal printed, without a sign when that is 0. */
static double no_negative_zero(double x) { return fabs(x) < 0.05 ? 0.0 : x; }

/* How far short of the target a round is: "-" when it is not (never a
 * negative or negative-zero shortfall), "<0.1%" below what one decimal
 * shows. */
static const char *short_text(const dtm_refine_round *r, char *buf, size_t len) {
  if (!(r->gap > 0))
    snprintf(buf, len, "-");
  else if (r->gap < 5e-4)
    snprintf(buf, len, "<0.1%%");
  else
    snprintf(buf, len, "%.1f%%", 100.0 * r->gap);
  return buf;
}

/* Whether the scene has a measure other than the phase error (a cohesive
 * zone, a diffusion length), from the kept mesh: every round has the same
 * kinds, the scene's. */
static int other_measures(const dtm_refine_result *rr) {
  dtm_measures *m = NULL;
  int other = 1, pending = dtm_error_code() != DTM_OK; /* unknown: "no" stays "no" */
  if (rr->analysis && dtm_measures_compute(rr->analysis, rr->frequency, NULL, &m) == DTM_OK) {
    other = 0;
    for (int k = 0; k < m->n; k++) other |= m->m[k].kind != DTM_MEASURE_PHASE;
  } else if (!pending) {
    dtm_error_clear(); /* this figure's failure is no error of the command */
  }
  dtm_measures_destroy(&m);
  return other;
}

/* Whether the round's measures are inside their bands: "-" when nothing
 * was measured (no phase error, shells and beams having no dispersion
 * model, and no other measure): nothing to judge. */
static const char *band_text(const dtm_refine_round *r, int other) {
  if (r->in_band) return "yes";
  return isnan(r->phase_error) && !r->unresolved && !other ? "-" : "no";
}

static void print_round(const dtm_refine_result *rr, int i, int other) {
  const dtm_refine_round *r = &rr->rounds[i];
  double c = dtm_refine_cost(r), c0 = i ? dtm_refine_cost(&rr->rounds[i - 1]) : c;
  char ph[32], ap[96], sh[16];
  printf("%5d %-6s %10zu %12.4e %12.4e %9s %12.4e %+9.1f%% %9zu %9s %5s %9.2f  %s%s%s\n", i,
         r->basis && !strcmp(r->basis, "global estimate") ? "global"
         : r->basis && !strcmp(r->basis, "nodal bound")   ? "nodal"
                                                          : "elem.",
         r->elements, r->dt_min, r->recommended, short_text(r, sh, sizeof sh), c,
         no_negative_zero(100.0 * (c / c0 - 1.0)), r->below, phase_text(r, ph, sizeof ph), band_text(r, other),
         r->seconds, applied_text(r, rr->scene.units, ap, sizeof ap),
         r->recommended >= rr->target ? "  target met" : "", i == rr->best ? "  (kept)" : "");
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

/* On stderr (even with -q), a kept mesh that meets the target but costs
 * more element-steps than the input: what grew, and the cheaper ways to
 * try (the same target on the input with point masses, or subcycling). */
static void warn_dearer(const dtm_refine_result *rr) {
  const dtm_refine_round *r0 = &rr->rounds[0], *rb = &rr->rounds[rr->best];
  double c0 = dtm_refine_cost(r0), cb = dtm_refine_cost(rb);
  if (rr->best == 0 || !(cb > c0) || rb->recommended < rr->target) return;
  fprintf(stderr,
          "dtmap: warning: the kept mesh meets the target but costs x%.3f the input's element-steps: %.3gx the "
          "elements (%zu against %zu) at a %.3gx longer step; point masses on the input (--max-added-mass) or "
          "subcycling may cost less\n",
          cb / c0, (double)rb->elements / (double)r0->elements, rb->elements, r0->elements,
          rb->recommended / r0->recommended);
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
  printf("\n%5s %-6s %10s %12s %12s %9s %12s %10s %9s %9s %5s %9s  %s\n", "round", "basis", "elements", "elem. bound",
         "recommended", "short by", rate ? "elem-steps/s" : "element-steps", "change", "below", "phase", "band",
         "time (s)", "applied");
  int other = other_measures(rr);
  for (int i = 0; i < rr->nrounds; i++) print_round(rr, i, other);
  print_unused_optimisers(rr);
  if (rr->nrounds == 1 && rr->stop == DTM_REFINE_MET)
    printf("met by the input mesh as it is (%s): no remesh; it is written unchanged with its views\n",
           rr->rounds[0].basis);
  else if (rr->rounds[rr->best].recommended >= rr->target)
    printf("met: kept round %d\n", rr->best);
  else
    printf("stopped: %s; kept round %d\n", dtm_refine_stop_text(rr->stop), rr->best);
  if (rr->forced_by && rr->forced >= 0.5)
    printf("accuracy: the bound '%s' asks for about %.0f more elements than the input's sizes give (%.4g "
           "element-steps at the kept step)\n",
           rr->forced_by, rr->forced,
           rr->forced * dtm_refine_cost(&rr->rounds[rr->best]) / rr->rounds[rr->best].elements);
  print_causes(rr);
}

/* On the global basis: the solver must be told the step; an element-by-
 * element estimate of its own would sit near the element bound. */
static void print_basis_note(const dtm_refine_result *rr) {
  const dtm_refine_round *b = &rr->rounds[rr->best];
  if (!b->basis || strcmp(b->basis, "global estimate")) return;
  printf("basis: the global estimate; a solver must run at this step fixed (a deck that sets it: dtmap deck), not\n"
         "at its own element-by-element estimate, which is at most about the element bound x safety, %.4e s\n"
         "(%.2fx smaller)\n",
         rr->element_bound, b->recommended / rr->element_bound);
}

static const char *const cert_words[] = {"an estimate", "PROVEN", "too dear", "unavailable", "refuted", "PROBABLE"};

/* The way mesh + selective mass in the list of ways: its round, step and
 * cost (the kept mesh's element-steps at the scaled step, times the time
 * per step the mass solves take), or why there is none. */
static void print_selective_way(const dtm_refine_result *rr, double c0) {
  const dtm_refine_selective *w = &rr->selective;
  int short_of = rr->rounds[rr->best].kind != DTM_ROUND_MESH || rr->rounds[rr->best].recommended < rr->target;
  if (w->state == DTM_REFINE_SMS_DONE) {
    printf("  mesh + selective mass: round %d scaled, recommended %.4e s (%s), target %s, cost x%.3f of the input with "
           "the mass solves\n",
           w->round, w->sms.recommended, cert_words[w->sms.global.certified], w->sms.target_met ? "met" : "NOT met",
           dtm_refine_selective_cost(rr) / c0);
  } else if (w->state == DTM_REFINE_SMS_REFUSED) {
    printf("  mesh + selective mass: refused: %s%s\n", w->why, rr->options.modes ? " (--modes: nothing to price)" : "");
  } else if (w->state == DTM_REFINE_SMS_NOT_NEEDED) {
    printf("  mesh + selective mass: not needed (a mesh meets the target)%s\n",
           rr->options.modes ? "; --modes prices it only where no mesh does" : "");
  } else if (short_of && rr->rounds[0].recommended < rr->target) {
    printf("  mesh + selective mass: not tried (--selective-mass scales the kept mesh to the target, its translational "
           "mass unchanged)\n");
  }
}

/* One row of the comparison: a label and the two ways' texts. */
static void compare_row(const char *label, const char *mass, const char *sms) {
  printf("  %-15s %-52s %s\n", label, mass, sms);
}

/* mesh + mass against mesh + selective mass on the kept mesh, side by
 * side: the step and what vouches for it, the target, the added mass, the
 * time per step and the run time against the kept mesh at its own step;
 * then how to use the selective way. */
static void print_selective_compare(const dtm_refine_result *rr) {
  const dtm_refine_selective *w = &rr->selective;
  if (w->state != DTM_REFINE_SMS_DONE) return;
  const dtm_selective_mass *m = &w->sms;
  const dtm_sms_stats *st = &m->stats;
  const char *M = dtm_scene_mass_unit(&rr->scene, dtm_analysis_mesh(rr->analysis)->dim);
  char a[160], b[200];
  printf("\nmesh + mass against mesh + selective mass on the kept mesh (round %d, recommended step %.4e s without "
         "added mass), target %.4e s:\n",
         w->round, w->lumped, rr->target);
  compare_row("", "point masses (deck --target's rule)", "selective mass scaling");
  if (isfinite(w->conventional_percent)) /* NaN: no nodal bound */
    snprintf(a, sizeof a, "every nodal bound lifted to %.4e s", rr->target / rr->scene.safety);
  else
    snprintf(a, sizeof a, "no nodal bound: not computed");
  snprintf(b, sizeof b, "global %.4e s, %s (Lanczos %d steps)", m->global.dt, cert_words[m->global.certified],
           m->global.iterations);
  compare_row("step (undamped)", a, b);
  snprintf(a, sizeof a, "%s", isfinite(w->conventional_percent) ? "the target, met (by the rule's construction)" : "-");
  snprintf(b, sizeof b, "%.4e s = %.2f x global: target %s", m->recommended, rr->scene.safety,
           m->target_met ? "met" : "NOT met");
  compare_row("recommended", a, b);
  int conv = isfinite(w->conventional_percent);
  snprintf(a, sizeof a, "+%.4g %% of the model's mass (%.4g %s, %zu nodes)", w->conventional_percent,
           w->conventional_added, M, w->conventional_nodes);
  if (!conv) snprintf(a, sizeof a, "-");
  int n = snprintf(b, sizeof b, "trace(M_add)/trace(M)");
  for (int c = 0; c < st->ncomp && n > 0 && (size_t)n < sizeof b; c++)
    n += snprintf(b + n, sizeof b - (size_t)n, " %c %.3g %%", "xyz"[c], 100 * st -> trace_add[c] / st -> trace_mass[c]);
  compare_row("added mass", a, b);
  snprintf(a, sizeof a, "+%.4g %% (every rigid translation slower)", w->conventional_percent);
  if (!conv) snprintf(a, sizeof a, "-");
  snprintf(b, sizeof b, "%.6g %s, the model's %.6g %s: %s", st->translational, M, st->translational_m, M,
           fabs(st->translational - st->translational_m) <= 1e-9 * st->translational_m ? "unchanged" : "CHANGED");
  compare_row("translational", a, b);
  snprintf(a, sizeof a, "%s", "x1 (the mass stays diagonal)");
  snprintf(b, sizeof b, "x%.2f (%.1f CG iterations per mass solve, an M_s product %.2f K products)", m->runtime_factor,
           m->cg_iterations, m->product_ratio);
  compare_row("time per step", a, b);
  snprintf(a, sizeof a, "x%.3f of the kept mesh's at its own step", w->lumped / rr->target);
  if (!conv) snprintf(a, sizeof a, "-");
  snprintf(b, sizeof b, "x%.3f", m->runtime_factor * w->lumped / m->recommended);
  compare_row("run time", a, b);
  printf("  the selective mass is not written into the mesh (no view holds it): to run it, a scene with the kept mesh "
         "as its <mesh> and\n    dtmap deck SCENE.xml --solver calculix|lsdyna --target %.4e --selective-mass\n",
         rr->target);
  if (rr->rounds[rr->best].kind == DTM_ROUND_MASS)
    printf("  (the mesh written carries the point masses of mesh + mass; the selective figures are of the mesh "
           "without them)\n");
}

/* The ways found to reach the target, cheapest first among those that
 * do: the mesh alone, the mesh with point masses, subcycling on the kept
 * mesh (the ideal speed-up of its levels). */
static void print_ways(const dtm_refine_result *rr, const dtm_cost *cost) {
  int mesh = -1, mass = -1;
  for (int i = 1; i < rr->nrounds; i++) {
    const dtm_refine_round *r = &rr->rounds[i];
    int *slot = r->kind == DTM_ROUND_MASS ? &mass : &mesh;
    if (r->recommended >= rr->target && (*slot < 0 || dtm_refine_cost(r) < dtm_refine_cost(&rr->rounds[*slot])))
      *slot = i;
  }
  double c0 = dtm_refine_cost(&rr->rounds[0]);
  printf("ways:\n");
  if (mesh >= 0)
    printf("  mesh only:       round %d, %zu elements, cost x%.3f of the input\n", mesh, rr->rounds[mesh].elements,
           dtm_refine_cost(&rr->rounds[mesh]) / c0);
  else
    printf("  mesh only:       %s\n", rr->rounds[0].recommended >= rr->target ? "the input meets it" : "not found");
  if (mass >= 0)
    printf("  mesh + mass:     round %d, +%.3g %% of the mass at %zu nodes, cost x%.3f of the input\n", mass,
           rr->rounds[mass].added_percent, rr->rounds[mass].mass_nodes, dtm_refine_cost(&rr->rounds[mass]) / c0);
  else if (isfinite(rr->mass_needed))
    printf("  mesh + mass:     %s %.3g %% of the mass, above the %.3g %% allowed\n",
           rr->mass_least ? "needs at least (searched)" : "dtmap's mass rule adds", rr->mass_needed,
           rr->options.max_added_mass);
  else if (!(rr->options.max_added_mass > 0) && mesh < 0 && rr->rounds[0].recommended < rr->target)
    printf("  mesh + mass:     not tried (--max-added-mass P allows P %% of the model's mass at the nodes)\n");
  print_selective_way(rr, c0);
  if (cost && cost->subcycling.speedup > 1.0005)
    printf("  subcycling:      the kept mesh's levels, ideal speed-up %.2fx (cost x%.3f of the input)\n",
           cost->subcycling.speedup, dtm_refine_cost(&rr->rounds[rr->best]) / cost->subcycling.speedup / c0);
}

static int report_rounds(const dtm_refine_result *rr, const cli_opts *o) {
  dtm_cost *cost = NULL;
  DTM_CHECK(dtm_cost_create(rr->analysis, &cost));
  dtm_results res = {rr->analysis, cost, rr, 0.0, 0.0, dtm_cli_top(o), 0, {NULL}, {NULL}, rr->selective.modes, NULL};
  dtm_cli_warn_flagged(rr->analysis);
  if (o->verbosity) print_rounds(rr), print_basis_note(rr), print_ways(rr, cost), print_selective_compare(rr);
  print_accuracy_change(rr, o->verbosity);
  warn_dearer(rr);
  if (o->verbosity) printf("\n"), dtm_summary_print(&res, stdout);
  int r = dtm_cli_write_outputs(&res, o, "_refined", NULL);
  dtm_cost_destroy(&cost);
  return r;
}

/* The exit message of a target not met: the stop's cause (the causes'
 * list printed it already unless quiet). */
static int not_met(const dtm_refine_result *rr, int verbose) {
  double best = dtm_analysis_recommended(rr->analysis);
  const char *why = verbose       ? "the causes are above"
                    : rr->ncauses ? rr->causes[0].text
                                  : dtm_refine_stop_text(rr->stop);
  const dtm_refine_selective *w = &rr->selective;
  const char *sms = w->state == DTM_REFINE_SMS_DONE && w->sms.target_met
                        ? "; mesh + selective mass meets it (not written into the mesh: dtmap deck --selective-mass)"
                        : "";
  return DTM_ERR(DTM_ERR_TARGET, "refine: the target %.4e s was not met (best recommended step %.4e s): %s%s",
                 rr->target, best, why, sms);
}

/* The met line: by the mesh alone, or with point masses. */
static void print_met(const dtm_refine_result *rr) {
  const dtm_refine_round *b = &rr->rounds[rr->best];
  if (b->kind == DTM_ROUND_MASS)
    printf("met: mesh + %.3g %% added mass at %zu nodes (%.4g %s)\n", b->added_percent, b->mass_nodes, b->added_mass,
           dtm_scene_mass_unit(&rr->scene, dtm_analysis_mesh(rr->analysis)->dim));
}

static int refine_scene(const dtm_scene *s, const dtm_refine_options *ro, const cli_opts *o) {
  dtm_refine_result *rr = NULL;
  int r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0);
  if (r == DTM_OK) r = dtm_refine_run(s, ro, &rr);
  if (r == DTM_OK) r = report_rounds(rr, o);
  if (r == DTM_OK && dtm_analysis_recommended(rr->analysis) < ro->target) r = not_met(rr, o->verbosity);
  if (r == DTM_OK && o->verbosity) print_met(rr);
  dtm_refine_destroy(&rr);
  dtm_gmsh_stop();
  return r;
}

/* --optimise LIST into DTM_OPTIMISE_* bits; -1 for a word it does not know. */
static int optimise_bits(const char *list) {
  static const struct {
    const char *name;
    unsigned bit;
  } words[] = {{"gmsh", DTM_OPTIMISE_GMSH},
               {"netgen", DTM_OPTIMISE_NETGEN},
               {"relocate", DTM_OPTIMISE_RELOCATE},
               {"laplace", DTM_OPTIMISE_LAPLACE2D},
               {"none", DTM_OPTIMISE_NONE}};
  unsigned bits = 0;
  for (const char *p = list; *p;) {
    size_t len = strcspn(p, ","), k = 0;
    while (k < sizeof words / sizeof words[0] && (strlen(words[k].name) != len || strncmp(p, words[k].name, len))) k++;
    if (k == sizeof words / sizeof words[0]) return -1;
    bits |= words[k].bit, p += len + (p[len] == ',');
  }
  return (int)bits;
}

/* The refine options from the command line and the scene. */
static dtm_refine_options options_of(const dtm_scene *s, const cli_opts *o, double target) {
  dtm_refine_options ro = {0};
  ro.optimise = o->optimise ? (unsigned)optimise_bits(o->optimise) : 0;
  ro.target = target, ro.max_rounds = o->max_iter, ro.global = o->posterior || s->posterior;
  ro.tol = o->tol, ro.lanczos_max = o->lanczos_max, ro.keep_counts = o->keep_counts;
  ro.max_added_mass = isnan(o->max_added_mass) ? s->max_added_mass : o->max_added_mass;
  ro.selective_mass = o->selective_mass, ro.modes = o->modes;
  return ro;
}

int dtm_cli_refine(const cli_opts *o) {
  int f;
  if (dtm_cli_format(&dtm_cli_commands[2], o->format, &f)) return DTM_ERR_INPUT;
  if (o->threads > 0) omp_set_num_threads(o->threads);
  dtm_scene *s = NULL;
  int r = dtm_scene_load(o->scene, &s);
  double target = o->target > 0 ? o->target : s ? s->target : 0;
  if (o->optimise && optimise_bits(o->optimise) < 0) {
    dtm_scene_destroy(&s);
    return dtm_cli_usage_error(&dtm_cli_commands[2],
                               "--optimise takes gmsh, netgen, relocate, laplace or none, "
                               "separated by commas; got '%s'",
                               o->optimise);
  }
  if (o->modes && !o->selective_mass) {
    dtm_scene_destroy(&s);
    return dtm_cli_usage_error(&dtm_cli_commands[2], "--modes prices the selective mass way: give --selective-mass");
  }
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
    dtm_refine_options ro = options_of(s, o, target);
    if (o->verbosity)
      printf("dtmap %s: refining %s to %.4e s on the %s\n", DTM_VERSION, s->path, target,
             ro.global ? "global estimate" : "nodal bound");
    r = refine_scene(s, &ro, o);
  }
  dtm_scene_destroy(&s);
  return r ? dtm_cli_fail(r, o->verbosity) : 0;
}
