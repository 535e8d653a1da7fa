/* What extraction leaves out of a model. The analysed dimension's elements
 * are extracted, and below it only the groups a section names; the other
 * curves and surfaces are not analysed. Most of them bound the analysed
 * elements (a solid's faces, a plate's edges) and lose nothing, but a
 * curve or surface that reaches nodes no analysed element has is a part of
 * the model left out: a tower's bars beside its shell walls, a plate
 * standing beside a solid. Right after extraction, while Gmsh holds the
 * model, this counts the nodes the analysed elements use and, when some
 * node is left over, lists per physical group the elements of every such
 * entity below the analysed dimension (the entities in no physical group
 * only when the model has none: with groups, Gmsh's model is what they
 * hold). The summary and the report name them with the section that
 * would include them. */
#include <gmshc.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

/* used[i] = 1 for the nodes (indices) the elements use; their count. */
static size_t mark_used(const dtm_mesh *m, unsigned char *used) {
  size_t n = 0;
  for (int b = 0; b < m->nblocks; b++)
    for (size_t k = 0; k < m->blocks[b].n * (size_t)m->blocks[b].nn; k++) {
      size_t i = m->blocks[b].conn[k];
      n += !used[i], used[i] = 1;
    }
  return n;
}

/* The same by node tag, by_tag[maxtag + 1] (calloc'ed; NULL: out of memory). */
static unsigned char *used_by_tag(const dtm_mesh *m, const unsigned char *used, size_t *maxtag) {
  *maxtag = 0;
  for (size_t i = 0; i < m->nnodes; i++) *maxtag = m->node_tags[i] > *maxtag ? m->node_tags[i] : *maxtag;
  unsigned char *by_tag = calloc(*maxtag + 1, 1);
  for (size_t i = 0; by_tag && i < m->nnodes; i++) by_tag[m->node_tags[i]] = used[i];
  return by_tag;
}

/* Whether entity (dim, tag) (its boundary included) has a node no analysed
 * element uses. */
static int reaches_free_node(int dim, int tag, const unsigned char *used, size_t maxtag) {
  size_t *nt = NULL, nn = 0, nc = 0, np = 0;
  double *c = NULL, *p = NULL;
  int ierr = 0, free_node = 0;
  gmshModelMeshGetNodes(&nt, &nn, &c, &nc, &p, &np, dim, tag, 1, 0, &ierr);
  for (size_t i = 0; !ierr && i < nn && !free_node; i++) free_node = nt[i] > maxtag || !used[nt[i]];
  gmshFree(nt), gmshFree(c), gmshFree(p);
  return free_node;
}

static size_t entity_elements(int dim, int tag) {
  int *types = NULL, ierr = 0;
  size_t nt = 0, ne = 0;
  gmshModelMeshGetElementTypes(&types, &nt, dim, tag, &ierr);
  for (size_t i = 0; !ierr && i < nt; i++) {
    size_t *et = NULL, n = 0, *ntag = NULL, nn = 0;
    gmshModelMeshGetElementsByType(types[i], &et, &n, &ntag, &nn, tag, 0, 1, &ierr);
    ne += ierr ? 0 : n;
    gmshFree(et), gmshFree(ntag);
  }
  gmshFree(types);
  return ne;
}

/* Add n elements to group (dim, tag) of m->left. */
static int add_left(dtm_mesh *m, int dim, int tag, size_t n) {
  for (int i = 0; i < m->nleft; i++)
    if (m->left[i].dim == dim && m->left[i].tag == tag) return m->left[i].elements += n, DTM_OK;
  dtm_left_out *l = realloc(m->left, ((size_t)m->nleft + 1) * sizeof *l);
  if (!l) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  m->left = l;
  l = &m->left[m->nleft++];
  *l = (dtm_left_out){dim, tag, "", n};
  char *name = NULL;
  int ierr = 0;
  if (tag >= 0) gmshModelGetPhysicalName(dim, tag, &name, &ierr);
  if (name) strncpy(l->name, name, sizeof l->name - 1);
  gmshFree(name);
  return DTM_OK;
}

/* Whether group (dim, tag) is one of the mesh's (a sectioned group). */
static int analysed_group(const dtm_mesh *m, int dim, int tag) {
  for (int g = 0; g < m->ngroups; g++)
    if (m->groups[g].dim == dim && m->groups[g].tag == tag) return 1;
  return 0;
}

/* The physical groups of entity (dim, tag) (caller gmshFrees *phys); 0
 * when it is analysed (in a sectioned group) or, in a model with groups,
 * in none: then it is not counted. */
static int counted(const dtm_mesh *m, int dim, int tag, int grouped, int **phys, size_t *np) {
  int ierr = 0, skip;
  *phys = NULL, *np = 0;
  gmshModelGetPhysicalGroupsForEntity(dim, tag, phys, np, &ierr);
  skip = ierr || (grouped && !*np);
  for (size_t i = 0; !skip && i < *np; i++) skip = analysed_group(m, dim, (*phys)[i]);
  return !skip;
}

static int in_list(const int *v, int n, int x) {
  for (int i = 0; i < n; i++)
    if (v[i] == x) return 1;
  return 0;
}

/* Pass 1: the groups (-1: none) with an entity that reaches a free node. */
static int free_groups(const dtm_mesh *m, int dim, const int *ents, size_t ne, int grouped, const unsigned char *used,
                       size_t maxtag, int *out, int *nout) {
  for (size_t i = 0; i < ne / 2; i++) {
    int *phys, tag = ents[2 * i + 1];
    size_t np;
    if (counted(m, dim, tag, grouped, &phys, &np) && reaches_free_node(dim, tag, used, maxtag))
      for (size_t k = 0; k < (np ? np : 1); k++)
        if (!in_list(out, *nout, np ? phys[k] : -1)) out[(*nout)++] = np ? phys[k] : -1;
    gmshFree(phys);
  }
  return DTM_OK;
}

/* Pass 2: every element of those groups, per group and once in all. */
static int count_groups(dtm_mesh *m, int dim, const int *ents, size_t ne, int grouped, const int *g, int ng) {
  int r = DTM_OK;
  for (size_t i = 0; i < ne / 2 && r == DTM_OK; i++) {
    int *phys, tag = ents[2 * i + 1], hit = 0;
    size_t np, n = 0;
    if (counted(m, dim, tag, grouped, &phys, &np))
      for (size_t k = 0; k < (np ? np : 1) && r == DTM_OK; k++) {
        int p = np ? phys[k] : -1;
        if (!in_list(g, ng, p)) continue;
        if (!hit) n = entity_elements(dim, tag), hit = 1, m->nleft_dim[dim] += n;
        r = add_left(m, dim, p, n);
      }
    gmshFree(phys);
  }
  return r;
}

/* The groups of dimension dim left out, into m->left. */
static int dim_left(dtm_mesh *m, int dim, int grouped, const unsigned char *used, size_t maxtag) {
  int *ents = NULL, ierr = 0, ng = 0, r = DTM_OK;
  size_t ne = 0;
  gmshModelGetEntities(&ents, &ne, dim, &ierr);
  int *g = ierr ? NULL : malloc((ne / 2 + 1) * sizeof *g);
  if (!ierr && !g) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (g) r = free_groups(m, dim, ents, ne, grouped, used, maxtag, g, &ng);
  if (g && r == DTM_OK && ng) r = count_groups(m, dim, ents, ne, grouped, g, ng);
  free(g);
  gmshFree(ents);
  return r;
}

static int model_has_groups(void) {
  int *dt = NULL, ierr = 0;
  size_t n = 0;
  gmshModelGetPhysicalGroups(&dt, &n, -1, &ierr);
  gmshFree(dt);
  return !ierr && n > 0;
}

int dtm_gmsh_left_out(dtm_mesh *m) {
  size_t maxtag = 0;
  unsigned char *used = calloc(m->nnodes + 1, 1), *by_tag = NULL;
  if (!used) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  m->nodes_used = mark_used(m, used);
  if (m->nodes_used < m->nnodes && m->dim > 1) by_tag = used_by_tag(m, used, &maxtag); /* a node left over */
  free(used);
  if (m->nodes_used < m->nnodes && m->dim > 1 && !by_tag) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = DTM_OK, grouped = by_tag && model_has_groups();
  for (int d = 1; d < m->dim && r == DTM_OK && by_tag; d++) r = dim_left(m, d, grouped, by_tag, maxtag);
  free(by_tag);
  return r;
}
