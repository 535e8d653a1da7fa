/* The report's "model" object: the scene's system of units, the unit the
 * geometry or mesh file was read in and the factor applied to it, the
 * model's mass (per physical group too) and its bounding box, all in the
 * scene's units (plausible.c computes them). */
#include <cJSON.h>

#include "dtmap/gmsh.h"
#include "output-impl.h"

static cJSON *import_json(const dtm_import_units *u) {
  cJSON *o = cJSON_CreateObject();
  if (u->found[0]) cJSON_AddStringToObject(o, "unit_found", u->found);
  if (u->given[0]) cJSON_AddStringToObject(o, "unit_given", u->given);
  cJSON_AddNumberToObject(o, "factor", u->factor);
  return o;
}

static cJSON *bbox_json(const dtm_model_extent *x) {
  cJSON *o = cJSON_CreateObject();
  double ext[3] = {x->hi[0] - x->lo[0], x->hi[1] - x->lo[1], x->hi[2] - x->lo[2]};
  cJSON_AddItemToObject(o, "min", cJSON_CreateDoubleArray(x->lo, 3));
  cJSON_AddItemToObject(o, "max", cJSON_CreateDoubleArray(x->hi, 3));
  cJSON_AddItemToObject(o, "extent", cJSON_CreateDoubleArray(ext, 3));
  return o;
}

struct cJSON *dtm_report_model(const dtm_analysis *a) {
  const dtm_scene *s = dtm_analysis_scene(a);
  const dtm_mesh *m = dtm_analysis_mesh(a);
  cJSON *o = cJSON_CreateObject();
  dtm_import_units u;
  dtm_model_extent x = {0};
  char lbl[64];
  cJSON_AddStringToObject(o, "units", s->units ? s->units : "SI");
  if (dtm_output_import(a, &u)) cJSON_AddItemToObject(o, "import", import_json(&u));
  if (dtm_output_model(a, &x)) return o;
  cJSON_AddNumberToObject(o, "mass", x.mass);
  cJSON *groups = cJSON_AddArrayToObject(o, "groups");
  for (int g = 0; g < x.ngroups; g++) {
    if (!(x.group_mass[g] > 0)) continue;
    cJSON *go = cJSON_CreateObject();
    cJSON_AddStringToObject(go, "group", dtm_mesh_group_label(m, g < m->ngroups ? g : -1, lbl, sizeof lbl));
    cJSON_AddNumberToObject(go, "mass", x.group_mass[g]);
    cJSON_AddItemToArray(groups, go);
  }
  cJSON_AddItemToObject(o, "bbox", bbox_json(&x));
  dtm_output_model_free(&x);
  return o;
}
