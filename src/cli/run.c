/* `dtmap run` and `dtmap verify`: analyse a scene, optionally estimate the
 * global step, then write the mesh with its views and the report, or
 * simulate the scene's effects at a step and judge stability. Also the
 * output step `refine` shares. With --solver-rule, each named solver's own
 * element steps (the rule its deck's header estimates with, src/deck/)
 * become a view "dt <solver>" and a line of the summary. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/deck.h"
#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "dtmap/parallel.h"
#include "dtmap/selective.h"
#include "dtmap/units.h"
#include "dtmap/util.h"
#include "dtmap/verify.h"

int dtm_cli_format(const cli_command *c, const char *word, int *out) {
  static const char *const names[] = {"auto", "ascii", "binary"}; /* DTM_MSH_* order */
  *out = DTM_MSH_AUTO;
  for (int i = 0; word && i < 3; i++)
    if (!strcmp(word, names[i])) return *out = i, DTM_OK;
  return word ? dtm_cli_usage_error(c, "--format '%s' is not ascii, binary or auto", word) : DTM_OK;
}

/* Begin the output mesh at out (write the mesh now, or start writing it
 * in the background, which then releases Gmsh's model); *seconds
 * accumulates. */
static int begin_output(const dtm_scene *s, const cli_opts *o, const char *out, size_t nel, int background,
                        dtm_output_file **f, double *seconds) {
  double t0 = dtm_wtime();
  dtm_output_opts oo = {DTM_MSH_AUTO, o->views_only, 0, background};
  dtm_cli_format(NULL, o->format, &oo.format); /* checked before the analysis */
  int r = dtm_output_begin(s, out, &oo, nel, f);
  *seconds += dtm_wtime() - t0;
  return r;
}

int dtm_cli_write_outputs(dtm_results *res, const cli_opts *o, const char *suffix, dtm_output_file **begun) {
  cli_outputs names;
  const dtm_scene *s = dtm_analysis_scene(res->analysis);
  dtm_cli_output_names(s, o, suffix, &names);
  const char *out = names.mesh, *rep = names.report[0] ? names.report : NULL;
  dtm_output_file *f = begun ? *begun : NULL;
  if (begun) *begun = NULL;
  if (!f) DTM_CHECK(begin_output(s, o, out, dtm_analysis_nelements(res->analysis), 0, &f, &res->t_output));
  double t0 = dtm_wtime();
  DTM_CHECK(dtm_output_finish(&f, res));
  res->t_output += dtm_wtime() - t0;
  if (rep) DTM_CHECK(dtm_report_write(res, rep));
  if (o->verbosity) printf("\nwrote        %s (+ .opt)%s%s\n", out, rep ? ", " : "", rep ? rep : "");
  if (o->verbosity && o->views_only) printf("             views only: gmsh %s %s\n", s->mesh, out);
  return DTM_OK;
}

/* verify's own summary: the mesh and the step it checks against, not the
 * whole of run's (run prints that). */
static void print_brief(const dtm_analysis *a) {
  const dtm_scene *s = dtm_analysis_scene(a);
  printf("mesh         %zu elements, %zu nodes\n", dtm_analysis_nelements(a), dtm_analysis_mesh(a)->nnodes);
  printf("recommended  %.4e s = %s %.2f x %.4e s (%s); dtmap run gives the whole summary\n",
         dtm_analysis_recommended(a),
         dtm_analysis_recommended_certified(a) ? "the probable bound's certified step, below safety" : "safety",
         s->safety, dtm_analysis_basis_step(a), dtm_analysis_basis(a));
}

static void print_verify(const dtm_analysis *a, double dt, int steps, const dtm_verify_effect *v) {
  printf("\nverify       %d steps of %.4e s (%.3fx the recommended step)\n", steps, dt,
         dt / dtm_analysis_recommended(a));
  printf("  growth: the largest energy norm over the run's second half / the norm at the start\n"
         "  (a few units when stable: the discrete energy is not exactly conserved; UNSTABLE above 1e6 or\n"
         "  not finite)\n");
  printf("  %-10s %-12s %-25s %-12s %s\n", "effect", "growth", "global dt bracket (s)", "time (s)", "verdict");
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    if (!v[k].simulated) continue;
    const dtm_global_info *g = dtm_analysis_global(a, k);
    printf("  %-10s %-12.4g [%.4e, %.4e] %-12.3f %s\n", dtm_analysis_effect(a, k)->name, v[k].growth, g->dt_low,
           g->dt_high, v[k].seconds, v[k].unstable ? "UNSTABLE" : "stable");
  }
}

/* The spec of --accuracy: branch, direction (normalised), frequency. */
static int wave_spec(const dtm_analysis *a, const cli_opts *o, dtm_wave_spec *w) {
  *w = (dtm_wave_spec){o->freq, {1, 0, 0}, 0, o->periods, !(o->freq > 0)};
  if (o->wave && (strcmp(o->wave, "P") && strcmp(o->wave, "S")))
    return DTM_ERR(DTM_ERR_INPUT, "verify --wave: expected P or S, got '%s'", o->wave);
  w->mode = o->wave && !strcmp(o->wave, "S");
  double *d = w->dir, len;
  char end = 0;
  if (o->direction && sscanf(o->direction, "%lf,%lf,%lf%c", d, d + 1, d + 2, &end) != 3)
    return DTM_ERR(DTM_ERR_INPUT, "verify --direction: expected X,Y,Z, got '%s'", o->direction);
  len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(len > 0) || !isfinite(len) || (dtm_analysis_mesh(a)->dim < 3 && d[2] != 0))
    return DTM_ERR(DTM_ERR_INPUT, "verify --direction: '%s' is not a direction (in the plane for a 2D mesh)",
                   o->direction);
  for (int c = 0; c < 3; c++) d[c] /= len;
  if (w->f > 0) return DTM_OK;
  dtm_measures *m = NULL;
  DTM_CHECK(dtm_measures_compute(a, 0, NULL, &m));
  for (int k = 0; k < m->n; k++)
    if (m->m[k].kind == DTM_MEASURE_PHASE) w->f = m->m[k].f;
  dtm_measures_destroy(&m);
  if (!(w->f > 0))
    return DTM_ERR(DTM_ERR_INPUT, "verify --accuracy: no frequency: the scene has no <time f-max> and no element "
                                  "has a dispersion model to take a default from; give --freq");
  return DTM_OK;
}

static void print_wave(const dtm_analysis *a, double dt, const dtm_wave_spec *w, const dtm_wave_result *r) {
  printf("\naccuracy     %s wave along (%.3g, %.3g, %.3g) at %.4g Hz, %d steps of %.4e s (%.3fx the recommended)\n",
         w->mode ? "S" : "P", r->dir[0], r->dir[1], r->dir[2], r->f, r->steps, dt, dt / dtm_analysis_recommended(a));
  if (r->periodic)
    printf("  a periodic sample: opposite faces joined, the whole wave fitted to the box (asked: %.4g Hz)\n", w->f);
  else if (r->f != w->f)
    printf("  the default %.4g Hz raised to %.4g Hz: the lowest at which a packet runs 3 periods in the mesh\n", w->f,
           r->f);
  const char *units = dtm_analysis_scene(a)->units, *L = dtm_units_name(units, DTM_UNIT_LENGTH);
  printf("  host material %s: c = %.1f %s, wavelength %.4g %s, window %.3g %s, %.2f periods, %d zero crossings, "
         "%.2f s\n",
         dtm_analysis_scene(a)->materials[r->material].m.name, r->speed, dtm_units_name(units, DTM_UNIT_SPEED),
         2 * 3.14159265358979323846 / r->k, L, r->sigma, L,
         r->duration * r->speed * r->k / (2 * 3.14159265358979323846), r->crossings, r->seconds);
  printf("  phase-speed error: measured %+.4f %%, predicted %+.4f %% (%s, mean over %zu elements; this wave's worst "
         "element alone %+.4f %%)\n",
         100 * r->measured, 100 * r->predicted.mean, dtm_dispersion_model_name(r->predicted.model),
         r->predicted.elements, 100 * r->predicted.worst);
  if (r->mesh.kind == DTM_MEASURE_PHASE && !r->mesh.unresolved && isfinite(r->mesh.worst)) {
    char line[256];
    dtm_summary_phase_worst(&r->mesh, line, sizeof line);
    printf("  the mesh as run gives it (P and S, every direction, at the recommended step and %.4g Hz): %s\n",
           r->mesh.f, line);
  }
  printf("  from the zero crossings: %+.4f %%\n", 100 * (r->omega_crossings / (r->speed * r->k) - 1));
  printf("  agreement: %+.1f %% of the prediction (band 20 %%): %s\n", 100 * r->agreement,
         fabs(r->agreement) <= 0.2 ? "agrees" : "DISAGREES");
}

static int accuracy_step(const dtm_analysis *a, const cli_opts *o, double dt) {
  dtm_wave_spec w;
  dtm_wave_result r;
  DTM_CHECK(wave_spec(a, o, &w));
  DTM_CHECK(dtm_verify_wave(a, dt, &w, &r));
  if (o->verbosity) print_wave(a, dt, &w, &r);
  if (o->report) DTM_CHECK(dtm_verify_wave_report_write(a, dt, &w, &r, o->report));
  if (o->report && o->verbosity) printf("\nwrote        %s\n", o->report);
  if (!(fabs(r.agreement) <= 0.2))
    return DTM_ERR(DTM_ERR_TARGET, "verify --accuracy: measured %+.4f %% against predicted %+.4f %%", 100 * r.measured,
                   100 * r.predicted.mean);
  return DTM_OK;
}

static int verify_step(const dtm_analysis *a, const cli_opts *o) {
  if (o->accuracy)
    return accuracy_step(a, o, o->dt > 0 ? o->dt : (o->factor > 0 ? o->factor : 1.0) * dtm_analysis_recommended(a));
  double dt = o->dt > 0 ? o->dt : (o->factor > 0 ? o->factor : 1.0) * dtm_analysis_recommended(a);
  dtm_verify_effect *v = calloc((size_t)dtm_analysis_neffects(a) + 1, sizeof *v);
  if (!v) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = dtm_verify(a, dt, o->steps, v), unstable = 0;
  if (r == DTM_OK && o->verbosity) print_verify(a, dt, o->steps, v);
  dtm_verify_report vr = {dt, dt / dtm_analysis_recommended(a), o->steps, v};
  if (r == DTM_OK && o->report) r = dtm_verify_report_write(a, &vr, o->report);
  if (r == DTM_OK && o->report && o->verbosity) printf("\nwrote        %s\n", o->report);
  for (int k = 0; k < dtm_analysis_neffects(a) && r == DTM_OK; k++) unstable |= v[k].unstable;
  free(v);
  if (r == DTM_OK && unstable) r = DTM_ERR(DTM_ERR_TARGET, "verify: the step %.4e s is unstable", dt);
  return r;
}

/* verify --selective-mass: the scaled model at --dt, --factor x its
 * global step, or the target. */
static int sms_verify_step(const dtm_analysis *a, const cli_opts *o, const dtm_selective_mass *m) {
  dtm_verify_result vr;
  double cg = NAN, dt = o->dt > 0 ? o->dt : o->factor > 0 ? o->factor * m->global.dt : m->target;
  DTM_CHECK(dtm_analysis_selective_verify(a, m, dt, o->steps, &vr, &cg));
  if (o->verbosity) {
    const char *how = m->global.certified == DTM_CERT_PROVEN     ? "proven"
                      : m->global.certified == DTM_CERT_PROBABLE ? "probable"
                                                                 : "an estimate";
    printf("\nverify       selective mass scaling: %d steps of %.4e s = %.4fx the scaled model's global step %.4e s "
           "(%s; the target %.4e s)\n",
           vr.steps, dt, dt / m->global.dt, m->global.dt, how, m->target);
    printf("  central differences on (K, M_s), undamped, %.1f CG iterations per step; growth (largest energy norm "
           "over the second half / the start) %.4g: %s, %.2f s\n",
           cg, vr.growth, vr.unstable ? "UNSTABLE" : "stable", vr.seconds);
  }
  return vr.unstable ? DTM_ERR(DTM_ERR_TARGET, "verify: the step %.4e s is unstable for the scaled model", dt) : DTM_OK;
}

/* The global estimate: verify needs its modes; only --posterior lets a
 * converged one become the basis, so that verify checks exactly the step
 * run reports. */
static unsigned global_flags(const cli_opts *o, int verify) {
  return (verify ? DTM_GLOBAL_MODES : 0u) | (o->posterior ? DTM_GLOBAL_BASIS : 0u);
}

/* ---- --solver-rule ---- */

#define MAX_RULES 8 /* solvers in one --solver-rule list (each once) */

typedef struct {
  int n;                           /* solvers */
  char names[MAX_RULES][16];       /* their names, in the list's order */
  dtm_deck_steps steps[MAX_RULES]; /* their element steps */
} solver_rules;

/* The solvers of LIST (comma-separated names, each once) into sr; 0, or
 * a message into why[len]. */
static int rule_names(const char *list, solver_rules *sr, char *why, size_t len) {
  sr->n = 0;
  for (const char *p = list;;) {
    size_t k = strcspn(p, ",");
    char name[16];
    snprintf(name, sizeof name, "%.*s", (int)(k < sizeof name ? k : sizeof name - 1), p);
    if (!k || k >= sizeof name || dtm_deck_solver(name, NULL)) {
      const char *near = k && k < sizeof name ? dtm_deck_solver_near(name) : NULL;
      dtm_error_clear();
      return snprintf(why, len, "--solver-rule '%s': '%.*s' is not a solver%s%s%s; the solvers are: %s", list, (int)k,
                      p, near ? " (did you mean " : "", near ? near : "", near ? "?)" : "", dtm_deck_solvers()),
             1;
    }
    for (int i = 0; i < sr->n; i++)
      if (!strcmp(sr->names[i], name))
        return snprintf(why, len, "--solver-rule '%s': %s is named twice", list, name), 1;
    if (sr->n == MAX_RULES) return snprintf(why, len, "--solver-rule '%s': more than %d solvers", list, MAX_RULES), 1;
    memcpy(sr->names[sr->n++], name, sizeof name);
    if (!p[k]) return 0;
    p += k + 1;
  }
}

/* Each solver's element steps on analysis a. */
static int rule_steps(const dtm_analysis *a, const char *list, solver_rules *sr) {
  char why[512];
  if (!list) return DTM_OK;
  if (rule_names(list, sr, why, sizeof why)) return DTM_ERR(DTM_ERR_INPUT, "%s", why);
  for (int i = 0; i < sr->n; i++) DTM_CHECK(dtm_deck_own_steps(a, sr->names[i], &sr->steps[i]));
  return DTM_OK;
}

static void rules_free(solver_rules *sr) {
  for (int i = 0; i < sr->n; i++) dtm_deck_steps_free(&sr->steps[i]);
}

/* The summary's lines: each solver's smallest step, where it is, and how
 * it compares with dtmap's smallest element step. */
static void print_rules(const dtm_analysis *a, const solver_rules *sr) {
  if (!sr->n) return;
  double dmin = dtm_analysis_dt_min(a, NULL);
  printf("\nsolver rules each solver's own element step (its deck's estimate), views 'dt <solver>'\n");
  for (int i = 0; i < sr->n; i++) {
    const dtm_deck_steps *st = &sr->steps[i];
    if (isnan(st->min)) {
      printf("  %-9s its rule covers none of these elements\n", st->solver);
      continue;
    }
    printf("  %-9s smallest %.10g s (%.3fx dtmap's %.4g s): element %zu at (%.6g, %.6g, %.6g) m\n", st->solver, st->min,
           st->min / dmin, dmin, st->element, st->centroid[0], st->centroid[1], st->centroid[2]);
  }
  printf("\nsolver runs  the step each solver takes with dtmap's deck, and the hours of the scene's duration\n");
  for (int i = 0; i < sr->n; i++) dtm_cli_print_solver_run(sr->steps[i].solver, &sr->steps[i].run);
}

/* The output of `run`, begun as soon as the mesh is extracted: Gmsh writes
 * the mesh on a thread of its own while the analysis computes (the one call
 * into Gmsh below, the layers' gap, answers NaN meanwhile:
 * dtm_gmsh_model_given), then releases its copy of the model, so the two
 * copies of a large mesh live only as long as that write. */
typedef struct {
  const dtm_scene *s;    /* the scene */
  const cli_opts *o;     /* the options */
  dtm_output_file *file; /* the output being written, or NULL */
  double seconds;        /* time spent writing, s */
} early_output;

static int write_early(void *user, size_t nelements) {
  early_output *e = user;
  cli_outputs names;
  dtm_cli_output_names(e->s, e->o, NULL, &names);
  return begin_output(e->s, e->o, names.mesh, nelements, 1, &e->file, &e->seconds);
}

/* ---- --modes ---- */

/* --selective-mass: the target of --target, else the scene's. */
static double sms_target(const dtm_scene *s, const cli_opts *o) { return o->target > 0 ? o->target : s->target; }

/* The natural frequencies of the model and, with a target (--target, or
 * --selective-mass's), those under the conventional point masses reaching
 * it (deck --target's); the selective variant is added after the scaled
 * model is made. */
static int modes_step(const dtm_analysis *a, const cli_opts *o, dtm_modes_price *p) {
  DTM_CHECK(dtm_modes_price_base(a, o->modes, p));
  double target = o->target > 0 || o->selective_mass ? sms_target(dtm_analysis_scene(a), o) : 0;
  if (target > 0) DTM_CHECK(dtm_modes_price_conventional(a, target, p));
  return DTM_OK;
}

static int selective(const dtm_analysis *a, const cli_opts *o, dtm_selective_mass *sms) {
  return dtm_analysis_selective_mass(a, sms_target(dtm_analysis_scene(a), o), o->tol, o->lanczos_max, sms);
}

/* What --selective-mass needs of the scene, before any work. */
static int sms_check(const dtm_scene *s, const cli_opts *o) {
  if (!o->selective_mass) return DTM_OK;
  if (!(sms_target(s, o) > 0))
    return DTM_ERR(DTM_ERR_INPUT, "%s: --selective-mass needs a target step: give --target DT or <time target>",
                   s->path);
  if (dtm_parallel_wanted(s))
    return DTM_ERR(DTM_ERR_INPUT, "%s: --selective-mass runs on one whole mesh, without mpirun or partition files",
                   s->path);
  return DTM_OK;
}

/* Analyse, then summarise and either write the outputs or verify. */
static int analyse(const dtm_scene *s, const cli_opts *o, double t_scene, int verify) {
  dtm_analysis *a = NULL;
  dtm_cost *cost = NULL;
  early_output early = {s, o, NULL, 0.0};
  solver_rules rules = {0};
  dtm_modes_price price = {0};
  dtm_selective_mass sms;
  int r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0);
  if (r == DTM_OK) r = dtm_analysis_run_ex(s, verify ? NULL : write_early, &early, &a);
  if (r == DTM_OK) dtm_cli_warn_flagged(a);
  if (r == DTM_OK) dtm_cli_warn_curved(a);
  if (r == DTM_OK && (!o->verbosity || verify)) dtm_cli_warn_units(a); /* else in run's summary */
  if (r == DTM_OK) dtm_analysis_set_lanczos_seed(a, (unsigned)o->seed);
  if (r == DTM_OK && o->modes && !verify) r = modes_step(a, o, &price);
  if (r == DTM_OK && (o->posterior || (verify && !o->accuracy && !o->selective_mass)))
    r = dtm_analysis_estimate_global(a, o->tol, o->lanczos_max, global_flags(o, verify));
  if (r == DTM_OK) r = dtm_cost_create(a, &cost);
  if (r == DTM_OK && o->selective_mass) r = selective(a, o, &sms);
  if (r == DTM_OK && o->selective_mass && o->modes && !verify) r = dtm_modes_price_selective(a, &sms, &price);
  if (r == DTM_OK && !verify) r = rule_steps(a, o->solver_rule, &rules);
  if (r == DTM_OK && rules.n && !early.file) r = write_early(&early, dtm_analysis_nelements(a));
  if (r == DTM_OK) {
    dtm_results res = {a,
                       cost,
                       NULL,
                       t_scene,
                       early.seconds,
                       dtm_cli_top(o),
                       rules.n,
                       {NULL},
                       {NULL},
                       o->modes && !verify ? &price : NULL,
                       NULL};
    for (int i = 0; i < rules.n; i++) res.solver_names[i] = rules.names[i], res.solver_runs[i] = &rules.steps[i].run;
    res.selective_mass = o->selective_mass ? &sms : NULL;
    if (o->verbosity && verify)
      print_brief(a);
    else if (o->verbosity)
      dtm_summary_print(&res, stdout);
    if (o->verbosity) print_rules(a, &rules);
    if (rules.n) dtm_output_solver_steps(early.file, rules.steps, rules.n);
    if (verify && o->selective_mass)
      r = sms_verify_step(a, o, &sms);
    else
      r = verify ? verify_step(a, o) : dtm_cli_write_outputs(&res, o, NULL, &early.file);
  }
  dtm_output_abort(&early.file); /* after a failure: no partial output */
  rules_free(&rules);
  dtm_modes_price_free(&price);
  dtm_cost_destroy(&cost);
  dtm_analysis_destroy(&a);
  dtm_gmsh_stop();
  return r;
}

/* mpirun -n P dtmap run, or a scene of partition files: every rank runs
 * this; the rank where an error arose has it pending and prints it. */
static int run_parallel(const dtm_scene *s, const cli_opts *o, double t_scene) {
  cli_outputs names;
  if (o->png)
    return DTM_ERR(DTM_ERR_INPUT, "%s: --png draws one output mesh; a distributed run writes one per part", s->path);
  if (o->solver_rule)
    return DTM_ERR(DTM_ERR_INPUT, "%s: --solver-rule runs on one whole mesh, without mpirun or partition files",
                   s->path);
  if (o->modes)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s: --modes factors the whole model: one whole mesh, without mpirun or partition "
                   "files",
                   s->path);
  dtm_cli_output_names(s, o, NULL, &names);
  dtm_parallel_opts po = {.out = names.mesh,
                          .report = names.report[0] ? names.report : NULL,
                          .posterior = o->posterior,
                          .tol = o->tol,
                          .max_products = o->lanczos_max,
                          .threads = o->threads,
                          .verbosity = o->verbosity,
                          .t_scene = t_scene,
                          .views_only = o->views_only,
                          .top = dtm_cli_top(o)};
  dtm_cli_format(NULL, o->format, &po.format); /* checked before */
  return dtm_parallel_run(s, &po);
}

static int run_scene(const cli_opts *given, int verify) {
  if (given->threads > 0) omp_set_num_threads(given->threads);
  dtm_scene *s = NULL;
  cli_outputs out;
  cli_opts scene_opts = *given, *o = &scene_opts;
  double t0 = dtm_wtime();
  int r = dtm_scene_load(o->scene, &s);
  if (r == DTM_OK) o->posterior |= s->posterior; /* <time posterior="true"> */
  if (r == DTM_OK) dtm_cli_output_names(s, o, NULL, &out);
  if (r == DTM_OK && !verify) r = dtm_cli_verified(s, o);
  if (r == DTM_OK && !verify) r = dtm_cli_check_outputs(s, &out);
  if (r == DTM_OK) r = sms_check(s, o);
  if (r == DTM_OK && verify && o->report) r = dtm_output_path_check(s, o->report, NULL, "--report");
  if (r == DTM_OK && dtm_parallel_wanted(s))
    r = verify ? DTM_ERR(DTM_ERR_INPUT, "%s: dtmap verify runs on one whole mesh, without mpirun", s->path)
               : run_parallel(s, o, dtm_wtime() - t0);
  else if (r == DTM_OK) {
    if (o->verbosity) printf("dtmap %s: %s\n", DTM_VERSION, s->path);
    r = analyse(s, o, dtm_wtime() - t0, verify);
  }
  if (r == DTM_OK && o->png && !dtm_parallel_wanted(s))
    r = dtm_cli_pictures(out.mesh, o->png, o->width, o->height, o->verbosity);
  dtm_scene_destroy(&s);
  r = r && dtm_error_code() ? dtm_cli_fail(r, o->verbosity) : r;
  dtm_parallel_finish(); /* after the error is printed: no rank leaves before */
  return r;
}

int dtm_cli_run(const cli_opts *o) {
  int f;
  if (dtm_cli_format(&dtm_cli_commands[0], o->format, &f)) return DTM_ERR_INPUT;
  if (o->png && o->views_only)
    return dtm_cli_usage_error(&dtm_cli_commands[0], "--png draws the output mesh, which --views-only leaves out");
  if (o->target > 0 && !o->modes && !o->selective_mass)
    return dtm_cli_usage_error(&dtm_cli_commands[0], "--target is the step of --selective-mass or of --modes' "
                                                     "conventional mass; give one of them");
  solver_rules names;
  char why[512];
  if (o->solver_rule && rule_names(o->solver_rule, &names, why, sizeof why))
    return dtm_cli_usage_error(&dtm_cli_commands[0], "%s", why);
  return run_scene(o, 0);
}
int dtm_cli_verify(const cli_opts *o) {
  if (o->factor > 0 && o->dt > 0)
    return dtm_cli_usage_error(&dtm_cli_commands[1], "--factor and --dt both give the step; give one");
  if (!o->accuracy && (o->wave || o->direction || o->freq > 0 || o->periods > 0))
    return dtm_cli_usage_error(&dtm_cli_commands[1], "--wave, --direction, --freq and --periods need --accuracy");
  if (o->target > 0 && !o->selective_mass)
    return dtm_cli_usage_error(&dtm_cli_commands[1], "--target is the target of --selective-mass; give both");
  if (o->selective_mass && (o->accuracy || o->report || o->posterior))
    return dtm_cli_usage_error(&dtm_cli_commands[1], "--selective-mass checks the scaled model's stability alone: "
                                                     "without --accuracy, --report or --posterior");
  return run_scene(o, 1);
}
