/* The nodal bound of every spectral effect (one with operator
 * coefficients): lambda_max(M^-1 K) <= max_a sum_{e ni a} lambda_e m_{e,a}/m_a,
 * where lambda_e is the element's own eigenvalue bound and m_{e,a} its
 * lumped contribution to node a. It stays tight on slivers because their
 * tiny mass is shared with their neighbours. Waves: dt_a = 2/sqrt(lambda_a),
 * times the smallest damping factor of the node's materials at
 * omega_a = sqrt(lambda_a); diffusion: dt_a = 2/lambda_a. One pass over the
 * elements (eigenvalues in parallel, the scatter serial). Shell and beam
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

#define NODAL_CHUNK 65536 /* elements whose lambda_e and masses are held at once */

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

/* lambda_e and the lumped contributions mw[e - e0][i] = capacity V w_i of
 * elements [e0, e1) of block b (and, when mrw is not NULL, the rotary
 * inertias mrw[e - e0][i] of shells and beams, 0 for the others). */
static int block_lambdas(const dtm_analysis *a, int k, int b, size_t e0, size_t e1, const coeff_cache *cc, double *lam,
                         double *mw, double *mrw) {
  const dtm_block *blk = &a->mesh->blocks[b];
  dtm_par_error pe = {0, ""};
#pragma omp parallel for schedule(static)
  for (size_t e = e0; e < e1; e++) {
    double x[DTM_MAX_NODES * 3], *w = mw + (e - e0) * blk->nn;
    dtm_mesh_gather_one(a->mesh, blk, e, x);
    const dtm_operator_coeffs *c = &cc->c[dtm_analysis_slot(a, blk, e)];
    int r = lambda_of(a, k, blk->type, c, x, a->offset[b] + e, &lam[e - e0]), done;
    double *mr = mrw ? mrw + (e - e0) * blk->nn : NULL;
    if (mr) memset(mr, 0, (size_t)blk->nn * sizeof *mr);
    if (r == DTM_OK) r = structural_masses(a, c, b, (size_t)e, x, w, mr, &done);
    if (r) dtm_par_error_keep(&pe, r);
    if (r || done) continue;
    int model = c->kind == DTM_OP_ELASTIC ? c->mod.integration : DTM_INTEGRATION_CONVERGED;
    double m = c->capacity * c->section_factor *
               dtm_elem_lumped_at(blk->type, x, model, dtm_analysis_level(a, b, (size_t)e), w);
    for (int i = 0; i < blk->nn; i++) w[i] *= m;
  }
  if (pe.code)
    return DTM_ERR(DTM_ERR_INPUT, "nodal bound: a degenerate element in block %s: %s", dtm_elem_name(blk->type),
                   pe.msg);
  return DTM_OK;
}

static int block_coeffs(const dtm_analysis *a, int k, coeff_cache *cc, const dtm_block *blk) {
  for (size_t e = 0; e < blk->n; e++) {
    const dtm_operator_coeffs *c;
    DTM_CHECK(coeffs_of(a, k, cc, dtm_analysis_slot(a, blk, e), &c));
  }
  return DTM_OK;
}

/* num[a] += lambda_e m_{e,a}, den[a] += m_{e,a} over elements [e0, e1);
 * with rotations (mrw not NULL), num[nn + a] and den[nn + a] the same over
 * the rotary inertias. */
static void scatter_chunk(const dtm_block *blk, size_t nnodes, size_t e0, size_t e1, const double *lam,
                          const double *mw, const double *mrw, double *num, double *den) {
  size_t nn = (size_t)blk->nn;
  for (size_t e = e0; e < e1; e++)
    for (size_t i = 0; i < nn; i++) {
      size_t v = blk->conn[e * nn + i], j = (e - e0) * nn + i;
      num[v] += lam[e - e0] * mw[j];
      den[v] += mw[j];
      if (!mrw || !(mrw[j] > 0)) continue;
      num[nnodes + v] += lam[e - e0] * mrw[j];
      den[nnodes + v] += mrw[j];
    }
}

/* num[a] += lambda_e m_{e,a}, den[a] += m_{e,a} over the elements, a chunk
 * at a time (the scatter is serial, in element order: with the mesh in
 * locality order it walks the node arrays nearly in sequence). */
static int scatter(const dtm_analysis *a, int k, coeff_cache *cc, int rot, double *num, double *den) {
  double *lam = malloc(NODAL_CHUNK * sizeof *lam), *mw = malloc(NODAL_CHUNK * DTM_MAX_NODES * sizeof *mw);
  double *mrw = rot ? malloc(NODAL_CHUNK * DTM_MAX_NODES * sizeof *mrw) : NULL;
  int r = lam && mw && (mrw || !rot) ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int b = 0; b < a->mesh->nblocks && r == DTM_OK; b++) {
    const dtm_block *blk = &a->mesh->blocks[b];
    r = block_coeffs(a, k, cc, blk);
    for (size_t e0 = 0; e0 < blk->n && r == DTM_OK; e0 += NODAL_CHUNK) {
      size_t e1 = blk->n - e0 < NODAL_CHUNK ? blk->n : e0 + NODAL_CHUNK;
      r = block_lambdas(a, k, b, e0, e1, cc, lam, mw, mrw);
      if (r == DTM_OK) scatter_chunk(blk, a->mesh->nnodes, e0, e1, lam, mw, mrw, num, den);
    }
  }
  free(lam), free(mw), free(mrw);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
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
