/* Writing the analysed mesh and its views to a .msh through Gmsh: the mesh
 * first, then each view appended with PostProcessing.SaveMesh=0 so the mesh
 * is not written again. Views are removed afterwards, so repeated writes
 * (refinement rounds) do not accumulate them. */
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

static int add_view(const char *model, const dtm_view *v, int *tag) {
  int ierr = 0;
  *tag = gmshViewAdd(v->name, -1, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot create a view");
  gmshViewAddHomogeneousModelData(*tag, 0, model, v->node_data ? "NodeData" : "ElementData", (size_t *)v->tags, v->n,
                                  (double *)v->values, v->n, 0.0, 1, 0, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, v->name);
  return DTM_OK;
}

static int write_views(const char *path, const char *model, const dtm_view *views, int nviews) {
  int ierr = 0, r = DTM_OK;
  for (int i = 0; i < nviews && r == DTM_OK; i++) {
    int tag;
    r = add_view(model, &views[i], &tag);
    if (r) break;
    gmshViewWrite(tag, path, 1, &ierr);
    if (ierr) r = dtm_gmsh_fail(DTM_ERR_INTERNAL, __FILE__, __LINE__, __func__, path);
    gmshViewRemove(tag, &ierr);
  }
  return r;
}

int dtm_gmsh_write(const char *path, const dtm_view *views, int nviews) {
  int ierr = 0;
  char *model = NULL;
  gmshOptionSetNumber("Mesh.SaveAll", 1, &ierr);
  gmshOptionSetNumber("Mesh.Binary", 0, &ierr);
  gmshWrite(path, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, path);
  gmshModelGetCurrent(&model, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "no current model");
  gmshOptionSetNumber("PostProcessing.SaveMesh", 0, &ierr);
  int r = write_views(path, model, views, nviews);
  gmshFree(model);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
