/* The JSON report of a distributed run, written by rank 0 from the global
 * figures (figures.c): the fields of the serial report under the same
 * names and meanings (mesh counts, effects, dt with where the minimum is,
 * each effect's minima and global estimate, accuracy, subcycling, mass
 * scaling, timings: the slowest part's; the lists of individual elements
 * merged from the parts' own), plus "parallel": ranks, the eigensolver,
 * and per part its elements (they sum to
 * mesh.elements), nodes (own and ghost), peak memory, stage times and,
 * for the global estimate, the CPU time of its operator products and the
 * wall time of their ghost exchanges. */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "parallel-impl.h"
#include "report.h"

static cJSON *where_json(const dtm_par_where *w) {
  cJSON *o = cJSON_CreateObject();
  if (!w->found) return o;
  cJSON_AddNumberToObject(o, "element", (double)w->tag);
  cJSON_AddStringToObject(o, "group", w->group);
  cJSON_AddItemToObject(o, "centroid", cJSON_CreateDoubleArray(w->centroid, 3));
  return o;
}

static cJSON *dt_json(const dtm_analysis *a, const dtm_par_figures *f) {
  cJSON *dt = where_json(&f->dt);
  dtm_report_steps(dt, a, f->dt.effect);
  return dt;
}

static cJSON *effect_json(const dtm_analysis *a, const dtm_par_figures *f, int k) {
  cJSON *o = dtm_analysis_effect_dt(a, k) ? where_json(&f->element[k]) : cJSON_CreateObject();
  dtm_report_effect(o, a, k, f->node[k].tag);
  return o;
}

static int has_accuracy(const dtm_analysis *a) {
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    if (dtm_analysis_resolution(a, k)) return 1;
  return 0;
}

static cJSON *accuracy_json(const dtm_analysis *a, const dtm_par_figures *f) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "under_resolved", f->under_resolved);
  cJSON_AddItemToObject(o, "under_resolved_elements", cJSON_Duplicate(f->under_list, 1));
  cJSON_AddNumberToObject(o, "listed_at_most", DTM_REPORT_LISTED);
  cJSON_AddNumberToObject(o, "target_conflicts", f->conflicts);
  if (!f->conflicts) return o;
  cJSON_AddNumberToObject(o, "dt_allowed_by_accuracy", f->dt_cap);
  cJSON_AddStringToObject(o, "binding_bound", dtm_analysis_effect(a, f->cap_effect)->indicator.view);
  cJSON_AddNumberToObject(o, "binding_hmax", f->cap_hmax);
  cJSON_AddNumberToObject(o, "binding_element", (double)f->cap.tag);
  double d = dtm_analysis_scene(a)->duration;
  if (d > 0) cJSON_AddNumberToObject(o, "element_steps_at_cap", f->elements * d / f->dt_cap);
  return o;
}

/* The cost of the whole mesh: the serial cost's figures from its element
 * count and the summed subcycling. */
static cJSON *cost_json(const dtm_par *p, const dtm_par_figures *f) {
  dtm_cost c = *p->cost;
  dtm_par_whole_cost(p, f, &c);
  if (c.duration > 0)
    c.element_steps = f->elements * c.steps, c.element_steps_subcycled = c.element_steps / f->sub.speedup;
  return dtm_report_cost(p->analysis, &c);
}

cJSON *dtm_par_warnings(const dtm_par *p, const dtm_par_figures *f) {
  const dtm_analysis *a = p->analysis;
  dtm_report_conflict c = {(size_t)f->conflicts, f->dt_cap, f->cap_hmax, NULL};
  if (f->conflicts) c.bound = dtm_analysis_effect(a, f->cap_effect)->indicator.view;
  char note[256];
  snprintf(note, sizeof note,
           "%.0f element(s) below the target: the scene's part files hold no model, so a distributed run of them "
           "does not tell which are shape-limited; run the scene of the one mesh for that advice",
           f->below);
  return dtm_report_warnings_of(a, f->mass, &c, p->scene->target > 0 && f->below > 0 && !p->advice ? note : NULL);
}

/* Column c of the per-part rows. */
static cJSON *column(const dtm_par *p, const dtm_par_figures *f, int c) {
  cJSON *arr = cJSON_CreateArray();
  for (int r = 0; r < p->size; r++) cJSON_AddItemToArray(arr, cJSON_CreateNumber(f->rows[r * ROW_COUNT + c]));
  return arr;
}

/* The slowest part's time of stage t. */
static double slowest(const dtm_par *p, const dtm_par_figures *f, int t) {
  double s = 0;
  for (int r = 0; r < p->size; r++) s = fmax(s, f->rows[r * ROW_COUNT + ROW_T + t]);
  return s;
}

static const char *const stage_names[PAR_T_COUNT] = {"read",  "extract", "layout", "effects",
                                                     "nodal", "global",  "output"};

static cJSON *parallel_json(const dtm_par *p, const dtm_par_figures *f) {
  cJSON *o = cJSON_CreateObject(), *t = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "ranks", p->size);
  cJSON_AddStringToObject(o, "parts",
                          p->scene->partitions ? "the scene's part files" : "split by rank 0 (Gmsh, METIS)");
  cJSON_AddStringToObject(o, "eigensolver", "SLEPc Krylov-Schur"); /* the global estimate */
  cJSON_AddItemToObject(o, "elements", column(p, f, ROW_ELEMENTS));
  cJSON_AddItemToObject(o, "nodes", column(p, f, ROW_NODES));
  cJSON_AddItemToObject(o, "owned_nodes", column(p, f, ROW_OWNED));
  cJSON_AddItemToObject(o, "ghost_nodes", column(p, f, ROW_GHOSTS));
  cJSON_AddItemToObject(o, "memory_bytes", column(p, f, ROW_MEMORY));
  for (int s = 0; s < PAR_T_COUNT; s++) cJSON_AddItemToObject(t, stage_names[s], column(p, f, ROW_T + s));
  cJSON_AddItemToObject(t, "products_cpu", column(p, f, ROW_PRODUCT_CPU)); /* the part's own work */
  cJSON_AddItemToObject(t, "exchange", column(p, f, ROW_EXCHANGE));        /* ghost scatters, wall */
  cJSON_AddItemToObject(o, "timings", t);
  return o;
}

static cJSON *timings_json(const dtm_par *p, const dtm_parallel_opts *o, const dtm_par_figures *f) {
  static const int stage[] = {PAR_T_READ, PAR_T_EXTRACT, PAR_T_EFFECTS, PAR_T_NODAL, PAR_T_GLOBAL, PAR_T_OUTPUT};
  static const char *const names[] = {"mesh", "extract", "effects", "nodal", "global", "output"};
  cJSON *t = cJSON_CreateObject();
  cJSON_AddNumberToObject(t, "scene", o->t_scene);
  for (size_t i = 0; i < sizeof stage / sizeof *stage; i++)
    cJSON_AddNumberToObject(t, names[i], slowest(p, f, stage[i]));
  /* the classification runs on rank 0's whole mesh */
  cJSON_AddNumberToObject(t, "advice", p->advice ? dtm_analysis_timing(p->advice, DTM_T_ADVICE) : 0.0);
  cJSON_AddNumberToObject(t, "threads", dtm_analysis_threads(p->analysis));
  return t;
}

/* The shape-limited elements and the layers, from rank 0's whole mesh
 * (none when the scene's part files hold no model). */
static void advice_json(const dtm_par *p, const dtm_par_figures *f, cJSON *root) {
  dtm_cost c = *p->cost;
  dtm_par_whole_cost(p, f, &c);
  c.subcycling = f->sub, c.shape_mass = c.layer_mass = NULL; /* the parts' masses are indexed by part */
  dtm_results res = {p->advice, &c, NULL, 0.0, 0.0, 0, 0, {NULL}, {NULL}, NULL, NULL};
  size_t n = 0;
  if (p->advice) dtm_analysis_shape_limited(p->advice, &n);
  cJSON_AddItemToObject(root, "shape_limited", p->advice ? dtm_report_shape(&res) : cJSON_CreateArray());
  cJSON_AddNumberToObject(root, "shape_limited_count", (double)n);
  cJSON_AddNumberToObject(root, "below_target", f->below);
  cJSON_AddItemToObject(root, "thickness_limited", p->advice ? dtm_report_layers(&res) : cJSON_CreateArray());
}

static cJSON *report_json(const dtm_par *p, const dtm_parallel_opts *o, const dtm_par_figures *f) {
  const dtm_analysis *a = p->analysis;
  cJSON *root = cJSON_CreateObject(), *mesh = cJSON_CreateObject(), *names;
  cJSON_AddStringToObject(root, "dtmap", DTM_VERSION);
  cJSON_AddStringToObject(root, "scene", p->scene->path);
  cJSON_AddNumberToObject(mesh, "elements", f->elements);
  cJSON_AddNumberToObject(mesh, "nodes", f->nodes);
  cJSON_AddNumberToObject(mesh, "dim", p->dim);
  cJSON_AddStringToObject(mesh, "algorithm", dtm_scene_algorithm_name(p->mesher.algorithm));
  cJSON_AddNumberToObject(mesh, "threads", p->mesher.threads);
  cJSON_AddBoolToObject(mesh, "reproducible", p->mesher.reproducible);
  cJSON_AddItemToObject(root, "mesh", mesh);
  names = cJSON_AddArrayToObject(root, "effects");
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    cJSON_AddItemToArray(names, cJSON_CreateString(dtm_analysis_effect(a, k)->name));
  cJSON_AddItemToObject(root, "dt", dt_json(a, f));
  cJSON *minima = cJSON_AddArrayToObject(root, "effect_minima");
  for (int k = 0; k < dtm_analysis_neffects(a); k++) cJSON_AddItemToArray(minima, effect_json(a, f, k));
  if (has_accuracy(a)) cJSON_AddItemToObject(root, "accuracy", accuracy_json(a, f));
  cJSON_AddItemToObject(root, "cost", cost_json(p, f));
  cJSON_AddItemToObject(root, "subcycling", dtm_report_subcycling(&f->sub));
  if (f->mass)
    cJSON_AddItemToObject(root, "mass_scaling", dtm_report_mass(a, f->mass, cJSON_Duplicate(f->most_added, 1)));
  cJSON_AddItemToObject(root, "cohesive", cJSON_Duplicate(f->zones, 1));
  cJSON_AddItemToObject(root, "damping", cJSON_Duplicate(f->damping, 1));
  advice_json(p, f, root);
  cJSON_AddItemToObject(root, "worst", cJSON_Duplicate(f->worst, 1));
  cJSON_AddItemToObject(root, "warnings", dtm_par_warnings(p, f));
  cJSON_AddItemToObject(root, "timings", timings_json(p, o, f));
  cJSON_AddItemToObject(root, "parallel", parallel_json(p, f));
  dtm_report_units(root, a, 1);
  return root;
}

int dtm_par_report(const dtm_par *p, const dtm_parallel_opts *o, const dtm_par_figures *f, char **json) {
  cJSON *root = report_json(p, o, f);
  *json = root ? cJSON_Print(root) : NULL;
  cJSON_Delete(root);
  return *json ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "cannot build the JSON report");
}
