/* The size suggestion (NodeData "size suggestion", m) and the accuracy
 * bookkeeping behind it.
 * A node's current size h_a is the mean over its elements of their mean edge
 * length. Without a target step that is the suggestion.
 * With a target dt_t (compared, like everything else, with the recommended
 * step, so the safety factor s is included), each limiting effect k whose
 * step scales as h^p_k reaches the target at h_a (dt_t / (s dt_k,a))^(1/p_k),
 * where dt_k,a is the node's own step: its nodal bound for a spectral effect
 * (smooth, and already sharing a sliver's tiny mass with its neighbours), or
 * the smallest element step around it otherwise. The node needs the largest
 * of these, and never less than h_a: a node whose step already meets the
 * target keeps its size (refining it would only raise the cost), a node
 * below it is asked for the larger size that reaches it. Accuracy bounds
 * (hmax: cohesive R/N, wavelength/N) then clamp it from above; where the
 * target and a bound conflict, the element is counted and the step the
 * bound allows, min_k dt_k,e (hmax_e/h_e)^p_k, is kept, and the elements
 * the clamp adds to a mesh at the suggestion are estimated per effect as
 * sum_e (h_e/h_clamped,e)^d - (h_e/h_free,e)^d (h_.,e: the mean of the
 * element's node values). */
#include <math.h>
#include <stdlib.h>

#include "analysis-impl.h"

static double scale(double r, double p) { return p == 1.0 ? r : p == 2.0 ? r * r : pow(r, p); }
static double root(double r, double p) { return p == 1.0 ? r : p == 2.0 ? sqrt(r) : pow(r, 1.0 / p); }

/* Per node: mean adjacent size h, smallest adjacent hmax, and for each
 * non-spectral effect the smallest adjacent element step. */
typedef struct {
  double *h, *hcap; /* [nnodes] */
  double *free;     /* [nnodes] suggestion before the accuracy clamp */
  double **emin;    /* [neffects][nnodes], rows only for non-spectral effects */
  unsigned *count;  /* [nnodes] */
} node_fields;

/* Element e of block b into its nodes in [lo, hi). */
static void gather_element(const dtm_analysis *a, node_fields *nf, int b, size_t e, size_t lo, size_t hi) {
  const dtm_block *blk = &a->mesh->blocks[b];
  size_t i = a->offset[b] + e;
  for (int c = 0; c < blk->nn; c++) {
    size_t v = blk->conn[e * blk->nn + c];
    if (v < lo || v >= hi) continue;
    nf->h[v] += a->h[i], nf->count[v]++;
    nf->hcap[v] = fmin(nf->hcap[v], a->hmax[i]);
    for (int k = 0; k < a->neffects; k++)
      if (nf->emin[k]) nf->emin[k][v] = fmin(nf->emin[k][v], a->dt_effect[k][i]);
  }
}

/* The sums and minima into the nodes of part p of a->parts, each node's in
 * the elements' order (block by block: the listed elements, then the core). */
static void gather_part(const dtm_analysis *a, node_fields *nf, int p) {
  const size_t *list;
  size_t lo, hi, nlist, e0, e1;
  dtm_mesh_node_part(&a->parts, p, &lo, &hi);
  for (int b = 0; b < a->mesh->nblocks; b++) {
    dtm_mesh_node_part_elements(&a->parts, p, b, &list, &nlist, &e0, &e1);
    for (size_t j = 0; j < nlist; j++) gather_element(a, nf, b, list[j], lo, hi);
    for (size_t e = e0; e < e1; e++) gather_element(a, nf, b, e, lo, hi);
  }
}

static void gather_nodes(const dtm_analysis *a, node_fields *nf) {
#pragma omp parallel for schedule(dynamic, 1)
  for (int p = 0; p < a->parts.n; p++) gather_part(a, nf, p);
}

/* Nodes shared with other parts of a distributed run: the sums (size,
 * count) and minima (bound, element steps) over every part (r: the caller's
 * status, agreed with them). */
static int exchange_fields(const dtm_analysis *a, node_fields *nf, int r) {
  if (!a->x) return r;
  size_t nn = a->mesh->nnodes;
  double *c = malloc((nn + 1) * sizeof *c);
  if (r == DTM_OK && !c) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < nn && r == DTM_OK; v++) c[v] = nf->count[v];
  r = dtm_x_nodes(a, r, nf->h, DTM_X_SUM);
  r = dtm_x_nodes(a, r, c, DTM_X_SUM);
  r = dtm_x_nodes(a, r, nf->hcap, DTM_X_MIN);
  for (int k = 0; k < a->neffects; k++)
    if (a->dt_effect[k] && !(a->node_dt && a->node_dt[k])) r = dtm_x_nodes(a, r, nf->emin[k], DTM_X_MIN);
  for (size_t v = 0; v < nn && r == DTM_OK; v++) nf->count[v] = (unsigned)c[v];
  free(c);
  return r;
}

/* The size at which node v reaches the target (its current size where no
 * effect has a step there). */
static double node_need(const dtm_analysis *a, const node_fields *nf, size_t v, double target) {
  double need = 0;
  for (int k = 0; k < a->neffects; k++) {
    const double *dt = a->node_dt && a->node_dt[k] ? a->node_dt[k] : nf->emin[k];
    if (!dt || !isfinite(dt[v])) continue;
    need = fmax(need, nf->h[v] * root(target / (a->scene->safety * dt[v]), a->effects[k].cls->exponent));
  }
  return need > 0 ? need : nf->h[v];
}

/* Step element i would have at size hmax_i. */
static double step_at_bound(const dtm_analysis *a, size_t i) {
  double dt = INFINITY;
  for (int k = 0; k < a->neffects; k++)
    if (a->dt_effect[k]) dt = fmin(dt, a->dt_effect[k][i] * scale(a->hmax[i] / a->h[i], a->effects[k].cls->exponent));
  return dt;
}

/* Elements the clamp adds at element i, (h/hs)^d - (h/hf)^d with hs and hf
 * the means of the clamped and free suggestion over its nodes. */
static double forced_at(const dtm_analysis *a, const node_fields *nf, const dtm_block *blk, size_t e, size_t i) {
  double hs = 0, hf = 0;
  for (int c = 0; c < blk->nn; c++) {
    size_t v = blk->conn[e * blk->nn + c];
    hs += a->size_node[v] / blk->nn, hf += nf->free[v] / blk->nn;
  }
  if (!(hs < hf)) return 0.0;
  int d = a->mesh->dim;
  return pow(a->h[i] / hs, d) - pow(a->h[i] / hf, d);
}

static void forced_accounting(dtm_analysis *a, const node_fields *nf) {
  dtm_accuracy *ac = &a->accuracy;
  ac->forced = 0, ac->forced_by = -1;
  for (int b = 0; b < a->mesh->nblocks; b++) {
    const dtm_block *blk = &a->mesh->blocks[b];
    for (size_t e = 0; e < blk->n; e++) {
      size_t i = a->offset[b] + e;
      int k = a->hmax_by[i];
      if (k >= 0) a->forced[k] += forced_at(a, nf, blk, e, i);
    }
  }
  for (int k = 0; k < a->neffects; k++) {
    ac->forced += a->forced[k];
    if (a->forced[k] > 0 && (ac->forced_by < 0 || a->forced[k] > a->forced[ac->forced_by])) ac->forced_by = k;
  }
}

/* Per element: under-resolved count, and conflicts between the target and
 * the accuracy bound. */
static void element_accounting(dtm_analysis *a, double target) {
  dtm_accuracy *ac = &a->accuracy;
  ac->under_resolved = ac->conflicts = 0;
  ac->dt_cap = NAN;
  for (size_t i = 0; i < a->nel; i++) {
    if (a->h[i] > a->hmax[i]) ac->under_resolved++;
    if (!(target > 0) || !isfinite(a->hmax[i])) continue;
    double cap = a->scene->safety * step_at_bound(a, i);
    if (cap >= target) continue;
    ac->conflicts++;
    if (isnan(ac->dt_cap) || cap < ac->dt_cap) ac->dt_cap = cap, ac->cap_element = i;
  }
}

static int alloc_fields(const dtm_analysis *a, node_fields *nf) {
  size_t nn = a->mesh->nnodes + 1;
  nf->h = calloc(nn, sizeof *nf->h), nf->hcap = malloc(nn * sizeof *nf->hcap);
  nf->free = malloc(nn * sizeof *nf->free), nf->count = calloc(nn, sizeof *nf->count);
  nf->emin = calloc((size_t)a->neffects + 1, sizeof *nf->emin);
  if (!nf->h || !nf->hcap || !nf->free || !nf->count || !nf->emin) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < nn; v++) nf->hcap[v] = INFINITY;
  for (int k = 0; k < a->neffects; k++) {
    if (!a->dt_effect[k] || (a->node_dt && a->node_dt[k])) continue;
    nf->emin[k] = malloc(nn * sizeof **nf->emin);
    if (!nf->emin[k]) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    for (size_t v = 0; v < nn; v++) nf->emin[k][v] = INFINITY;
  }
  return DTM_OK;
}

static void free_fields(const dtm_analysis *a, node_fields *nf) {
  for (int k = 0; nf->emin && k < a->neffects; k++) free(nf->emin[k]);
  free(nf->emin), free(nf->h), free(nf->hcap), free(nf->free), free(nf->count);
}

/* Node v's suggestion with calibration c: the free size (the current one,
 * raised to c x what reaches the target), then the accuracy clamp; free[]
 * gets the free size. */
static void suggest_node(const dtm_analysis *a, node_fields *nf, size_t v, double c, double *size) {
  double target = a->advice_target;
  if (!nf->count[v]) { /* a node of no analysed element */
    size[v] = nf->free[v] = NAN;
    return;
  }
  nf->h[v] /= nf->count[v];
  nf->free[v] = target > 0 ? fmax(nf->h[v], c * node_need(a, nf, v, target)) : nf->h[v];
  size[v] = fmin(nf->free[v], nf->hcap[v]);
}

static int field(const dtm_analysis *a, double c, double *size, node_fields *nf) {
  int r = alloc_fields(a, nf);
  if (r == DTM_OK) gather_nodes(a, nf);
  DTM_CHECK(exchange_fields(a, nf, r)); /* the nodes shared with other parts of a distributed run */
#pragma omp parallel for schedule(static)
  for (size_t v = 0; v < a->mesh->nnodes; v++) suggest_node(a, nf, v, c, size);
  return DTM_OK;
}

int dtm_analysis_size_field(const dtm_analysis *a, double c, double *size) {
  node_fields nf = {0};
  int r = field(a, c, size, &nf);
  free_fields(a, &nf);
  return r;
}

int dtm_size_suggest(dtm_analysis *a) {
  node_fields nf = {0};
  a->size_node = malloc((a->mesh->nnodes + 1) * sizeof *a->size_node);
  a->forced = calloc((size_t)a->neffects + 1, sizeof *a->forced);
  int r = dtm_x_agree(a, a->size_node && a->forced ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
  if (r == DTM_OK) r = field(a, 1.0, a->size_node, &nf);
  if (r == DTM_OK) {
    element_accounting(a, a->advice_target);
    forced_accounting(a, &nf);
  }
  free_fields(a, &nf);
  return r;
}
