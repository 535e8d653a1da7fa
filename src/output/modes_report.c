/* The natural frequencies of `run --modes` (a dtm_modes_price,
 * src/cost/modes_price.c) in the summary and the report: the model's lowest
 * elastic frequencies, its rigid-body modes by count, and one column per
 * modified model (conventional point masses reaching the target, and any
 * other a caller adds, such as selective mass scaling) with each mode's
 * shift in percent against the model's mode of the same shape (MAC), or
 * why it has none. */
#include <math.h>
#include <stdio.h>

#include "output-impl.h"
#include "report.h"

#define COL 24 /* characters of a variant's column */

/* ---- summary ---------------------------------------------------------- */

static void print_heading(const dtm_modes_price *p, FILE *f) {
  const dtm_modes *b = &p->base;
  fprintf(f, "\nmodes        the lowest %d elastic natural frequencies of the free model (shift-invert Lanczos on a\n",
          b->nelastic);
  fprintf(f, "             sparse factorisation, %d steps, %.2f s%s); %d rigid-body mode(s) below them\n", b->steps,
          b->seconds, b->converged ? "" : ", NOT CONVERGED", b->nrigid);
  if (b->counted == 0)
    fprintf(
        f, "             WARNING: the Sturm count finds %ld eigenvalues below %.6g Hz, Lanczos %d: a mode is missing\n",
        b->sturm, sqrt(b->sturm_at) / 6.283185307179586, b->n);
  else if (b->counted == 1)
    fprintf(f, "             Sturm check: none missed (the inertia of K - s M counts exactly these %d below %.6g Hz)\n",
            b->n, sqrt(b->sturm_at) / 6.283185307179586);
  else
    fprintf(f, "             Sturm check not done (%s): a mode Lanczos missed would go unseen\n",
            b->counted == -2 ? "its factorisation would cost more than 1e9 flops" : "a zero pivot");
}

/* The line under the table that says what a variant added. */
static void print_variant_note(const dtm_analysis *a, const dtm_modes_price *p, const dtm_modes_variant *v, FILE *f) {
  const char *kg = dtm_output_unit(a, DTM_UNIT_MASS);
  if (!v->computed) {
    fprintf(f, "  %s: not computed: %s (target %.4e s)\n", v->name, v->why, p->target);
    return;
  }
  if (v->deformation > 0) {
    fprintf(f,
            "  %s: %.4g %s per direction added to the deformation modes only (%.3g %% of the model's %.4g %s), none "
            "to rigid translation, reaching the target %.4e s\n",
            v->name, v->deformation, kg, 100.0 * v->deformation / p->model_mass, p->model_mass, kg, p->target);
    return;
  }
  fprintf(f, "  %s: %.4g %s added (%.3g %% of the model's %.4g %s)", v->name, v->added_mass, kg, v->added_percent,
          p->model_mass, kg);
  if (v->nodes) fprintf(f, " at %zu node(s), reaching the target %.4e s", v->nodes, p->target);
  if (!v->nodes && p->target > 0 && v->added_mass == 0) fprintf(f, ": the model already meets %.4e s", p->target);
  fprintf(f, "\n");
}

/* One cell: the shift and MAC of base mode i in variant v. */
static void print_cell(const dtm_modes_variant *v, int i, FILE *f) {
  char cell[64];
  if (!v->computed)
    snprintf(cell, sizeof cell, "-");
  else if (v->shift[i].match < 0)
    snprintf(cell, sizeof cell, "no match (MAC %.2f)", v->shift[i].mac);
  else
    snprintf(cell, sizeof cell, "%+.3f %% (MAC %.2f)", v->shift[i].shift, v->shift[i].mac);
  fprintf(f, " %-*s", COL, cell);
}

void dtm_summary_modes(const dtm_analysis *a, const dtm_modes_price *p, void *stream) {
  FILE *f = stream;
  const dtm_modes *b = &p->base;
  print_heading(p, f);
  fprintf(f, "  %4s %14s", "mode", "model (Hz)");
  for (int k = 0; k < p->nvariants; k++) fprintf(f, " %-*s", COL, p->variant[k].name);
  fprintf(f, "\n");
  for (int i = 0; i < b->nelastic; i++) {
    fprintf(f, "  %4d %14.6g", i + 1, b->mode[b->nrigid + i].freq);
    for (int k = 0; k < p->nvariants; k++) print_cell(&p->variant[k], i, f);
    fprintf(f, "\n");
  }
  if (p->nvariants)
    fprintf(f, "  shift: 100 (f / f_model - 1) for the mode of the same shape (largest MAC, at least %.1f)\n",
            DTM_MODES_MAC_MIN);
  for (int k = 0; k < p->nvariants; k++) print_variant_note(a, p, &p->variant[k], f);
}

/* ---- report ----------------------------------------------------------- */

/* The elastic frequencies of m, Hz, and their residuals. */
static void frequencies_json(cJSON *o, const dtm_modes *m) {
  cJSON *fr = cJSON_AddArrayToObject(o, "frequencies"), *res = cJSON_AddArrayToObject(o, "residuals");
  for (int i = m->nrigid; i < m->n; i++) {
    cJSON_AddItemToArray(fr, cJSON_CreateNumber(m->mode[i].freq));
    cJSON_AddItemToArray(res, cJSON_CreateNumber(m->mode[i].residual));
  }
  cJSON_AddNumberToObject(o, "rigid", m->nrigid);
  cJSON_AddNumberToObject(o, "steps", m->steps);
  cJSON_AddBoolToObject(o, "converged", m->converged);
  if (m->counted >= 0) cJSON_AddBoolToObject(o, "counted", m->counted);
  cJSON_AddNumberToObject(o, "seconds", m->seconds);
  cJSON_AddNumberToObject(o, "factor_seconds", m->factor_seconds);
}

static cJSON *variant_json(const dtm_modes_price *p, const dtm_modes_variant *v) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "name", v->name);
  cJSON_AddBoolToObject(o, "computed", v->computed);
  if (!v->computed) return cJSON_AddStringToObject(o, "why", v->why), o;
  cJSON_AddNumberToObject(o, "added_mass", v->added_mass);
  cJSON_AddNumberToObject(o, "added_percent", v->added_percent);
  cJSON_AddNumberToObject(o, "nodes", (double)v->nodes);
  if (v->deformation > 0) cJSON_AddNumberToObject(o, "deformation_mass", v->deformation);
  frequencies_json(o, &v->modes);
  cJSON *sh = cJSON_AddArrayToObject(o, "shifts"), *ma = cJSON_AddArrayToObject(o, "match");
  cJSON *mac = cJSON_AddArrayToObject(o, "mac");
  for (int i = 0; i < p->base.nelastic; i++) {
    const dtm_mode_shift *s = &v->shift[i];
    cJSON_AddItemToArray(sh, s->match >= 0 ? cJSON_CreateNumber(s->shift) : cJSON_CreateNull());
    cJSON_AddItemToArray(ma, s->match >= 0 ? cJSON_CreateNumber(s->match + 1) : cJSON_CreateNull());
    cJSON_AddItemToArray(mac, cJSON_CreateNumber(s->mac));
  }
  return o;
}

cJSON *dtm_report_modes(const dtm_analysis *a, const dtm_modes_price *p) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "effect", dtm_analysis_effect(a, p->effect)->name);
  cJSON_AddNumberToObject(o, "asked", p->n);
  frequencies_json(o, &p->base);
  cJSON_AddNumberToObject(o, "sigma", p->base.sigma);
  cJSON_AddNumberToObject(o, "model_mass", p->model_mass);
  cJSON_AddNumberToObject(o, "rigid_tolerance", DTM_MODES_RIGID_TOL);
  cJSON_AddNumberToObject(o, "tolerance", DTM_MODES_TOL);
  cJSON_AddNumberToObject(o, "mac_min", DTM_MODES_MAC_MIN);
  if (p->target > 0) cJSON_AddNumberToObject(o, "target", p->target);
  cJSON *vs = cJSON_AddArrayToObject(o, "variants");
  for (int k = 0; k < p->nvariants; k++) cJSON_AddItemToArray(vs, variant_json(p, &p->variant[k]));
  return o;
}
