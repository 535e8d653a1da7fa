/* Splitting the nodes of a mesh into parts for a scatter that runs in
 * parallel and still adds in order. A loop that adds element values into
 * their nodes (a node's mean size, the nodal bound's sums) is serial
 * because two elements share nodes; made parallel with atomics or
 * per-thread copies, each node's sum would be added in another order and
 * round differently from run to run. Here each part owns a range of node
 * indices and walks, in order, only the elements that touch it, adding only
 * into its own nodes: each node's contributions are added in the serial
 * loop's order (block by block, element by element), so the sums are the
 * same bits whatever the number of threads.
 *
 * It relies on the locality order (order.c: the elements of each block
 * sorted by their smallest node). A part's elements are then its core, the
 * contiguous run of elements whose smallest node is its own, and a few
 * others from before that run which reach into it from a lower part (an
 * element straddling the split, or one whose nodes lie far apart along the
 * Hilbert curve), listed in order. A block in another order gets one part:
 * the serial loop. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/mesh.h"

/* The split: part p owns the nodes [bound[p], bound[p + 1]), bound[p] =
 * p nn / np (dtm_mesh_node_part). */
typedef struct {
  int np;
  const size_t *bound; /* [np + 1] */
} split;

/* The part that holds node v: the last p with bound[p] <= v. */
static int part_of(const split *sp, size_t v) {
  int lo = 0, hi = sp->np - 1;
  while (lo < hi) {
    int mid = (lo + hi + 1) / 2;
    if (sp->bound[mid] <= v)
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

static size_t smallest_node(const dtm_block *b, size_t e) {
  const size_t *c = b->conn + e * (size_t)b->nn;
  size_t lo = c[0];
  for (int k = 1; k < b->nn; k++) lo = c[k] < lo ? c[k] : lo;
  return lo;
}

/* The first element of sorted block b whose smallest node is at least v. */
static size_t first_at(const dtm_block *b, size_t v) {
  size_t lo = 0, hi = b->n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (smallest_node(b, mid) < v)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

/* The parts above its core part q that element e reaches into, into reach
 * (ascending, distinct); their count. Most nodes lie in q: one comparison. */
static int reached(const dtm_block *b, size_t e, const split *sp, int q, int *reach) {
  int n = 0;
  for (int k = 0; k < b->nn; k++) {
    size_t v = b->conn[e * (size_t)b->nn + (size_t)k];
    if (v < sp->bound[q + 1]) continue;
    int p = part_of(sp, v), i = n;
    while (i > 0 && reach[i - 1] > p) i--;
    if (i > 0 && reach[i - 1] == p) continue;
    memmove(reach + i + 1, reach + i, (size_t)(n - i) * sizeof *reach);
    reach[i] = p, n++;
  }
  return n;
}

/* Chunk c of NCHUNKS of block b's elements: [*e0, *e1). */
#define NCHUNKS 16
static void chunk(const dtm_block *b, int c, size_t *e0, size_t *e1) {
  *e0 = (size_t)c * b->n / NCHUNKS, *e1 = (size_t)(c + 1) * b->n / NCHUNKS;
}

/* Count (list NULL) or write, at next[part], the elements of chunk c that
 * reach into a part from below; 0 when an element's smallest node is below
 * the one before it (the block is not in locality order), else 1. */
static int reaching_chunk(const dtm_block *b, const split *sp, int c, size_t *next, size_t *list) {
  size_t e0, e1, prev;
  int reach[DTM_MAX_NODES];
  chunk(b, c, &e0, &e1);
  prev = e0 < e1 && e0 > 0 ? smallest_node(b, e0 - 1) : 0;
  int q = part_of(sp, prev);
  for (size_t e = e0; e < e1; e++) {
    size_t mn = smallest_node(b, e);
    if (mn < prev) return 0;
    prev = mn;
    while (mn >= sp->bound[q + 1]) q++;
    int n = reached(b, e, sp, q, reach);
    for (int i = 0; i < n; i++)
      if (list)
        list[next[reach[i]]++] = e;
      else
        next[reach[i]]++;
  }
  return 1;
}

/* The elements of block b that reach into a part from below, each part's
 * in ascending order: counted per chunk, then written from each chunk's
 * offsets (the chunks fixed, whatever the threads). at[np + 1] gets the
 * offsets into *list; *sorted 0 (and no list) when the block is not in
 * locality order. */
static int list_reaching(const dtm_block *b, const split *sp, size_t *at, size_t **list, int *sorted) {
  int np = sp->np, ok = 1;
  size_t *count = calloc((size_t)NCHUNKS * (size_t)np + 1, sizeof *count), total = 0;
  if (!count) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
#pragma omp parallel for schedule(dynamic, 1) reduction(&& : ok)
  for (int c = 0; c < NCHUNKS; c++) ok = reaching_chunk(b, sp, c, count + (size_t)c * (size_t)np, NULL) && ok;
  *sorted = ok;
  if (!ok) return free(count), DTM_OK;
  for (int p = 0; p < np; p++) {
    at[p] = total;
    for (int c = 0; c < NCHUNKS; c++) {
      size_t k = count[(size_t)c * (size_t)np + (size_t)p];
      count[(size_t)c * (size_t)np + (size_t)p] = total, total += k;
    }
  }
  at[np] = total;
  *list = malloc((total + 1) * sizeof **list);
  if (!*list) return free(count), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < NCHUNKS; c++) reaching_chunk(b, sp, c, count + (size_t)c * (size_t)np, *list);
  free(count);
  return DTM_OK;
}

static int split_block(const dtm_block *b, const split *sp, dtm_node_parts *out, int bi, int *sorted) {
  int np = sp->np;
  size_t *core = out->core + (size_t)bi * (size_t)(np + 1), *at = out->at + (size_t)bi * (size_t)(np + 1);
  DTM_CHECK(list_reaching(b, sp, at, &out->list[bi], sorted));
  for (int p = 0; *sorted && p < np; p++) core[p] = first_at(b, sp->bound[p]);
  core[0] = 0, core[np] = b->n;
  return DTM_OK;
}

/* One part: every block's elements its core, none listed. */
static int one_part(const dtm_mesh *m, dtm_node_parts *out) {
  out->n = 1;
  for (int b = 0; b < m->nblocks; b++) {
    out->core[2 * b] = 0, out->core[2 * b + 1] = m->blocks[b].n;
    out->at[2 * b] = out->at[2 * b + 1] = 0;
  }
  return DTM_OK;
}

int dtm_mesh_node_parts(const dtm_mesh *m, int np, dtm_node_parts *out) {
  size_t nb = (size_t)m->nblocks + 1;
  memset(out, 0, sizeof *out);
  np = np > DTM_NODE_PARTS_MAX ? DTM_NODE_PARTS_MAX : np < 1 ? 1 : np;
  if ((size_t)np > m->nnodes) np = m->nnodes ? (int)m->nnodes : 1;
  out->n = np, out->nblocks = m->nblocks, out->nnodes = m->nnodes;
  out->core = malloc(nb * (size_t)(np + 1) * sizeof *out->core);
  out->at = malloc(nb * (size_t)(np + 1) * sizeof *out->at);
  out->list = calloc(nb, sizeof *out->list);
  if (!out->core || !out->at || !out->list)
    return dtm_mesh_node_parts_free(out), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (np == 1) return one_part(m, out);
  size_t bound[DTM_NODE_PARTS_MAX + 1];
  for (int p = 0; p <= np; p++) bound[p] = (size_t)p * m->nnodes / (size_t)np;
  split sp = {np, bound};
  int sorted = 1;
  for (int b = 0; b < m->nblocks && sorted; b++) {
    int r = split_block(&m->blocks[b], &sp, out, b, &sorted);
    if (r) return dtm_mesh_node_parts_free(out), r;
  }
  if (sorted) return DTM_OK;
  for (int b = 0; b < m->nblocks; b++) free(out->list[b]), out->list[b] = NULL;
  return one_part(m, out);
}

void dtm_mesh_node_part(const dtm_node_parts *parts, int p, size_t *lo, size_t *hi) {
  *lo = (size_t)p * parts->nnodes / (size_t)parts->n;
  *hi = parts->n == 1 ? SIZE_MAX : (size_t)(p + 1) * parts->nnodes / (size_t)parts->n;
}

void dtm_mesh_node_part_elements(const dtm_node_parts *parts, int p, int b, const size_t **list, size_t *nlist,
                                 size_t *e0, size_t *e1) {
  const size_t *core = parts->core + (size_t)b * (size_t)(parts->n + 1),
               *at = parts->at + (size_t)b * (size_t)(parts->n + 1);
  *list = parts->list[b] ? parts->list[b] + at[p] : NULL;
  *nlist = at[p + 1] - at[p];
  *e0 = core[p], *e1 = core[p + 1];
}

void dtm_mesh_node_parts_free(dtm_node_parts *parts) {
  for (int b = 0; parts->list && b < parts->nblocks; b++) free(parts->list[b]);
  free(parts->list), free(parts->core), free(parts->at);
  memset(parts, 0, sizeof *parts);
}
