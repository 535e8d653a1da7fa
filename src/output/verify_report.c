/* The report of `dtmap verify --report V.json`: which step was checked
 * (and how it relates to dt.recommended and its basis), how many steps ran,
 * each simulated effect's energy growth and verdict, and the overall
 * verdict; with --accuracy, the plane wave run and its measured and
 * predicted phase-speed errors instead. Written atomically. */
#include <cJSON.h>
#include <math.h>

#include "output-impl.h"

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
  return dtm_json_write(verify_json(a, v), path, "verify report");
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
  cJSON_AddItemToObject(o, "direction", vector_json(w->dir));
  cJSON_AddItemToObject(o, "polarisation", vector_json(r->pol));
  cJSON_AddNumberToObject(o, "frequency", w->f);
  cJSON_AddStringToObject(o, "host", dtm_analysis_scene(a)->materials[r->material].m.name);
  cJSON_AddNumberToObject(o, "speed", r->speed);
  cJSON_AddNumberToObject(o, "wavelength", 2 * 3.14159265358979323846 / r->k);
  cJSON_AddNumberToObject(o, "window", r->sigma);
  cJSON_AddNumberToObject(o, "periods", r->duration * r->speed * r->k / (2 * 3.14159265358979323846));
  add_number(o, "measured", r->measured);
  add_number(o, "measured_crossings", r->omega_crossings / (r->speed * r->k) - 1);
  add_number(o, "predicted", r->predicted.mean);
  add_number(o, "predicted_worst_element", r->predicted.worst);
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
  return dtm_json_write(root, path, "verify report");
}
