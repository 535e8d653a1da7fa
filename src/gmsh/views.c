/* Writing the analysed mesh and its views to a .msh: the mesh through
 * Gmsh's own writer (ASCII or binary, Mesh.SaveAll=1), then every view
 * appended directly in the same encoding (msh_data.c), or, for a views-only
 * file, just the format header and the views, which Gmsh merges on top of
 * the mesh it already has open (a .msh without $Nodes adds views to the
 * current model). No Gmsh view is created. */
#include <errno.h>
#include <gmshc.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdio.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

int dtm_gmsh_write_mesh(const char *path, int binary) {
  int ierr = 0;
  gmshOptionSetNumber("Mesh.SaveAll", 1, &ierr);
  gmshOptionSetNumber("Mesh.Binary", binary ? 1 : 0, &ierr);
  gmshOptionSetNumber("Mesh.MshFileVersion", 4.1, &ierr);
  gmshWrite(path, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, path);
  return DTM_OK;
}

void dtm_gmsh_release(void) {
  int ierr = 0;
  gmshClear(&ierr);
#ifdef __GLIBC__
  malloc_trim(0); /* Gmsh's many small blocks: give the pages back */
#endif
}

int dtm_gmsh_write(const char *path, const dtm_view *views, int nviews, const dtm_msh_format *fmt) {
  dtm_msh_format def = {0, 0};
  if (!fmt) fmt = &def;
  if (!fmt->views_only) DTM_CHECK(dtm_gmsh_write_mesh(path, fmt->binary));
  return dtm_gmsh_write_views(path, views, nviews, fmt);
}

int dtm_gmsh_write_views(const char *path, const dtm_view *views, int nviews, const dtm_msh_format *fmt) {
  FILE *f = fopen(path, fmt->views_only ? "wb" : "ab");
  if (!f) return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", path, strerror(errno));
  int r = fmt->views_only && dtm_msh_header(f, fmt->binary) ? DTM_ERR(DTM_ERR_INPUT, "%s: cannot write", path) : DTM_OK;
  for (int i = 0; i < nviews && r == DTM_OK; i++) r = dtm_msh_write_view(f, &views[i], fmt->binary);
  if (fclose(f) && r == DTM_OK) r = DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", path, strerror(errno));
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
