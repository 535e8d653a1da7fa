/* Mass scaling, the alternative to remeshing for a target step, in the two
 * forms of include/dtmap/cost.h. Element by element: every element whose
 * own wave step dt_e (the smallest over the wave-type effects, exponent 1,
 * damping already applied) is below the target dt_t gets
 * m_e ((dt_t/dt_e)^2 - 1) of added mass, m_e = rho_e V_e with V_e the
 * element's measure (times its section's thickness or area when it has one;
 * else per unit thickness in 2D, per unit cross-section in
 * 1D). At the nodes: node a of lumped mass m_a = sum_e m_e w_ea (w the
 * element's lumped weights) whose nodal-bound step dt_a (the smallest over
 * the spectral wave effects) is below dt_t needs m_a (dt_t/dt_a)^2 in all;
 * the non-spectral wave effects are first met element by element, which
 * already adds to the node masses. A point mass the mesh already carries
 * counts in m_a. Node mass is attributed to the elements
 * around the node in proportion to their share of it. Reported per
 * element, per physical group (the last slot collects the elements in no
 * group) and in total. Elements whose material has no density count no
 * mass; elements without a finite wave step get none. In one part of a
 * distributed run the node masses are summed over the parts sharing a
 * node, so each part's elements get their share of the whole node's
 * addition. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "distributed.h"
#include "dtmap/cost.h"
#include "dtmap/error.h"
#include "dtmap/kernel.h"

/* The element's own wave step: min over the wave-type effects (only the
 * non-spectral ones when spectral_too is 0), s; +inf when none limits it. */
static double wave_dt_of(const dtm_analysis *a, size_t i, int spectral_too) {
  double dt = INFINITY;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const double *dk = dtm_analysis_effect_dt(a, k);
    if (!spectral_too && dtm_analysis_effect_nodal(a, k)) continue;
    if (dk && dtm_effect_is_wave(dtm_analysis_effect(a, k)) && dk[i] < dt) dt = dk[i];
  }
  return dt;
}

static double wave_dt(const dtm_analysis *a, size_t i) { return wave_dt_of(a, i, 1); }

/* rho V of element e of block blk, kg (0 without a density), times its
 * section's thickness or area (a truss: rho A L), and its lumped weights
 * w[nn] when w is not NULL. */
static double element_mass_w(const dtm_analysis *a, const dtm_block *blk, size_t e, int irho, double *w) {
  int mi = blk->mat[e];
  if (mi < 0) return 0.0;
  const dtm_material *m = &dtm_analysis_scene(a)->materials[mi].m;
  if (!dtm_material_has(m, irho)) return 0.0;
  double x[DTM_MAX_NODES * 3];
  dtm_block one = *blk;
  one.n = 1;
  one.conn = blk->conn + e * (size_t)blk->nn;
  dtm_mesh_gather(dtm_analysis_mesh(a), &one, x);
  double v = fabs(dtm_elem_measure(blk->type, x));
  if (w) dtm_elem_lumped_weights(blk->type, x, w);
  double f = blk->section && blk->section[e] >= 0
                 ? dtm_section_factor(&dtm_analysis_scene(a)->sections[blk->section[e]])
                 : 1.0;
  return isfinite(v) ? dtm_material_get(m, irho) * v * f : 0.0;
}

/* Index of the density among the scene's properties. */
static int rho_index(const dtm_analysis *a) { return dtm_scene_property_index(dtm_analysis_scene(a), "rho"); }

/* One element as the passes below see it. */
typedef struct {
  const dtm_block *blk;    /* its block */
  size_t e, i;             /* index in the block, global index */
  double m;                /* rho V, kg */
  double w[DTM_MAX_NODES]; /* lumped weights (when asked for) */
} elem;

typedef void (*elem_fn)(const dtm_analysis *a, const elem *el, void *ctx);

/* Call fn on every element, in the global order. */
static void each_element(const dtm_analysis *a, int weights, elem_fn fn, void *ctx) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  int irho = rho_index(a);
  size_t first = 0;
  elem el;
  for (int b = 0; b < m->nblocks; first += m->blocks[b].n, b++)
    for (size_t e = 0; e < m->blocks[b].n; e++) {
      el.blk = &m->blocks[b], el.e = e, el.i = first + e;
      el.m = element_mass_w(a, el.blk, e, irho, weights ? el.w : NULL);
      fn(a, &el, ctx);
    }
}

/* Mass to add to an element of mass m and wave step dt to reach target. */
static double added_mass(double m, double dt, double target) {
  if (!(dt > 0) || !isfinite(dt) || dt >= target) return 0.0;
  double r = target / dt;
  return m * (r * r - 1.0);
}

static int alloc_scaling(const dtm_analysis *a, dtm_mass_scaling *ms) {
  size_t nel = dtm_analysis_nelements(a);
  ms->ngroups = dtm_analysis_mesh(a)->ngroups + 1;
  ms->added = calloc(nel + 1, sizeof *ms->added);
  ms->group_mass = calloc((size_t)ms->ngroups, sizeof *ms->group_mass);
  ms->group_added = calloc((size_t)ms->ngroups, sizeof *ms->group_added);
  if (!ms->added || !ms->group_mass || !ms->group_added) {
    dtm_mass_scaling_free(ms);
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the mass scaling of %zu elements", nel);
  }
  return DTM_OK;
}

/* Node fields of the nodal form. */
typedef struct {
  double *m0;  /* [nnodes] lumped mass before scaling, kg */
  double *m1;  /* [nnodes] after the element-by-element part, kg */
  double *add; /* [nnodes] mass added at the node, kg */
  char *in;    /* [nnodes] 1 for a node of a selected element */
} node_mass;

/* Ratio by which element i's mass grows for the non-spectral wave effects. */
static double element_ratio(const dtm_analysis *a, size_t i, double target) {
  double dt = wave_dt_of(a, i, 0), r = target / dt;
  return dt > 0 && isfinite(dt) && dt < target ? r * r : 1.0;
}

/* The nodal form's passes: the selection, the node fields, the result. */
typedef struct {
  const unsigned char *only; /* [nel] selected elements, or NULL: all */
  node_mass *nm;             /* the node fields */
  dtm_mass_scaling *ms;      /* the result, target included */
} nodal_ctx;

/* Pass 0: node masses before and after the element part (and that part
 * into ms). */
static void node_pass0(const dtm_analysis *a, const elem *el, void *ctx) {
  nodal_ctx *c = ctx;
  int sel = !c->only || c->only[el->i];
  double r = sel ? element_ratio(a, el->i, c->ms->target) : 1.0;
  for (int k = 0; k < el->blk->nn && el->m > 0; k++) {
    size_t v = el->blk->conn[el->e * el->blk->nn + k];
    c->nm->m0[v] += el->m * el->w[k], c->nm->m1[v] += r * el->m * el->w[k], c->nm->in[v] |= sel;
  }
  c->ms->added[el->i] = (r - 1.0) * el->m;
}

/* Pass 1: the node additions shared out to the elements. */
static void node_pass1(const dtm_analysis *a, const elem *el, void *ctx) {
  nodal_ctx *c = ctx;
  double r = !c->only || c->only[el->i] ? element_ratio(a, el->i, c->ms->target) : 1.0;
  for (int k = 0; k < el->blk->nn && el->m > 0; k++) {
    size_t v = el->blk->conn[el->e * el->blk->nn + k];
    if (c->nm->m1[v] > 0) c->ms->added[el->i] += c->nm->add[v] * r * el->m * el->w[k] / c->nm->m1[v];
  }
}

/* Mass node v needs on top of m1 (and the point mass it carries, which its
 * nodal bound includes) for the spectral wave effects. */
static double node_need(const dtm_analysis *a, const node_mass *nm, size_t v, double target) {
  const double *pm = dtm_analysis_point_masses(a);
  double ratio = 1.0, carried = pm ? pm[v] : 0.0;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const double *nd = dtm_analysis_effect_nodal(a, k);
    if (!nd || !dtm_effect_is_wave(dtm_analysis_effect(a, k)) || !(nd[v] < target) || !(nd[v] > 0)) continue;
    ratio = fmax(ratio, (target / nd[v]) * (target / nd[v]));
  }
  return fmax(0.0, ratio * (nm->m0[v] + carried) - (nm->m1[v] + carried));
}

/* Totals, groups and counts from ms->added. */
static void tally_one(const dtm_analysis *a, const elem *el, void *ctx) {
  dtm_mass_scaling *ms = ctx;
  int g = el->blk->group[el->e], slot = g >= 0 && g < ms->ngroups - 1 ? g : ms->ngroups - 1;
  ms->total_mass += el->m, ms->total_added += ms->added[el->i];
  ms->group_mass[slot] += el->m, ms->group_added[slot] += ms->added[el->i];
  ms->scaled += ms->added[el->i] > 0;
  (void)a;
}

/* A node of a distributed run shared with other parts: its masses summed
 * over them, and selected when any of them selects it (r: the caller's
 * status, agreed with the other parts; the add field is the scratch). */
static int combine_parts(const dtm_analysis *a, int r, node_mass *nm, size_t nn) {
  if (!dtm_analysis_is_distributed(a)) return r;
  for (size_t v = 0; v < nn && r == DTM_OK; v++) nm->add[v] = nm->in[v];
  r = dtm_analysis_combine_nodes(a, r, nm->m0, DTM_X_SUM);
  r = dtm_analysis_combine_nodes(a, r, nm->m1, DTM_X_SUM);
  r = dtm_analysis_combine_nodes(a, r, nm->add, DTM_X_MAX);
  for (size_t v = 0; v < nn && r == DTM_OK; v++) nm->in[v] = nm->add[v] > 0;
  return r;
}

/* The mass each node receives in all (its elements' part, m1 - m0, and
 * its own addition), kept in ms (which takes over nm->add). */
static void keep_node_added(node_mass *nm, size_t nn, dtm_mass_scaling *ms) {
  for (size_t v = 0; v < nn; v++) {
    nm->add[v] += nm->m1[v] - nm->m0[v];
    ms->nodes += nm->add[v] > 0;
  }
  ms->node_added = nm->add, nm->add = NULL;
}

int dtm_mass_scaling_nodal(const dtm_analysis *a, double target, const unsigned char *only, dtm_mass_scaling *ms) {
  memset(ms, 0, sizeof *ms);
  ms->target = target, ms->nodal = 1;
  if (!(target > 0) || !isfinite(target))
    return DTM_ERR(DTM_ERR_INPUT, "mass scaling: the target step must be positive and finite, got %g s", target);
  size_t nn = dtm_analysis_mesh(a)->nnodes + 1;
  node_mass nm = {calloc(nn, sizeof(double)), calloc(nn, sizeof(double)), calloc(nn, sizeof(double)), calloc(nn, 1)};
  int r = alloc_scaling(a, ms);
  if (r == DTM_OK && !(nm.m0 && nm.m1 && nm.add && nm.in)) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  nodal_ctx ctx = {only, &nm, ms};
  if (r == DTM_OK) each_element(a, 1, node_pass0, &ctx);
  r = combine_parts(a, r, &nm, nn - 1);
  if (r == DTM_OK) {
    for (size_t v = 0; v + 1 < nn; v++) nm.add[v] = nm.in[v] ? node_need(a, &nm, v, target) : 0.0;
    each_element(a, 1, node_pass1, &ctx);
    each_element(a, 0, tally_one, ms);
    keep_node_added(&nm, nn - 1, ms);
  }
  free(nm.m0), free(nm.m1), free(nm.add), free(nm.in);
  if (r) dtm_mass_scaling_free(ms);
  return r;
}

/* Pass 1 of point masses given at the nodes: each node's addition shared
 * out to its elements by their share of its mass. */
static void given_pass(const dtm_analysis *a, const elem *el, void *ctx) {
  nodal_ctx *c = ctx;
  (void)a;
  for (int k = 0; k < el->blk->nn && el->m > 0; k++) {
    size_t v = el->blk->conn[el->e * el->blk->nn + k];
    if (c->nm->m0[v] > 0) c->ms->added[el->i] += c->nm->add[v] * el->m * el->w[k] / c->nm->m0[v];
  }
}

int dtm_mass_scaling_of_nodes(const dtm_analysis *a, const double *kg, double target, dtm_mass_scaling *ms) {
  memset(ms, 0, sizeof *ms);
  ms->nodal = 1, ms->target = target;
  size_t nn = dtm_analysis_mesh(a)->nnodes + 1;
  node_mass nm = {calloc(nn, sizeof(double)), calloc(nn, sizeof(double)), malloc(nn * sizeof(double)), calloc(nn, 1)};
  dtm_mass_scaling given = {.target = NAN}; /* pass 0 without an element part */
  nodal_ctx ctx = {NULL, &nm, &given};
  int r = alloc_scaling(a, ms);
  given.added = ms->added;
  if (r == DTM_OK && !(nm.m0 && nm.m1 && nm.add && nm.in)) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) {
    memcpy(nm.add, kg, (nn - 1) * sizeof *nm.add);
    each_element(a, 1, node_pass0, &ctx); /* m0; with a NaN target no element part (added stays 0) */
    each_element(a, 1, given_pass, &ctx);
    each_element(a, 0, tally_one, ms);
    keep_node_added(&nm, nn - 1, ms);
  }
  free(nm.m0), free(nm.m1), free(nm.add), free(nm.in);
  if (r) dtm_mass_scaling_free(ms);
  return r;
}

/* Pass of dtm_mass_lumped: each element's lumped mass into its nodes. */
static void lump_pass(const dtm_analysis *a, const elem *el, void *ctx) {
  double *m = ctx;
  (void)a;
  for (int k = 0; k < el->blk->nn && el->m > 0; k++) m[el->blk->conn[el->e * el->blk->nn + k]] += el->m * el->w[k];
}

int dtm_mass_lumped(const dtm_analysis *a, double *m) {
  size_t nn = dtm_analysis_mesh(a)->nnodes;
  const double *pm = dtm_analysis_point_masses(a);
  for (size_t v = 0; v < nn; v++) m[v] = pm ? pm[v] : 0.0;
  each_element(a, 1, lump_pass, m);
  return DTM_OK;
}

/* The element-by-element form. */
static void element_added(const dtm_analysis *a, const elem *el, void *ctx) {
  dtm_mass_scaling *ms = ctx;
  ms->added[el->i] = added_mass(el->m, wave_dt(a, el->i), ms->target);
}

int dtm_mass_scaling_compute(const dtm_analysis *a, double target, dtm_mass_scaling *ms) {
  memset(ms, 0, sizeof *ms);
  ms->target = target;
  if (!(target > 0) || !isfinite(target))
    return DTM_ERR(DTM_ERR_INPUT, "mass scaling: the target step must be positive and finite, got %g s", target);
  DTM_CHECK(alloc_scaling(a, ms));
  each_element(a, 0, element_added, ms);
  each_element(a, 0, tally_one, ms);
  return DTM_OK;
}

void dtm_mass_scaling_free(dtm_mass_scaling *ms) {
  free(ms->added);
  free(ms->group_mass);
  free(ms->group_added);
  free(ms->node_added);
  ms->added = ms->group_mass = ms->group_added = ms->node_added = NULL;
  ms->ngroups = 0;
}
