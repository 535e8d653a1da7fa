/* The report of `dtmap verify --report V.json`: which step was checked
 * (and how it relates to dt.recommended and its basis), how many steps ran,
 * each simulated effect's energy growth and verdict, and the overall
 * verdict; with --accuracy, the plane wave run and its measured and
 * predicted phase-speed errors instead. Written atomically; the latter is
 * read back by run, sweep and refine (--verified). */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "output-impl.h"
#include "report.h"

static cJSON *effect_json(const dtm_analysis *a, int k, const dtm_verify_effect *v) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "name", dtm_analysis_effect(a, k)->name);
  cJSON_AddNumberToObject(o, "growth", v->growth);
  cJSON_AddStringToObject(o, "verdict", v->unstable ? "unstable" : "stable");
  cJSON_AddNumberToObject(o, "seconds", v->seconds);
  return o;
}

/* The fields both reports share: version, scene, the step and its basis. */
static cJSON *step_json(const dtm_analysis *a, double step, double factor, int steps) {
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "dtmap", DTM_VERSION);
  cJSON_AddStringToObject(root, "scene", dtm_analysis_scene(a)->path);
  cJSON_AddNumberToObject(root, "step", step);
  cJSON_AddNumberToObject(root, "factor", factor);
  cJSON_AddNumberToObject(root, "recommended", dtm_analysis_recommended(a));
  cJSON_AddStringToObject(root, "basis", dtm_analysis_basis(a));
  cJSON_AddNumberToObject(root, "steps", steps);
  return root;
}

static cJSON *verify_json(const dtm_analysis *a, const dtm_verify_report *v) {
  cJSON *root = step_json(a, v->step, v->factor, v->steps), *arr = cJSON_CreateArray();
  double growth = 0;
  int unstable = 0;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    if (!v->effect[k].simulated) continue;
    cJSON_AddItemToArray(arr, effect_json(a, k, &v->effect[k]));
    growth = v->effect[k].growth > growth ? v->effect[k].growth : growth;
    unstable |= v->effect[k].unstable;
  }
  cJSON_AddNumberToObject(root, "growth", growth);
  cJSON_AddStringToObject(root, "verdict", unstable ? "unstable" : "stable");
  cJSON_AddItemToObject(root, "effects", arr);
  return root;
}

int dtm_verify_report_write(const dtm_analysis *a, const dtm_verify_report *v, const char *path) {
  cJSON *root = verify_json(a, v);
  if (root) dtm_report_units(root, a, 1);
  return dtm_json_write(root, path, "verify report");
}

/* A JSON number, or null when it is not finite (cJSON would write NaN). */
static void add_number(cJSON *o, const char *key, double v) {
  if (isfinite(v))
    cJSON_AddNumberToObject(o, key, v);
  else
    cJSON_AddNullToObject(o, key);
}

static cJSON *vector_json(const double *v) {
  cJSON *arr = cJSON_CreateArray();
  for (int c = 0; c < 3; c++) cJSON_AddItemToArray(arr, cJSON_CreateNumber(v[c]));
  return arr;
}

static cJSON *wave_json(const dtm_analysis *a, const dtm_wave_spec *w, const dtm_wave_result *r) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "wave", w->mode ? "S" : "P");
  cJSON_AddItemToObject(o, "direction", vector_json(r->dir));
  cJSON_AddItemToObject(o, "polarisation", vector_json(r->pol));
  cJSON_AddNumberToObject(o, "frequency", r->f);
  cJSON_AddNumberToObject(o, "frequency_asked", w->f);
  cJSON_AddBoolToObject(o, "periodic", r->periodic);
  cJSON_AddStringToObject(o, "model", dtm_dispersion_model_name(r->predicted.model));
  cJSON_AddStringToObject(o, "host", dtm_analysis_scene(a)->materials[r->material].m.name);
  cJSON_AddNumberToObject(o, "speed", r->speed);
  cJSON_AddNumberToObject(o, "wavelength", 2 * 3.14159265358979323846 / r->k);
  cJSON_AddNumberToObject(o, "window", r->sigma);
  cJSON_AddNumberToObject(o, "periods", r->duration * r->speed * r->k / (2 * 3.14159265358979323846));
  add_number(o, "measured", r->measured);
  add_number(o, "measured_crossings", r->omega_crossings / (r->speed * r->k) - 1);
  add_number(o, "predicted", r->predicted.mean);
  add_number(o, "predicted_worst_element", r->predicted.worst);
  if (r->mesh.kind == DTM_MEASURE_PHASE) cJSON_AddItemToObject(o, "mesh_measure", dtm_report_measure(a, &r->mesh));
  cJSON_AddNumberToObject(o, "elements", (double)r->predicted.elements);
  cJSON_AddNumberToObject(o, "unresolved", (double)r->predicted.unresolved);
  add_number(o, "agreement", r->agreement);
  cJSON_AddNumberToObject(o, "band", 0.2);
  cJSON_AddNumberToObject(o, "seconds", r->seconds);
  return o;
}

int dtm_verify_wave_report_write(const dtm_analysis *a, double dt, const dtm_wave_spec *w, const dtm_wave_result *r,
                                 const char *path) {
  cJSON *root = step_json(a, dt, dt / dtm_analysis_recommended(a), r->steps);
  cJSON_AddStringToObject(root, "verdict", fabs(r->agreement) <= 0.2 ? "agrees" : "disagrees");
  cJSON_AddItemToObject(root, "accuracy", wave_json(a, w, r));
  dtm_report_units(root, a, 1);
  return dtm_json_write(root, path, "verify report");
}

/* The whole of the file at path, NUL-terminated (NULL when it cannot be read). */
static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  char *text = NULL;
  long n = f && !fseek(f, 0, SEEK_END) ? ftell(f) : -1;
  if (n >= 0 && !fseek(f, 0, SEEK_SET) && (text = malloc((size_t)n + 1)) && fread(text, 1, (size_t)n, f) == (size_t)n)
    text[n] = 0;
  else
    free(text), text = NULL;
  if (f) fclose(f);
  return text;
}

/* The number at key of o into *v; 0 when it is not one. */
static int number_at(const cJSON *o, const char *key, double *v) {
  const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
  return cJSON_IsNumber(x) ? (*v = x->valuedouble, 1) : 0;
}

int dtm_verify_wave_report_read(const char *path, dtm_wave_check *c) {
  char *text = slurp(path);
  if (!text) return DTM_ERR(DTM_ERR_INPUT, "%s: cannot read the verify report", path);
  cJSON *root = cJSON_Parse(text);
  free(text);
  const cJSON *acc = cJSON_GetObjectItemCaseSensitive(root, "accuracy");
  const cJSON *wave = cJSON_GetObjectItemCaseSensitive(acc, "wave"),
              *dir = cJSON_GetObjectItemCaseSensitive(acc, "direction");
  int ok = cJSON_IsString(wave) && (!strcmp(wave->valuestring, "P") || !strcmp(wave->valuestring, "S")) &&
           cJSON_GetArraySize(dir) == 3 && number_at(acc, "frequency", &c->f) &&
           number_at(acc, "measured", &c->measured) && number_at(acc, "predicted", &c->predicted);
  for (int i = 0; ok && i < 3; i++) ok = cJSON_IsNumber(cJSON_GetArrayItem(dir, i));
  if (ok) {
    c->mode = !strcmp(wave->valuestring, "S");
    for (int i = 0; i < 3; i++) c->dir[i] = cJSON_GetArrayItem(dir, i)->valuedouble;
  }
  cJSON_Delete(root);
  return ok ? DTM_OK
            : DTM_ERR(DTM_ERR_INPUT,
                      "%s: not a verify --accuracy report with a measured and a predicted error (dtmap verify "
                      "--accuracy --report)",
                      path);
}
