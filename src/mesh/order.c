/* Renumbering a mesh for locality. Meshers number elements and nodes in the
 * order they create them: in Gmsh's 3D Delaunay numbering consecutive
 * elements reference nodes some 33,000 indices apart, so every loop that
 * gathers node data per element (the element map, the nodal bound, the
 * size suggestion, the matrix-free product of the global estimate) misses
 * the cache on almost every node. dtm_mesh_reorder numbers the nodes along
 * a Hilbert curve (16 bits per axis over the bounding box; a stable LSD
 * radix sort of the keys), then sorts the elements of each block by their
 * smallest new node number (a counting sort), so that consecutive elements
 * share nodes and sweep the node arrays once, in order. Both sorts are
 * O(n). Element and node tags travel with their elements and nodes, so
 * everything reported by tag (Gmsh's numbering) is unchanged; only array
 * positions move. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/mesh.h"

#define HILBERT_BITS 10 /* per axis: 2^30 cells over the bounding box, 30-bit keys */

/* The 10 low bits of v spread to every third bit (bit i to bit 3i). */
static uint64_t spread3(uint64_t v) {
  v &= 0x3ff;
  v = (v | v << 16) & 0x30000ffull;
  v = (v | v << 8) & 0x300f00full;
  v = (v | v << 4) & 0x30c30c3ull;
  return (v | v << 2) & 0x9249249ull;
}

/* Hilbert index of the integer point x[3] (HILBERT_BITS bits per axis), by
 * Skilling's transpose ("Programming the Hilbert curve", AIP Conf. Proc.
 * 707, 2004), the transposed bits interleaved into one key. */
static uint64_t hilbert_key(uint32_t x[3]) {
  uint32_t t;
  for (uint32_t q = 1u << (HILBERT_BITS - 1); q > 1; q >>= 1) {
    uint32_t p = q - 1;
    for (int i = 0; i < 3; i++)
      if (x[i] & q)
        x[0] ^= p;
      else
        t = (x[0] ^ x[i]) & p, x[0] ^= t, x[i] ^= t;
  }
  x[1] ^= x[0], x[2] ^= x[1];
  t = 0;
  for (uint32_t q = 1u << (HILBERT_BITS - 1); q > 1; q >>= 1)
    if (x[2] & q) t ^= q - 1;
  return spread3(x[0] ^ t) << 2 | spread3(x[1] ^ t) << 1 | spread3(x[2] ^ t);
}

typedef struct {
  uint64_t key; /* Hilbert key */
  size_t idx;   /* node index */
} keyed;

#define DIGIT 15             /* radix bits per pass: 2 passes over 30-bit keys */
#define COPY_CHUNK (1 << 14) /* elements copied back at a time by one thread */

/* Stable LSD radix sort of a[n] by key; tmp[n] is scratch. */
static void radix_sort(keyed *a, keyed *tmp, size_t n, int bits) {
  size_t *count = malloc(((1u << DIGIT) + 1) * sizeof *count);
  keyed *orig = a;
  if (!count) return; /* unsorted: still a valid order */
  for (int shift = 0; shift < bits; shift += DIGIT) {
    const uint64_t mask = (1u << DIGIT) - 1;
    memset(count, 0, ((1u << DIGIT) + 1) * sizeof *count);
    for (size_t i = 0; i < n; i++) count[((a[i].key >> shift) & mask) + 1]++;
    for (size_t d = 0; d < (1u << DIGIT); d++) count[d + 1] += count[d];
    for (size_t i = 0; i < n; i++) tmp[count[(a[i].key >> shift) & mask]++] = a[i];
    keyed *t = a;
    a = tmp, tmp = t;
  }
  free(count);
  if (a != orig) memcpy(orig, a, n * sizeof *a); /* an odd number of passes */
}

/* Bounding box of the nodes: lo[3] and the scale to [0, 2^b). */
static void box(const dtm_mesh *m, double lo[3], double *scale) {
  double hi[3] = {-INFINITY, -INFINITY, -INFINITY}, ext = 0;
  lo[0] = lo[1] = lo[2] = INFINITY;
  for (size_t v = 0; v < m->nnodes; v++)
    for (int i = 0; i < 3; i++) lo[i] = fmin(lo[i], m->xyz[3 * v + i]), hi[i] = fmax(hi[i], m->xyz[3 * v + i]);
  for (int i = 0; i < 3; i++) ext = fmax(ext, hi[i] - lo[i]);
  *scale = ext > 0 && isfinite(ext) ? ((double)(1u << HILBERT_BITS) - 1) / ext : 0;
}

/* Node order along the Hilbert curve: old_of[new] = old, new_of[old] = new. */
static int node_order(const dtm_mesh *m, size_t *new_of, size_t *old_of) {
  size_t n = m->nnodes;
  keyed *k = malloc((n + 1) * sizeof *k), *tmp = malloc((n + 1) * sizeof *tmp);
  if (!k || !tmp) return free(k), free(tmp), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  double lo[3], sc;
  box(m, lo, &sc);
#pragma omp parallel for schedule(static)
  for (size_t v = 0; v < n; v++) {
    uint32_t x[3];
    for (int i = 0; i < 3; i++) {
      double q = (m->xyz[3 * v + i] - lo[i]) * sc;
      x[i] = q > 0 ? (uint32_t)fmin(q, (double)((1u << HILBERT_BITS) - 1)) : 0;
    }
    k[v] = (keyed){hilbert_key(x), v};
  }
  radix_sort(k, tmp, n, 3 * HILBERT_BITS);
  for (size_t v = 0; v < n; v++) old_of[v] = k[v].idx, new_of[k[v].idx] = v;
  free(k), free(tmp);
  return DTM_OK;
}

/* Renumber b's connectivity and sort its elements by their smallest new
 * node number (stable counting sort): order[old] = new position. count
 * has nnodes + 1 entries. */
static void element_order(dtm_block *b, const size_t *new_of, size_t nnodes, size_t *count, size_t *order) {
  size_t nn = (size_t)b->nn;
  memset(count, 0, (nnodes + 1) * sizeof *count);
#pragma omp parallel for schedule(static)
  for (size_t e = 0; e < b->n; e++) {
    size_t lo = SIZE_MAX, *c = b->conn + e * nn;
    for (size_t a = 0; a < nn; a++) c[a] = new_of[c[a]], lo = c[a] < lo ? c[a] : lo;
    order[e] = lo; /* the key, for now */
  }
  for (size_t e = 0; e < b->n; e++) count[order[e] + 1]++;
  for (size_t v = 0; v < nnodes; v++) count[v + 1] += count[v];
  for (size_t e = 0; e < b->n; e++) {
    size_t key = order[e];
    order[e] = count[key]; /* the new position of e ... */
    count[key]++;
  }
}

/* Apply the element order (pos[old] = new) to one per-element array of w
 * bytes per element, a multiple of 4, through scratch (at least n w
 * bytes), so that no fresh memory is touched per array; both passes on
 * the threads. *field may be NULL: nothing to do. */
static void permute(void *field, size_t w, const size_t *pos, size_t n, uint32_t *scratch) {
  if (!field) return;
  uint32_t *f = field;
  size_t q = w / 4;
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (size_t e = 0; e < n; e++)
      for (size_t k = 0; k < q; k++) scratch[pos[e] * q + k] = f[e * q + k];
    const size_t chunks = (n + COPY_CHUNK - 1) / COPY_CHUNK;
#pragma omp for schedule(static)
    for (size_t c = 0; c < chunks; c++) {
      size_t e0 = c * COPY_CHUNK, k = n - e0 < COPY_CHUNK ? n - e0 : COPY_CHUNK;
      memcpy(f + e0 * q, scratch + e0 * q, k * w);
    }
  }
}

/* The connectivity (the largest array) permuted into *scratch, which
 * becomes the block's, its old array the scratch of the rest: no copy
 * back. Only when *scratch is the size of the largest block (cap). */
static void permute_conn(dtm_block *b, const size_t *pos, uint32_t **scratch, size_t cap) {
  size_t w = (size_t)b->nn * sizeof *b->conn;
  if (b->n * w != cap) {
    permute(b->conn, w, pos, b->n, *scratch);
    return;
  }
  const uint32_t *f = (const uint32_t *)b->conn;
  uint32_t *to = *scratch;
  size_t q = w / 4;
#pragma omp parallel for schedule(static)
  for (size_t e = 0; e < b->n; e++)
    for (size_t k = 0; k < q; k++) to[pos[e] * q + k] = f[e * q + k];
  *scratch = (uint32_t *)b->conn;
  b->conn = (size_t *)to;
}

static void permute_block(dtm_block *b, const size_t *pos, uint32_t **scratch, size_t cap) {
  permute_conn(b, pos, scratch, cap);
  uint32_t *s = *scratch;
  permute(b->tags, sizeof *b->tags, pos, b->n, s);
  permute(b->group, sizeof *b->group, pos, b->n, s);
  permute(b->mat, sizeof *b->mat, pos, b->n, s);
  permute(b->gmask, sizeof *b->gmask, pos, b->n, s);
  permute(b->entity, sizeof *b->entity, pos, b->n, s);
  permute(b->section, sizeof *b->section, pos, b->n, s);
}

static int sort_blocks(dtm_mesh *m, const size_t *new_of) {
  size_t nmax = 0, wmax = 0;
  for (int ib = 0; ib < m->nblocks; ib++) {
    size_t n = m->blocks[ib].n, w = n * (size_t)m->blocks[ib].nn * sizeof(size_t);
    nmax = n > nmax ? n : nmax, wmax = w > wmax ? w : wmax;
  }
  size_t *count = malloc((m->nnodes + 2) * sizeof *count), *pos = malloc((nmax + 1) * sizeof *pos);
  uint32_t *scratch = malloc(wmax + sizeof(size_t));
  int r = count && pos && scratch ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int ib = 0; ib < m->nblocks && r == DTM_OK; ib++) {
    element_order(&m->blocks[ib], new_of, m->nnodes, count, pos);
    permute_block(&m->blocks[ib], pos, &scratch, wmax);
  }
  free(count), free(pos), free(scratch);
  return r;
}

static int permute_nodes(dtm_mesh *m, const size_t *old_of) {
  double *xyz = malloc((3 * m->nnodes + 1) * sizeof *xyz);
  size_t *tags = m->node_tags ? malloc((m->nnodes + 1) * sizeof *tags) : NULL;
  double *mass = m->node_mass ? malloc((m->nnodes + 1) * sizeof *mass) : NULL;
  if (!xyz || (m->node_tags && !tags) || (m->node_mass && !mass))
    return free(xyz), free(tags), free(mass), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < m->nnodes; v++) memcpy(xyz + 3 * v, m->xyz + 3 * old_of[v], 3 * sizeof *xyz);
  for (size_t v = 0; tags && v < m->nnodes; v++) tags[v] = m->node_tags[old_of[v]];
  for (size_t v = 0; mass && v < m->nnodes; v++) mass[v] = m->node_mass[old_of[v]];
  free(m->xyz), m->xyz = xyz;
  if (tags) free(m->node_tags), m->node_tags = tags;
  if (mass) free(m->node_mass), m->node_mass = mass;
  return DTM_OK;
}

static int check_conn(const dtm_mesh *m) {
  for (int ib = 0; ib < m->nblocks; ib++) {
    const size_t *c = m->blocks[ib].conn, n = m->blocks[ib].n * (size_t)m->blocks[ib].nn;
    size_t bad = SIZE_MAX; /* the first entry out of range */
#pragma omp parallel for schedule(static) reduction(min : bad)
    for (size_t k = 0; k < n; k++)
      if (c[k] >= m->nnodes && k < bad) bad = k;
    if (bad != SIZE_MAX)
      return DTM_ERR(DTM_ERR_INTERNAL, "element connectivity refers to node %zu of %zu", c[bad], m->nnodes);
  }
  return DTM_OK;
}

int dtm_mesh_reorder(dtm_mesh *m) {
  DTM_CHECK(check_conn(m));
  size_t *new_of = malloc((m->nnodes + 1) * sizeof *new_of), *old_of = malloc((m->nnodes + 1) * sizeof *old_of);
  int r = new_of && old_of ? node_order(m, new_of, old_of) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = sort_blocks(m, new_of);
  if (r == DTM_OK) r = permute_nodes(m, old_of);
  free(new_of), free(old_of);
  return r;
}
