/* The refine part of the JSON report: each round (what it was, its basis,
 * how far short of the target, its cost, what was applied: the size
 * field's calibration, the transfinite counts set, Gmsh's optimisers, the
 * point masses), the kept round and why the loop stopped, the causes of a
 * target the mesh alone does not meet, the counts refine set, and the ways
 * found (mesh only, mesh and point masses, the kept mesh with selective
 * mass scaling beside the point masses of deck --target's rule, subcycling
 * on the kept mesh).
 * Also the point masses a mesh carries (refine's, or read back with the
 * .msh): their total, share of the model's mass, nodes, the groups their
 * elements' shares fall in, and the largest by node. */
#include <cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "dtmap/cost.h"
#include "output-impl.h"
#include "report.h"

#define TOP_NODES 10 /* nodes listed with the largest point masses */

static const char *const kind_names[] = {"input", "mesh", "mass"};

/* Gmsh's optimiser passes of bits, by name. */
static cJSON *optimisers_json(unsigned bits) {
  static const struct {
    unsigned bit;
    const char *name;
  } names[] = {{DTM_OPTIMISE_GMSH, "gmsh"},
               {DTM_OPTIMISE_NETGEN, "netgen"},
               {DTM_OPTIMISE_RELOCATE, "relocate"},
               {DTM_OPTIMISE_LAPLACE2D, "laplace"}};
  cJSON *arr = cJSON_CreateArray();
  for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
    if (bits & names[k].bit) cJSON_AddItemToArray(arr, cJSON_CreateString(names[k].name));
  return arr;
}

static cJSON *round_json(const dtm_refine_result *rr, int i) {
  const dtm_refine_round *r = &rr->rounds[i];
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "round", i);
  cJSON_AddStringToObject(o, "kind", kind_names[r->kind]);
  cJSON_AddStringToObject(o, "basis", r->basis);
  cJSON_AddNumberToObject(o, "elements", (double)r->elements);
  cJSON_AddNumberToObject(o, "dt_min", r->dt_min);
  cJSON_AddNumberToObject(o, "recommended", r->recommended);
  cJSON_AddNumberToObject(o, "gap", r->gap);
  dtm_report_number(o, "element_steps", r->element_steps);
  cJSON_AddNumberToObject(o, "element_steps_per_second", r->rate);
  cJSON_AddNumberToObject(o, "below_target", (double)r->below);
  cJSON_AddNumberToObject(o, "shape_limited", (double)r->shape_limited);
  cJSON_AddNumberToObject(o, "seconds", r->seconds);
  if (r->kind != DTM_ROUND_MESH) return o;
  if (r->strategy) cJSON_AddStringToObject(o, "strategy", r->strategy);
  if (isfinite(r->uniform)) cJSON_AddNumberToObject(o, "uniform_size", r->uniform);
  cJSON_AddNumberToObject(o, "mesh_seconds", r->mesh_seconds);
  if (isfinite(r->calibration)) cJSON_AddNumberToObject(o, "calibration", r->calibration);
  cJSON_AddNumberToObject(o, "counts", r->counts);
  cJSON_AddItemToObject(o, "optimisers", optimisers_json(r->optimise));
  return o;
}

static void mass_round_json(cJSON *o, const dtm_refine_round *r) {
  cJSON_AddNumberToObject(o, "added_mass", r->added_mass);
  cJSON_AddNumberToObject(o, "added_percent", r->added_percent);
  cJSON_AddNumberToObject(o, "mass_nodes", (double)r->mass_nodes);
}

static cJSON *cause_json(const dtm_cause *c) {
  cJSON *o = cJSON_CreateObject(), *ents;
  cJSON_AddStringToObject(o, "kind", c->kind);
  cJSON_AddStringToObject(o, "message", c->text);
  ents = cJSON_AddArrayToObject(o, "entities");
  for (int i = 0; i < c->nent && i < DTM_CAUSE_ENTITIES; i++) {
    cJSON *e = cJSON_CreateObject();
    cJSON_AddNumberToObject(e, "dim", c->dim[i]);
    cJSON_AddNumberToObject(e, "tag", c->tag[i]);
    cJSON_AddItemToArray(ents, e);
  }
  if (c->nent > DTM_CAUSE_ENTITIES) cJSON_AddNumberToObject(o, "entities_total", c->nent);
  if (c->fix[0]) cJSON_AddStringToObject(o, "fix", c->fix);
  return o;
}

static cJSON *counts_json(const dtm_refine_result *rr) {
  cJSON *arr = cJSON_CreateArray();
  for (int i = 0; i < rr->ncounts; i++) {
    cJSON *c = cJSON_CreateObject();
    cJSON_AddNumberToObject(c, "curve", rr->counts[i].tag);
    cJSON_AddNumberToObject(c, "from", rr->counts[i].from);
    cJSON_AddNumberToObject(c, "to", rr->counts[i].to);
    cJSON_AddItemToArray(arr, c);
  }
  return arr;
}

/* A way to the target: the cheapest round of that kind that meets it. */
static cJSON *way_json(const dtm_refine_result *rr, int kind) {
  int best = -1;
  for (int i = 1; i < rr->nrounds; i++) {
    const dtm_refine_round *r = &rr->rounds[i];
    if (r->kind == kind && r->recommended >= rr->target &&
        (best < 0 || dtm_refine_cost(r) < dtm_refine_cost(&rr->rounds[best])))
      best = i;
  }
  if (best < 0) return cJSON_CreateNull();
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "round", best);
  cJSON_AddNumberToObject(o, "cost_ratio", dtm_refine_cost(&rr->rounds[best]) / dtm_refine_cost(&rr->rounds[0]));
  return o;
}

static const char *const sms_states[] = {"not asked", "not needed", "refused", "computed"};

/* The point masses the selective way is compared with. */
static cJSON *conventional_json(const dtm_refine_selective *w) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "rule", "deck --target: every nodal bound lifted to target / safety");
  dtm_report_number(o, "added_mass", w->conventional_added);
  dtm_report_number(o, "added_percent", w->conventional_percent);
  cJSON_AddNumberToObject(o, "nodes", (double)w->conventional_nodes);
  return o;
}

/* The way mesh + selective mass: null when not asked, else its state,
 * and when computed the kept mesh's round scaled, the run-time figures
 * against the input and the whole selective_mass object of that mesh. */
static cJSON *selective_way_json(const dtm_results *r) {
  const dtm_refine_result *rr = r->refine;
  const dtm_refine_selective *w = &rr->selective;
  if (w->state == DTM_REFINE_SMS_NOT_ASKED) return cJSON_CreateNull();
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "state", sms_states[w->state]);
  if (w->state == DTM_REFINE_SMS_REFUSED) cJSON_AddStringToObject(o, "why", w->why);
  if (w->state != DTM_REFINE_SMS_DONE) return o;
  dtm_results one = *r;
  one.selective_mass = &w->sms;
  cJSON_AddNumberToObject(o, "round", w->round);
  cJSON_AddNumberToObject(o, "lumped_recommended", w->lumped);
  cJSON_AddNumberToObject(o, "cost_ratio", dtm_refine_selective_cost(rr) / dtm_refine_cost(&rr->rounds[0]));
  cJSON_AddNumberToObject(o, "runtime_ratio", w->sms.runtime_factor * w->lumped / w->sms.recommended);
  cJSON_AddItemToObject(o, "conventional", conventional_json(w));
  cJSON_AddItemToObject(o, "selective_mass", dtm_report_selective_mass(&one));
  return o;
}

static cJSON *ways_json(const dtm_results *r) {
  const dtm_refine_result *rr = r->refine;
  cJSON *o = cJSON_CreateObject();
  cJSON_AddItemToObject(o, "mesh", way_json(rr, DTM_ROUND_MESH));
  cJSON_AddItemToObject(o, "mesh_and_mass", way_json(rr, DTM_ROUND_MASS));
  cJSON_AddItemToObject(o, "mesh_and_selective_mass", selective_way_json(r));
  if (r->cost) {
    cJSON *s = cJSON_AddObjectToObject(o, "subcycling");
    double c = dtm_refine_cost(&rr->rounds[rr->best]) / dtm_refine_cost(&rr->rounds[0]);
    cJSON_AddNumberToObject(s, "speedup", r->cost->subcycling.speedup);
    cJSON_AddNumberToObject(s, "cost_ratio", c / r->cost->subcycling.speedup);
  }
  return o;
}

/* How the kept round met the target: "input", "mesh", "mesh and point
 * masses", or "not met". */
static const char *met_by(const dtm_refine_result *rr) {
  const dtm_refine_round *b = &rr->rounds[rr->best];
  if (b->recommended < rr->target) return "not met";
  return b->kind == DTM_ROUND_INPUT ? "input" : b->kind == DTM_ROUND_MESH ? "mesh" : "mesh and point masses";
}

cJSON *dtm_report_refine(const dtm_results *r) {
  const dtm_refine_result *rr = r->refine;
  cJSON *o = cJSON_CreateObject(), *arr = cJSON_AddArrayToObject(o, "rounds");
  for (int i = 0; i < rr->nrounds; i++) {
    cJSON *ro = round_json(rr, i);
    if (rr->rounds[i].kind == DTM_ROUND_MASS) mass_round_json(ro, &rr->rounds[i]);
    cJSON_AddItemToArray(arr, ro);
  }
  cJSON_AddNumberToObject(o, "target", rr->target);
  cJSON_AddStringToObject(o, "basis", rr->options.global ? "global estimate" : "nodal bound");
  cJSON_AddNumberToObject(o, "best", rr->best);
  cJSON_AddStringToObject(o, "stopped", dtm_refine_stop_text(rr->stop));
  cJSON_AddBoolToObject(o, "met", rr->rounds[rr->best].recommended >= rr->target);
  cJSON_AddStringToObject(o, "met_by", met_by(rr));
  double c0 = dtm_refine_cost(&rr->rounds[0]), c1 = dtm_refine_cost(&rr->rounds[rr->best]);
  cJSON_AddNumberToObject(o, "cost_change", c1 / c0 - 1.0);
  cJSON_AddNumberToObject(o, "element_bound", rr->element_bound);
  if (isfinite(rr->mass_needed)) cJSON_AddNumberToObject(o, "mass_needed_percent", rr->mass_needed);
  if (isfinite(rr->mass_needed)) cJSON_AddStringToObject(o, "mass_needed_by", rr->mass_least ? "search" : "rule");
  if (rr->uniform > 0) cJSON_AddNumberToObject(o, "uniform_size", rr->uniform);
  if (rr->forced_by) cJSON_AddStringToObject(o, "accuracy_bound", rr->forced_by);
  if (rr->forced_by) cJSON_AddNumberToObject(o, "accuracy_elements", rr->forced);
  cJSON_AddItemToObject(o, "counts", counts_json(rr));
  cJSON *causes = cJSON_AddArrayToObject(o, "causes");
  for (int i = 0; i < rr->ncauses; i++) cJSON_AddItemToArray(causes, cause_json(&rr->causes[i]));
  cJSON_AddItemToObject(o, "ways", ways_json(r));
  return o;
}

/* The TOP_NODES nodes with the largest masses m[nnodes], by Gmsh tag. */
static cJSON *largest_nodes(const dtm_mesh *mesh, const double *m) {
  size_t idx[TOP_NODES];
  int k = dtm_report_largest(m, mesh->nnodes, idx, TOP_NODES);
  cJSON *arr = cJSON_CreateArray();
  for (int r = 0; r < k; r++) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "node", (double)mesh->node_tags[idx[r]]);
    cJSON_AddNumberToObject(o, "mass", m[idx[r]]);
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

/* The groups the elements' shares of the masses fall in. */
static cJSON *groups_json(const dtm_mesh *mesh, const dtm_mass_scaling *ms) {
  cJSON *arr = cJSON_CreateArray();
  char lbl[64];
  for (int g = 0; g < ms->ngroups; g++) {
    if (!(ms->group_added[g] > 0)) continue;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "group", dtm_mesh_group_label(mesh, g < mesh->ngroups ? g : -1, lbl, sizeof lbl));
    cJSON_AddNumberToObject(o, "mass", ms->group_added[g]);
    cJSON_AddNumberToObject(o, "percent", 100.0 * ms->group_added[g] / ms->group_mass[g]);
    cJSON_AddItemToArray(arr, o);
  }
  return arr;
}

cJSON *dtm_report_point_masses(const dtm_analysis *a) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  const double *pm = dtm_analysis_point_masses(a);
  dtm_mass_scaling ms;
  if (dtm_mass_scaling_of_nodes(a, pm, NAN, &ms)) return dtm_error_clear(), cJSON_CreateNull();
  cJSON *o = cJSON_CreateObject();
  cJSON_AddStringToObject(o, "view", DTM_VIEW_NODE_MASS);
  cJSON_AddNumberToObject(o, "total", ms.total_added);
  cJSON_AddNumberToObject(o, "percent", 100.0 * ms.total_added / ms.total_mass);
  cJSON_AddNumberToObject(o, "nodes", (double)ms.nodes);
  cJSON_AddItemToObject(o, "groups", groups_json(mesh, &ms));
  cJSON_AddItemToObject(o, "largest_nodes", largest_nodes(mesh, pm));
  dtm_mass_scaling_free(&ms);
  return o;
}
