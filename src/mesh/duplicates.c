/* Elements that appear twice in a mesh: two elements of one type with the
 * same set of nodes. Gmsh 4.8 reads a .msh holding two $Nodes and two
 * $Elements blocks (a view appended to a mesh file with
 * PostProcessing.SaveMesh = 1 writes the mesh again) as the mesh twice,
 * every element tag listed twice on the same node tags; analysed so, every
 * element would count twice (mass, run time, histograms) and nothing would
 * say so. The search is exact and O(n): the elements of a block are bucketed
 * by their smallest node (a counting sort), and only elements of one bucket
 * are compared (two elements with the same nodes have the same smallest
 * node; a bucket holds about as many elements as meet at a node). */
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "mesh-impl.h"

/* What the search found. */
typedef struct {
  size_t count; /* elements that repeat an earlier one */
  int block;    /* the first pair's block (-1: none) */
  size_t first; /* its elements' indices in that block */
  size_t second;
} dup_found;

static size_t min_node(const size_t *c, int nn) {
  size_t v = c[0];
  for (int i = 1; i < nn; i++) v = c[i] < v ? c[i] : v;
  return v;
}

/* Whether every node of a is one of b's (elements of one type: as many nodes each). */
static int same_nodes(const size_t *a, const size_t *b, int nn) {
  for (int i = 0; i < nn; i++) {
    int in = 0;
    for (int j = 0; j < nn && !in; j++) in = a[i] == b[j];
    if (!in) return 0;
  }
  return 1;
}

/* The elements of block blk ordered by their smallest node into order[n],
 * with start[nnodes + 1] the first of each node's bucket and key[n] the sum
 * of each one's nodes (in order's order: a cheap filter before the set
 * comparison). */
static void bucket(const dtm_mesh *m, const dtm_block *blk, size_t *start, size_t *order, size_t *key) {
  const size_t nn = (size_t)blk->nn;
  memset(start, 0, (m->nnodes + 1) * sizeof *start);
  for (size_t e = 0; e < blk->n; e++) start[min_node(blk->conn + e * nn, blk->nn) + 1]++;
  for (size_t v = 0; v < m->nnodes; v++) start[v + 1] += start[v];
  for (size_t e = 0; e < blk->n; e++) {
    const size_t *c = blk->conn + e * nn;
    size_t at = start[min_node(c, blk->nn)]++, sum = 0;
    for (size_t i = 0; i < nn; i++) sum += c[i];
    order[at] = e, key[at] = sum;
  }
  for (size_t v = m->nnodes; v > 0; v--) start[v] = start[v - 1]; /* back to each bucket's first */
  start[0] = 0;
}

/* The elements of bucket order[lo, hi) of block blk that repeat an earlier
 * one of it; the first such pair into *first and *second when not NULL. */
static size_t bucket_pairs(const dtm_block *blk, const size_t *order, const size_t *key, size_t lo, size_t hi,
                           size_t *first, size_t *second) {
  const size_t nn = (size_t)blk->nn;
  size_t count = 0;
  for (size_t i = lo + 1; i < hi; i++)
    for (size_t j = lo; j < i; j++)
      if (key[i] == key[j] && same_nodes(blk->conn + order[i] * nn, blk->conn + order[j] * nn, blk->nn)) {
        if (count++ == 0 && first) *first = order[j], *second = order[i];
        break; /* counted once, however often it repeats */
      }
  return count;
}

/* The repeated elements of block b into f: counted over the buckets on the
 * OpenMP threads, the first pair taken from the first bucket that has one. */
static void block_duplicates(const dtm_mesh *m, int b, size_t *start, size_t *order, size_t *key, dup_found *f) {
  const dtm_block *blk = &m->blocks[b];
  bucket(m, blk, start, order, key);
  size_t count = 0, firstv = m->nnodes;
  const long long nv = (long long)m->nnodes;
#pragma omp parallel for schedule(static) reduction(+ : count) reduction(min : firstv)
  for (long long v = 0; v < nv; v++) {
    size_t c = start[v + 1] - start[v] > 1 ? bucket_pairs(blk, order, key, start[v], start[v + 1], NULL, NULL) : 0;
    count += c;
    if (c && (size_t)v < firstv) firstv = (size_t)v;
  }
  if (!count) return;
  if (!f->count) f->block = b, bucket_pairs(blk, order, key, start[firstv], start[firstv + 1], &f->first, &f->second);
  f->count += count;
}

static int refuse(const dtm_mesh *m, const char *src, const dup_found *f) {
  const dtm_block *blk = &m->blocks[f->block];
  char place[256];
  dtm_mesh_element_place(m, f->block, f->first, place, sizeof place);
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: the mesh is in the file twice: %zu element%s repeat%s another of the same type on the same "
                 "nodes (the first: %s, and element %zu%s); each would be counted twice. Gmsh writes such a file when "
                 "a view is appended to a .msh that holds the mesh, saving the mesh again (PostProcessing.SaveMesh "
                 "= 1): write the mesh alone (from its model, or a copy of the file without the second $Nodes and "
                 "$Elements sections) and views to files of their own",
                 src, f->count, f->count == 1 ? "" : "s", f->count == 1 ? "s" : "", place, blk->tags[f->second],
                 blk->tags[f->second] == blk->tags[f->first] ? ", the same tag listed twice" : "");
}

int dtm_mesh_check_duplicates(const dtm_mesh *m, const char *src) {
  size_t most = 0;
  for (int b = 0; b < m->nblocks; b++) most = m->blocks[b].n > most ? m->blocks[b].n : most;
  size_t *start = malloc((m->nnodes + 1) * sizeof *start), *order = malloc((2 * most + 1) * sizeof *order);
  dup_found f = {0, -1, 0, 0};
  if (!start || !order) return free(start), free(order), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int b = 0; b < m->nblocks; b++)
    if (m->blocks[b].n > 1) block_duplicates(m, b, start, order, order + most, &f);
  free(start), free(order);
  return f.count ? refuse(m, src, &f) : DTM_OK;
}
