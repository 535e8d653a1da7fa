/* The report of `dtmap verify --report V.json`: which step was checked
 * (and how it relates to dt.recommended and its basis), how many steps ran,
 * each simulated effect's energy growth and verdict, and the overall
 * verdict. Written atomically. */
#include <cJSON.h>

#include "output-impl.h"

static cJSON *effect_json(const dtm_analysis *a, int k, const dtm_verify_effect *v) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "name", dtm_analysis_effect(a, k)->name);
  cJSON_AddNumberToObject(o, "growth", v->growth);
  cJSON_AddStringToObject(o, "verdict", v->unstable ? "unstable" : "stable");
  cJSON_AddNumberToObject(o, "seconds", v->seconds);
  return o;
}

static cJSON *verify_json(const dtm_analysis *a, const dtm_verify_report *v) {
  cJSON *root = cJSON_CreateObject(), *arr = cJSON_CreateArray();
  double growth = 0;
  int unstable = 0;
  cJSON_AddStringToObject(root, "dtmap", DTM_VERSION);
  cJSON_AddStringToObject(root, "scene", dtm_analysis_scene(a)->path);
  cJSON_AddNumberToObject(root, "step", v->step);
  cJSON_AddNumberToObject(root, "factor", v->factor);
  cJSON_AddNumberToObject(root, "recommended", dtm_analysis_recommended(a));
  cJSON_AddStringToObject(root, "basis", dtm_analysis_basis(a));
  cJSON_AddNumberToObject(root, "steps", v->steps);
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
