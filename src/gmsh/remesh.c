/* Remeshing the current model with a size field given at the nodes of its
 * current mesh (the refine loop of src/study/refine.c). The sizes become a
 * list-based view (a PostView field cannot use a view built on the model it
 * is remeshing), which is the only size source of a fresh mesh of the same
 * geometry: sizes from points, curvature and the boundary are switched off.
 * Gmsh's optimisers then run, the passes the caller asks for
 * (DTM_OPTIMISE_*): in 3D the default tetrahedral optimiser and Netgen's
 * (not built into Debian's Gmsh: it logs an error and leaves the mesh),
 * and Relocate3D, which moves nodes to improve the worst elements; in 2D
 * Relocate2D and Laplace2D. A pass that fails is not the input's fault:
 * the mesh before it is kept. A partitioned model is made whole first
 * (src/gmsh/unpartition.c). */
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/kernel.h"
#include "dtmap/progress.h"
#include "gmsh-impl.h"

/* List-view type of a linear parent element ("ST" = scalar triangle...). */
static const char *list_type(int type, int *ncorner) {
  static const struct {
    int t[3];
    const char *name;
    int n;
  } map[] = {{{1, 0, 0}, "SL", 2},   {{2, 9, 0}, "ST", 3},   {{3, 10, 16}, "SQ", 4}, {{4, 11, 0}, "SS", 4},
             {{5, 12, 17}, "SH", 8}, {{6, 13, 18}, "SI", 6}, {{7, 14, 19}, "SY", 5}};
  for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
    for (int j = 0; j < 3; j++)
      if (map[i].t[j] == type) return *ncorner = map[i].n, map[i].name;
  return *ncorner = 0, NULL;
}

/* Data of one block: per element x[n], y[n], z[n], then the sizes [n]. */
static int add_block(int view, const dtm_mesh *m, const double *size, const dtm_block *b, double scale) {
  int nc, ierr = 0;
  const char *lt = list_type(b->type, &nc);
  if (!lt || !b->n) return DTM_OK;
  size_t per = 4 * (size_t)nc, n = b->n;
  double *d = malloc(n * per * sizeof *d);
  if (!d) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t e = 0; e < n; e++)
    for (int k = 0; k < nc; k++) {
      size_t v = b->conn[e * b->nn + k];
      for (int c = 0; c < 3; c++) d[e * per + c * nc + k] = m->xyz[3 * v + c];
      d[e * per + 3 * nc + k] = scale * size[v];
    }
  gmshViewAddListData(view, lt, (int)n, d, n * per, &ierr);
  free(d);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot build the size view");
  return DTM_OK;
}

static int size_view(const dtm_mesh *m, const double *size, double scale, int *view) {
  int ierr = 0;
  *view = gmshViewAdd("dtmap size field", -1, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot create the size view");
  for (int b = 0; b < m->nblocks; b++) DTM_CHECK(add_block(*view, m, size, &m->blocks[b], scale));
  return DTM_OK;
}

/* The options a remesh changes: only the background field sets sizes. */
static const char *const size_keys[] = {"Mesh.MeshSizeExtendFromBoundary",
                                        "Mesh.MeshSizeFromPoints",
                                        "Mesh.MeshSizeFromCurvature",
                                        "Mesh.MeshSizeMin",
                                        "Mesh.MeshSizeMax",
                                        "Mesh.MeshSizeFactor"};
#define NKEYS 6

/* Set them for the remesh, keeping the old values in old[NKEYS]: the
 * field alone, or with the floor, curvature sizes and cap sizes asks for. */
static void size_options(double *old, const dtm_remesh_sizes *sizes) {
  double set[NKEYS] = {0, 0, 0, 0, 1e22, 1};
  set[2] = sizes ? sizes->curvature : 0, set[3] = sizes ? sizes->min_size : 0;
  if (sizes && sizes->max_size > 0) set[4] = sizes->max_size;
  int ierr = 0;
  for (int i = 0; i < NKEYS; i++) {
    gmshOptionGetNumber(size_keys[i], &old[i], &ierr);
    gmshOptionSetNumber(size_keys[i], set[i], &ierr);
  }
}

/* Give them back, so that a later load of a scene in the same process
 * meshes as it would in a fresh one. */
static void restore_options(const double *old) {
  int ierr = 0;
  for (int i = 0; i < NKEYS; i++) gmshOptionSetNumber(size_keys[i], old[i], &ierr);
}

/* Gmsh's optimisers log an error when they are not compiled in (Netgen in
 * Debian's build) and leave the mesh as it was: their messages are not the
 * input's fault, so the log is checked after meshing and after the order
 * change only. */
typedef struct {
  int dim, order;    /* dimension to mesh, element order */
  unsigned optimise; /* DTM_OPTIMISE_* passes asked for */
} remesh_job;

/* The optimiser passes of a dimension, in the order they run. */
static const struct {
  unsigned bit;       /* DTM_OPTIMISE_* */
  int dim;            /* the mesh dimension it applies to */
  const char *method; /* Gmsh's name for it */
} passes[] = {{DTM_OPTIMISE_GMSH, 3, ""},
              {DTM_OPTIMISE_NETGEN, 3, "Netgen"},
              {DTM_OPTIMISE_RELOCATE, 3, "Relocate3D"},
              {DTM_OPTIMISE_RELOCATE, 2, "Relocate2D"},
              {DTM_OPTIMISE_LAPLACE2D, 2, "Laplace2D"}};

/* The passes the job asks for in its dimension, once each. */
static void optimise(const remesh_job *j) {
  for (size_t k = 0; k < sizeof passes / sizeof passes[0]; k++) {
    int ierr = 0;
    if ((j->optimise & passes[k].bit) && passes[k].dim == j->dim) {
      dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
      gmshModelMeshOptimize(passes[k].method, 0, 1, NULL, 0, &ierr);
    }
  }
}

/* Whether this Gmsh has the optimiser method (Netgen is an optional part
 * of Gmsh's build, absent from Debian's: asked for, it logs an error and
 * leaves the mesh as it was). */
static int built_in(const char *method) {
  if (strcmp(method, "Netgen")) return 1;
  char *opts = NULL;
  int ierr = 0;
  gmshOptionGetString("General.BuildOptions", &opts, &ierr);
  int has = !ierr && opts && strstr(opts, "Netgen") != NULL;
  gmshFree(opts);
  return has;
}

unsigned dtm_gmsh_optimisers(int dim, unsigned asked) {
  unsigned ran = 0;
  for (size_t k = 0; k < sizeof passes / sizeof passes[0]; k++)
    if ((asked & passes[k].bit) && passes[k].dim == dim && built_in(passes[k].method)) ran |= passes[k].bit;
  return ran;
}

static int generate(void *arg) {
  const remesh_job *j = arg;
  int dim = j->dim, order = j->order, ierr = 0;
  dtm_gmsh_log_reset();
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshModelMeshGenerate(dim, &ierr);
  DTM_GMSH_CHECK_LOG(ierr, DTM_ERR_INPUT, "remeshing with the size suggestion failed");
  optimise(j);
  dtm_gmsh_log_reset();
  if (order > 1) gmshModelMeshSetOrder(order, &ierr);
  DTM_GMSH_CHECK_LOG(ierr, DTM_ERR_INPUT, "remeshing with the size suggestion failed");
  return DTM_OK;
}

int dtm_gmsh_remesh(const dtm_mesh *m, const double *size, double scale, int dim, int order, int round,
                    unsigned optimise) {
  return dtm_gmsh_remesh_sized(m, size, scale, dim, order, round, optimise, NULL);
}

int dtm_gmsh_remesh_sized(const dtm_mesh *m, const double *size, double scale, int dim, int order, int round,
                          unsigned optimise, const dtm_remesh_sizes *sizes) {
  int view, ierr = 0;
  remesh_job job = {dim, order, optimise};
  char stage[64];
  snprintf(stage, sizeof stage, "remeshing after round %d", round);
  DTM_CHECK(size_view(m, size, scale, &view));
  DTM_CHECK(dtm_gmsh_unpartition());
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshModelMeshClear(NULL, 0, &ierr);
  int field = gmshModelMeshFieldAdd("PostView", -1, &ierr);
  gmshModelMeshFieldSetNumber(field, "ViewTag", view, &ierr);
  gmshModelMeshFieldSetAsBackgroundMesh(field, &ierr);
  double old[NKEYS];
  size_options(old, sizes);
  dtm_gmsh_mesher_apply(NULL); /* the algorithm and threads of the scene's load */
  dtm_progress_begin("meshing");
  int r = dtm_gmsh_contained(stage, generate, &job, 1); /* a crash in Gmsh ends the round, not dtmap */
  dtm_progress_end();
  restore_options(old);
  dtm_gmsh_restore_threads();
  gmshModelMeshFieldRemove(field, &ierr);
  gmshViewRemove(view, &ierr);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
