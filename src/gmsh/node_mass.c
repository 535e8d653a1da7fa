/* Point masses a mesh carries from an earlier refine or deck: the NodeData
 * view DTM_VIEW_NODE_MASS ("added mass at nodes", kg per node) that Gmsh
 * loaded with the .msh. When the open session holds such a view, its
 * values become the extracted mesh's node_mass, matched by node tag, so
 * that run, verify and deck on the refined mesh include the mass refine
 * added. Only a view of that exact name is read, and only through its
 * model data (a .msh holds no list-based view). A mass that is negative
 * or not finite, or sits on a node no analysed element holds, is bad
 * input naming the node. */
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

/* The tag of the last view named DTM_VIEW_NODE_MASS, or -1. */
static int find_view(void) {
  int *tags = NULL, ierr = 0, found = -1;
  size_t n = 0;
  gmshViewGetTags(&tags, &n, &ierr);
  for (size_t i = 0; !ierr && i < n; i++) {
    char key[64], *name = NULL;
    int index = gmshViewGetIndex(tags[i], &ierr);
    snprintf(key, sizeof key, "View[%d].Name", index);
    gmshOptionGetString(key, &name, &ierr);
    if (!ierr && name && strcmp(name, DTM_VIEW_NODE_MASS) == 0) found = tags[i];
    gmshFree(name);
  }
  gmshFree(tags);
  return found;
}

/* index[tag] = node index + 1 (0: not in the mesh), for tags up to max. */
static size_t *tag_index(const dtm_mesh *m, size_t *max) {
  *max = 0;
  for (size_t v = 0; v < m->nnodes; v++)
    if (m->node_tags[v] > *max) *max = m->node_tags[v];
  size_t *index = calloc(*max + 1, sizeof *index);
  for (size_t v = 0; index && v < m->nnodes; v++) index[m->node_tags[v]] = v + 1;
  return index;
}

/* The view's n values at node tags into m->node_mass. */
static int assign(dtm_mesh *m, const size_t *tags, const double *data, size_t n, const char *src, const char *unit) {
  size_t max, *index = tag_index(m, &max);
  m->node_mass = calloc(m->nnodes + 1, sizeof *m->node_mass);
  if (!index || !m->node_mass) return free(index), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = DTM_OK;
  for (size_t i = 0; i < n && r == DTM_OK; i++) {
    size_t at = tags[i] <= max ? index[tags[i]] : 0;
    if (!isfinite(data[i]) || data[i] < 0)
      r = DTM_ERR(DTM_ERR_INPUT, "%s: view '%s': node %zu carries %g %s; a mass must be finite and not negative", src,
                  DTM_VIEW_NODE_MASS, tags[i], data[i], unit);
    else if (!at && data[i] > 0)
      r = DTM_ERR(DTM_ERR_INPUT, "%s: view '%s': node %zu carries %g %s but no analysed element holds it", src,
                  DTM_VIEW_NODE_MASS, tags[i], data[i], unit);
    else if (at)
      m->node_mass[at - 1] = data[i];
  }
  free(index);
  return r;
}

int dtm_gmsh_node_masses(dtm_mesh *m, const char *src, const char *mass_unit) {
  int view = find_view(), ierr = 0, ncomp = 0;
  if (view < 0 || !m->node_tags) return DTM_OK;
  char *type = NULL;
  size_t *tags = NULL, ntags = 0, ndata = 0;
  double *data = NULL, time = 0;
  gmshViewGetHomogeneousModelData(view, 0, &type, &tags, &ntags, &data, &ndata, &time, &ncomp, &ierr);
  int r = DTM_OK;
  if (ierr || !type || strcmp(type, "NodeData") || ncomp != 1 || ndata != ntags)
    r = DTM_ERR(DTM_ERR_INPUT, "%s: view '%s' must be NodeData with one value per node (kg)", src, DTM_VIEW_NODE_MASS);
  if (r == DTM_OK) r = assign(m, tags, data, ntags, src, mass_unit);
  gmshFree(type), gmshFree(tags), gmshFree(data);
  if (r) free(m->node_mass), m->node_mass = NULL;
  return r;
}
