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
 * of these; it is the size at which every node sits at the target, which is
 * what a background size field for the target wants. Accuracy bounds
 * (hmax: cohesive R/N, wavelength/N) clamp it from above; where the two
 * conflict, the element is counted and the step the accuracy bound allows,
 * min_k dt_k,e (hmax_e/h_e)^p_k, is kept. */
#include <math.h>
#include <stdlib.h>

#include "analysis-impl.h"

static double scale(double r, double p) { return p == 1.0 ? r : p == 2.0 ? r * r : pow(r, p); }
static double root(double r, double p) { return p == 1.0 ? r : p == 2.0 ? sqrt(r) : pow(r, 1.0 / p); }

/* Per node: mean adjacent size h, smallest adjacent hmax, and for each
 * non-spectral effect the smallest adjacent element step. */
typedef struct {
  double *h, *hcap; /* [nnodes] */
  double **emin;    /* [neffects][nnodes], rows only for non-spectral effects */
  unsigned *count;  /* [nnodes] */
} node_fields;

static void gather_nodes(const dtm_analysis *a, node_fields *nf) {
  const dtm_mesh *m = a->mesh;
  for (int b = 0; b < m->nblocks; b++) {
    const dtm_block *blk = &m->blocks[b];
    for (size_t e = 0; e < blk->n; e++) {
      size_t i = a->offset[b] + e;
      for (int c = 0; c < blk->nn; c++) {
        size_t v = blk->conn[e * blk->nn + c];
        nf->h[v] += a->h[i], nf->count[v]++;
        nf->hcap[v] = fmin(nf->hcap[v], a->hmax[i]);
        for (int k = 0; k < a->neffects; k++)
          if (nf->emin[k]) nf->emin[k][v] = fmin(nf->emin[k][v], a->dt_effect[k][i]);
      }
    }
  }
}

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
  nf->count = calloc(nn, sizeof *nf->count);
  nf->emin = calloc((size_t)a->neffects + 1, sizeof *nf->emin);
  if (!nf->h || !nf->hcap || !nf->count || !nf->emin) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
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
  free(nf->emin), free(nf->h), free(nf->hcap), free(nf->count);
}

int dtm_size_suggest(dtm_analysis *a) {
  size_t nn = a->mesh->nnodes;
  double target = a->scene->target;
  node_fields nf = {0};
  a->size_node = malloc((nn + 1) * sizeof *a->size_node);
  int r = a->size_node ? alloc_fields(a, &nf) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) {
    gather_nodes(a, &nf);
    for (size_t v = 0; v < nn; v++) {
      if (!nf.count[v]) {
        a->size_node[v] = NAN;
        continue;
      } /* a node of no analysed element */
      nf.h[v] /= nf.count[v];
      a->size_node[v] = fmin(target > 0 ? node_need(a, &nf, v, target) : nf.h[v], nf.hcap[v]);
    }
    element_accounting(a, target);
  }
  free_fields(a, &nf);
  return r;
}
