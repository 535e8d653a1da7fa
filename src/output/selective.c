/* What `run --selective-mass` adds to the summary and to the report
 * (include/dtmap/selective.h): the scaled model's global step and what
 * vouches for it, whether the target is met, the elements scaled, the
 * added mass beside the translational mass it leaves exact, and the
 * solver's cost of the mass solves. The summary is in the scene's units
 * with their names; the report's masses and centroid are converted to SI
 * by report_units.c like every other field (keys named there). */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "output-impl.h"
#include "report.h"

static const char *const cert_names[] = {"none", "proven", "too dear", "unavailable", "refuted", "probable"};

static const char *vouch(const dtm_sms_global *g) {
  switch (g->certified) {
  case DTM_CERT_PROVEN: return "PROVEN (sigma M_s - K factored positive definite: every eigenvalue below)";
  case DTM_CERT_PROBABLE: return "PROBABLE (Kuczynski-Wozniakowski bound, failure probability 1e-12)";
  case DTM_CERT_REFUTED: return "an ESTIMATE (the factorisation refuted every bound tried: not converged)";
  default: return "an ESTIMATE (no bound could be made)";
  }
}

static void print_step(const dtm_analysis *a, const dtm_selective_mass *m, FILE *f) {
  const dtm_sms_global *g = &m->global;
  double safety = dtm_analysis_scene(a)->safety, lumped = dtm_analysis_recommended(a);
  fprintf(f,
          "\nselective mass scaling at the target %.4e s (recommended step; elements scaled to their own undamped "
          "step %.4e s = target / safety %.2f)\n",
          m->target, m->element_target, safety);
  fprintf(f, "  scaled model global step %.4e s (undamped), %s; Lanczos on (K, M_s) %d steps, residual %.2g relative\n",
          g->dt, vouch(g), g->iterations, g->residual / g->theta);
  fprintf(f,
          "  recommended  %.2f x %.4e s = %.4e s against the target %.4e s: target %s (the lumped model's "
          "recommended step: %.4e s)\n",
          safety, g->dt, m->recommended, m->target, m->target_met ? "MET" : "NOT MET", lumped);
}

static void print_elements(const dtm_analysis *a, const dtm_selective_mass *m, FILE *f) {
  const dtm_sms_stats *st = &m->stats;
  fprintf(f, "  elements     %zu of %zu scaled; smallest element step %.4e s before, %.4e s after", st->scaled,
          dtm_analysis_nelements(a), m->dt_input, m->element_min);
  if (m->beta_element != (size_t)-1) {
    double c[3];
    dtm_analysis_centroid(a, m->beta_element, c);
    fprintf(f, "; largest beta %.4g at element %zu (%.4g, %.4g, %.4g) %s", st->beta_max,
            dtm_analysis_tag(a, m->beta_element), c[0], c[1], c[2], dtm_output_unit(a, DTM_UNIT_LENGTH));
  }
  fprintf(f, "\n");
}

static void print_mass(const dtm_analysis *a, const dtm_selective_mass *m, FILE *f) {
  const dtm_sms_stats *st = &m->stats;
  const char *M = dtm_output_unit(a, DTM_UNIT_MASS);
  int d = st->ncomp;
  fprintf(f, "  added mass   trace(M_add) / trace(M) per direction:");
  for (int c = 0; c < d; c++)
    fprintf(f, " %c %.3g %% (%.4g of %.4g %s)", "xyz"[c], 100 * st -> trace_add[c] / st -> trace_mass[c],
            st -> trace_add[c], st -> trace_mass[c], M);
  fprintf(f,
          "\n  translational mass %.6g %s, the model's own %.6g %s: %s (M_add leaves every rigid translation's "
          "inertia exact)\n",
          st->translational, M, st->translational_m, M,
          fabs(st->translational - st->translational_m) <= 1e-9 * st->translational_m ? "unchanged" : "CHANGED");
}

/* The solver runs at the target where it is met (the deck's increment),
 * else at the scaled model's recommended step. */
static void print_cost(const dtm_analysis *a, const dtm_selective_mass *m, FILE *f) {
  double lumped = dtm_analysis_recommended(a), step = fmin(m->target, m->recommended);
  double net = m->runtime_factor * lumped / step;
  fprintf(f,
          "  solver cost  %.1f CG iterations per mass solve (Jacobi PCG to %.0e relative); an M_s product costs "
          "%.2f K products on this mesh: %.2fx the time per step of the lumped model, %.2fx its run time "
          "at the %.2fx larger step %.4e s\n",
          m->cg_iterations, DTM_SMS_SOLVER_RTOL, m->product_ratio, m->runtime_factor, net, step / lumped, step);
}

/* The largest |shift| (%) of the lowest modes under variant name of p,
 * INFINITY when a mode has no match (its shape changed), NaN when p has
 * no such computed variant. */
static double max_shift(const dtm_modes_price *p, const char *name) {
  for (int k = 0; p && k < p->nvariants; k++) {
    const dtm_modes_variant *v = &p->variant[k];
    if (strcmp(v->name, name) || !v->computed) continue;
    double w = 0;
    for (int i = 0; i < p->base.nelastic; i++) w = fmax(w, v->shift[i].match < 0 ? INFINITY : fabs(v->shift[i].shift));
    return w;
  }
  return NAN;
}

#define SMS_SHIFT_LIMIT 1.0 /* % of a low mode's frequency: what selective scaling should leave (issue 44) */

/* With --modes: how far the lowest modes moved, and why where it is more
 * than SMS_SHIFT_LIMIT. */
static void print_accuracy(const dtm_results *r, const dtm_selective_mass *m, FILE *f) {
  double s = max_shift(r->modes, "selective mass"), c = max_shift(r->modes, "conventional mass");
  if (isnan(s)) return;
  size_t n = dtm_analysis_nelements(r->analysis);
  fprintf(f,
          "  accuracy     the lowest %d elastic modes move by up to %.3g %% (conventional mass reaching the target: ",
          r->modes->base.nelastic, s);
  fprintf(f, isnan(c) ? "not computed)" : "%.3g %%)", c);
  if (s <= SMS_SHIFT_LIMIT) {
    fprintf(f, ": within %.0f %%\n", SMS_SHIFT_LIMIT);
    return;
  }
  fprintf(f,
          "\nWARNING: selective mass moves the low modes by more than %.0f %%: %zu of the %zu elements are scaled "
          "(largest beta %.3g), so the added mass also reaches the strain of the low modes; a smaller target, or a "
          "mesh whose thin parts are scaled less, keeps them\n",
          SMS_SHIFT_LIMIT, m->stats.scaled, n, m->stats.beta_max);
}

void dtm_summary_selective_mass(const dtm_results *r, void *stream) {
  const dtm_selective_mass *m = r->selective_mass;
  FILE *f = stream;
  if (!m) return;
  print_step(r->analysis, m, f);
  print_elements(r->analysis, m, f);
  print_mass(r->analysis, m, f);
  print_cost(r->analysis, m, f);
  print_accuracy(r, m, f);
}

/* ---- the report ---------------------------------------------------------- */

static cJSON *global_json(const dtm_sms_global *g) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "dt", g->dt);
  cJSON_AddStringToObject(o, "certificate", cert_names[g->certified]);
  cJSON_AddStringToObject(o, "deterministic", cert_names[g->deterministic]);
  cJSON_AddNumberToObject(o, "theta", g->theta);
  cJSON_AddNumberToObject(o, "residual", g->residual);
  dtm_report_number(o, "bound", g->bound);
  dtm_report_number(o, "eps", g->eps);
  cJSON_AddNumberToObject(o, "iterations", g->iterations);
  cJSON_AddBoolToObject(o, "converged", g->converged);
  cJSON_AddNumberToObject(o, "cg_mean", g->cg_mean);
  cJSON_AddNumberToObject(o, "cg_rtol", DTM_SMS_LANCZOS_RTOL);
  cJSON_AddNumberToObject(o, "seconds", g->seconds);
  return o;
}

static cJSON *mass_json(const dtm_sms_stats *st, int d) {
  cJSON *o = cJSON_CreateObject();
  double share[3];
  for (int c = 0; c < d; c++) share[c] = st->trace_add[c] / st->trace_mass[c];
  cJSON_AddItemToObject(o, "added_mass", cJSON_CreateDoubleArray(st->trace_add, d));
  cJSON_AddItemToObject(o, "model_mass", cJSON_CreateDoubleArray(st->trace_mass, d));
  cJSON_AddItemToObject(o, "share", cJSON_CreateDoubleArray(share, d));
  cJSON_AddNumberToObject(o, "translational_mass", st->translational);
  cJSON_AddNumberToObject(o, "translational_mass_lumped", st->translational_m);
  return o;
}

static cJSON *elements_json(const dtm_analysis *a, const dtm_selective_mass *m) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "scaled", (double)m->stats.scaled);
  cJSON_AddNumberToObject(o, "dt_input", m->dt_input);
  cJSON_AddNumberToObject(o, "dt_min", m->element_min);
  cJSON_AddNumberToObject(o, "beta_max", m->stats.beta_max);
  if (m->beta_element == (size_t)-1) return cJSON_AddNullToObject(o, "beta_max_at"), o;
  double c[3];
  char lbl[64];
  cJSON *w = cJSON_CreateObject();
  dtm_analysis_centroid(a, m->beta_element, c);
  cJSON_AddNumberToObject(w, "element", (double)dtm_analysis_tag(a, m->beta_element));
  cJSON_AddStringToObject(
      w, "group", dtm_mesh_group_label(dtm_analysis_mesh(a), dtm_analysis_group(a, m->beta_element), lbl, sizeof lbl));
  cJSON_AddItemToObject(w, "centroid", cJSON_CreateDoubleArray(c, 3));
  cJSON_AddItemToObject(o, "beta_max_at", w);
  return o;
}

static cJSON *cost_json(const dtm_selective_mass *m) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "cg_iterations", m->cg_iterations);
  cJSON_AddNumberToObject(o, "cg_rtol", DTM_SMS_SOLVER_RTOL);
  cJSON_AddNumberToObject(o, "product_ratio", m->product_ratio);
  cJSON_AddNumberToObject(o, "runtime_factor", m->runtime_factor);
  return o;
}

cJSON *dtm_report_selective_mass(const dtm_results *r) {
  const dtm_selective_mass *m = r->selective_mass;
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "target", m->target);
  cJSON_AddNumberToObject(o, "element_target", m->element_target);
  cJSON_AddNumberToObject(o, "recommended", m->recommended);
  cJSON_AddBoolToObject(o, "target_met", m->target_met);
  cJSON_AddItemToObject(o, "global", global_json(&m->global));
  cJSON_AddItemToObject(o, "elements", elements_json(r->analysis, m));
  cJSON_AddItemToObject(o, "mass", mass_json(&m->stats, m->stats.ncomp));
  cJSON_AddItemToObject(o, "cost", cost_json(m));
  double sh = max_shift(r->modes, "selective mass"), cs = max_shift(r->modes, "conventional mass");
  if (!isnan(sh)) {
    cJSON *acc = cJSON_AddObjectToObject(o, "accuracy");
    cJSON_AddNumberToObject(acc, "modes", r->modes->base.nelastic);
    dtm_report_number(acc, "max_shift", isinf(sh) ? NAN : sh);
    dtm_report_number(acc, "max_shift_conventional", isinf(cs) ? NAN : cs);
    cJSON_AddBoolToObject(acc, "within_limit", sh <= SMS_SHIFT_LIMIT);
    cJSON_AddNumberToObject(acc, "limit", SMS_SHIFT_LIMIT);
  }
  cJSON_AddNumberToObject(o, "seconds", m->seconds);
  return o;
}
