/* Shaping a size field to what the geometry and the mesher allow: no node
 * on a model curve (or point) is asked for more than the length of that
 * curve (or of the shortest curve through the point), since an element
 * there cannot be larger and asking for it only distorts its neighbours;
 * and grading: no node's size may exceed that of
 * another by more than g times their distance along mesh edges,
 * s_b <= min_a (s_a + g d_ab), computed as a shortest-path problem from
 * every node at once (Dijkstra with a binary heap over the mesh's edges),
 * and never below the floor (the current size: grading must not refine).
 * Without it a node asked to grow among nodes that keep their size gets a
 * spike the mesher cannot follow, and the elements around a kept feature
 * come out distorted. */
#include <math.h>
#include <stdlib.h>

#include "dtmap/topology.h"
#include "study-impl.h"

/* Neighbours of each node along element edges (CSR, with duplicates). */
typedef struct {
  size_t *start; /* [nnodes + 2] */
  size_t *nb;    /* [start[nnodes]] */
} adjacency;

static void visit_edges(const dtm_mesh *m, adjacency *g, int fill) {
  for (int b = 0; b < m->nblocks; b++) {
    const dtm_block *blk = &m->blocks[b];
    const int(*ed)[2];
    int ne = dtm_elem_edges(blk->type, &ed);
    for (size_t e = 0; e < blk->n; e++)
      for (int k = 0; k < ne; k++) {
        size_t u = blk->conn[e * blk->nn + ed[k][0]], v = blk->conn[e * blk->nn + ed[k][1]];
        if (fill)
          g->nb[g->start[u + 1]++] = v, g->nb[g->start[v + 1]++] = u;
        else
          g->start[u + 2]++, g->start[v + 2]++;
      }
  }
}

static int build(const dtm_mesh *m, adjacency *g) {
  g->start = calloc(m->nnodes + 2, sizeof *g->start);
  if (!g->start) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  visit_edges(m, g, 0);
  for (size_t v = 0; v < m->nnodes; v++) g->start[v + 2] += g->start[v + 1];
  g->nb = malloc((g->start[m->nnodes + 1] + 1) * sizeof *g->nb);
  if (!g->nb) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  visit_edges(m, g, 1);
  return DTM_OK;
}

/* A binary min-heap of nodes keyed by size, with positions for decrease-key. */
typedef struct {
  size_t *node;      /* [n] heap order */
  size_t *pos;       /* [nnodes] position in node[], SIZE_MAX when out */
  size_t n;          /* nodes in the heap */
  const double *key; /* [nnodes] the sizes it orders by */
} heap;

static void swap_at(heap *h, size_t i, size_t j) {
  size_t t = h->node[i];
  h->node[i] = h->node[j], h->node[j] = t;
  h->pos[h->node[i]] = i, h->pos[h->node[j]] = j;
}

static void up(heap *h, size_t i) {
  while (i > 0 && h->key[h->node[(i - 1) / 2]] > h->key[h->node[i]]) swap_at(h, i, (i - 1) / 2), i = (i - 1) / 2;
}

static void down(heap *h, size_t i) {
  for (;;) {
    size_t l = 2 * i + 1, r = l + 1, s = i;
    if (l < h->n && h->key[h->node[l]] < h->key[h->node[s]]) s = l;
    if (r < h->n && h->key[h->node[r]] < h->key[h->node[s]]) s = r;
    if (s == i) return;
    swap_at(h, i, s), i = s;
  }
}

static size_t pop(heap *h) {
  size_t top = h->node[0];
  swap_at(h, 0, --h->n);
  h->pos[top] = (size_t)-1;
  down(h, 0);
  return top;
}

static double dist(const dtm_mesh *m, size_t u, size_t v) {
  const double *a = m->xyz + 3 * u, *b = m->xyz + 3 * v;
  return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

static void relax(const dtm_mesh *m, const adjacency *g, heap *h, double *s, double slope) {
  while (h->n) {
    size_t u = pop(h);
    for (size_t j = g->start[u]; j < g->start[u + 1]; j++) {
      size_t v = g->nb[j];
      double t = s[u] + slope * dist(m, u, v);
      if (h->pos[v] == (size_t)-1 || !(t < s[v])) continue;
      s[v] = t;
      up(h, h->pos[v]);
    }
  }
}

/* Shortest model curve through each model point: [nent] by entity index. */
static double point_cap(const dtm_geo *g, int p) {
  double cap = INFINITY;
  for (int e = 0; e < g->nent; e++)
    for (int k = 0; g->ent[e].dim == 1 && g->ent[e].size > 0 && k < g->ent[e].npoints; k++)
      if (g->ent[e].points[k] == p) cap = fmin(cap, g->ent[e].size);
  return cap;
}

void dtm_cap_at_features(const dtm_geo *g, const double *floor, double *size) {
  for (size_t v = 0; g && v < g->nnodes; v++) {
    double cap = INFINITY;
    if (g->node_dim[v] == 1) {
      const dtm_geo_entity *c = dtm_geo_find(g, 1, g->node_tag[v]);
      cap = c && c->size > 0 ? c->size : INFINITY;
    } else if (g->node_dim[v] == 0) {
      cap = point_cap(g, g->node_tag[v]);
    }
    if (size[v] > cap) size[v] = fmax(cap, floor[v]);
  }
}

int dtm_grade_sizes(const dtm_mesh *m, double slope, const double *floor, double *size) {
  adjacency g = {NULL, NULL};
  heap h = {malloc((m->nnodes + 1) * sizeof(size_t)), malloc((m->nnodes + 1) * sizeof(size_t)), 0, size};
  int r = h.node && h.pos ? build(m, &g) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < m->nnodes && r == DTM_OK; v++) {
    h.pos[v] = (size_t)-1;
    if (isfinite(size[v])) h.node[h.n] = v, h.pos[v] = h.n++, up(&h, h.n - 1);
  }
  if (r == DTM_OK) relax(m, &g, &h, size, slope);
  for (size_t v = 0; v < m->nnodes && r == DTM_OK; v++)
    if (isfinite(floor[v]) && size[v] < floor[v]) size[v] = floor[v];
  free(g.start), free(g.nb), free(h.node), free(h.pos);
  return r;
}
