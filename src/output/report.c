/* The JSON report (cJSON): mesh counts, effects in scene order, the step
 * summary (dt.min, dt.element, dt.effect, dt.safety, dt.recommended, and
 * where the minimum sits), each effect's own minimum, accuracy findings, the
 * cost from the one basis (element-steps, subcycling, mass scaling), the
 * cohesive zone, damping factors, the shape-limited elements, the smallest
 * steps, the refine rounds, the elements analysed although inverted at a
 * node, warnings and stage timings. Written atomically. */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/operator.h"
#include "dtmap/util.h"
#include "output-impl.h"
#include "report.h"

static cJSON *where_json(const dtm_analysis *a, size_t i) {
  cJSON *o = cJSON_CreateObject();
  double c[3];
  char lbl[64];
  dtm_analysis_centroid(a, i, c);
  cJSON_AddNumberToObject(o, "element", (double)dtm_analysis_tag(a, i));
  cJSON_AddStringToObject(o, "group",
                          dtm_mesh_group_label(dtm_analysis_mesh(a), dtm_analysis_group(a, i), lbl, sizeof lbl));
  cJSON_AddItemToObject(o, "centroid", cJSON_CreateDoubleArray(c, 3));
  return o;
}

void dtm_report_steps(cJSON *dt, const dtm_analysis *a, int effect) {
  const dtm_scene *s = dtm_analysis_scene(a);
  cJSON_AddNumberToObject(dt, "min", dtm_analysis_dt_min(a, NULL));
  cJSON_AddStringToObject(dt, "effect", dtm_analysis_effect(a, effect)->name);
  cJSON_AddNumberToObject(dt, "safety", s->safety);
  cJSON_AddStringToObject(dt, "min_is", "the element bound: the dt map's own minimum, not the step to use");
  cJSON_AddNumberToObject(dt, "recommended", dtm_analysis_recommended(a));
  cJSON_AddStringToObject(dt, "basis", dtm_analysis_basis(a));
  cJSON_AddNumberToObject(dt, "basis_step", dtm_analysis_basis_step(a));
  if (isfinite(dtm_analysis_dt_nodal(a))) cJSON_AddNumberToObject(dt, "nodal", dtm_analysis_dt_nodal(a));
  if (isfinite(dtm_analysis_dt_global(a))) cJSON_AddNumberToObject(dt, "global", dtm_analysis_dt_global(a));
  cJSON_AddBoolToObject(dt, "recommended_certified", dtm_analysis_recommended_certified(a));
  if (s->target > 0) cJSON_AddNumberToObject(dt, "target", s->target);
}

static cJSON *dt_json(const dtm_analysis *a) {
  size_t el;
  dtm_analysis_dt_min(a, &el);
  cJSON *dt = where_json(a, el);
  dtm_report_steps(dt, a, dtm_analysis_limiting(a)[el]);
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
  cJSON_AddNumberToObject(o, "quadrature_margin", g->quad_err);
  static const char *const cert[] = {"none", "proven", "too dear", "unavailable", "refuted", "probable"};
  if (g->certified >= 0 && g->certified <= DTM_CERT_PROBABLE)
    cJSON_AddStringToObject(o, "certificate", cert[g->certified]);
  if (g->deterministic >= 0 && g->deterministic <= DTM_CERT_REFUTED)
    cJSON_AddStringToObject(o, "deterministic", cert[g->deterministic]);
  cJSON_AddNumberToObject(o, "seed", g->seed);
  if (g->certified == DTM_CERT_PROBABLE) {
    cJSON *p = cJSON_AddObjectToObject(o, "probable");
    cJSON_AddNumberToObject(p, "failure", g->failure);
    cJSON_AddNumberToObject(p, "eps", g->eps);
    cJSON_AddNumberToObject(p, "steps", g->iterations);
    cJSON_AddNumberToObject(p, "n", g->nbound);
    cJSON_AddNumberToObject(p, "dt_certified", g->dt_certified);
  }
  return o;
}

void dtm_report_effect(cJSON *o, const dtm_analysis *a, int k, size_t nodal_node) {
  const dtm_effect_min *pe = dtm_analysis_effect_min(a, k);
  int limits = dtm_analysis_effect_dt(a, k) != NULL;
  cJSON_AddStringToObject(o, "name", dtm_analysis_effect(a, k)->name);
  cJSON_AddNumberToObject(o, "index", k);
  if (limits) cJSON_AddNumberToObject(o, "min", pe->min);
  if (isfinite(pe->nodal)) cJSON_AddNumberToObject(o, "nodal", pe->nodal);
  if (isfinite(pe->nodal)) cJSON_AddNumberToObject(o, "nodal_node", (double)nodal_node);
  if (isfinite(pe->global)) cJSON_AddNumberToObject(o, "global", pe->global);
  if (dtm_analysis_global(a, k)) cJSON_AddItemToObject(o, "lanczos", lanczos_json(dtm_analysis_global(a, k)));
  if (limits) cJSON_AddNumberToObject(o, "safe", pe->safe);
}

static cJSON *effect_detail(const dtm_analysis *a, int k) {
  const dtm_effect_min *pe = dtm_analysis_effect_min(a, k);
  cJSON *o = dtm_analysis_effect_dt(a, k) ? where_json(a, pe->element) : cJSON_CreateObject();
  dtm_report_effect(o, a, k, isfinite(pe->nodal) ? dtm_analysis_mesh(a)->node_tags[pe->node] : 0);
  return o;
}

static cJSON *effects_detail(const dtm_analysis *a) {
  cJSON *arr = cJSON_CreateArray();
  for (int k = 0; k < dtm_analysis_neffects(a); k++) cJSON_AddItemToArray(arr, effect_detail(a, k));
  return arr;
}

static int has_accuracy(const dtm_analysis *a) {
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    if (dtm_analysis_resolution(a, k)) return 1;
  return 0;
}

cJSON *dtm_report_under_resolved(const dtm_analysis *a) {
  const double *h = dtm_analysis_size(a), *hmax = dtm_analysis_hmax(a);
  cJSON *arr = cJSON_CreateArray();
  int listed = 0;
  for (size_t i = 0; i < dtm_analysis_nelements(a) && listed < DTM_REPORT_LISTED; i++) {
    if (!(h[i] > hmax[i])) continue;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "element", (double)dtm_analysis_tag(a, i));
    cJSON_AddNumberToObject(o, "h", h[i]);
    cJSON_AddNumberToObject(o, "hmax", hmax[i]);
    cJSON_AddItemToArray(arr, o);
    listed++;
  }
  return arr;
}

static void binding_json(const dtm_analysis *a, const dtm_accuracy *ac, cJSON *o) {
  const dtm_scene *s = dtm_analysis_scene(a);
  size_t i = ac->cap_element;
  cJSON_AddNumberToObject(o, "dt_allowed_by_accuracy", ac->dt_cap);
  cJSON_AddStringToObject(o, "binding_bound", dtm_analysis_effect(a, dtm_analysis_hmax_by(a)[i])->indicator.view);
  cJSON_AddNumberToObject(o, "binding_hmax", dtm_analysis_hmax(a)[i]);
  cJSON_AddNumberToObject(o, "binding_element", (double)dtm_analysis_tag(a, i));
  if (s->duration > 0)
    cJSON_AddNumberToObject(o, "element_steps_at_cap", (double)dtm_analysis_nelements(a) * s->duration / ac->dt_cap);
}

static cJSON *accuracy_json(const dtm_analysis *a) {
  dtm_accuracy ac;
  dtm_analysis_accuracy(a, &ac);
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "under_resolved", (double)ac.under_resolved);
  cJSON_AddItemToObject(o, "under_resolved_elements", dtm_report_under_resolved(a));
  cJSON_AddNumberToObject(o, "listed_at_most", DTM_REPORT_LISTED);
  cJSON_AddNumberToObject(o, "target_conflicts", (double)ac.conflicts);
  if (ac.conflicts) binding_json(a, &ac, o);
  return o;
}

cJSON *dtm_report_subcycling(const dtm_subcycling *sc) {
  cJSON *o = cJSON_CreateObject(), *lv = cJSON_AddArrayToObject(o, "levels");
  for (int k = 0; k < sc->nlevels; k++) cJSON_AddItemToArray(lv, cJSON_CreateNumber((double)sc->count[k]));
  cJSON_AddNumberToObject(o, "speedup", sc->speedup);
  cJSON_AddNumberToObject(o, "basis", sc->basis);
  return o;
}

/* A number, or null when it is not one (no duration). */
void dtm_report_number(cJSON *o, const char *key, double v) {
  if (isfinite(v))
    cJSON_AddNumberToObject(o, key, v);
  else
    cJSON_AddNullToObject(o, key);
}

cJSON *dtm_report_cost(const dtm_analysis *a, const dtm_cost *c) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "duration", c->duration);
  dtm_report_number(o, "steps", c->steps);
  dtm_report_number(o, "element_steps", c->element_steps);
  dtm_report_number(o, "element_steps_subcycled", c->element_steps_subcycled);
  cJSON_AddNumberToObject(o, "basis", c->basis);
  cJSON_AddStringToObject(o, "basis_estimate", dtm_analysis_basis(a));
  cJSON_AddNumberToObject(o, "per_element_step", c->per_element_step);
  cJSON_AddStringToObject(o, "per_element_step_source", c->per_element_step_source);
  dtm_report_number(o, "hours", c->element_steps * c->per_element_step / 3600);
  dtm_report_number(o, "hours_subcycled", c->element_steps_subcycled * c->per_element_step / 3600);
  return o;
}

cJSON *dtm_report_zones(const dtm_analysis *a) {
  dtm_zone_row *rows = NULL;
  int n = 0;
  cJSON *arr = cJSON_CreateArray();
  if (dtm_zone_rows(a, &rows, &n)) n = 0;
  for (int j = 0; j < n; j++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "material", dtm_analysis_scene(a)->materials[rows[j].mat].m.name);
    cJSON_AddNumberToObject(o, "R", rows[j].R);
    cJSON_AddNumberToObject(o, "h_max", rows[j].hmax);
    cJSON_AddItemToArray(arr, o);
  }
  free(rows);
  return arr;
}

cJSON *dtm_report_damping(const dtm_analysis *a) {
  dtm_damping_row *rows = NULL;
  int n = 0;
  cJSON *arr = cJSON_CreateArray();
  if (dtm_damping_rows(a, &rows, &n)) n = 0;
  for (int j = 0; j < n; j++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "effect", dtm_analysis_effect(a, rows[j].effect)->name);
    cJSON_AddStringToObject(o, "material", dtm_analysis_scene(a)->materials[rows[j].mat].m.name);
    cJSON_AddNumberToObject(o, "omega", rows[j].omega);
    cJSON_AddNumberToObject(o, "factor", rows[j].factor);
    dtm_report_number(o, "element_factor_min", rows[j].emin);
    dtm_report_number(o, "element_factor_max", rows[j].emax);
    cJSON_AddItemToArray(arr, o);
  }
  free(rows);
  return arr;
}

cJSON *dtm_report_worst(const dtm_results *r) {
  const dtm_analysis *a = r->analysis;
  size_t *idx = NULL;
  int n = dtm_worst(a, dtm_results_top(r), &idx);
  cJSON *arr = cJSON_CreateArray();
  for (int j = 0; j < n; j++) {
    size_t i = idx[j];
    int b;
    size_t l;
    char lbl[64];
    dtm_analysis_locate(a, i, &b, &l);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "element", (double)dtm_analysis_tag(a, i));
    cJSON_AddStringToObject(o, "type", dtm_elem_name(dtm_analysis_mesh(a)->blocks[b].type));
    cJSON_AddStringToObject(o, "group",
                            dtm_mesh_group_label(dtm_analysis_mesh(a), dtm_analysis_group(a, i), lbl, sizeof lbl));
    double c[3];
    dtm_analysis_centroid(a, i, c);
    cJSON_AddItemToObject(o, "centroid", cJSON_CreateDoubleArray(c, 3));
    cJSON_AddNumberToObject(o, "dt", dtm_analysis_dt(a)[i]);
    cJSON_AddNumberToObject(o, "length", dtm_analysis_length(a)[i]);
    cJSON_AddStringToObject(o, "effect", dtm_analysis_effect(a, dtm_analysis_limiting(a)[i])->name);
    cJSON_AddItemToArray(arr, o);
  }
  free(idx);
  return arr;
}

#define SHAPE_LISTED 100 /* shape-limited elements listed in the report */

static cJSON *shape_entry(const dtm_results *r, const dtm_shape_limited *s) {
  char buf[256];
  cJSON *o = where_json(r->analysis, s->element), *f = cJSON_CreateObject(), *m = cJSON_CreateObject();
  cJSON_AddStringToObject(f, "kind", dtm_feature_name(s->feature));
  dtm_report_number(f, "angle", s->angle);
  cJSON_AddNumberToObject(f, "entity_dim", s->entity_dim);
  cJSON_AddNumberToObject(f, "entity", s->entity_tag);
  cJSON_AddNumberToObject(f, "size", s->size);
  cJSON_AddStringToObject(f, "text", dtm_feature_text(r->analysis, s, buf, sizeof buf));
  cJSON_AddItemToObject(o, "feature", f);
  cJSON_AddNumberToObject(o, "quality", s->quality);
  cJSON_AddNumberToObject(o, "reach", s->reach);
  cJSON_AddStringToObject(m, "kind", dtm_remedy_name(s->remedy));
  dtm_report_number(m, "size", s->split);
  if (r->cost && r->cost->shape_mass) cJSON_AddNumberToObject(m, "mass", r->cost->shape_mass->added[s->element]);
  cJSON_AddStringToObject(m, "text", dtm_remedy_text(r, s, buf, sizeof buf));
  cJSON_AddItemToObject(o, "remedy", m);
  return o;
}

cJSON *dtm_report_shape(const dtm_results *r) {
  size_t n;
  const dtm_shape_limited *sl = dtm_analysis_shape_limited(r->analysis, &n);
  cJSON *arr = cJSON_CreateArray();
  for (size_t j = 0; j < n && j < SHAPE_LISTED; j++) cJSON_AddItemToArray(arr, shape_entry(r, &sl[j]));
  return arr;
}

/* The remedies of layer k (the mass its elements need: the cost's
 * layer_mass over them). */
static cJSON *layer_remedies(const dtm_results *r, size_t k, const dtm_layer *l) {
  cJSON *o = cJSON_CreateObject();
  const dtm_mass_scaling *ms = r->cost ? r->cost->layer_mass : NULL;
  int slot = l->group >= 0 ? l->group : (ms ? ms->ngroups - 1 : 0);
  double added = dtm_layer_added_mass(r, k);
  if (ms && ms->group_mass[slot] > 0 && isfinite(added)) {
    cJSON_AddNumberToObject(o, "mass_added", added);
    cJSON_AddNumberToObject(o, "mass_percent", 100.0 * added / ms->group_mass[slot]);
  }
  if (r->cost) cJSON_AddNumberToObject(o, "subcycling_speedup", r->cost->subcycling.speedup);
  if (isfinite(l->shell_step)) {
    cJSON_AddNumberToObject(o, "shell_rule_step", l->shell_step);
    cJSON_AddNumberToObject(o, "shell_thickness", l->thickness);
  }
  return o;
}

cJSON *dtm_report_layers(const dtm_results *r) {
  size_t n;
  const dtm_layer *ly = dtm_analysis_layers(r->analysis, &n);
  cJSON *arr = cJSON_CreateArray();
  for (size_t k = 0; k < n; k++) {
    char lbl[64];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "group",
                            dtm_mesh_group_label(dtm_analysis_mesh(r->analysis), ly[k].group, lbl, sizeof lbl));
    cJSON_AddNumberToObject(o, "elements", (double)ly[k].elements);
    cJSON_AddNumberToObject(o, "thickness", ly[k].thickness);
    cJSON *fc = cJSON_CreateArray();
    for (int q = 0; q < 2; q++) {
      int pair[2] = {ly[k].faces[q][0], ly[k].faces[q][1]};
      cJSON_AddItemToArray(fc, cJSON_CreateIntArray(pair, 2));
    }
    cJSON_AddItemToObject(o, "boundaries", fc);
    cJSON_AddNumberToObject(o, "reach", ly[k].reach);
    cJSON_AddNumberToObject(o, "element", (double)dtm_analysis_tag(r->analysis, ly[k].worst));
    cJSON_AddNumberToObject(o, "size", ly[k].size);
    cJSON_AddBoolToObject(o, "at_minimum", ly[k].at_minimum);
    cJSON_AddItemToObject(o, "remedies", ly[k].at_minimum ? cJSON_CreateObject() : layer_remedies(r, k, &ly[k]));
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

static cJSON *advice_json(const dtm_results *r, cJSON *root) {
  size_t n;
  dtm_analysis_shape_limited(r->analysis, &n);
  cJSON_AddItemToObject(root, "shape_limited", dtm_report_shape(r));
  cJSON_AddNumberToObject(root, "shape_limited_count", (double)n);
  cJSON_AddNumberToObject(root, "below_target", (double)dtm_analysis_below_target(r->analysis));
  cJSON_AddItemToObject(root, "thickness_limited", dtm_report_layers(r));
  const dtm_mass_scaling *ms = r->cost ? r->cost->shape_mass : NULL;
  if (ms) {
    cJSON *o = cJSON_AddObjectToObject(root, "shape_limited_mass");
    cJSON_AddNumberToObject(o, "added", ms->total_added);
    cJSON_AddNumberToObject(o, "percent_added", 100.0 * ms->total_added / ms->total_mass);
  }
  return root;
}

int dtm_report_largest(const double *m, size_t n, size_t *idx, int max) {
  int k = 0;
  for (size_t i = 0; i < n; i++) {
    if (!(m[i] > 0) || (k == max && m[i] <= m[idx[k - 1]])) continue;
    int j = k < max ? k++ : max - 1;
    while (j > 0 && m[idx[j - 1]] < m[i]) idx[j] = idx[j - 1], j--;
    idx[j] = i;
  }
  return k;
}

cJSON *dtm_report_top_added(const dtm_analysis *a, const double *m) {
  size_t idx[DTM_REPORT_TOP_ADDED];
  int k = dtm_report_largest(m, dtm_analysis_nelements(a), idx, DTM_REPORT_TOP_ADDED);
  cJSON *arr = cJSON_CreateArray();
  for (int r = 0; r < k; r++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "element", (double)dtm_analysis_tag(a, idx[r]));
    cJSON_AddNumberToObject(o, "added", m[idx[r]]);
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

static cJSON *group_mass_json(const dtm_mesh *mesh, const dtm_mass_scaling *ms, int g) {
  char lbl[64];
  cJSON *go = cJSON_CreateObject();
  cJSON_AddStringToObject(go, "group", dtm_mesh_group_label(mesh, g < mesh->ngroups ? g : -1, lbl, sizeof lbl));
  cJSON_AddNumberToObject(go, "mass", ms->group_mass[g]);
  cJSON_AddNumberToObject(go, "added", ms->group_added[g]);
  cJSON_AddNumberToObject(go, "percent_added", 100.0 * ms->group_added[g] / ms->group_mass[g]);
  return go;
}

cJSON *dtm_report_mass(const dtm_analysis *a, const dtm_mass_scaling *ms, cJSON *most_added) {
  cJSON *o = cJSON_CreateObject(), *groups = cJSON_AddArrayToObject(o, "groups");
  cJSON_AddNumberToObject(o, "element_step_target", ms->target);
  cJSON_AddStringToObject(o, "where", ms->nodal ? "nodes" : "elements");
  cJSON_AddNumberToObject(o, "total_mass", ms->total_mass);
  cJSON_AddNumberToObject(o, "total_added", ms->total_added);
  cJSON_AddNumberToObject(o, "percent_added", 100.0 * ms->total_added / ms->total_mass);
  cJSON_AddNumberToObject(o, "elements_scaled", (double)ms->scaled);
  for (int g = 0; g < ms->ngroups; g++)
    if (ms->group_mass[g] > 0) cJSON_AddItemToArray(groups, group_mass_json(dtm_analysis_mesh(a), ms, g));
  cJSON_AddItemToObject(o, "most_added", most_added ? most_added : dtm_report_top_added(a, ms->added));
  return o;
}

static cJSON *warnings_array(const dtm_warnings *w) {
  cJSON *arr = cJSON_CreateArray();
  for (int j = 0; j < w->n; j++) cJSON_AddItemToArray(arr, cJSON_CreateString(w->text[j]));
  return arr;
}

static cJSON *warnings_json(const dtm_results *r) {
  dtm_warnings w;
  dtm_output_warnings(r, &w);
  return warnings_array(&w);
}

cJSON *dtm_report_warnings_of(const dtm_analysis *a, const dtm_mass_scaling *ms, const dtm_report_conflict *c,
                              const char *note) {
  dtm_warnings w = {0, {{0}}};
  if (ms) dtm_output_mass_warnings(a, ms, "mass scaling to the target", &w);
  if (c && c->conflicts)
    dtm_output_conflict_warning(&w, dtm_analysis_scene(a), c->bound, c->hmax, c->dt_cap, c->conflicts);
  if (note && w.n < DTM_WARN_MAX) snprintf(w.text[w.n++], sizeof w.text[0], "%s", note);
  return warnings_array(&w);
}

static cJSON *timings_json(const dtm_results *r) {
  static const char *const names[DTM_T_COUNT] = {"mesh", "extract", "effects", "nodal", "global", "advice"};
  cJSON *t = cJSON_CreateObject();
  cJSON_AddNumberToObject(t, "scene", r->t_scene);
  for (int i = 0; i < DTM_T_COUNT; i++) cJSON_AddNumberToObject(t, names[i], dtm_analysis_timing(r->analysis, i));
  if (r->cost) cJSON_AddNumberToObject(t, "cost", r->cost->seconds);
  if (r->cost) cJSON_AddNumberToObject(t, "measures", r->cost->seconds_measures);
  cJSON_AddNumberToObject(t, "output", r->t_output);
  cJSON_AddNumberToObject(t, "threads", dtm_analysis_threads(r->analysis));
  return t;
}

/* The nodes of the analysed elements and the groups left out (when counted). */
static void left_out_json(const dtm_mesh *m, cJSON *mesh) {
  if (m->nodes_used) cJSON_AddNumberToObject(mesh, "nodes_analysed", (double)m->nodes_used);
  if (!m->nodes_used) return;
  cJSON *arr = cJSON_AddArrayToObject(mesh, "left_out");
  for (int i = 0; i < m->nleft; i++) {
    cJSON *o = cJSON_CreateObject();
    char tag[32];
    snprintf(tag, sizeof tag, "%d", m->left[i].tag);
    cJSON_AddStringToObject(o, "group", m->left[i].tag < 0 ? "(none)" : m->left[i].name[0] ? m->left[i].name : tag);
    cJSON_AddNumberToObject(o, "dim", m->left[i].dim);
    cJSON_AddNumberToObject(o, "elements", (double)m->left[i].elements);
    cJSON_AddItemToArray(arr, o);
  }
}

static cJSON *mesh_json(const dtm_analysis *a) {
  cJSON *mesh = cJSON_CreateObject();
  cJSON_AddNumberToObject(mesh, "elements", (double)dtm_analysis_nelements(a));
  cJSON_AddNumberToObject(mesh, "nodes", (double)dtm_analysis_mesh(a)->nnodes);
  cJSON_AddNumberToObject(mesh, "dim", dtm_analysis_mesh(a)->dim);
  cJSON_AddNumberToObject(mesh, "space_dim", dtm_analysis_space_dim(a));
  const dtm_mesher_info *mi = dtm_analysis_mesher(a);
  cJSON_AddStringToObject(mesh, "algorithm", dtm_scene_algorithm_name(mi->algorithm));
  cJSON_AddNumberToObject(mesh, "threads", mi->threads);
  cJSON_AddBoolToObject(mesh, "reproducible", mi->reproducible);
  left_out_json(dtm_analysis_mesh(a), mesh);
  return mesh;
}

/* Gmsh tag of the node where a flagged element is worst (-1: a rule point). */
static double flagged_node(const dtm_mesh *m, const dtm_flagged *f) {
  const dtm_block *b = &m->blocks[f->block];
  return f->node < 0 ? -1.0 : (double)m->node_tags[b->conn[f->index * (size_t)b->nn + (size_t)f->node]];
}

/* Elements analysed although inverted at a node (dtm_mesh_check): where
 * they are, their smallest scaled Jacobian and the node where it is. */
static cJSON *invalid_json(const dtm_analysis *a) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  cJSON *o = cJSON_CreateObject(), *arr = cJSON_CreateArray();
  cJSON_AddNumberToObject(o, "count", (double)m->nflagged);
  for (size_t i = 0; i < m->nflagged; i++) {
    const dtm_flagged *f = &m->flagged[i];
    size_t g = f->index;
    for (int b = 0; b < f->block; b++) g += m->blocks[b].n;
    cJSON *e = where_json(a, g);
    cJSON_AddNumberToObject(e, "min_scaled_jacobian", f->min_jacobian);
    if (f->node >= 0) cJSON_AddNumberToObject(e, "node", flagged_node(m, f));
    cJSON_AddItemToArray(arr, e);
  }
  cJSON_AddItemToObject(o, "elements", arr);
  return o;
}

/* A shell's or beam's rotary-inertia convention, the one the step uses,
 * and the other's figures. */
static void rotary_json(cJSON *o, const dtm_section *sec, const dtm_section_stats *st) {
  cJSON *r = cJSON_AddObjectToObject(o, "rotary_inertia");
  int scaled = sec->rotary == DTM_ROTARY_SCALED_INERTIA;
  cJSON_AddStringToObject(r, "convention", scaled ? "scaled" : "physical");
  cJSON_AddStringToObject(r, "step_uses", scaled ? "scaled" : "physical");
  cJSON_AddNumberToObject(r, "scale_max", st->scale_max);
  cJSON_AddNumberToObject(r, "dt_physical_min", st->dt_physical_min);
  cJSON_AddNumberToObject(r, "physical_element", (double)st->physical_element);
  if (sec->kind == DTM_SECTION_BEAM) {
    cJSON_AddNumberToObject(o, "iy", sec->iy);
    cJSON_AddNumberToObject(o, "iz", sec->iz);
    cJSON_AddNumberToObject(o, "j", sec->jt);
  }
}

/* The curvature of the second-order elements (src/analysis/curvature.c);
 * absent without any. */
static cJSON *curvature_json(const dtm_analysis *a) {
  const dtm_curvature_summary *s = dtm_analysis_curvature(a);
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "integration", dtm_integration_name(s->model));
  cJSON_AddNumberToObject(o, "second_order", (double)s->second_order);
  cJSON_AddNumberToObject(o, "curved", (double)s->curved);
  cJSON_AddNumberToObject(o, "strongly_curved", (double)s->strong);
  cJSON_AddNumberToObject(o, "strong_ratio", DTM_CURVED_STRONG);
  cJSON_AddNumberToObject(o, "rule_sensitive", (double)s->sensitive);
  cJSON_AddNumberToObject(o, "max_rule_dependence", s->max_dependence);
  cJSON_AddNumberToObject(o, "max_node_offset", s->max_offset);
  cJSON_AddNumberToObject(o, "worst_jacobian_ratio", s->worst_ratio);
  if (s->worst_element != (size_t)-1) cJSON_AddItemToObject(o, "worst", where_json(a, s->worst_element));
  return o;
}

/* Per scene section: kind, groups, thickness or area, and what its
 * elements come to (dtm_analysis_sections). */
static cJSON *sections_json(const dtm_analysis *a) {
  const dtm_scene *s = dtm_analysis_scene(a);
  dtm_section_stats *st = calloc((size_t)s->nsections + 1, sizeof *st);
  cJSON *arr = cJSON_CreateArray();
  if (!st) return arr;
  dtm_analysis_sections(a, st);
  for (int i = 0; i < s->nsections; i++) {
    const dtm_section *sec = &s->sections[i];
    cJSON *o = cJSON_CreateObject(), *groups = cJSON_AddArrayToObject(o, "groups");
    cJSON_AddStringToObject(o, "kind", dtm_section_kind_name(sec->kind));
    for (int g = 0; g < sec->ngroups; g++) cJSON_AddItemToArray(groups, cJSON_CreateString(sec->groups[g]));
    cJSON_AddBoolToObject(o, "default", sec->is_default);
    if (sec->thickness > 0) cJSON_AddNumberToObject(o, "thickness", sec->thickness);
    if (sec->area > 0) cJSON_AddNumberToObject(o, "area", sec->area);
    cJSON_AddNumberToObject(o, "elements", (double)st[i].elements);
    if (isfinite(st[i].dt_min)) cJSON_AddNumberToObject(o, "dt_min", st[i].dt_min);
    if (isfinite(st[i].dt_min)) cJSON_AddNumberToObject(o, "element", (double)st[i].element);
    if (isfinite(st[i].anchor_min)) {
      cJSON *an = cJSON_AddObjectToObject(o, "anchor");
      cJSON_AddStringToObject(an, "rule", st[i].anchor);
      cJSON_AddNumberToObject(an, "dt_min", st[i].anchor_min);
    }
    if (isfinite(st[i].dt_physical_min)) rotary_json(o, sec, &st[i]);
    cJSON_AddItemToArray(arr, o);
  }
  free(st);
  return arr;
}

/* solvers[]: for each solver named, the step it takes with dtmap's deck,
 * why, and the hours (element-steps x its cost per element-step; null
 * where that cost is not known). */
static cJSON *solvers_json(const dtm_results *r) {
  cJSON *arr = cJSON_CreateArray();
  for (int i = 0; i < r->nsolvers; i++) {
    const dtm_solver_run *s = r->solver_runs[i];
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "solver", r->solver_names[i]);
    cJSON_AddNumberToObject(o, "step", s->step);
    cJSON_AddStringToObject(o, "basis", s->basis);
    dtm_report_number(o, "element_steps", s->element_steps);
    dtm_report_number(o, "cost_per_element_step", s->cost);
    cJSON_AddStringToObject(o, "cost_source", s->cost_source);
    dtm_report_number(o, "hours", s->hours);
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

cJSON *dtm_report_json(const dtm_results *r) {
  const dtm_analysis *a = r->analysis;
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "dtmap", DTM_VERSION);
  cJSON_AddStringToObject(root, "scene", dtm_analysis_scene(a)->path);
  cJSON_AddItemToObject(root, "mesh", mesh_json(a));
  cJSON_AddItemToObject(root, "model", dtm_report_model(a));
  cJSON *names = cJSON_AddArrayToObject(root, "effects");
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    cJSON_AddItemToArray(names, cJSON_CreateString(dtm_analysis_effect(a, k)->name));
  cJSON_AddItemToObject(root, "dt", dt_json(a));
  cJSON_AddItemToObject(root, "effect_minima", effects_detail(a));
  cJSON_AddItemToObject(root, "invalid_elements", invalid_json(a));
  if (dtm_analysis_curvature(a)->second_order) cJSON_AddItemToObject(root, "curvature", curvature_json(a));
  if (dtm_analysis_scene(a)->nsections) cJSON_AddItemToObject(root, "sections", sections_json(a));
  if (has_accuracy(a)) cJSON_AddItemToObject(root, "accuracy", accuracy_json(a));
  if (r->refine) cJSON_AddItemToObject(root, "refine", dtm_report_refine(r));
  if (dtm_analysis_point_masses(a)) cJSON_AddItemToObject(root, "point_masses", dtm_report_point_masses(a));
  if (r->cost) cJSON_AddItemToObject(root, "cost", dtm_report_cost(a, r->cost));
  if (r->nsolvers) cJSON_AddItemToObject(root, "solvers", solvers_json(r));
  if (r->modes) cJSON_AddItemToObject(root, "modes", dtm_report_modes(a, r->modes));
  if (r->cost) cJSON_AddItemToObject(root, "accuracy_measures", dtm_report_measures(a, r->cost->measures));
  if (r->cost) cJSON_AddItemToObject(root, "subcycling", dtm_report_subcycling(&r->cost->subcycling));
  if (r->cost && r->cost->mass) cJSON_AddItemToObject(root, "mass_scaling", dtm_report_mass(a, r->cost->mass, NULL));
  if (r->selective_mass) cJSON_AddItemToObject(root, "selective_mass", dtm_report_selective_mass(r));
  cJSON_AddItemToObject(root, "cohesive", dtm_report_zones(a));
  cJSON_AddItemToObject(root, "damping", dtm_report_damping(a));
  advice_json(r, root);
  cJSON_AddItemToObject(root, "worst", dtm_report_worst(r));
  cJSON_AddItemToObject(root, "warnings", warnings_json(r));
  cJSON_AddItemToObject(root, "timings", timings_json(r));
  dtm_report_units(root, a, 1);
  return root;
}

int dtm_json_write(struct cJSON *root, const char *path, const char *what) {
  char *text = root ? cJSON_Print(root) : NULL;
  cJSON_Delete(root);
  if (!text) return DTM_ERR(DTM_ERR_INTERNAL, "cannot build the %s", what);
  int rc = dtm_atomic_write_text(path, text, 1);
  free(text);
  return rc;
}

int dtm_report_write(const dtm_results *r, const char *path) {
  return dtm_json_write(dtm_report_json(r), path, "JSON report");
}
