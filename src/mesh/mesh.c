/* dtm_mesh helpers that do not need Gmsh: counts, group look-up, gathering
 * element coordinates, destruction. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
  free(m->node_tags);
  free(m->xyz);
  free(m);
  *pm = NULL;
}
