/* The size suggestion (NodeData "size suggestion", m) and the accuracy
 * bookkeeping behind it.
 * Without a target step it is the current local size: the mean over a
 * node's elements of their mean edge length.
 * With a target step dt_t, each limiting effect k, whose step scales as
 * h^p_k, reaches the target at h_e (dt_t / dt_k,e)^(1/p_k); the element
 * needs the largest of these. Accuracy bounds (hmax_e) clamp it from above;
 * where the two conflict the element is counted, and the step the accuracy
 * bound allows, min_k dt_k,e (hmax_e/h_e)^p_k, is kept. A node takes the
 * largest need of its elements, so every element around it reaches the
 * target, clamped by the smallest hmax around it. */
#include <math.h>
#include <stdlib.h>

#include "analysis_impl.h"

static double scale(double r, double p) { return p == 1.0 ? r : p == 2.0 ? r * r : pow(r, p); }
static double root(double r, double p) { return p == 1.0 ? r : p == 2.0 ? sqrt(r) : pow(r, 1.0 / p); }

static double element_need(const dtm_analysis *a, size_t i, double target) {
  double need = 0;
  for (int k = 0; k < a->neffects; k++) {
    if (!a->dt_effect[k] || !isfinite(a->dt_effect[k][i])) continue;
    double hk = a->h[i] * root(target / a->dt_effect[k][i], a->effects[k].cls->exponent);
    need = fmax(need, hk);
  }
  return need > 0 ? need : a->h[i];
}

/* Step element i would have at size hmax_i. */
static double step_at_bound(const dtm_analysis *a, size_t i) {
  double dt = INFINITY;
  for (int k = 0; k < a->neffects; k++)
    if (a->dt_effect[k])
      dt = fmin(dt, a->dt_effect[k][i] * scale(a->hmax[i] / a->h[i], a->effects[k].cls->exponent));
  return dt;
}

/* Element i's suggested size, with the conflict bookkeeping. */
static double element_size(dtm_analysis *a, size_t i, double target) {
  if (a->h[i] > a->hmax[i]) a->under_resolved++;
  if (!(target > 0)) return fmin(a->h[i], a->hmax[i]);
  double need = element_need(a, i, target);
  if (need <= a->hmax[i]) return need;
  a->conflicts++;
  double cap = step_at_bound(a, i);
  if (isnan(a->dt_accuracy_cap) || cap < a->dt_accuracy_cap) a->dt_accuracy_cap = cap;
  return a->hmax[i];
}

static void accumulate(dtm_analysis *a, double *hcap, unsigned *count) {
  const dtm_mesh *m = a->mesh;
  int has_target = a->scene->target > 0;
  for (int b = 0; b < m->nblocks; b++) {
    const dtm_block *blk = &m->blocks[b];
    for (size_t e = 0; e < blk->n; e++) {
      size_t i = a->offset[b] + e;
      double s = element_size(a, i, a->scene->target);
      for (int k = 0; k < blk->nn; k++) {
        size_t v = blk->conn[e * blk->nn + k];
        a->size_node[v] = has_target ? fmax(a->size_node[v], s) : a->size_node[v] + s;
        hcap[v] = fmin(hcap[v], a->hmax[i]);
        count[v]++;
      }
    }
  }
}

int dtm_size_suggest(dtm_analysis *a) {
  size_t nn = a->mesh->nnodes;
  a->size_node = calloc(nn + 1, sizeof *a->size_node);
  double *hcap = malloc((nn + 1) * sizeof *hcap);
  unsigned *count = calloc(nn + 1, sizeof *count);
  int ok = a->size_node && hcap && count;
  if (ok) {
    for (size_t v = 0; v < nn; v++) hcap[v] = INFINITY;
    a->under_resolved = a->conflicts = 0;
    a->dt_accuracy_cap = NAN;
    accumulate(a, hcap, count);
    for (size_t v = 0; v < nn; v++) {
      if (!count[v]) a->size_node[v] = NAN; /* a node of no analysed element */
      else if (!(a->scene->target > 0)) a->size_node[v] /= count[v];
      a->size_node[v] = fmin(a->size_node[v], hcap[v]);
    }
  }
  free(hcap);
  free(count);
  return ok ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
}
