/* Views of the analysed mesh through Gmsh. Written to a .msh: the mesh
 * through Gmsh's own writer (ASCII or binary, Mesh.SaveAll=1; the options
 * this sets get their values back, so a script's session keeps its own),
 * then every view appended directly in the same encoding (msh_data.c), or,
 * for a views-only file, just the format header and the views, which Gmsh
 * merges on top of the mesh it already has open. No Gmsh view is created
 * for a file. Or added to the open session of a script, where they stay as
 * Gmsh views, with their display options.
 *
 * A failed write names the file and the system's reason. Gmsh's writer
 * does not check its writes, so a mesh it could not finish is recognised by
 * its end (every .msh section ends with a "$End..." line); the reason, for
 * Gmsh's writes as for dtmap's own stream, is what the system says when the
 * file is written to again (the caller gives the file up anyway). */
#include <errno.h>
#include <gmshc.h>
#include <math.h>
#include <pthread.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "dtmap/gmsh.h"
#include "base.h"
#include "gmsh-impl.h"

/* The options dtm_gmsh_write_mesh sets, given back their values after. */
static const char *const write_options[] = {"Mesh.SaveAll", "Mesh.Binary", "Mesh.MshFileVersion"};
#define NWRITE_OPTIONS (sizeof write_options / sizeof write_options[0])

static void swap_options(const double *set, double *old) {
  int ierr = 0;
  for (size_t i = 0; i < NWRITE_OPTIONS; i++) {
    if (old) gmshOptionGetNumber(write_options[i], &old[i], &ierr);
    gmshOptionSetNumber(write_options[i], set[i], &ierr);
  }
}

/* ---- write failures ---------------------------------------------------- */

/* Raise "<path>: cannot write <what>: <reason>" for f, whose writes failed,
 * in place of the error its writer raised (which names neither). */
static int stream_fail(FILE *f, const char *path, const char *what) {
  char why[256];
  dtm_write_reason(dtm_write_errno(f), why, sizeof why);
  dtm_error_clear();
  return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write %s: %s", path, what, why);
}

/* Whether the file at path ends as a .msh does: its last line starts with
 * "$End". */
static int msh_complete(const char *path) {
  char tail[64];
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  int whole = fseek(f, -(long)sizeof tail, SEEK_END) != 0;
  if (whole) fseek(f, 0, SEEK_SET);
  size_t n = fread(tail, 1, sizeof tail, f), i = n > 0 ? n - 1 : 0;
  fclose(f);
  if (n < 5 || tail[n - 1] != '\n') return 0;
  while (i > 0 && tail[i - 1] != '\n') i--;
  return (i > 0 || whole) && n - i > 4 && !strncmp(tail + i, "$End", 4);
}

/* Gmsh's mesh at path is whole, else the error with the reason. */
static int check_mesh_written(const char *path) {
  if (msh_complete(path)) return DTM_OK;
  FILE *f = fopen(path, "ab");
  if (!f) return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write the mesh: %s", path, strerror(errno));
  int r = stream_fail(f, path, "the mesh");
  fclose(f);
  return r;
}

/* ---- the .msh --------------------------------------------------------- */

int dtm_gmsh_write_mesh(const char *path, int binary) {
  int ierr = 0;
  const double set[NWRITE_OPTIONS] = {1, binary ? 1 : 0, 4.1};
  double old[NWRITE_OPTIONS];
  swap_options(set, old);
  gmshWrite(path, &ierr);
  swap_options(old, NULL);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, path);
  return check_mesh_written(path);
}

int dtm_gmsh_write_mesh_as_read(const char *path, int binary, int release) {
  const char *at = dtm_gmsh_source_unchanged();
  char src[4096];
  long long n = at ? dtm_msh_mesh_extent(at, binary) : -1;
  if (n < 0) {
    int r = dtm_gmsh_write_mesh(path, binary);
    if (release) dtm_gmsh_release();
    return r;
  }
  snprintf(src, sizeof src, "%s", at);
  if (release) dtm_gmsh_release(); /* before the copy: the file is all it needs */
  return dtm_msh_copy_bytes(src, path, n);
}

static pthread_mutex_t gmsh_lock = PTHREAD_MUTEX_INITIALIZER;
static int given; /* the model is run's background writer's (under gmsh_lock) */

void dtm_gmsh_lock(void) { pthread_mutex_lock(&gmsh_lock); }
void dtm_gmsh_unlock(void) { pthread_mutex_unlock(&gmsh_lock); }

void dtm_gmsh_model_given(int on) {
  dtm_gmsh_lock();
  given = on;
  dtm_gmsh_unlock();
}

int dtm_gmsh_model_is_given(void) { return given; } /* read under gmsh_lock */

void dtm_gmsh_release(void) {
  int ierr = 0;
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshClear(&ierr);
#ifdef __GLIBC__
  malloc_trim(0); /* Gmsh's many small blocks: give the pages back */
#endif
}

int dtm_gmsh_write(const char *path, const dtm_view *views, int nviews, const dtm_msh_format *fmt) {
  dtm_msh_format def = {0, 0, 0};
  if (!fmt) fmt = &def;
  if (!fmt->views_only) DTM_CHECK(dtm_gmsh_write_mesh(path, fmt->binary));
  return dtm_gmsh_write_views(path, views, nviews, fmt);
}

/* Write the views to f (after the header of a views-only file). */
static int put_views(FILE *f, const char *path, const dtm_view *views, int nviews, const dtm_msh_format *fmt) {
  if (fmt->views_only && dtm_msh_header(f, fmt->binary)) return stream_fail(f, path, "the format header");
  for (int i = 0; i < nviews; i++) {
    int r = dtm_msh_write_view(f, &views[i], fmt->binary, fmt->partition);
    if (r && !ferror(f)) return dtm_error_trace(r, __FILE__, __LINE__, __func__);
    if (r) {
      char what[160];
      snprintf(what, sizeof what, "view '%s'", views[i].name);
      return stream_fail(f, path, what);
    }
  }
  return DTM_OK;
}

int dtm_gmsh_write_views(const char *path, const dtm_view *views, int nviews, const dtm_msh_format *fmt) {
  FILE *f = fopen(path, fmt->views_only ? "wb" : "ab");
  if (!f) return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", path, strerror(errno));
  char why[256];
  int r = put_views(f, path, views, nviews, fmt);
  errno = 0;
  if (fclose(f) && r == DTM_OK)
    r = DTM_ERR(DTM_ERR_INPUT, "%s: cannot write the views: %s", path,
                dtm_write_reason(errno ? errno : EIO, why, sizeof why));
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

/* ---- views in the open session of a script --------------------------- */

/* The records of v as Gmsh's API takes them: tags and doubles (integer
 * values converted; only finite ones with finite_only). */
static size_t view_arrays(const dtm_view *v, size_t *tags, double *vals) {
  size_t k = 0;
  for (size_t i = 0; i < v->n; i++) {
    double x = v->ivalues ? (double)v->ivalues[i] : v->values[i];
    if (v->finite_only && !isfinite(x)) continue;
    tags[k] = v->tags[i], vals[k++] = x;
  }
  return k;
}

/* Create view v on model; *tag is its tag, or -1 when none was created. */
static int add_view(const char *model, const dtm_view *v, int *tag) {
  int ierr = 0;
  size_t *tags = malloc((v->n + 1) * sizeof *tags);
  double *vals = malloc((v->n + 1) * sizeof *vals);
  *tag = -1;
  if (!tags || !vals) return free(tags), free(vals), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t n = view_arrays(v, tags, vals);
  *tag = gmshViewAdd(v->name, -1, &ierr);
  if (ierr) *tag = -1;
  if (!ierr)
    gmshViewAddHomogeneousModelData(*tag, 0, model, v->node_data ? "NodeData" : "ElementData", tags, n, vals, n, 0.0, 1,
                                    0, &ierr);
  free(tags), free(vals);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, v->name);
  return DTM_OK;
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
