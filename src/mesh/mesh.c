/* dtm_mesh helpers that do not need Gmsh: counts, group look-up, gathering
 * element coordinates, destruction. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/mesh.h"

size_t dtm_mesh_nelements(const dtm_mesh *m) {
  size_t n = 0;
  for (int b = 0; b < m->nblocks; b++) n += m->blocks[b].n;
  return n;
}

const char *dtm_mesh_group_label(const dtm_mesh *m, int g, char *buf, size_t len) {
  if (g < 0 || g >= m->ngroups) {
    snprintf(buf, len, "(none)");
    return buf;
  }
  if (m->groups[g].name[0]) return m->groups[g].name;
  snprintf(buf, len, "%d", m->groups[g].tag);
  return buf;
}

int dtm_mesh_group_find(const dtm_mesh *m, const char *ref) {
  for (int g = 0; g < m->ngroups; g++)
    if (strcmp(m->groups[g].name, ref) == 0) return g;
  char *end = NULL;
  long tag = strtol(ref, &end, 10);
  if (end == ref || *end) return -1;
  for (int g = 0; g < m->ngroups; g++)
    if (m->groups[g].tag == tag) return g;
  return -1;
}

void dtm_mesh_gather(const dtm_mesh *m, const dtm_block *b, double *x) {
  /* x has shape [n][nn][3] */
  const size_t nn = (size_t)b->nn;
  for (size_t e = 0; e < b->n; e++)
    for (size_t a = 0; a < nn; a++) {
      const double *p = m->xyz + 3 * b->conn[e * nn + a];
      double *q = x + 3 * (e * nn + a);
      q[0] = p[0];
      q[1] = p[1];
      q[2] = p[2];
    }
}

void dtm_mesh_gather_one(const dtm_mesh *m, const dtm_block *b, size_t e, double *x) {
  dtm_block one = *b;
  one.n = 1, one.conn = b->conn + e * (size_t)b->nn;
  dtm_mesh_gather(m, &one, x);
}

void dtm_mesh_materials_used(const dtm_mesh *m, int nmat, char *used) {
  memset(used, 0, (size_t)nmat);
  for (int b = 0; b < m->nblocks; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++)
      if (m->blocks[b].mat[e] >= 0 && m->blocks[b].mat[e] < nmat) used[m->blocks[b].mat[e]] = 1;
}

void dtm_mesh_destroy(dtm_mesh **pm) {
  dtm_mesh *m = *pm;
  if (!m) return;
  for (int b = 0; b < m->nblocks; b++) {
    free(m->blocks[b].tags);
    free(m->blocks[b].conn);
    free(m->blocks[b].group);
    free(m->blocks[b].gmask);
    free(m->blocks[b].entity);
    free(m->blocks[b].section);
    free(m->blocks[b].mat);
  }
  for (int g = 0; g < m->ngroups; g++) free(m->groups[g].name);
  free(m->blocks);
  free(m->groups);
  free(m->flagged);
  free(m->left);
  free(m->node_tags);
  free(m->node_mass);
  free(m->xyz);
  free(m);
  *pm = NULL;
}

/* Whether every node index of the elements is below the node count. */
static int conn_in_range(const dtm_mesh *m) {
  for (int ib = 0; ib < m->nblocks; ib++) {
    const dtm_block *b = &m->blocks[ib];
    size_t top = 0;
    for (size_t k = 0; k < b->n * (size_t)b->nn; k++) top = b->conn[k] > top ? b->conn[k] : top;
    if (b->n && top >= m->nnodes) return 0;
  }
  return 1;
}

/* Extent per component, into ext[3], of the nodes the elements use (all:
 * of every node, a bound of it). */
static void node_extent(const dtm_mesh *m, int all, double ext[3]) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t v = 0; all && v < m->nnodes; v++)
    for (int i = 0; i < 3; i++) lo[i] = fmin(lo[i], m->xyz[3 * v + i]), hi[i] = fmax(hi[i], m->xyz[3 * v + i]);
  for (int ib = 0; !all && ib < m->nblocks; ib++) {
    const dtm_block *b = &m->blocks[ib];
    for (size_t k = 0; k < b->n * (size_t)b->nn; k++)
      for (int i = 0; i < 3; i++) {
        double x = m->xyz[3 * b->conn[k] + i];
        lo[i] = fmin(lo[i], x), hi[i] = fmax(hi[i], x);
      }
  }
  for (int i = 0; i < 3; i++) ext[i] = hi[i] >= lo[i] ? hi[i] - lo[i] : 0;
}

int dtm_mesh_extent(const dtm_mesh *m, double ext[3]) {
  if (!conn_in_range(m))
    return DTM_ERR(DTM_ERR_INTERNAL, "element connectivity refers to a node beyond the mesh's %zu nodes", m->nnodes);
  node_extent(m, 0, ext);
  return DTM_OK;
}

static double extent_size(const double ext[3]) { return fmax(ext[0], fmax(ext[1], ext[2])); }

/* The space the unknowns live in, *d: the mesh's dimension when its
 * nodes allow (a 2D mesh in a plane z = const, a 1D mesh along x), else the
 * smallest that holds them (a 1D mesh in a plane z = const: 2; anything
 * else: 3). Elements of lower dimension than *d are manifold elements. */
int dtm_mesh_space_dim(const dtm_mesh *m, int *d) {
  double ext[3], size;
  if (m->space_dim > 0) return *d = m->space_dim, DTM_OK;
  if (!conn_in_range(m))
    return DTM_ERR(DTM_ERR_INTERNAL, "element connectivity refers to a node beyond the mesh's %zu nodes", m->nnodes);
  node_extent(m, 1, ext); /* a 3D mesh is 3D whatever its extent: every node's, finite, is enough */
  if (m->dim < 3 || !isfinite(extent_size(ext))) node_extent(m, 0, ext);
  size = extent_size(ext);
  if (!isfinite(size)) return DTM_ERR(DTM_ERR_INPUT, "the mesh has non-finite node coordinates");
  int flat_z = ext[2] <= 1e-9 * size, flat_y = ext[1] <= 1e-9 * size;
  *d = m->dim == 3 || !flat_z ? 3 : m->dim == 2 || !flat_y ? 2 : 1;
  return DTM_OK;
}
