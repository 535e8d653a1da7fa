/* Pictures of a result drawn by Gmsh's own renderer: Gmsh opens the .msh
 * (and merges its .opt, so the pictures show what a user sees on opening
 * it), a window is created whose drawing area has the requested size,
 * and each shot sets which views are visible, draws and writes a PNG through
 * a temporary renamed into place. The camera (frame.c) frames the whole
 * model between the text and the colour scales, and turns a model that
 * spans 3D to an oblique view facing its worst elements; a shot of the
 * worst elements of a flat model frames them and shows them opaque over a
 * faint dt; the worst element is ringed and tagged with its tag and step
 * (frame.c). dtmap's figures, which
 * the .opt prints (Printf lines), are drawn at the top by a text view made
 * here: it lives only in this session, so no file holds a list-based view
 * (gmsh.view.getModelData aborts on one). A file without the dt view is not
 * a result: no picture. */
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/util.h"
#include "gmsh-impl.h"

#define ANNOTATION "dtmap" /* name of the text view of dtmap's figures */
#define FIGURES 3          /* its lines */

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

static int nviews(void) {
  double n = 0;
  int ierr = 0;
  gmshOptionGetNumber("PostProcessing.NbViews", &n, &ierr);
  return ierr ? 0 : (int)n;
}

/* Show only the view named only (opaque, with its colour bar; dt with its
 * skin) and the annotation. */
static void show_only(const char *only) {
  for (int i = 0, n = nviews(); i < n; i++) {
    int keep = dtm_gmsh_view_is(i, only), skin = !strcmp(only, "dt") && dtm_gmsh_view_is(i, DTM_VIEW_DT_SKIN),
        text = dtm_gmsh_view_is(i, ANNOTATION);
    view_option(i, "Visible", keep || skin || text);
    if (keep) view_option(i, "ColormapAlpha", 1.0), view_option(i, "ShowScale", 1);
  }
}

/* A flat model's worst picture: the worst elements' view opaque with its
 * colour bar, over dt drawn faint (without its bar) for the context. */
static void show_worst(void) {
  for (int i = 0, n = nviews(); i < n; i++) {
    int worst = dtm_gmsh_view_is(i, "below target [s]") || dtm_gmsh_view_is(i, "smallest 1% [s]");
    if (worst) view_option(i, "Visible", 1), view_option(i, "ColormapAlpha", 1.0), view_option(i, "ShowScale", 1);
    if (dtm_gmsh_view_is(i, "dt")) view_option(i, "ColormapAlpha", 0.2), view_option(i, "ShowScale", 0);
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

/* The text of one `Printf("...");` line of the .opt into out (its "%%"
 * read as '%'); 0 when line is not one. */
static int figure_of(const char *line, char *out, size_t len) {
  static const char head[] = "Printf(\"";
  const char *end = strstr(line, "\");");
  if (strncmp(line, head, sizeof head - 1) || !end) return 0;
  size_t k = 0;
  for (const char *c = line + sizeof head - 1; c < end && k + 1 < len; c++) {
    out[k++] = *c;
    if (c[0] == '%' && c[1] == '%') c++;
  }
  out[k] = '\0';
  return 1;
}

/* The text view of dtmap's figures, from msh.opt (none without it). */
static void annotate(const char *msh) {
  char path[DTM_PATH_MAX + 8], line[1200], text[1100];
  snprintf(path, sizeof path, "%s.opt", msh);
  FILE *f = fopen(path, "r");
  int ierr = 0, tag = -1, k = 0;
  while (f && k < FIGURES && fgets(line, sizeof line, f)) {
    if (!figure_of(line, text, sizeof text)) continue;
    if (tag < 0) tag = gmshViewAdd(ANNOTATION, -1, &ierr);
    double xy[2] = {10, 22 + 20 * k++};
    char *data[1] = {text};
    if (!ierr) gmshViewAddListDataString(tag, xy, 2, data, 1, NULL, 0, &ierr);
  }
  if (f) fclose(f);
}

/* DTM_ERR_INPUT unless the model has dtmap's dt view. */
static int check_result(const char *msh) {
  for (int i = 0, n = nviews(); i < n; i++)
    if (dtm_gmsh_view_is(i, "dt")) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: no view named 'dt': not a result of dtmap run (snapshot draws the dt map that run writes "
                 "into its output mesh)",
                 msh);
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
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshOpen(msh, &ierr);
  DTM_GMSH_CHECK_LOG(ierr, DTM_ERR_INPUT, what);
  DTM_CHECK(check_result(msh));
  annotate(msh);
  dtm_gmsh_snapshot_camera(width, height);
  gmshFltkInitialize(&ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INPUT, "Gmsh cannot open a window (is DISPLAY a working X display?)");
  return DTM_OK;
}

int dtm_gmsh_snapshot(const char *msh, const dtm_snapshot_shot *shots, int nshots, int width, int height) {
  int ierr = 0, r = open_window(msh, width, height);
  for (int s = 0; s < nshots && r == DTM_OK; s++) {
    if (shots[s].only) show_only(shots[s].only);
    if (!shots[s].worst || !dtm_gmsh_snapshot_camera_worst(width, height))
      dtm_gmsh_snapshot_camera(width, height);
    else
      show_worst();
    if (shots[s].worst) dtm_gmsh_snapshot_mark_worst(width, height);
    r = write_png(shots[s].png);
  }
  gmshFinalize(&ierr);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
