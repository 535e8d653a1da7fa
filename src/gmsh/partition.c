/* Gmsh's partitions, for the distributed run (src/parallel/): splitting
 * the current model with METIS into one binary .msh per part, as Gmsh's
 * own `-part N -part_split` does, and reading back which partition a part
 * file holds (its partition entities name their partitions). */
#include <gmshc.h>
#include <stdio.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

int dtm_gmsh_partition_write(int nparts, const char *path) {
  int ierr = 0;
  char what[4200];
  snprintf(what, sizeof what, "%s: cannot partition the mesh into %d parts", path, nparts);
  /* No partition boundaries: dtmap finds the interfaces by node tag, and
   * Gmsh 4.8 reports a spurious error building them for a mesh read from
   * a file that holds no elements of some lower dimension. */
  gmshOptionSetNumber("Mesh.PartitionCreateTopology", 0, &ierr);
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshModelMeshPartition(nparts, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INPUT, what);
  gmshOptionSetNumber("Mesh.PartitionSplitMeshFiles", 1, &ierr);
  gmshOptionSetNumber("Mesh.Binary", 1, &ierr);
  gmshOptionSetNumber("Mesh.SaveAll", 0, &ierr);
  gmshWrite(path, &ierr);
  int bad = ierr;
  gmshOptionSetNumber("Mesh.PartitionSplitMeshFiles", 0, &ierr);
  gmshOptionSetNumber("Mesh.PartitionCreateTopology", 1, &ierr);
  gmshOptionSetNumber("Mesh.Binary", 0, &ierr);
  snprintf(what, sizeof what, "%s: cannot write the %d parts", path, nparts);
  DTM_GMSH_CHECK(bad, DTM_ERR_INPUT, what);
  return DTM_OK;
}

/* Partitions of entity (dim, tag): sets *one to its partition when it has
 * exactly one, 0 when none, -1 when several; raises *maxpart. */
static int entity_partitions(int dim, int tag, int *one, int *maxpart) {
  int *p = NULL, ierr = 0;
  size_t n = 0;
  gmshModelGetPartitions(dim, tag, &p, &n, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot read the partitions of an entity");
  for (size_t i = 0; i < n; i++)
    if (p[i] > *maxpart) *maxpart = p[i];
  *one = n == 1 ? p[0] : n ? -1 : 0;
  gmshFree(p);
  return DTM_OK;
}

static int has_elements(int dim, int tag) {
  int *types = NULL, ierr = 0;
  size_t nt = 0;
  gmshModelMeshGetElementTypes(&types, &nt, dim, tag, &ierr);
  gmshFree(types);
  return !ierr && nt > 0;
}

int dtm_gmsh_partition_info(int dim, int *part, int *maxpart) {
  int *ents = NULL, ierr = 0, r = DTM_OK, first = 1;
  size_t ne = 0;
  *part = 0, *maxpart = 0;
  gmshModelGetEntities(&ents, &ne, -1, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot list entities");
  for (size_t i = 0; i < ne / 2 && r == DTM_OK; i++) {
    int d = ents[2 * i], one = 0;
    r = entity_partitions(d, ents[2 * i + 1], &one, maxpart);
    if (r || d != dim || !has_elements(d, ents[2 * i + 1])) continue;
    if (first || one != *part) *part = first ? one : -1;
    first = 0;
  }
  gmshFree(ents);
  return r;
}
