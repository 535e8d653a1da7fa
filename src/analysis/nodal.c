/* The nodal bound of every spectral effect (one with operator
 * coefficients): lambda_max(M^-1 K) <= max_a sum_{e ni a} lambda_e m_{e,a}/m_a,
 * where lambda_e is the element's own eigenvalue bound and m_{e,a} its
 * lumped contribution to node a. It stays tight on slivers because their
 * tiny mass is shared with their neighbours. Waves: dt_a = 2/sqrt(lambda_a),
 * times the smallest damping factor of the node's materials at
 * omega_a = sqrt(lambda_a); diffusion: dt_a = 2/lambda_a. One pass over the
 * elements in parallel, each thread adding into its own part of the nodes
 * in the elements' order (src/mesh/node_parts.c). Shell and beam
 * elements also carry rotations, whose lumped rotary inertia is the same
 * about every axis: K_e <= lambda_e M_e over all their unknowns gives the
 * same weighted mean over the rotary inertias J_{e,a}, and a node's bound
 * is the larger of its translational and rotational means.
 * Point masses at the nodes (dtm_mesh.node_mass) add to a wave effect's
 * translational m_a with no stiffness: K <= max_a (num_a / (m_a + M_a)) M
 * still holds, so the bound stays rigorous and rises where mass was
 * added. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "reference.h"

/* Coefficients of effect k for each scene material, computed on first use. */
typedef struct {
  dtm_operator_coeffs *c; /* [nmat] */
  char *ready;            /* [nmat] */
} coeff_cache;

static int coeffs_of(const dtm_analysis *a, int k, coeff_cache *cc, int slot, const dtm_operator_coeffs **out) {
  if (!cc->ready[slot]) {
    DTM_CHECK(dtm_analysis_coefficients(a, k, slot, &cc->c[slot]));
    cc->ready[slot] = 1;
  }
  *out = &cc->c[slot];
  return DTM_OK;
}

static int element_lambda(int type, const dtm_operator_coeffs *c, const double *x, double *lambda) {
  if (c->kind == DTM_OP_ELASTIC) return dtm_kernel_elastic_lambda(type, &c->mod, x, lambda);
  return dtm_kernel_diffusion_lambda(type, c->conductivity / c->capacity, x, lambda);
}

/* lambda_e of element i (global index) of effect k: from its own step
 * when that is the element bound (undamped), else from the kernel. */
static int lambda_of(const dtm_analysis *a, int k, int type, const dtm_operator_coeffs *c, const double *x, size_t i,
                     double *lam) {
  if (!c->dt_is_bound) return element_lambda(type, c, x, lam);
  double dt = a->dt_bare && a->dt_bare[k] ? a->dt_bare[k][i] : a->dt_effect[k][i];
  *lam = c->kind == DTM_OP_ELASTIC ? 4.0 / (dt * dt) : 2.0 / dt;
  return DTM_OK;
}

/* The translational and rotary masses of shell or beam element e of block
 * b, kept by dtm_analysis_rotary (its kernel again for one it refused, to
 * raise the kernel's error), into w[nn] and mr[nn]; 0 when element e has no
 * rotations. */
static int structural_masses(const dtm_analysis *a, const dtm_operator_coeffs *c, int b, size_t e, const double *x,
                             double *w, double *mr, int *done) {
  const dtm_block *blk = &a->mesh->blocks[b];
  *done = 0;
  if (!mr || c->kind != DTM_OP_ELASTIC || !c->section || !dtm_section_has_rotations(c->section->kind)) return DTM_OK;
  dtm_section_bounds sb;
  const dtm_section_bounds *kept = a->rot && a->rot[b] && a->rot[b][e].nn ? &a->rot[b][e] : NULL;
  if (!kept) DTM_CHECK(dtm_section_element_step(c->section, blk->type, c->E, c->nu, c->capacity, x, &sb));
  for (int i = 0; i < blk->nn; i++) w[i] = (kept ? kept : &sb)->mt[i], mr[i] = (kept ? kept : &sb)->mr[i];
  *done = 1;
  return DTM_OK;
}

/* lambda_e and the lumped contributions w[i] = capacity V w_i of element e
 * of block b (and, when mr is not NULL, the rotary inertias mr[i] of shells
 * and beams, 0 for the others). */
static int element_masses(const dtm_analysis *a, int k, int b, size_t e, const coeff_cache *cc, double *lam, double *w,
                          double *mr) {
  const dtm_block *blk = &a->mesh->blocks[b];
  double x[DTM_MAX_NODES * 3];
  dtm_mesh_gather_one(a->mesh, blk, e, x);
  const dtm_operator_coeffs *c = &cc->c[dtm_analysis_slot(a, blk, e)];
  int r = lambda_of(a, k, blk->type, c, x, a->offset[b] + e, lam), done = 0;
  if (mr) memset(mr, 0, (size_t)blk->nn * sizeof *mr);
  if (r == DTM_OK) r = structural_masses(a, c, b, e, x, w, mr, &done);
  if (r || done) return r;
  int model = c->kind == DTM_OP_ELASTIC ? c->mod.integration : DTM_INTEGRATION_CONVERGED;
  double m = c->capacity * c->section_factor * dtm_elem_lumped_at(blk->type, x, model, dtm_analysis_level(a, b, e), w);
  for (int i = 0; i < blk->nn; i++) w[i] *= m;
  return DTM_OK;
}

static int block_coeffs(const dtm_analysis *a, int k, coeff_cache *cc, const dtm_block *blk) {
  for (size_t e = 0; e < blk->n; e++) {
    const dtm_operator_coeffs *c;
    DTM_CHECK(coeffs_of(a, k, cc, dtm_analysis_slot(a, blk, e), &c));
  }
  return DTM_OK;
}

/* Sums into the nodes [lo, hi) of the node arrays (nodes: their count):
 * num[v] += lambda_e m_{e,v} and den[v] += m_{e,v} over element e of block
 * b; with rotations (rot), num[nodes + v] and den[nodes + v] the same over
 * the rotary inertias. */
typedef struct {
  const dtm_analysis *a;
  int k, b, rot;
  const coeff_cache *cc;
  size_t lo, hi;
  double *num, *den;
} node_sums;

static int add_element(const node_sums *ns, size_t e) {
  const dtm_block *blk = &ns->a->mesh->blocks[ns->b];
  size_t nodes = ns->a->mesh->nnodes;
  double lam, w[DTM_MAX_NODES], mr[DTM_MAX_NODES];
  DTM_CHECK(element_masses(ns->a, ns->k, ns->b, e, ns->cc, &lam, w, ns->rot ? mr : NULL));
  for (int i = 0; i < blk->nn; i++) {
    size_t v = blk->conn[e * (size_t)blk->nn + (size_t)i];
    if (v < ns->lo || v >= ns->hi) continue;
    ns->num[v] += lam * w[i];
    ns->den[v] += w[i];
    if (!ns->rot || !(mr[i] > 0)) continue;
    ns->num[nodes + v] += lam * mr[i];
    ns->den[nodes + v] += mr[i];
  }
  return DTM_OK;
}

/* The sums of part p of a->parts over block b: its listed elements, then
 * its core, in ascending order. */
static void part_sums(node_sums ns, int p, dtm_par_error *pe) {
  const size_t *list;
  size_t nlist, e0, e1;
  int r;
  dtm_mesh_node_part(&ns.a->parts, p, &ns.lo, &ns.hi);
  dtm_mesh_node_part_elements(&ns.a->parts, p, ns.b, &list, &nlist, &e0, &e1);
  for (size_t j = 0; j < nlist; j++)
    if ((r = add_element(&ns, list[j]))) dtm_par_error_keep(pe, r);
  for (size_t e = e0; e < e1; e++)
    if ((r = add_element(&ns, e))) dtm_par_error_keep(pe, r);
}

/* num[a] += lambda_e m_{e,a}, den[a] += m_{e,a} over the elements, a block
 * at a time, each part of the nodes on a thread: each node's sums in the
 * elements' order, the same bits as one thread walking the elements. */
static int scatter(const dtm_analysis *a, int k, coeff_cache *cc, int rot, double *num, double *den) {
  for (int b = 0; b < a->mesh->nblocks; b++) {
    const dtm_block *blk = &a->mesh->blocks[b];
    node_sums ns = {a, k, b, rot, cc, 0, 0, num, den};
    dtm_par_error pe = {0, ""};
    DTM_CHECK(block_coeffs(a, k, cc, blk));
#pragma omp parallel for schedule(dynamic, 1)
    for (int p = 0; p < a->parts.n; p++) part_sums(ns, p, &pe);
    if (pe.code)
      return DTM_ERR(DTM_ERR_INPUT, "nodal bound: a degenerate element in block %s: %s", dtm_elem_name(blk->type),
                     pe.msg);
  }
  return DTM_OK;
}

/* Smallest damping factor over the materials of the elements around each
 * node, at the node's own top frequency. */
static int node_factors(const dtm_analysis *a, const double *omega, double *fac) {
  for (int j = 0; j < a->neffects; j++) {
    const dtm_effect *mj = &a->effects[j];
    if (!(mj->cls->role & DTM_ROLE_MODIFIES_WAVES)) continue;
    for (int b = 0; b < a->mesh->nblocks; b++) {
      const dtm_block *blk = &a->mesh->blocks[b];
      for (size_t e = 0; e < blk->n; e++)
        for (int i = 0; i < blk->nn; i++) {
          size_t v = blk->conn[e * blk->nn + i];
          double f = 1.0;
          if (!(omega[v] > 0)) continue;
          DTM_CHECK(mj->cls->wave_factor(mj->state, &a->scene->materials[blk->mat[e]].m, omega[v], &f));
          fac[v] = fmin(fac[v], f);
        }
    }
  }
  return DTM_OK;
}

/* Node steps of effect k into dt[] (+inf where no element of it); the sums
 * and the damping factors of nodes shared with other parts are combined
 * over the parts (r: the caller's status, agreed with them). */
static int effect_nodal(const dtm_analysis *a, int k, coeff_cache *cc, int r, double *dt, double *work) {
  size_t nn = a->mesh->nnodes;
  int rot = dtm_analysis_has_rotations(a);
  double *num = work, *den = work + 2 * nn, *fac = work + 4 * nn; /* num, den: [2 nn] with rotations */
  if (r == DTM_OK) memset(work, 0, 5 * nn * sizeof *work), r = scatter(a, k, cc, rot, num, den);
  for (int part = 0; part <= rot; part++) {
    r = dtm_x_nodes(a, r, num + part * nn, DTM_X_SUM);
    r = dtm_x_nodes(a, r, den + part * nn, DTM_X_SUM);
  }
  DTM_CHECK(r);
  int wave = dtm_analysis_is_wave(a, k);
  const double *pm = wave ? a->mesh->node_mass : NULL; /* after the sums: each part holds the whole node's */
  for (size_t v = 0; v < nn; v++) {
    double lam = den[v] > 0 ? num[v] / (den[v] + (pm ? pm[v] : 0.0)) : 0;
    if (rot && den[nn + v] > 0) lam = fmax(lam, num[nn + v] / den[nn + v]);
    num[v] = wave ? sqrt(lam) : lam; /* omega (waves) or lambda (diffusion) */
    fac[v] = 1.0;
  }
  if (wave) DTM_CHECK(dtm_x_nodes(a, node_factors(a, num, fac), fac, DTM_X_MIN));
  for (size_t v = 0; v < nn; v++) dt[v] = num[v] > 0 ? 2.0 / num[v] * fac[v] : INFINITY;
  return DTM_OK;
}

/* Whether every material's element step is the element eigenvalue bound. */
static int all_bounds(const dtm_analysis *a, const coeff_cache *cc) {
  for (int i = 0; i < dtm_analysis_nslots(a); i++)
    if (cc->ready[i] && !cc->c[i].dt_is_bound) return 0;
  return 1;
}

/* The effect's smallest node step, and (waves) the undamped top frequency
 * omega[] there. */
static void record_min(dtm_analysis *a, int k, const double *dt, const double *omega) {
  dtm_effect_min *pe = &a->per_effect[k];
  const size_t *tags = a->mesh->node_tags;
  pe->nodal = INFINITY;
  for (size_t v = 0; v < a->mesh->nnodes; v++) {
    int tie = dt[v] == pe->nodal && tags && tags[v] < tags[pe->node]; /* by Gmsh tag, whatever the node order */
    if (dt[v] < pe->nodal || tie) pe->nodal = dt[v], pe->node = v;
    a->nodal_node[v] = fmin(a->nodal_node[v], dt[v]);
  }
  pe->omega = dtm_analysis_is_wave(a, k) && isfinite(pe->nodal) ? omega[pe->node] : NAN;
}

/* Each effect's nodal minimum and whether its element steps are bounds,
 * over every part, and the top frequency where the minimum is (the node
 * index stays this part's minimum). */
static int global_nodal(dtm_analysis *a) {
  int ne = a->neffects;
  double *v = malloc(2 * ((size_t)ne + 1) * sizeof *v);
  for (int k = 0; k < ne && v; k++) {
    v[k] = isnan(a->per_effect[k].nodal) ? INFINITY : a->per_effect[k].nodal;
    v[ne + k] = a->per_effect[k].element_rigorous; /* the min of the flags is their AND */
  }
  int r = dtm_x_reduce(a, v ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"), v, 2 * ne, DTM_X_MIN);
  for (int k = 0; k < ne && r == DTM_OK; k++) {
    a->per_effect[k].element_rigorous = v[ne + k] > 0;
    if (isnan(a->per_effect[k].nodal)) continue;
    if (dtm_analysis_is_wave(a, k)) r = dtm_x_at_min(a, r, a->per_effect[k].nodal, v[k], &a->per_effect[k].omega);
    a->per_effect[k].nodal = v[k];
  }
  free(v);
  return r;
}

int dtm_nodal_bounds(dtm_analysis *a) {
  size_t nn = a->mesh->nnodes, nm = (size_t)dtm_analysis_nslots(a) + 1;
  a->nodal_node = malloc((nn + 1) * sizeof *a->nodal_node);
  a->node_dt = calloc((size_t)a->neffects + 1, sizeof *a->node_dt);
  double *work = malloc((5 * nn + 1) * sizeof *work);
  coeff_cache cc = {calloc(nm, sizeof *cc.c), calloc(nm, 1)};
  int r =
      (a->nodal_node && a->node_dt && work && cc.c && cc.ready) ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < nn && r == DTM_OK; v++) a->nodal_node[v] = INFINITY;
  r = dtm_x_agree(a, r);
  for (int k = 0; k < a->neffects && r == DTM_OK; k++) {
    a->per_effect[k].nodal = NAN;
    if (!a->dt_effect[k] || !a->effects[k].cls->coefficients) continue; /* not spectral */
    memset(cc.ready, 0, nm);
    a->node_dt[k] = malloc((nn + 1) * sizeof **a->node_dt);
    r = effect_nodal(a, k, &cc, a->node_dt[k] ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"), a->node_dt[k],
                     work);
    a->per_effect[k].element_rigorous = r == DTM_OK && all_bounds(a, &cc);
    if (r == DTM_OK) record_min(a, k, a->node_dt[k], work);
  }
  if (r == DTM_OK) r = global_nodal(a);
  free(work);
  free(cc.c);
  free(cc.ready);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
