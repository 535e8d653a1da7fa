/* Pictures of a result drawn by Gmsh's own renderer: Gmsh opens the .msh
 * (and merges its .opt, so the pictures show what a user sees on opening
 * it), a window is created whose drawing area has the requested size,
 * and each shot sets which views are visible, draws and writes a PNG through
 * a temporary renamed into place. The camera (frame.c) frames the whole
 * model between the text and the colour scales, and turns a model that
 * spans 3D to an oblique view facing its worst elements. */
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/util.h"
#include "gmsh-impl.h"

#define ANNOTATION "dtmap" /* name of the text view the .opt creates */

static void view_option(int index, const char *opt, double v) {
  char name[96];
  int ierr = 0;
  snprintf(name, sizeof name, "View[%d].%s", index, opt);
  gmshOptionSetNumber(name, v, &ierr);
}

int dtm_gmsh_view_is(int index, const char *name) {
  char key[64], *value = NULL;
  int ierr = 0;
  snprintf(key, sizeof key, "View[%d].Name", index);
  gmshOptionGetString(key, &value, &ierr);
  int same = !ierr && value && !strcmp(value, name);
  gmshFree(value);
  return same;
}

/* Show only the view named only (opaque; dt with its skin) and the
 * annotation. */
static void show_only(int nviews, const char *only) {
  for (int i = 0; i < nviews; i++) {
    int keep = dtm_gmsh_view_is(i, only) || (!strcmp(only, "dt") && dtm_gmsh_view_is(i, DTM_VIEW_DT_SKIN)),
        text = dtm_gmsh_view_is(i, ANNOTATION);
    view_option(i, "Visible", keep || text);
    if (keep) view_option(i, "ColormapAlpha", 1.0);
  }
}

static int write_png(const char *png) {
  dtm_atomic w;
  int ierr = 0;
  DTM_CHECK(dtm_atomic_open(&w, png, ".png", 0));
  gmshGraphicsDraw(&ierr);
  if (!ierr) gmshWrite(w.tmp, &ierr);
  if (ierr) {
    dtm_atomic_abort(&w);
    return dtm_gmsh_fail(DTM_ERR_INPUT, __FILE__, __LINE__, __func__, png);
  }
  return dtm_atomic_commit(&w);
}

static int open_window(const char *msh, int width, int height) {
  int ierr = 0;
  char what[4200];
  gmshInitialize(0, NULL, 0, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot initialise Gmsh");
  gmshOptionSetNumber("General.AbortOnError", 0, &ierr);
  gmshOptionSetNumber("General.Terminal", 0, &ierr);
  double menu = 0;
  gmshOptionGetNumber("General.MenuWidth", &menu, &ierr);
  gmshOptionSetNumber("General.GraphicsWidth", width + menu, &ierr); /* the window holds the module tree too */
  gmshOptionSetNumber("General.GraphicsHeight", height, &ierr);
  gmshLoggerStart(&ierr);
  snprintf(what, sizeof what, "%s: Gmsh cannot read it", msh);
  DTM_CHECK(dtm_gmsh_check_msh(msh));
  gmshOpen(msh, &ierr);
  DTM_GMSH_CHECK_LOG(ierr, DTM_ERR_INPUT, what);
  dtm_gmsh_snapshot_camera(width, height);
  gmshFltkInitialize(&ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INPUT, "Gmsh cannot open a window (is DISPLAY a working X display?)");
  return DTM_OK;
}

int dtm_gmsh_snapshot(const char *msh, const dtm_snapshot_shot *shots, int nshots, int width, int height) {
  int ierr = 0, r = open_window(msh, width, height);
  double nviews = 0;
  gmshOptionGetNumber("PostProcessing.NbViews", &nviews, &ierr);
  for (int s = 0; s < nshots && r == DTM_OK; s++) {
    if (shots[s].only) show_only((int)nviews, shots[s].only);
    r = write_png(shots[s].png);
  }
  gmshFinalize(&ierr);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
