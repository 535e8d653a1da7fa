/* The refine loop behind `dtmap refine`. The size suggestion of the current
 * mesh becomes a list-based view (a PostView field cannot use a view built
 * on the model it is remeshing), which drives a fresh mesh of the same
 * geometry as its only size source; Gmsh's optimisers then remove the
 * slivers that set the step, and the new mesh is analysed.
 * The suggestion puts every node at the target, but a fresh mesh has a
 * spread of element shapes, and its worst nodes sit below its typical ones
 * (measured on Gmsh meshes of uniform size: the smallest nodal step is about
 * 0.64 of the median in 3D, 0.8 in 2D). The field is therefore the
 * suggestion times a calibration c: the first round uses that spread, and
 * each later one corrects c by the shortfall it measured,
 * c <- c (target / recommended)^(1/p) x 1.02, p the size exponent of the
 * effect that sets the step. */
#include <gmshc.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/refine.h"
#include "gmsh_util.h"

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
static int add_block(int view, const dtm_analysis *a, const dtm_block *b, double c) {
  int nc, ierr = 0;
  const char *lt = list_type(b->type, &nc);
  if (!lt || !b->n) return DTM_OK;
  size_t per = 4 * (size_t)nc, n = b->n;
  double *d = malloc(n * per * sizeof *d);
  if (!d) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t e = 0; e < n; e++)
    for (int k = 0; k < nc; k++) {
      size_t v = b->conn[e * b->nn + k];
      for (int c = 0; c < 3; c++) d[e * per + c * nc + k] = a->mesh->xyz[3 * v + c];
      d[e * per + 3 * nc + k] = c * a->size_node[v];
    }
  gmshViewAddListData(view, lt, (int)n, d, n * per, &ierr);
  free(d);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot build the size view");
  return DTM_OK;
}

static int size_view(const dtm_analysis *a, double c, int *view) {
  int ierr = 0;
  *view = gmshViewAdd("dtmap size field", -1, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot create the size view");
  for (int b = 0; b < a->mesh->nblocks; b++) DTM_CHECK(add_block(*view, a, &a->mesh->blocks[b], c));
  return DTM_OK;
}

/* Only the background field sets sizes. */
static void size_options(void) {
  static const char *const off[] = {"Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints",
                                    "Mesh.MeshSizeFromCurvature"};
  int ierr = 0;
  for (int i = 0; i < 3; i++) gmshOptionSetNumber(off[i], 0, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMin", 0, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", 1e22, &ierr);
}

static int remesh(const dtm_analysis *a, int dim, int order, double c) {
  int view, ierr = 0;
  DTM_CHECK(size_view(a, c, &view));
  gmshModelMeshClear(NULL, 0, &ierr);
  int field = gmshModelMeshFieldAdd("PostView", -1, &ierr);
  gmshModelMeshFieldSetNumber(field, "ViewTag", view, &ierr);
  gmshModelMeshFieldSetAsBackgroundMesh(field, &ierr);
  size_options();
  dtm_gmsh_serial();
  gmshModelMeshGenerate(dim, &ierr);
  if (!ierr && dim == 3) gmshModelMeshOptimize("", 0, 1, NULL, 0, &ierr);
  if (!ierr && dim == 3) gmshModelMeshOptimize("Netgen", 0, 1, NULL, 0, &ierr);
  if (!ierr && order > 1) gmshModelMeshSetOrder(order, &ierr);
  int bad = ierr;
  dtm_gmsh_restore_threads();
  gmshModelMeshFieldRemove(field, &ierr);
  gmshViewRemove(view, &ierr);
  DTM_GMSH_CHECK(bad, DTM_ERR_INPUT, "remeshing with the size suggestion failed");
  return DTM_OK;
}

/* Size exponent of the effect whose step is the recommendation's basis. */
static double basis_exponent(const dtm_analysis *a) {
  int best = -1;
  for (int k = 0; k < a->neffects; k++)
    if (a->dt_effect[k] && (best < 0 || a->per_effect[k].safe < a->per_effect[best].safe)) best = k;
  return best >= 0 ? a->effects[best].cls->exponent : 1.0;
}

static double first_calibration(const dtm_analysis *a) {
  double spread = a->mesh->dim == 3 ? 0.78 : a->mesh->dim == 2 ? 0.8 : 1.0;
  return pow(1.0 / spread, 1.0 / basis_exponent(a));
}

static void record(const dtm_analysis *a, double seconds, dtm_refine_round *r) {
  *r = (dtm_refine_round){a->nel, a->dt_min, a->recommended, seconds};
}

int dtm_refine(const dtm_scene *s, double target, int max_rounds, dtm_scene *sc, dtm_refine_round *rounds, int *nrounds,
               dtm_analysis **out) {
  if (!s->geometry) return DTM_ERR(DTM_ERR_INPUT, "%s: refine needs a <geometry>, not a <mesh>", s->path);
  *sc = *s;
  sc->target = target;
  if (max_rounds > DTM_REFINE_MAX_ROUNDS - 1) max_rounds = DTM_REFINE_MAX_ROUNDS - 1;
  double t0 = dtm_wtime();
  dtm_analysis *a = NULL;
  int dim;
  DTM_CHECK(dtm_gmsh_load(sc, &dim));
  DTM_CHECK(dtm_analysis_current(sc, dim, &a));
  record(a, dtm_wtime() - t0, &rounds[0]);
  int n = 1;
  double c = first_calibration(a);
  while (a->recommended < target && n <= max_rounds) {
    t0 = dtm_wtime();
    double before = a->recommended;
    if (n > 1) c *= 1.02 * pow(target / a->recommended, 1.0 / basis_exponent(a));
    int r = remesh(a, dim, sc->mesh_order, c);
    dtm_analysis *next = NULL;
    if (r == DTM_OK) r = dtm_analysis_current(sc, dim, &next);
    if (r) return dtm_analysis_destroy(&a), dtm_error_trace(r, __FILE__, __LINE__, __func__);
    dtm_analysis_destroy(&a);
    a = next;
    record(a, dtm_wtime() - t0, &rounds[n++]);
    if (a->recommended < 1.01 * before) break; /* no progress */
  }
  *nrounds = n;
  *out = a;
  return DTM_OK;
}
