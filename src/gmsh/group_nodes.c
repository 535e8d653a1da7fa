/* The nodes of a physical group of the current model: what a solver deck
 * needs for the node sets of the groups below the analysed dimension
 * (faces, edges and points where loads and supports go), read from Gmsh
 * while the model is still loaded. */
#include <gmshc.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

int dtm_gmsh_group_nodes(int dim, int tag, size_t **tags, size_t *n) {
  size_t *nt = NULL, nn = 0, nc = 0;
  double *xyz = NULL;
  int ierr = 0;
  *tags = NULL, *n = 0;
  gmshModelMeshGetNodesForPhysicalGroup(dim, tag, &nt, &nn, &xyz, &nc, &ierr);
  gmshFree(xyz);
  if (ierr) {
    gmshFree(nt);
    return DTM_ERR(DTM_ERR_INTERNAL, "Gmsh cannot list the nodes of physical group (%d, %d)", dim, tag);
  }
  *tags = malloc((nn + 1) * sizeof **tags);
  if (!*tags) return gmshFree(nt), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (nn) memcpy(*tags, nt, nn * sizeof *nt);
  gmshFree(nt);
  *n = nn;
  return DTM_OK;
}
