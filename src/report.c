/* The JSON report (cJSON): mesh counts, effects in scene order, the step
 * summary (dt.min, dt.element, dt.effect, dt.safety, dt.recommended, and
 * where the minimum sits), each effect's own minimum, and stage timings.
 * Written to a temporary file and renamed into place. */
#include <cJSON.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "analysis_impl.h"
#include "dtmap/cost.h"
#include "dtmap/refine.h"

static const char *const timing_names[DTM_T_COUNT] = {"scene", "mesh",   "extract", "effects",
                                                      "nodal", "global", "output"};

static cJSON *where_json(const dtm_analysis *a, size_t i) {
  cJSON *o = cJSON_CreateObject();
  double c[3];
  char lbl[64];
  dtm_analysis_centroid(a, i, c);
  cJSON_AddNumberToObject(o, "element", (double)dtm_analysis_tag(a, i));
  cJSON_AddStringToObject(o, "group", dtm_mesh_group_label(a->mesh, dtm_analysis_group(a, i), lbl, sizeof lbl));
  cJSON_AddItemToObject(o, "centroid", cJSON_CreateDoubleArray(c, 3));
  return o;
}

static cJSON *dt_json(const dtm_analysis *a) {
  cJSON *dt = where_json(a, a->el_min);
  cJSON_AddNumberToObject(dt, "min", a->dt_min);
  cJSON_AddStringToObject(dt, "effect", a->effects[a->limiting[a->el_min]].cls->name);
  cJSON_AddNumberToObject(dt, "safety", a->scene->safety);
  cJSON_AddNumberToObject(dt, "recommended", a->recommended);
  cJSON_AddStringToObject(dt, "basis", a->basis);
  if (isfinite(a->dt_nodal)) cJSON_AddNumberToObject(dt, "nodal", a->dt_nodal);
  if (isfinite(a->dt_global)) cJSON_AddNumberToObject(dt, "global", a->dt_global);
  if (a->scene->target > 0) cJSON_AddNumberToObject(dt, "target", a->scene->target);
  return dt;
}

static cJSON *lanczos_json(const dtm_global_info *g) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "theta", g->theta);
  cJSON_AddNumberToObject(o, "residual", g->residual);
  cJSON_AddNumberToObject(o, "iterations", g->iterations);
  cJSON_AddBoolToObject(o, "converged", g->converged);
  cJSON_AddNumberToObject(o, "seconds", g->seconds);
  double br[2] = {g->dt_low, g->dt_high};
  cJSON_AddItemToObject(o, "dt_bracket", cJSON_CreateDoubleArray(br, 2));
  return o;
}

static cJSON *effects_detail(const dtm_analysis *a) {
  cJSON *arr = cJSON_CreateArray();
  for (int k = 0; k < a->neffects; k++) {
    cJSON *o = a->dt_effect[k] ? where_json(a, a->per_effect[k].element) : cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", a->effects[k].cls->name);
    cJSON_AddNumberToObject(o, "index", k);
    const dtm_effect_min *pe = &a->per_effect[k];
    if (a->dt_effect[k]) cJSON_AddNumberToObject(o, "min", pe->min);
    if (isfinite(pe->nodal)) cJSON_AddNumberToObject(o, "nodal", pe->nodal);
    if (isfinite(pe->nodal)) cJSON_AddNumberToObject(o, "nodal_node", (double)a->mesh->node_tags[pe->node]);
    if (isfinite(pe->global)) cJSON_AddNumberToObject(o, "global", pe->global);
    if (a->global && a->global[k].done) cJSON_AddItemToObject(o, "lanczos", lanczos_json(&a->global[k]));
    if (a->dt_effect[k]) cJSON_AddNumberToObject(o, "safe", pe->safe);
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

#define MAX_LISTED 100 /* under-resolved elements listed by tag */

static int has_accuracy(const dtm_analysis *a) {
  for (int k = 0; k < a->neffects; k++)
    if (a->resolution[k]) return 1;
  return 0;
}

static cJSON *under_resolved_list(const dtm_analysis *a) {
  cJSON *arr = cJSON_CreateArray();
  int listed = 0;
  for (size_t i = 0; i < a->nel && listed < MAX_LISTED; i++) {
    if (!(a->h[i] > a->hmax[i])) continue;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "element", (double)dtm_analysis_tag(a, i));
    cJSON_AddNumberToObject(o, "h", a->h[i]);
    cJSON_AddNumberToObject(o, "hmax", a->hmax[i]);
    cJSON_AddItemToArray(arr, o);
    listed++;
  }
  return arr;
}

static cJSON *accuracy_json(const dtm_analysis *a) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "under_resolved", (double)a->under_resolved);
  cJSON_AddItemToObject(o, "under_resolved_elements", under_resolved_list(a));
  cJSON_AddNumberToObject(o, "listed_at_most", MAX_LISTED);
  cJSON_AddNumberToObject(o, "target_conflicts", (double)a->conflicts);
  if (a->conflicts) {
    size_t i = a->cap_element;
    cJSON_AddNumberToObject(o, "dt_allowed_by_accuracy", a->dt_accuracy_cap);
    cJSON_AddStringToObject(o, "binding_bound", a->effects[a->hmax_by[i]].cls->accuracy_view);
    cJSON_AddNumberToObject(o, "binding_hmax", a->hmax[i]);
    cJSON_AddNumberToObject(o, "binding_element", (double)dtm_analysis_tag(a, i));
    if (a->scene->duration > 0)
      cJSON_AddNumberToObject(o, "element_steps_at_cap", (double)a->nel * a->scene->duration / a->dt_accuracy_cap);
  }
  return o;
}

static cJSON *subcycling_json(const dtm_analysis *a) {
  const dtm_subcycling *sc = a->subcycling;
  cJSON *o = cJSON_CreateObject(), *lv = cJSON_AddArrayToObject(o, "levels");
  for (int k = 0; k < sc->nlevels; k++) cJSON_AddItemToArray(lv, cJSON_CreateNumber((double)sc->count[k]));
  cJSON_AddNumberToObject(o, "speedup", sc->speedup);
  return o;
}

#define TOP_ADDED 10 /* elements listed with the most added mass */

static cJSON *top_added(const dtm_analysis *a) {
  const double *m = a->mass_scaling->added;
  size_t idx[TOP_ADDED];
  int k = 0;
  for (size_t i = 0; i < a->nel; i++) {
    if (!(m[i] > 0) || (k == TOP_ADDED && m[i] <= m[idx[k - 1]])) continue;
    int j = k < TOP_ADDED ? k++ : TOP_ADDED - 1;
    while (j > 0 && m[idx[j - 1]] < m[i]) idx[j] = idx[j - 1], j--;
    idx[j] = i;
  }
  cJSON *arr = cJSON_CreateArray();
  for (int r = 0; r < k; r++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "element", (double)dtm_analysis_tag(a, idx[r]));
    cJSON_AddNumberToObject(o, "added", m[idx[r]]);
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

static cJSON *mass_json(const dtm_analysis *a) {
  const dtm_mass_scaling *ms = a->mass_scaling;
  cJSON *o = cJSON_CreateObject(), *groups = cJSON_AddArrayToObject(o, "groups");
  char lbl[64];
  cJSON_AddNumberToObject(o, "element_step_target", ms->target);
  cJSON_AddNumberToObject(o, "total_mass", ms->total_mass);
  cJSON_AddNumberToObject(o, "total_added", ms->total_added);
  cJSON_AddNumberToObject(o, "percent_added", 100.0 * ms->total_added / ms->total_mass);
  cJSON_AddNumberToObject(o, "elements_scaled", (double)ms->scaled);
  for (int g = 0; g < ms->ngroups; g++) {
    if (!(ms->group_mass[g] > 0)) continue;
    cJSON *go = cJSON_CreateObject();
    cJSON_AddStringToObject(go, "group", dtm_mesh_group_label(a->mesh, g < a->mesh->ngroups ? g : -1, lbl, sizeof lbl));
    cJSON_AddNumberToObject(go, "mass", ms->group_mass[g]);
    cJSON_AddNumberToObject(go, "added", ms->group_added[g]);
    cJSON_AddNumberToObject(go, "percent_added", 100.0 * ms->group_added[g] / ms->group_mass[g]);
    cJSON_AddItemToArray(groups, go);
  }
  cJSON_AddItemToObject(o, "most_added", top_added(a));
  return o;
}

static cJSON *refine_json(const dtm_analysis *a) {
  cJSON *arr = cJSON_CreateArray();
  for (int i = 0; i < a->nrefine; i++) {
    const dtm_refine_round *r = &a->refine_rounds[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "round", i);
    cJSON_AddNumberToObject(o, "elements", (double)r->elements);
    cJSON_AddNumberToObject(o, "dt_min", r->dt_min);
    cJSON_AddNumberToObject(o, "recommended", r->recommended);
    cJSON_AddNumberToObject(o, "seconds", r->seconds);
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

static cJSON *report_json(const dtm_analysis *a) {
  cJSON *root = cJSON_CreateObject(), *mesh = cJSON_AddObjectToObject(root, "mesh");
  cJSON_AddStringToObject(root, "dtmap", DTM_VERSION);
  cJSON_AddStringToObject(root, "scene", a->scene->path);
  cJSON_AddNumberToObject(mesh, "elements", (double)a->nel);
  cJSON_AddNumberToObject(mesh, "nodes", (double)a->mesh->nnodes);
  cJSON_AddNumberToObject(mesh, "dim", a->mesh->dim);
  cJSON *names = cJSON_AddArrayToObject(root, "effects");
  for (int k = 0; k < a->neffects; k++) cJSON_AddItemToArray(names, cJSON_CreateString(a->effects[k].cls->name));
  cJSON_AddItemToObject(root, "dt", dt_json(a));
  cJSON_AddItemToObject(root, "effect_minima", effects_detail(a));
  if (has_accuracy(a)) cJSON_AddItemToObject(root, "accuracy", accuracy_json(a));
  if (a->nrefine) cJSON_AddItemToObject(root, "refine", refine_json(a));
  cJSON_AddItemToObject(root, "subcycling", subcycling_json(a));
  if (a->mass_scaling) cJSON_AddItemToObject(root, "mass_scaling", mass_json(a));
  cJSON *t = cJSON_AddObjectToObject(root, "timings");
  for (int i = 0; i < DTM_T_COUNT; i++) cJSON_AddNumberToObject(t, timing_names[i], a->timings[i]);
  cJSON_AddNumberToObject(t, "threads", a->threads);
  return root;
}

int dtm_report_write(const dtm_analysis *a, const char *path) {
  cJSON *root = report_json(a);
  char *text = root ? cJSON_Print(root) : NULL;
  cJSON_Delete(root);
  if (!text) return DTM_ERR(DTM_ERR_INTERNAL, "cannot build the JSON report");
  char tmp[PATH_MAX + 64];
  dtm_tmp_path(path, "", tmp, sizeof tmp);
  FILE *f = fopen(tmp, "w");
  int ok = f && fputs(text, f) >= 0 && fputc('\n', f) != EOF;
  ok = (f && fclose(f) == 0) && ok;
  free(text);
  if (!ok || rename(tmp, path)) {
    int e = errno;
    unlink(tmp);
    return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write the report: %s", path, strerror(e));
  }
  return DTM_OK;
}
