/* A partitioned model made whole again before refine remeshes it. A .geo
 * that ends with `PartitionMesh N` (Gmsh's tutorial t21) leaves its mesh
 * in partition entities, which are discrete: a fresh mesh of the model
 * meshes the original entities, and the partition entities keep only
 * their boundaries (t21: 10 elements, no triangle). Gmsh's unpartition
 * moves the elements back to their parents, but it also removes every
 * physical group whose name holds a '_' (the partitioner's own names), so
 * the user's groups of that kind are recorded first and put back, with
 * their entities that are not partition entities. An unpartitioned model
 * is left alone. */
#include <gmshc.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

/* Whether the entity is a partition entity (it belongs to partitions). */
static int in_partition(int dim, int tag) {
  int *p = NULL, ierr = 0;
  size_t n = 0;
  gmshModelGetPartitions(dim, tag, &p, &n, &ierr);
  gmshFree(p);
  return n > 0;
}

static int model_partitioned(void) {
  int *dt = NULL, ierr = 0, found = 0;
  size_t n = 0;
  gmshModelGetEntities(&dt, &n, -1, &ierr);
  for (size_t i = 0; i + 1 < n && !found; i += 2) found = in_partition(dt[i], dt[i + 1]);
  gmshFree(dt);
  return found;
}

typedef struct {
  int dim, tag; /* the group */
  char *name;   /* its name (Gmsh's allocation) */
  int *ents;    /* its entities outside the partitions */
  size_t n;     /* how many */
} kept_group;

/* The group's entities that are not partition entities, in place. */
static void keep_parents(kept_group *g) {
  int ierr = 0;
  size_t k = 0;
  gmshModelGetEntitiesForPhysicalGroup(g->dim, g->tag, &g->ents, &g->n, &ierr);
  for (size_t i = 0; i < g->n; i++)
    if (!in_partition(g->dim, g->ents[i])) g->ents[k++] = g->ents[i];
  g->n = k;
}

/* The groups whose names Gmsh's unpartition would take for its own, or
 * with all, every group. */
static kept_group *record(int all, size_t *count) {
  int *dt = NULL, ierr = 0;
  size_t n = 0, k = 0;
  gmshModelGetPhysicalGroups(&dt, &n, -1, &ierr);
  kept_group *g = calloc(n / 2 + 1, sizeof *g);
  for (size_t i = 0; g && i + 1 < n; i += 2) {
    kept_group *c = &g[k];
    c->dim = dt[i], c->tag = dt[i + 1];
    gmshModelGetPhysicalName(c->dim, c->tag, &c->name, &ierr);
    if (!c->name || (!all && !strchr(c->name, '_'))) {
      gmshFree(c->name), c->name = NULL;
      continue;
    }
    keep_parents(c);
    k++;
  }
  gmshFree(dt);
  *count = k;
  return g;
}

/* Whether the model still has the group (asked without an error in Gmsh's
 * log, which a missing group would leave). */
static int has_group(int dim, int tag) {
  int *dt = NULL, ierr = 0, found = 0;
  size_t n = 0;
  gmshModelGetPhysicalGroups(&dt, &n, dim, &ierr);
  for (size_t i = 0; i + 1 < n && !found; i += 2) found = dt[i + 1] == tag;
  gmshFree(dt);
  return found;
}

static void add_group(const kept_group *g) {
  int ierr = 0;
  gmshModelAddPhysicalGroup(g->dim, g->ents, g->n, g->tag, &ierr);
  gmshModelSetPhysicalName(g->dim, g->tag, g->name, &ierr);
}

static void free_groups(kept_group *g, size_t n) {
  for (size_t i = 0; g && i < n; i++) gmshFree(g[i].name), gmshFree(g[i].ents);
  free(g);
}

/* Put back the groups g[n] the unpartition removed. A model read from a
 * .geo still holds them in its script's definitions, where Gmsh refuses
 * to add them again ("already exists") and where removing one alone frees
 * it twice at the end (Gmsh 4.8.4): every group is removed at once and
 * added back, those the model kept and the missing ones. */
static int restore(kept_group *g, size_t n) {
  size_t nc = 0, missing = 0;
  for (size_t i = 0; i < n; i++)
    if (g[i].n == 0 || has_group(g[i].dim, g[i].tag))
      g[i].n = 0;
    else
      missing++;
  if (!missing) return DTM_OK;
  kept_group *cur = record(1, &nc);
  if (!cur) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int ierr = 0;
  gmshModelRemovePhysicalGroups(NULL, 0, &ierr);
  for (size_t i = 0; i < nc; i++) add_group(&cur[i]);
  for (size_t i = 0; i < n; i++)
    if (g[i].n) add_group(&g[i]);
  free_groups(cur, nc);
  return DTM_OK;
}

int dtm_gmsh_unpartition(void) {
  if (!model_partitioned()) return DTM_OK;
  size_t n = 0;
  kept_group *g = record(0, &n);
  if (!g) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int ierr = 0;
  dtm_gmsh_log_reset();
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshModelMeshUnpartition(&ierr);
  int r = dtm_gmsh_check_log(ierr, DTM_ERR_INPUT, __FILE__, __LINE__, __func__,
                             "making the partitioned mesh whole before remeshing failed");
  if (r == DTM_OK) r = restore(g, n);
  free_groups(g, n);
  return r;
}
