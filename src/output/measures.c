/* The accuracy measures of an analysed mesh (dtm_measures, computed by the
 * cost module) and the run time in hours, as the JSON report and the
 * terminal summary show them: one entry per measure with its worst and
 * median value, the band it is judged against, whether the worst is inside
 * it, and one note when something was missing or assumed (no f-max: the
 * mesh's default frequency). An unresolved phase error is written as
 * "unresolved" (JSON null), never as a number. */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>

#include "output-impl.h"
#include "report.h"

static void put_number(cJSON *o, const char *key, double v) {
  if (isfinite(v))
    cJSON_AddNumberToObject(o, key, v);
  else
    cJSON_AddNullToObject(o, key);
}

static cJSON *measure_json(const dtm_analysis *a, const dtm_measure *m) {
  cJSON *o = cJSON_CreateObject();
  char lbl[64];
  cJSON_AddStringToObject(o, "measure", dtm_measure_name(m->kind));
  cJSON_AddStringToObject(o, "effect", dtm_analysis_effect(a, m->effect)->name);
  if (m->kind == DTM_MEASURE_ZONE)
    cJSON_AddStringToObject(o, "group", dtm_mesh_group_label(dtm_analysis_mesh(a), m->group, lbl, sizeof lbl));
  cJSON_AddStringToObject(o, "unit", m->kind == DTM_MEASURE_PHASE ? "fraction" : "elements");
  put_number(o, "worst", m->worst);
  put_number(o, "median", m->median);
  if (m->elements && isfinite(m->worst))
    cJSON_AddNumberToObject(o, "worst_element", (double)dtm_analysis_tag(a, m->worst_element));
  if (m->kind == DTM_MEASURE_PHASE) {
    put_number(o, "worst_alone", m->worst_alone);
    if (m->elements && isfinite(m->worst_alone))
      cJSON_AddNumberToObject(o, "worst_alone_element", (double)dtm_analysis_tag(a, m->worst_alone_element));
    cJSON_AddNumberToObject(o, "worst_rings", m->rings);
  }
  cJSON_AddNumberToObject(o, "elements", (double)m->elements);
  if (m->kind == DTM_MEASURE_PHASE) cJSON_AddNumberToObject(o, "unresolved", (double)m->unresolved);
  cJSON *band = cJSON_AddArrayToObject(o, "band");
  cJSON_AddItemToArray(band, cJSON_CreateNumber(m->band_lo));
  cJSON_AddItemToArray(band, isfinite(m->band_hi) ? cJSON_CreateNumber(m->band_hi) : cJSON_CreateNull());
  cJSON_AddBoolToObject(o, "in_band", m->in_band);
  if (m->kind == DTM_MEASURE_PHASE && isfinite(m->f)) {
    cJSON_AddNumberToObject(o, "frequency", m->f);
    cJSON_AddStringToObject(o, "frequency_from", m->f_default ? "mesh default" : "scene f-max");
  }
  if (m->kind == DTM_MEASURE_PHASE && m->wave >= 0) {
    cJSON_AddStringToObject(o, "wave", m->wave ? "S" : "P");
    cJSON_AddItemToObject(o, "direction", cJSON_CreateDoubleArray(m->direction, 3));
    cJSON_AddStringToObject(o, "model", dtm_dispersion_model_name(m->model));
  }
  if (m->note[0]) cJSON_AddStringToObject(o, "note", m->note);
  return o;
}

cJSON *dtm_report_measure(const dtm_analysis *a, const dtm_measure *m) { return measure_json(a, m); }

cJSON *dtm_report_measures(const dtm_analysis *a, const dtm_measures *ms) {
  cJSON *arr = cJSON_CreateArray();
  for (int i = 0; ms && i < ms->n; i++) cJSON_AddItemToArray(arr, measure_json(a, &ms->m[i]));
  return arr;
}

/* A phase error in per cent, or "unresolved". */
static const char *percent(double v, char *buf, size_t len) {
  if (isfinite(v))
    snprintf(buf, len, "%+.3g %%", 100 * v);
  else
    snprintf(buf, len, "unresolved");
  return buf;
}

void dtm_summary_phase_worst(const dtm_measure *m, char *buf, size_t len) {
  char a[32], b[32];
  if (m->rings)
    snprintf(buf, len, "worst %s averaged over its neighbourhood (%d rings of elements), %s element alone",
             percent(m->worst, a, sizeof a), m->rings, percent(m->worst_alone, b, sizeof b));
  else
    snprintf(buf, len, "worst %s element alone (the same averaged over its neighbourhood: no element's model averages)",
             percent(m->worst_alone, b, sizeof b));
}

/* One measure on one line: its value, its band and its verdict (a phase
 * error: its two worst figures on a second line). */
static void print_measure(const dtm_analysis *a, const dtm_measure *m, FILE *f) {
  char lbl[64];
  fprintf(f, "  %-27s %-9s", dtm_measure_name(m->kind), dtm_analysis_effect(a, m->effect)->name);
  if (m->kind == DTM_MEASURE_ZONE)
    fprintf(f, " group %s:", dtm_mesh_group_label(dtm_analysis_mesh(a), m->group, lbl, sizeof lbl));
  if (m->kind == DTM_MEASURE_PHASE && m->unresolved)
    fprintf(f, " unresolved: %zu of %zu elements have fewer than 2 per wavelength at %.4g Hz\n", m->unresolved,
            m->elements, m->f);
  else if (m->kind == DTM_MEASURE_PHASE && isfinite(m->worst))
    fprintf(f, " worst %+.3g%% (%s along (%.2g, %.2g, %.2g), %s), median %+.3g%% at %.4g Hz (band +-%g%%): %s\n",
            100 * m->worst, m->wave ? "S" : "P", m->direction[0], m->direction[1], m->direction[2],
            dtm_dispersion_model_name(m->model), 100 * m->median, m->f, 100 * m->band_hi,
            m->in_band ? "inside" : "OUTSIDE");
  else if (isfinite(m->worst) && isfinite(m->band_hi))
    fprintf(f, " smallest %.3g, median %.3g (band %g-%g): %s\n", m->worst, m->median, m->band_lo, m->band_hi,
            m->in_band ? (m->worst > m->band_hi ? "above (finer than needed)" : "inside") : "BELOW");
  else if (isfinite(m->worst))
    fprintf(f, " smallest %.3g, median %.3g (band >= %g): %s\n", m->worst, m->median, m->band_lo,
            m->in_band ? "inside" : "BELOW");
  else
    fprintf(f, " not measured\n");
  if (m->kind == DTM_MEASURE_PHASE && !m->unresolved && isfinite(m->worst)) {
    char line[256];
    dtm_summary_phase_worst(m, line, sizeof line);
    fprintf(f, "  %-27s %s\n", "", line);
  }
  if (m->note[0]) fprintf(f, "  %-27s %s\n", "", m->note);
}

void dtm_summary_measures(const dtm_analysis *a, const dtm_cost *c, void *stream) {
  FILE *f = stream;
  if (isfinite(c->hours))
    fprintf(f, "run time     %.4g h (%.4g h with subcycling) at %.3g ns per element-step: %s\n", c->hours,
            c->hours_subcycled, 1e9 * c->per_element_step, c->per_element_step_source);
  else
    fprintf(f, "run time     no <time duration>: %.3g ns per element-step (%s)\n", 1e9 * c->per_element_step,
            c->per_element_step_source);
  if (!c->measures || !c->measures->n) return;
  fprintf(f, "accuracy at the recommended step:\n");
  for (int i = 0; i < c->measures->n; i++) print_measure(a, &c->measures->m[i], f);
}
