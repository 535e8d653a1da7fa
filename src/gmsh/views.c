/* Views of the analysed mesh through Gmsh. Written to a .msh: the mesh
 * first, then each view appended with PostProcessing.SaveMesh=0 so the mesh
 * is not written again, and removed afterwards, so repeated writes
 * (refinement rounds) do not accumulate them; the options this sets are
 * given their values back. Or added to the open session of a script, where
 * they stay, with their display options. */
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

/* Create view v on model; *tag is its tag, or -1 when none was created. */
static int add_view(const char *model, const dtm_view *v, int *tag) {
  int ierr = 0;
  *tag = gmshViewAdd(v->name, -1, &ierr);
  if (ierr) *tag = -1;
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

static int current_model(char **model) {
  int ierr = 0;
  gmshModelGetCurrent(model, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "no current model");
  return DTM_OK;
}

int dtm_gmsh_add_views(const dtm_view *views, int nviews, int *tags) {
  char *model = NULL;
  DTM_CHECK(current_model(&model));
  int r = DTM_OK, n = 0, ierr = 0, *own = malloc(((size_t)nviews + 1) * sizeof *own);
  if (!own) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (; r == DTM_OK && n < nviews; n++) r = add_view(model, &views[n], &own[n]);
  for (int i = 0; r && own && i < n; i++)
    if (own[i] >= 0) gmshViewRemove(own[i], &ierr);
  for (int i = 0; r == DTM_OK && tags && i < nviews; i++) tags[i] = own[i];
  gmshFree(model);
  free(own);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_gmsh_view_option(int tag, const dtm_view_option *o) {
  int ierr = 0;
  char name[256];
  int index = gmshViewGetIndex(tag, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "no such view");
  snprintf(name, sizeof name, "View[%d].%s", index, o->name);
  if (o->text)
    gmshOptionSetString(name, o->text, &ierr);
  else
    gmshOptionSetNumber(name, o->number, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, name);
  return DTM_OK;
}

/* The options dtm_gmsh_write sets, kept so a script's session gets its own
 * values back. */
static const char *const write_options[] = {"Mesh.SaveAll", "Mesh.Binary", "PostProcessing.SaveMesh"};
#define NWRITE_OPTIONS (sizeof write_options / sizeof write_options[0])

static void swap_options(const double *set, double *old) {
  int ierr = 0;
  for (size_t i = 0; i < NWRITE_OPTIONS; i++) {
    if (old) gmshOptionGetNumber(write_options[i], &old[i], &ierr);
    gmshOptionSetNumber(write_options[i], set[i], &ierr);
  }
}

/* The mesh, then the views appended without it. */
static int write_all(const char *path, const dtm_view *views, int nviews) {
  int ierr = 0;
  char *model = NULL;
  gmshWrite(path, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, path);
  DTM_CHECK(current_model(&model));
  int r = write_views(path, model, views, nviews);
  gmshFree(model);
  return r;
}

int dtm_gmsh_write(const char *path, const dtm_view *views, int nviews) {
  const double set[NWRITE_OPTIONS] = {1, 0, 0}; /* all elements, as text; views without the mesh */
  double old[NWRITE_OPTIONS];
  swap_options(set, old);
  int r = write_all(path, views, nviews);
  swap_options(old, NULL);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
