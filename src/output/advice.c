/* The advice as the summary and the report show it: warnings (added mass
 * above 5 % of a group or of the model, a refined mesh that costs more
 * than its input and which accuracy bound makes it so, a target the
 * accuracy bounds forbid), the wording of shape-limited features and their
 * remedies, the damping factor per wave effect and material, the cohesive
 * process zone per material, and the smallest steps. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "output-impl.h"

void dtm_output_warn(dtm_warnings *w, const char *fmt, ...) {
  if (w->n >= DTM_WARN_MAX) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(w->text[w->n++], sizeof w->text[0], fmt, ap);
  va_end(ap);
}

void dtm_output_mass_warnings(const dtm_analysis *a, const dtm_mass_scaling *ms, const char *what, dtm_warnings *w) {
  char lbl[64];
  const dtm_mesh *m = dtm_analysis_mesh(a);
  double total = 100.0 * ms->total_added / ms->total_mass;
  if (total > DTM_MASS_WARN)
    dtm_output_warn(w, "%s adds %.3g %% to the model's mass (above %g %%: the dynamics change)", what, total,
                    DTM_MASS_WARN);
  for (int g = 0; g < ms->ngroups; g++) {
    double p = ms->group_mass[g] > 0 ? 100.0 * ms->group_added[g] / ms->group_mass[g] : 0;
    if (p > DTM_MASS_WARN)
      dtm_output_warn(w, "%s adds %.3g %% to the mass of group '%s' (above %g %%)", what, p,
                      dtm_mesh_group_label(m, g < m->ngroups ? g : -1, lbl, sizeof lbl), DTM_MASS_WARN);
  }
}

static void refine_warning(const dtm_refine_result *rr, dtm_warnings *w) {
  double c0 = dtm_refine_cost(&rr->rounds[0]), c1 = dtm_refine_cost(&rr->rounds[rr->best]);
  if (!(c1 > c0)) return;
  if (rr->forced_by && rr->forced > 0)
    dtm_output_warn(
        w,
        "the refined mesh costs %.3g %% more than the input: the accuracy bound '%s' asks for about %.0f more "
        "elements (%.3g element-steps at the refined step)",
        100.0 * (c1 / c0 - 1.0), rr->forced_by, rr->forced,
        rr->forced * rr->rounds[rr->best].element_steps / (double)rr->rounds[rr->best].elements);
  else
    dtm_output_warn(w, "the refined mesh costs %.3g %% more than the input", 100.0 * (c1 / c0 - 1.0));
}

void dtm_output_conflict_warning(dtm_warnings *w, const dtm_scene *s, const char *bound, double hmax, double dt_cap,
                                 size_t n) {
  dtm_output_warn(w,
                  "the target %.4e s is forbidden by the accuracy bound '%s': h <= %.4g %s caps the step at %.4e s "
                  "(%zu element(s))",
                  s->target, bound, hmax, dtm_unit_label(s, DTM_UNIT_LENGTH), dt_cap, n);
}

static void conflict_warning(const dtm_analysis *a, dtm_warnings *w) {
  dtm_accuracy ac;
  dtm_analysis_accuracy(a, &ac);
  if (!ac.conflicts) return;
  size_t i = ac.cap_element;
  dtm_output_conflict_warning(w, dtm_analysis_scene(a),
                              dtm_analysis_effect(a, dtm_analysis_hmax_by(a)[i])->indicator.view,
                              dtm_analysis_hmax(a)[i], ac.dt_cap, ac.conflicts);
}

/* A phase-speed error some element cannot carry: fewer than 2 cells per
 * wavelength at the frequency, so the error is unresolved, not small. */
static void unresolved_warning(const dtm_cost *c, dtm_warnings *w) {
  for (int k = 0; c->measures && k < c->measures->n; k++) {
    const dtm_measure *m = &c->measures->m[k];
    if (m->kind == DTM_MEASURE_PHASE && m->unresolved)
      dtm_output_warn(
          w,
          "%zu of %zu elements have fewer than 2 cells per wavelength at %.4g Hz%s: the phase-speed error is "
          "unresolved there (the mesh cannot carry that frequency; refine it or lower <time f-max>)",
          m->unresolved, m->elements, m->f, m->f_default ? " (the mesh's default frequency)" : "");
  }
}

/* Curved elements whose step depends on the integration rule. */
static void curvature_warning(const dtm_analysis *a, dtm_warnings *w) {
  const dtm_curvature_summary *s = dtm_analysis_curvature(a);
  if (!s->sensitive || w->n >= DTM_WARN_MAX) return;
  snprintf(w->text[w->n++], sizeof w->text[0],
           "%zu curved element%s a step that changes by more than 1e-3 with the integration rule (up to %.2g): "
           "the steps are for the %s integration; a solver integrating them otherwise has another stable step",
           s->sensitive, s->sensitive == 1 ? " has" : "s have", s->max_dependence,
           s->model == DTM_INTEGRATION_FULL ? "full-rule" : dtm_integration_name(s->model));
}

void dtm_output_warnings(const dtm_results *r, dtm_warnings *w) {
  w->n = 0;
  dtm_output_plausibility_warnings(r->analysis, w);
  if (r->cost && r->cost->mass) dtm_output_mass_warnings(r->analysis, r->cost->mass, "mass scaling to the target", w);
  if (r->cost && r->cost->shape_mass)
    dtm_output_mass_warnings(r->analysis, r->cost->shape_mass, "mass for the shape-limited elements", w);
  if (r->refine) refine_warning(r->refine, w);
  conflict_warning(r->analysis, w);
  dtm_output_outlier_warning(r->analysis, w);
  if (r->cost) unresolved_warning(r->cost, w);
  curvature_warning(r->analysis, w);
  dtm_output_section_warnings(r->analysis, w);
}

int dtm_output_warning_lines(const dtm_results *r, char *buf, size_t len) {
  dtm_warnings *w = malloc(sizeof *w);
  if (!w) return 0;
  dtm_output_warnings(r, w);
  size_t k = 0;
  if (len) buf[0] = '\0';
  for (int j = 0; j < w->n && k < len; j++) {
    int n = snprintf(buf + k, len - k, "%s\n", w->text[j]);
    k = n > 0 ? k + (size_t)n : k;
  }
  int n = w->n;
  free(w);
  return n;
}

const char *dtm_feature_name(int kind) {
  static const char *const names[] = {"none", "flat angle", "small angle", "short curve", "thin"};
  return kind >= 1 && kind <= 4 ? names[kind] : names[0];
}

const char *dtm_remedy_name(int remedy) {
  static const char *const names[] = {"none", "split the angle", "optimise", "mass"};
  return remedy >= 1 && remedy <= 3 ? names[remedy] : names[0];
}

static const char *entity_name(int dim) { return dim == 0 ? "point" : dim == 1 ? "curve" : "surface"; }

const char *dtm_feature_text(const dtm_analysis *a, const dtm_shape_limited *s, char *buf, size_t len) {
  const char *where = dtm_analysis_mesh(a)->dim == 2 ? "angle between model curves" : "dihedral between model surfaces";
  switch (s->feature) {
  case DTM_FEATURE_FLAT_ANGLE:
  case DTM_FEATURE_SMALL_ANGLE:
    snprintf(buf, len, "%.1f deg %s at model %s %d%s", s->angle, where, entity_name(s->entity_dim), s->entity_tag,
             s->feature == DTM_FEATURE_FLAT_ANGLE ? ", held by this one element" : "");
    break;
  case DTM_FEATURE_SHORT_CURVE:
    snprintf(buf, len, "model curve %d is %.3g %s long", s->entity_tag, s->size, dtm_output_unit(a, DTM_UNIT_LENGTH));
    break;
  default:
    snprintf(buf, len, "thin: boundaries %.3g %s apart (model %s %d)", s->size, dtm_output_unit(a, DTM_UNIT_LENGTH),
             entity_name(s->entity_dim), s->entity_tag);
  }
  return buf;
}

const char *dtm_layer_faces_text(const dtm_layer *l, char *buf, size_t len) {
  if (l->faces[0][0] == l->faces[1][0])
    snprintf(buf, len, "between model %ss %d and %d", entity_name(l->faces[0][0]), l->faces[0][1], l->faces[1][1]);
  else
    snprintf(buf, len, "between model %s %d and model %s %d", entity_name(l->faces[0][0]), l->faces[0][1],
             entity_name(l->faces[1][0]), l->faces[1][1]);
  return buf;
}

/* The mass added at the nodes of layer k's elements, each node once (the
 * nodal form), else the mass of its elements (element by element). */
double dtm_layer_added_mass(const dtm_results *r, size_t k) {
  const dtm_mass_scaling *ms = r->cost ? r->cost->layer_mass : NULL;
  const dtm_mesh *m = dtm_analysis_mesh(r->analysis);
  size_t n;
  const dtm_shape_limited *sl = dtm_analysis_shape_limited(r->analysis, &n);
  double sum = 0;
  if (!ms || !ms->added) return NAN;
  unsigned char *seen = ms->node_added ? calloc(m->nnodes + 1, 1) : NULL;
  if (ms->node_added && !seen) return NAN;
  for (size_t j = 0; j < n; j++) {
    int b;
    size_t e;
    if (sl[j].layer != (int)k) continue;
    if (!seen) {
      sum += ms->added[sl[j].element];
      continue;
    }
    dtm_analysis_locate(r->analysis, sl[j].element, &b, &e);
    const dtm_block *blk = &m->blocks[b];
    for (int q = 0; q < blk->nn; q++) {
      size_t v = blk->conn[e * blk->nn + q];
      if (!seen[v]) seen[v] = 1, sum += ms->node_added[v];
    }
  }
  free(seen);
  return sum;
}

const char *dtm_remedy_text(const dtm_results *r, const dtm_shape_limited *s, char *buf, size_t len) {
  const dtm_mass_scaling *ms = r->cost ? r->cost->shape_mass : NULL;
  if (s->remedy == DTM_REMEDY_SPLIT)
    snprintf(buf, len, "split the angle: a local size of %.3g %s at model point %d", s->split,
             dtm_output_unit(r->analysis, DTM_UNIT_LENGTH), s->entity_tag);
  else if (s->remedy == DTM_REMEDY_OPTIMISE)
    snprintf(buf, len, "an optimiser pass (swaps) at model %s %d", entity_name(s->entity_dim), s->entity_tag);
  else if (ms)
    snprintf(buf, len, "mass scaling: +%.3g %s at its nodes", ms->added[s->element],
             dtm_output_unit(r->analysis, DTM_UNIT_MASS));
  else
    snprintf(buf, len, "mass scaling at its nodes");
  return buf;
}

/* Undamped top frequency of wave effect k where its basis sits. */
static double basis_omega(const dtm_analysis *a, int k) {
  const dtm_global_info *g = dtm_analysis_global(a, k);
  if (g && g->converged && !strcmp(dtm_analysis_basis(a), "global estimate")) return g->omega_top;
  return dtm_analysis_effect_min(a, k)->omega;
}

static int has_damping(const dtm_analysis *a) {
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    if (dtm_analysis_effect(a, k)->role & DTM_ROLE_MODIFIES_WAVES) return 1;
  return 0;
}

/* Range of dt / undamped dt over the elements of material mat. */
static void element_range(const dtm_analysis *a, int k, int mat, dtm_damping_row *row) {
  const double *dt = dtm_analysis_effect_dt(a, k), *bare = dtm_analysis_effect_dt_undamped(a, k);
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t first = 0;
  row->emin = INFINITY, row->emax = -INFINITY;
  for (int b = 0; b < m->nblocks; first += m->blocks[b].n, b++)
    for (size_t e = 0; e < m->blocks[b].n; e++) {
      size_t i = first + e;
      if (m->blocks[b].mat[e] != mat || !isfinite(dt[i]) || !(bare[i] > 0)) continue;
      row->emin = fmin(row->emin, dt[i] / bare[i]), row->emax = fmax(row->emax, dt[i] / bare[i]);
    }
}

int dtm_damping_rows(const dtm_analysis *a, dtm_damping_row **rows, int *n) {
  int nm = dtm_analysis_scene(a)->nmaterials, ne = dtm_analysis_neffects(a);
  char *used = calloc((size_t)nm + 1, 1);
  *rows = malloc(((size_t)nm * (size_t)ne + 1) * sizeof **rows), *n = 0;
  if (!used || !*rows) return free(used), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  dtm_mesh_materials_used(dtm_analysis_mesh(a), nm, used);
  int r = DTM_OK;
  for (int k = 0; k < ne && r == DTM_OK && has_damping(a); k++) {
    if (!dtm_analysis_effect_dt(a, k) || !dtm_effect_is_wave(dtm_analysis_effect(a, k))) continue;
    for (int i = 0; i < nm && r == DTM_OK; i++) {
      if (!used[i]) continue;
      dtm_damping_row *row = &(*rows)[*n];
      row->effect = k, row->mat = i, row->omega = basis_omega(a, k);
      r = dtm_analysis_wave_factor(a, i, row->omega, &row->factor);
      element_range(a, k, i, row);
      *n += isfinite(row->emin); /* only where the effect applies to the material */
    }
  }
  free(used);
  return r;
}

static int is_cohesive(const dtm_analysis *a, int k) {
  const dtm_effect_class *c = dtm_analysis_effect(a, k);
  return !strcmp(c->name, "cohesive") && dtm_analysis_resolution(a, k) && dtm_analysis_effect_hmax(a, k);
}

/* R = (R/h) h and h_max of the first element of material mat where the
 * zone applies. */
static int zone_of(const dtm_analysis *a, int k, int mat, dtm_zone_row *row) {
  const double *res = dtm_analysis_resolution(a, k), *hm = dtm_analysis_effect_hmax(a, k), *h = dtm_analysis_size(a);
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t first = 0;
  for (int b = 0; b < m->nblocks; first += m->blocks[b].n, b++)
    for (size_t e = 0; e < m->blocks[b].n; e++)
      if (m->blocks[b].mat[e] == mat && isfinite(res[first + e])) {
        *row = (dtm_zone_row){k, mat, res[first + e] * h[first + e], hm[first + e]};
        return 1;
      }
  return 0;
}

int dtm_zone_rows(const dtm_analysis *a, dtm_zone_row **rows, int *n) {
  int nm = dtm_analysis_scene(a)->nmaterials, ne = dtm_analysis_neffects(a);
  *rows = malloc(((size_t)nm * (size_t)ne + 1) * sizeof **rows), *n = 0;
  if (!*rows) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int k = 0; k < ne; k++)
    for (int i = 0; i < nm && is_cohesive(a, k); i++) *n += zone_of(a, k, i, &(*rows)[*n]);
  return DTM_OK;
}

int dtm_results_top(const dtm_results *r) { return r->top > 0 ? r->top : r->top < 0 ? 0 : DTM_TOP_DEFAULT; }

int dtm_worst(const dtm_analysis *a, int top, size_t **out) {
  const double *dt = dtm_analysis_dt(a);
  size_t *idx = malloc(((size_t)top + 1) * sizeof *idx);
  int k = 0;
  *out = idx;
  for (size_t i = 0; idx && top > 0 && i < dtm_analysis_nelements(a); i++) {
    if (k == top && dt[i] >= dt[idx[k - 1]]) continue;
    int j = k < top ? k++ : top - 1;
    while (j > 0 && dt[idx[j - 1]] > dt[i]) idx[j] = idx[j - 1], j--;
    idx[j] = i;
  }
  return k;
}
