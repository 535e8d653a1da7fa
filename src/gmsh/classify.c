/* Where the mesh sits on the model: for every node the model entity Gmsh
 * classified it on, for every element its model entity, and for the
 * entities below the mesh's dimension their model points and (curves)
 * their length. The advice reads angles and short or thin features off
 * this (src/analysis/shape.c); nothing here computes a step. Also saving
 * and restoring the current mesh, which the refine loop uses to keep its
 * best round. */
#include <gmshc.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

/* A map from Gmsh tags to dense indices. */
typedef struct {
  size_t *index; /* [max + 1], SIZE_MAX where none */
  size_t max;    /* largest tag */
} tag_map;

static int map_build(const size_t *tags, size_t n, tag_map *tm) {
  tm->max = 0;
  for (size_t i = 0; i < n; i++)
    if (tags[i] > tm->max) tm->max = tags[i];
  tm->index = malloc((tm->max + 1) * sizeof *tm->index);
  if (!tm->index) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  memset(tm->index, 0xff, (tm->max + 1) * sizeof *tm->index);
  for (size_t i = 0; i < n; i++) tm->index[tags[i]] = i;
  return DTM_OK;
}

static size_t map_get(const tag_map *tm, size_t tag) { return tag <= tm->max ? tm->index[tag] : SIZE_MAX; }

/* Element tags of the mesh in global order. */
static size_t *element_tags(const dtm_mesh *m, size_t *n) {
  *n = dtm_mesh_nelements(m);
  size_t *t = malloc((*n + 1) * sizeof *t), k = 0;
  for (int b = 0; t && b < m->nblocks; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++) t[k++] = m->blocks[b].tags[e];
  return t;
}

/* Nodes classified on entity (dim, tag), without its boundary. */
static int classify_nodes(const tag_map *nodes, int dim, int tag, dtm_geo *g) {
  size_t *tags = NULL, n = 0, nc = 0, np = 0;
  double *xyz = NULL, *par = NULL;
  int ierr = 0;
  gmshModelMeshGetNodes(&tags, &n, &xyz, &nc, &par, &np, dim, tag, 0, 0, &ierr);
  gmshFree(xyz), gmshFree(par);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot read the nodes of a model entity");
  for (size_t i = 0; i < n; i++) {
    size_t v = map_get(nodes, tags[i]);
    if (v != SIZE_MAX) g->node_dim[v] = dim, g->node_tag[v] = tag;
  }
  gmshFree(tags);
  return DTM_OK;
}

/* The elements of entity (dim, tag): element tags (per type) and, for
 * curves, the sum of the chords between their first two nodes. */
static int entity_elements(const dtm_mesh *m, const tag_map *nodes, const tag_map *els, int dim, int tag, dtm_geo *g,
                           double *length) {
  int *types = NULL, ierr = 0;
  size_t nt = 0, **et = NULL, *net = NULL, ne = 0, **nt_ = NULL, *nnt = NULL, nn = 0;
  gmshModelMeshGetElements(&types, &nt, &et, &net, &ne, &nt_, &nnt, &nn, dim, tag, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot read the elements of a model entity");
  *length = 0;
  for (size_t i = 0; i < nt; i++) {
    size_t per = net[i] ? nnt[i] / net[i] : 0;
    for (size_t e = 0; e < net[i]; e++) {
      if (dim == m->dim && els->index && map_get(els, et[i][e]) != SIZE_MAX)
        g->elem_entity[map_get(els, et[i][e])] = tag;
      size_t a = per >= 2 ? map_get(nodes, nt_[i][e * per]) : SIZE_MAX,
             b = per >= 2 ? map_get(nodes, nt_[i][e * per + 1]) : SIZE_MAX;
      if (dim != 1 || a == SIZE_MAX || b == SIZE_MAX) continue;
      const double *xa = m->xyz + 3 * a, *xb = m->xyz + 3 * b;
      *length += sqrt((xa[0] - xb[0]) * (xa[0] - xb[0]) + (xa[1] - xb[1]) * (xa[1] - xb[1]) +
                      (xa[2] - xb[2]) * (xa[2] - xb[2]));
    }
    gmshFree(et[i]), gmshFree(nt_[i]);
  }
  gmshFree(types), gmshFree(et), gmshFree(net), gmshFree(nt_), gmshFree(nnt);
  return DTM_OK;
}

/* The model points in the closure of entity e. */
static int entity_points(dtm_geo_entity *e) {
  int in[2] = {e->dim, e->tag}, *out = NULL, ierr = 0;
  size_t n = 0;
  if (e->dim == 0) {
    e->points = malloc(sizeof *e->points);
    if (!e->points) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    e->points[0] = e->tag, e->npoints = 1;
    return DTM_OK;
  }
  gmshModelGetBoundary(in, 2, &out, &n, 0, 0, 1, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot read the boundary of a model entity");
  e->points = malloc((n / 2 + 1) * sizeof *e->points);
  if (!e->points) return gmshFree(out), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < n / 2; i++)
    if (out[2 * i] == 0) e->points[e->npoints++] = abs(out[2 * i + 1]);
  gmshFree(out);
  return DTM_OK;
}

static int alloc_geo(const dtm_mesh *m, size_t nel, size_t nent, dtm_geo *g) {
  g->nnodes = m->nnodes, g->nel = nel;
  g->node_dim = malloc((m->nnodes + 1) * sizeof *g->node_dim);
  g->node_tag = malloc((m->nnodes + 1) * sizeof *g->node_tag);
  g->elem_entity = malloc((nel + 1) * sizeof *g->elem_entity);
  g->ent = calloc(nent + 1, sizeof *g->ent);
  if (!g->node_dim || !g->node_tag || !g->elem_entity || !g->ent) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < m->nnodes; v++) g->node_dim[v] = m->dim, g->node_tag[v] = -1;
  for (size_t i = 0; i < nel; i++) g->elem_entity[i] = -1;
  return DTM_OK;
}

/* Copy the element entities extraction recorded (every block's entity
 * array) into g in global order; 0, copying nothing, when a block has none
 * (the elements of the mesh's dimension are then read from Gmsh again). */
static int copy_entities(const dtm_mesh *m, dtm_geo *g) {
  for (int b = 0; b < m->nblocks; b++)
    if (!m->blocks[b].entity) return 0;
  size_t k = 0;
  for (int b = 0; b < m->nblocks; k += m->blocks[b].n, b++)
    memcpy(g->elem_entity + k, m->blocks[b].entity, m->blocks[b].n * sizeof *g->elem_entity);
  return 1;
}

/* One model entity: its nodes, its elements, and below the mesh's
 * dimension its record. Gmsh lists entities by dimension, then tag. */
static int visit(const dtm_mesh *m, const tag_map *nodes, const tag_map *els, int dim, int tag, dtm_geo *g) {
  double length = 0;
  if (dim < m->dim) DTM_CHECK(classify_nodes(nodes, dim, tag, g));
  if (dim == 1 || (dim == m->dim && els->index)) DTM_CHECK(entity_elements(m, nodes, els, dim, tag, g, &length));
  if (dim >= m->dim) return DTM_OK;
  dtm_geo_entity *e = &g->ent[g->nent++];
  e->dim = dim, e->tag = tag, e->size = dim == 1 ? length : 0;
  return entity_points(e);
}

/* The dense index of the elements by tag, needed only when extraction
 * recorded no entities (els->index then stays NULL). */
static int element_map(const dtm_mesh *m, dtm_geo *g, tag_map *els) {
  if (copy_entities(m, g)) return DTM_OK;
  size_t nel = 0, *etags = element_tags(m, &nel);
  int r = etags ? map_build(etags, nel, els) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  free(etags);
  return r;
}

static int fill(const dtm_mesh *m, dtm_geo *g) {
  int *dt = NULL, ierr = 0, r = DTM_OK;
  size_t n = 0;
  tag_map nodes = {NULL, 0}, els = {NULL, 0};
  gmshModelGetEntities(&dt, &n, -1, &ierr);
  if (ierr) r = dtm_gmsh_fail(DTM_ERR_INTERNAL, __FILE__, __LINE__, __func__, "cannot list the model entities");
  if (r == DTM_OK) r = alloc_geo(m, dtm_mesh_nelements(m), n / 2, g);
  if (r == DTM_OK) r = map_build(m->node_tags, m->nnodes, &nodes);
  if (r == DTM_OK) r = element_map(m, g, &els);
  for (size_t i = 0; i < n / 2 && r == DTM_OK; i++) r = visit(m, &nodes, &els, dt[2 * i], dt[2 * i + 1], g);
  gmshFree(dt);
  free(nodes.index), free(els.index);
  return r;
}

int dtm_gmsh_geo(const dtm_mesh *m, dtm_geo **out) {
  dtm_geo *g = calloc(1, sizeof *g);
  if (!g) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = fill(m, g);
  if (r) {
    dtm_gmsh_geo_destroy(&g);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = g;
  return DTM_OK;
}

void dtm_gmsh_geo_destroy(dtm_geo **pg) {
  dtm_geo *g = *pg;
  if (!g) return;
  for (int i = 0; g->ent && i < g->nent; i++) free(g->ent[i].points);
  free(g->ent), free(g->node_dim), free(g->node_tag), free(g->elem_entity);
  free(g);
  *pg = NULL;
}

const dtm_geo_entity *dtm_geo_find(const dtm_geo *g, int dim, int tag) {
  int lo = 0, hi = g->nent - 1;
  while (lo <= hi) {
    int mid = (lo + hi) / 2;
    const dtm_geo_entity *e = &g->ent[mid];
    if (e->dim == dim && e->tag == tag) return e;
    if (e->dim < dim || (e->dim == dim && e->tag < tag))
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return NULL;
}

static int has_point(const dtm_geo_entity *e, int p) {
  for (int i = 0; i < e->npoints; i++)
    if (e->points[i] == p) return 1;
  return 0;
}

int dtm_geo_node_on(const dtm_geo *g, size_t v, const dtm_geo_entity *e) {
  if (g->node_dim[v] == e->dim && g->node_tag[v] == e->tag) return 1;
  return g->node_dim[v] == 0 && has_point(e, g->node_tag[v]);
}

int dtm_geo_touch(const dtm_geo *g, size_t v, size_t w) {
  const dtm_geo_entity *a = dtm_geo_find(g, g->node_dim[v], g->node_tag[v]),
                       *b = dtm_geo_find(g, g->node_dim[w], g->node_tag[w]);
  if (!a || !b) return 1; /* an interior node touches everything */
  for (int i = 0; i < a->npoints; i++)
    if (has_point(b, a->points[i])) return 1;
  return a == b;
}

int dtm_gmsh_save_mesh(const char *path) {
  int ierr = 0;
  double all = 0, binary = 0;
  gmshOptionGetNumber("Mesh.SaveAll", &all, &ierr);
  gmshOptionGetNumber("Mesh.Binary", &binary, &ierr);
  gmshOptionSetNumber("Mesh.SaveAll", 1, &ierr);
  gmshOptionSetNumber("Mesh.Binary", 1, &ierr);
  gmshWrite(path, &ierr);
  int bad = ierr;
  gmshOptionSetNumber("Mesh.SaveAll", all, &ierr);
  gmshOptionSetNumber("Mesh.Binary", binary, &ierr);
  DTM_GMSH_CHECK(bad, DTM_ERR_INTERNAL, path);
  return dtm_gmsh_strip_periodic(path); /* its pairs may name nodes of a cleared mesh: refine's kept mesh */
}

int dtm_gmsh_restore_mesh(const char *path) {
  int ierr = 0;
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshClear(&ierr);
  gmshOpen(path, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, path);
  return DTM_OK;
}
