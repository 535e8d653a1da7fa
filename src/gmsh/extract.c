/* Reading the current Gmsh model into a dtm_mesh: the dimension to analyse,
 * physical groups of that dimension, a node index, and one structure-of-arrays block
 * per element type, with each element's group, material and model entity
 * (the shape classification reads it, classify.c) resolved per model
 * entity. Elements are read a type at a time, in arrays Gmsh sizes once;
 * when the model is a .msh that dtmap also read itself while Gmsh read it
 * (msh_beside.c), the nodes and each entity's elements of a type come from
 * that reading instead of Gmsh's listing (the same arrays, in the same
 * order: tests/t337). The arrays handed over are kept, not copied, where they can be: the
 * node tags and coordinates always, and a block's element tags and
 * connectivity (node tags turned into indices in place) when one entity
 * holds all its elements, as in most meshes. Node tags that are 1..N in
 * order (what Gmsh gives) need no index: index = tag - 1; the sparse tags
 * of one part of a partitioned mesh are looked up in a sorted list, in
 * memory proportional to the part. So extraction streams through memory;
 * per element it costs 16 % more at 1e7 than at 1e6 (docs/performance.md:
 * Gmsh's own listing chases pointers past the cache). Messages name an
 * element by tag, group and centroid; node and element tags too large for
 * the views are refused (budget.c). */
#include <gmshc.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/kernel.h"
#include "gmsh-impl.h"

static char *dup_str(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

/* What messages call the model: the scene's file, or the current model. */
static const char *source_name(const dtm_scene *s) {
  return s->mesh ? s->mesh : s->geometry ? s->geometry : "the current Gmsh model";
}

int dtm_gmsh_model_dim(const dtm_scene *s, int *dim) {
  int ierr = 0, *types = NULL;
  size_t nt = 0;
  int d = s->mesh_dim > 0 ? s->mesh_dim : gmshModelGetDimension(&ierr);
  if (ierr || d < 1 || d > 3)
    return DTM_ERR(DTM_ERR_INPUT, "the current Gmsh model has no curve, surface or volume "
                                  "(is Gmsh initialised, and the model built or opened?)");
  gmshModelMeshGetElementTypes(&types, &nt, d, -1, &ierr);
  gmshFree(types);
  if (ierr || !nt)
    return DTM_ERR(DTM_ERR_INPUT, "the current Gmsh model has no element of dimension %d: mesh it first", d);
  *dim = d;
  return DTM_OK;
}

int dtm_gmsh_groups(int dim, dtm_group **groups, int *ngroups) {
  int *dt = NULL, ierr = 0;
  size_t n = 0;
  gmshModelGetPhysicalGroups(&dt, &n, dim, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot list physical groups");
  dtm_group *g = calloc(n / 2 + 1, sizeof *g);
  if (!g) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < n / 2; i++) {
    char *name = NULL;
    g[i].dim = dt[2 * i];
    g[i].tag = dt[2 * i + 1];
    gmshModelGetPhysicalName(g[i].dim, g[i].tag, &name, &ierr);
    g[i].name = dup_str(name ? name : "");
    gmshFree(name);
  }
  gmshFree(dt);
  *groups = g;
  *ngroups = (int)(n / 2);
  return DTM_OK;
}

/* Whether a section of s names group g (as dtm_mesh_group_find matches a
 * reference: by name, else by number) and none of the groups have does. */
static int named_by_section(const dtm_scene *s, dtm_group *g, dtm_group *have, int nhave) {
  dtm_mesh one = {.ngroups = 1, .groups = g}, old = {.ngroups = nhave, .groups = have};
  for (int i = 0; i < s->nsections; i++)
    for (int k = 0; k < s->sections[i].ngroups; k++) {
      const char *ref = s->sections[i].groups[k];
      if (dtm_mesh_group_find(&one, ref) >= 0 && dtm_mesh_group_find(&old, ref) < 0) return 1;
    }
  return 0;
}

/* Append group g (taking its name) to *groups. */
static int group_push(dtm_group **groups, int *ngroups, dtm_group *g) {
  dtm_group *ng = realloc(*groups, ((size_t)*ngroups + 2) * sizeof *ng);
  if (!ng) return free(g->name), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  ng[(*ngroups)++] = *g;
  *groups = ng;
  return DTM_OK;
}

int dtm_gmsh_groups_sectioned(int dim, const dtm_scene *s, dtm_group **groups, int *ngroups) {
  int r = DTM_OK, nhave = *ngroups;
  for (int d = dim - 1; d >= 1 && r == DTM_OK && s->nsections; d--) {
    dtm_group *low = NULL;
    int nlow = 0;
    r = dtm_gmsh_groups(d, &low, &nlow);
    for (int i = 0; i < nlow; i++) {
      if (r == DTM_OK && named_by_section(s, &low[i], *groups, nhave))
        r = group_push(groups, ngroups, &low[i]);
      else
        free(low[i].name);
    }
    free(low);
  }
  return r;
}

/* Node numbering: position in m->node_tags of a Gmsh node tag. The
 * identity when the tags are 1..N in order; dense (index[tag]) when they
 * are nearly so; a sorted list of tags searched by bisection when they are
 * sparse, as in one part of a partitioned mesh, so that memory follows the
 * part's nodes and not the whole mesh's largest tag. */
typedef struct {
  size_t *index;  /* dense: [max_tag + 1], SIZE_MAX where no node; else NULL */
  size_t *sorted; /* sparse: [n] (tag, position) pairs by tag; else NULL */
  size_t n;       /* nodes */
  size_t max_tag; /* largest node tag */
  int identity;   /* node tags are 1..N in order: index = tag - 1 */
} node_index;

static int by_tag(const void *a, const void *b) {
  size_t x = *(const size_t *)a, y = *(const size_t *)b;
  return x < y ? -1 : x > y;
}

static int index_nodes(node_index *ni, const size_t *tags) {
  size_t n = ni->n;
  if (ni->max_tag <= 2 * n + 1024) {
    ni->index = malloc((ni->max_tag + 1) * sizeof *ni->index);
    if (!ni->index) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    memset(ni->index, 0xff, (ni->max_tag + 1) * sizeof *ni->index);
    for (size_t i = 0; i < n; i++) ni->index[tags[i]] = i;
    return DTM_OK;
  }
  ni->sorted = malloc((2 * n + 1) * sizeof *ni->sorted);
  if (!ni->sorted) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < n; i++) ni->sorted[2 * i] = tags[i], ni->sorted[2 * i + 1] = i;
  qsort(ni->sorted, n, 2 * sizeof *ni->sorted, by_tag);
  return DTM_OK;
}

/* Position of node tag t (not the identity), SIZE_MAX when no such node. */
static size_t node_at(const node_index *ni, size_t t) {
  if (t > ni->max_tag) return SIZE_MAX;
  if (ni->index) return ni->index[t];
  size_t lo = 0, hi = ni->n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (ni->sorted[2 * mid] < t)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < ni->n && ni->sorted[2 * lo] == t ? ni->sorted[2 * lo + 1] : SIZE_MAX;
}

/* Every node, from the file's own reading when there is one (taken from
 * it), else listed by Gmsh. */
static int read_nodes(dtm_mesh *m, node_index *ni, dtm_msh_parsed *parsed) {
  size_t *tags = NULL, n = 0, nc = 0, np = 0;
  double *xyz = NULL, *par = NULL;
  int ierr = 0;
  if (parsed) {
    tags = parsed->node_tags, xyz = parsed->xyz, n = parsed->nnodes;
    parsed->node_tags = NULL, parsed->xyz = NULL;
  } else {
    gmshModelMeshGetNodes(&tags, &n, &xyz, &nc, &par, &np, -1, -1, 0, 0, &ierr);
    DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot read the mesh nodes");
    gmshFree(par);
  }
  ni->max_tag = 0, ni->identity = 1, ni->n = n;
  for (size_t i = 0; i < n; i++) {
    if (tags[i] > ni->max_tag) ni->max_tag = tags[i];
    ni->identity &= tags[i] == i + 1;
  }
  m->nnodes = n;
  m->node_tags = tags; /* gmshFree and free are both the C allocator here */
  m->xyz = xyz;
  return ni->identity ? DTM_OK : index_nodes(ni, tags);
}

/* Group of an entity of dimension dim: its first physical group that has a
 * material, else its first group, else -1; *mask gets every group it is
 * in. Below the mesh's dimension only groups with a section count. */
static int entity_group(const dtm_mesh *m, int dim, int tag, const dtm_group_map *map, unsigned long long *mask) {
  int *phys = NULL, ierr = 0, best = -1, found = 0;
  const int *group_mat = map->group_mat;
  size_t n = 0;
  *mask = 0;
  gmshModelGetPhysicalGroupsForEntity(dim, tag, &phys, &n, &ierr);
  for (size_t i = 0; i < n; i++) {
    int g = -1;
    for (int k = 0; k < m->ngroups; k++)
      if (m->groups[k].tag == phys[i] && m->groups[k].dim == dim) g = k;
    if (g < 0 || (dim < m->dim && (!map->group_sec || map->group_sec[g] < 0))) continue;
    if (g < DTM_MAX_MASK_GROUPS) *mask |= 1ull << g;
    if (best < 0) best = g;
    if (group_mat[g] >= 0 && !found) best = g, found = 1;
  }
  gmshFree(phys);
  return best;
}

static dtm_block *block_for(dtm_mesh *m, int type) {
  for (int b = 0; b < m->nblocks; b++)
    if (m->blocks[b].type == type) return &m->blocks[b];
  dtm_block *nb = realloc(m->blocks, (m->nblocks + 1) * sizeof *nb);
  if (!nb) return NULL;
  m->blocks = nb;
  dtm_block *b = &m->blocks[m->nblocks++];
  memset(b, 0, sizeof *b);
  b->type = type;
  dtm_elem_info(type, &b->dim, &b->nn);
  return b;
}

static int block_grow(dtm_block *b, size_t add) {
  size_t n = b->n + add;
  size_t *tags = realloc(b->tags, n * sizeof *tags);
  if (tags) b->tags = tags;
  size_t *conn = realloc(b->conn, n * b->nn * sizeof *conn);
  if (conn) b->conn = conn;
  int *group = realloc(b->group, n * sizeof *group);
  if (group) b->group = group;
  int *mat = realloc(b->mat, n * sizeof *mat);
  if (mat) b->mat = mat;
  unsigned long long *gmask = realloc(b->gmask, n * sizeof *gmask);
  if (gmask) b->gmask = gmask;
  int *entity = realloc(b->entity, n * sizeof *entity);
  if (entity) b->entity = entity;
  int *section = b->section ? realloc(b->section, n * sizeof *section) : NULL;
  if (section) b->section = section;
  if (!tags || !conn || !group || !mat || !gmask || !entity || (b->section && !section))
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  return DTM_OK;
}

/* Context of one extraction, for error messages. */
typedef struct {
  const dtm_scene *s;
  const int *group_mat;
  int default_mat;
  node_index ni;
  const dtm_group_map *map; /* materials and sections of the groups */
  dtm_msh_parsed *parsed;   /* the file's own reading (msh_read.c); NULL: Gmsh lists */
} extract_ctx;

static const char *src_of(const extract_ctx *c) { return source_name(c->s); }

/* "element T at (x, y, z)" for an element not yet extracted: its nn node
 * tags enodes (the centroid of those that exist). */
static const char *raw_place(const extract_ctx *c, const dtm_mesh *m, size_t tag, const size_t *enodes, int nn,
                             char *buf, size_t len) {
  double p[3] = {0, 0, 0};
  int k = 0;
  for (int a = 0; a < nn; a++) {
    size_t v = c->ni.identity ? (enodes[a] - 1 < c->ni.max_tag ? enodes[a] - 1 : SIZE_MAX) : node_at(&c->ni, enodes[a]);
    if (v == SIZE_MAX) continue;
    for (int i = 0; i < 3; i++) p[i] += m->xyz[3 * v + i];
    k++;
  }
  snprintf(buf, len, "element %zu at (%.6g, %.6g, %.6g)", tag, k ? p[0] / k : 0, k ? p[1] / k : 0, k ? p[2] / k : 0);
  return buf;
}

/* "in physical group 'G' (dimension d)" or "in no physical group of
 * dimension d". */
static const char *group_phrase(const dtm_mesh *m, int g, char *buf, size_t len) {
  char lbl[64];
  if (g >= 0)
    snprintf(buf, len, "in physical group '%s' (dimension %d)", dtm_mesh_group_label(m, g, lbl, sizeof lbl),
             m->groups[g].dim);
  else
    snprintf(buf, len, "in no physical group of dimension %d", m->dim);
  return buf;
}

/* An element of an unsupported type: which, where, and what to do. */
static int check_type(const extract_ctx *c, const dtm_mesh *m, int g, int type, size_t n, const size_t *tags,
                      const size_t *nodes) {
  int d, nn;
  if (dtm_elem_info(type, &d, &nn) == DTM_OK) return DTM_OK;
  dtm_error_clear();
  char *name = NULL, place[256], grp[128];
  int dim, order, nnodes = 0, npv, ierr = 0;
  double *lc = NULL;
  size_t nlc = 0;
  gmshModelMeshGetElementProperties(type, &name, &dim, &order, &nnodes, &lc, &nlc, &npv, &ierr);
  raw_place(c, m, n ? tags[0] : 0, nodes, n ? nnodes : 0, place, sizeof place);
  int r = DTM_ERR(DTM_ERR_INPUT, "%s: %s, %s, is a %s (Gmsh type %d, order %d): %s", src_of(c), place,
                  group_phrase(m, g, grp, sizeof grp), name ? name : "?", type, order,
                  order > 2 ? "dtmap handles first- and second-order elements; mesh with order=\"1\" or \"2\""
                            : "dtmap does not handle this element type");
  gmshFree(name);
  gmshFree(lc);
  return r;
}

static int material_of(const extract_ctx *c, const dtm_mesh *m, int g, const char *place, int *out) {
  int mat = g >= 0 ? c->group_mat[g] : -1;
  char grp[128];
  if (mat < 0) mat = c->default_mat;
  *out = mat;
  if (mat >= 0) return DTM_OK;
  if (g < 0)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s: %s is %s, and scene %s has no default material (add default=\"true\" to a <material>)",
                   src_of(c), place, group_phrase(m, g, grp, sizeof grp), c->s->path);
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: %s is %s, which no <material groups=...> of scene %s names, and there is no "
                 "default material",
                 src_of(c), place, group_phrase(m, g, grp, sizeof grp), c->s->path);
}

static int missing_node(const extract_ctx *c, const dtm_mesh *m, int g, int type, size_t tag, size_t node) {
  char grp[128];
  return DTM_ERR(DTM_ERR_INPUT, "%s: element %zu (%s), %s, references node %zu, which does not exist", src_of(c), tag,
                 dtm_elem_name(type), group_phrase(m, g, grp, sizeof grp), node);
}

/* Node tags nodes[n] into indices, in place; the position of a tag that
 * names no node, or SIZE_MAX. */
static size_t tags_to_indices(const node_index *ni, size_t *nodes, size_t n) {
  size_t bad = SIZE_MAX;
  if (ni->identity) {
    for (size_t k = 0; k < n; k++) {
      size_t t = nodes[k];
      if (t - 1 >= ni->max_tag) bad = bad == SIZE_MAX ? k : bad; /* t = 0 wraps around */
      nodes[k] = t - 1;
    }
    return bad;
  }
  for (size_t k = 0; k < n && bad == SIZE_MAX; k++) {
    size_t t = nodes[k], v = node_at(ni, t);
    if (v == SIZE_MAX) bad = k;
    nodes[k] = bad == SIZE_MAX ? v : t;
  }
  return bad;
}

/* Give b the n elements tags[n], conn[n][nn] (indices), adopting the two
 * arrays when b is empty (*owned is then set: the caller must not free
 * them), else appending a copy. */
static int take_elements(dtm_block *b, size_t *tags, size_t *conn, size_t n, int sections, int *owned) {
  if (b->n == 0 && !b->tags) {
    b->tags = tags, b->conn = conn, *owned = 1;
    b->group = malloc((n + 1) * sizeof *b->group), b->mat = malloc((n + 1) * sizeof *b->mat);
    b->gmask = malloc((n + 1) * sizeof *b->gmask), b->entity = malloc((n + 1) * sizeof *b->entity);
    b->section = sections ? malloc((n + 1) * sizeof *b->section) : NULL;
    return b->group && b->mat && b->gmask && b->entity && (!sections || b->section)
               ? DTM_OK
               : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  DTM_CHECK(block_grow(b, n));
  memcpy(b->tags + b->n, tags, n * sizeof *tags);
  memcpy(b->conn + b->n * (size_t)b->nn, conn, n * (size_t)b->nn * sizeof *conn);
  return DTM_OK;
}

/* Section of the elements of entity ent (group g, type type): the group's,
 * else (at the mesh's dimension) the first section among all the entity's
 * groups, else the default section; -1 when none. */
static int section_of(const extract_ctx *c, const dtm_mesh *m, int ent, int g, int type) {
  const dtm_group_map *map = c->map;
  int d;
  if (!map->group_sec) return -1;
  if (g >= 0 && map->group_sec[g] >= 0) return map->group_sec[g];
  dtm_elem_info(type, &d, NULL);
  if (d < m->dim) return -1;
  int *phys = NULL, ierr = 0, sec = -1;
  size_t n = 0;
  gmshModelGetPhysicalGroupsForEntity(d, ent, &phys, &n, &ierr);
  for (size_t i = 0; i < n && sec < 0; i++)
    for (int k = 0; k < m->ngroups && sec < 0; k++)
      if (m->groups[k].tag == phys[i] && m->groups[k].dim == d) sec = map->group_sec[k];
  gmshFree(phys);
  return sec >= 0 ? sec : map->default_sec;
}

/* Append one entity's elements of one type; takes tags and nodes (Gmsh's
 * arrays) when *owned is set on return. */
static int append_type(const extract_ctx *c, dtm_mesh *m, int ent, int g, unsigned long long mask, int type,
                       size_t *tags, size_t n, size_t *nodes, int *owned) {
  int sec = section_of(c, m, ent, g, type);
  *owned = 0;
  DTM_CHECK(check_type(c, m, g, type, n, tags, nodes));
  int mat, nn;
  char place[256];
  dtm_elem_info(type, NULL, &nn);
  DTM_CHECK(material_of(c, m, g, raw_place(c, m, n ? tags[0] : 0, nodes, n ? nn : 0, place, sizeof place), &mat));
  dtm_block *b = block_for(m, type);
  if (!b) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t bad = tags_to_indices(&c->ni, nodes, n * (size_t)b->nn);
  if (bad != SIZE_MAX) return missing_node(c, m, g, type, tags[bad / b->nn], nodes[bad] + (c->ni.identity ? 1 : 0));
  size_t n0 = b->n;
  DTM_CHECK(take_elements(b, tags, nodes, n, c->map->group_sec != NULL, owned));
  for (size_t e = n0; e < n0 + n; e++) b->group[e] = g, b->gmask[e] = mask, b->mat[e] = mat, b->entity[e] = ent;
  for (size_t e = n0; b->section && e < n0 + n; e++) b->section[e] = sec;
  b->n += n;
  return DTM_OK;
}

/* The file's block of entity (dim, tag) and type, NULL when none. */
static dtm_msh_eblock *parsed_block(const extract_ctx *c, int dim, int tag, int type) {
  if (!c->parsed) return NULL;
  dtm_msh_eblock key = {.dim = dim, .tag = tag, .type = type};
  dtm_msh_eblock *b = bsearch(&key, c->parsed->blocks, (size_t)c->parsed->nblocks, sizeof key, dtm_msh_block_order);
  return b && b->tags ? b : NULL;
}

/* One entity's elements, a type at a time: Gmsh sizes the arrays of one
 * type before filling them, where its all-types call grows them element by
 * element (at 1e7 tets that growth, its copies and their page faults were
 * a third of the extraction); from the file's own reading instead when it
 * has that entity and type. */
static int extract_type(const extract_ctx *c, dtm_mesh *m, int dim, int tag, int g, unsigned long long mask, int type) {
  size_t *etags = NULL, ne = 0, *ntags = NULL, nn = 0;
  int ierr = 0, owned = 0;
  dtm_msh_eblock *b = parsed_block(c, dim, tag, type);
  if (b) {
    etags = b->tags, ntags = b->conn, ne = b->n;
    b->tags = b->conn = NULL; /* freed below or adopted by the block */
  } else {
    gmshModelMeshGetElementsByType(type, &etags, &ne, &ntags, &nn, tag, 0, 1, &ierr);
  }
  int r = ierr ? dtm_gmsh_fail(DTM_ERR_INTERNAL, __FILE__, __LINE__, __func__, "cannot read elements") : DTM_OK;
  if (r == DTM_OK) r = append_type(c, m, tag, g, mask, type, etags, ne, ntags, &owned);
  if (!owned) gmshFree(etags), gmshFree(ntags); /* else the block has them now */
  return r;
}

/* The elements of entity (dim, tag); below the mesh's dimension only when
 * the entity is in a group with a section. */
static int extract_entity(const extract_ctx *c, dtm_mesh *m, int dim, int tag) {
  int *types = NULL, ierr = 0, r = DTM_OK;
  size_t nt = 0;
  unsigned long long mask;
  int g = entity_group(m, dim, tag, c->map, &mask);
  if (dim < m->dim && g < 0) return DTM_OK;
  gmshModelMeshGetElementTypes(&types, &nt, dim, tag, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot read element types");
  for (size_t i = 0; i < nt && r == DTM_OK; i++) r = extract_type(c, m, dim, tag, g, mask, types[i]);
  gmshFree(types);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

/* Element tags too large for the views (budget.c). */
static int check_element_tags(const extract_ctx *c, const dtm_mesh *m) {
  size_t max = 0;
  for (int b = 0; b < m->nblocks; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++) max = m->blocks[b].tags[e] > max ? m->blocks[b].tags[e] : max;
  return dtm_gmsh_check_tags(src_of(c), "element", max, dtm_mesh_nelements(m));
}

/* Whether a group of dimension d has a section. */
static int has_sections(const dtm_mesh *m, const dtm_group_map *map, int d) {
  for (int g = 0; map->group_sec && g < m->ngroups; g++)
    if (m->groups[g].dim == d && map->group_sec[g] >= 0) return 1;
  return 0;
}

/* The elements of every entity of dimension d. */
static int extract_dim(const extract_ctx *c, dtm_mesh *m, int d) {
  int *ents = NULL, ierr = 0, r = DTM_OK;
  size_t ne = 0;
  gmshModelGetEntities(&ents, &ne, d, &ierr);
  for (size_t i = 0; i < ne / 2 && r == DTM_OK && !ierr; i++) r = extract_entity(c, m, d, ents[2 * i + 1]);
  gmshFree(ents);
  if (ierr) return dtm_gmsh_fail(DTM_ERR_INTERNAL, __FILE__, __LINE__, __func__, "cannot list entities");
  return r;
}

int dtm_gmsh_extract(int dim, const int *group_mat, int default_mat, const dtm_scene *s, dtm_mesh *m) {
  dtm_group_map map = {group_mat, default_mat, NULL, -1};
  return dtm_gmsh_extract_map(dim, &map, s, m);
}

int dtm_gmsh_extract_map(int dim, const dtm_group_map *map, const dtm_scene *s, dtm_mesh *m) {
  dtm_msh_parsed parsed;
  int own = dtm_gmsh_parsed_take(&parsed);
  extract_ctx c = {s, map->group_mat, map->default_mat, {NULL, NULL, 0, 0, 0}, map, own ? &parsed : NULL};
  int r = DTM_OK;
  m->dim = dim;
  r = read_nodes(m, &c.ni, c.parsed);
  if (r) {
    dtm_msh_parsed_free(&parsed);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  r = dtm_gmsh_check_tags(src_of(&c), "node", c.ni.max_tag, m->nnodes);
  for (int d = dim; d >= 1 && r == DTM_OK; d--)
    if (d == dim || has_sections(m, map, d)) r = extract_dim(&c, m, d);
  if (r == DTM_OK) r = check_element_tags(&c, m);
  dtm_msh_parsed_free(&parsed);
  free(c.ni.index);
  free(c.ni.sorted);
  DTM_CHECK(r);
  if (dtm_mesh_nelements(m) == 0)
    return DTM_ERR(DTM_ERR_INPUT, "%s: %s no element of dimension %d", source_name(s),
                   s->geometry ? "meshing produced" : "it has", dim);
  return DTM_OK;
}
