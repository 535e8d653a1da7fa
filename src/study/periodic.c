/* A periodic sample for `verify --accuracy` (src/study/wave.c): a mesh of a
 * box whose opposite faces carry the same nodes (Gmsh's periodic meshes,
 * `Periodic Surface` or gmsh.model.mesh.setPeriodic, and structured meshes
 * of a box) tiles space when each node on a face is made one unknown with
 * its image on the opposite face. A plane wave whose wave vector fits the
 * box then meets no boundary and runs for as many periods as asked: the
 * measurement a phase speed needs (the packet on a bounded mesh only runs
 * until its window meets the boundary).
 * The faces are matched, dimension by dimension, by sorting the nodes on
 * each face by their other coordinates; twins are joined by union-find, so
 * that edge and corner nodes end up in one class with all their images. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "wave-impl.h"

/* The sort of a face's nodes: their coordinates other than c, within tol equal. */
typedef struct {
  const double *xyz; /* [nnodes][3] */
  int c;             /* the face's normal axis */
  double tol;        /* m */
} face_sort;

static int by_other(const face_sort *s, size_t na, size_t nb) {
  const double *a = s->xyz + 3 * na, *b = s->xyz + 3 * nb;
  for (int j = 0; j < 3; j++)
    if (j != s->c && fabs(a[j] - b[j]) > s->tol) return a[j] < b[j] ? -1 : 1;
  return 0;
}

/* Merge sort of v[n] by by_other (tmp: n more). */
static void sort_face(const face_sort *s, size_t *v, size_t n, size_t *tmp) {
  if (n < 2) return;
  size_t h = n / 2, i = 0, j = h, k = 0;
  sort_face(s, v, h, tmp), sort_face(s, v + h, n - h, tmp);
  while (i < h || j < n) tmp[k++] = j == n || (i < h && by_other(s, v[i], v[j]) <= 0) ? v[i++] : v[j++];
  memcpy(v, tmp, n * sizeof *v);
}

static size_t root_of(size_t *parent, size_t a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

/* The nodes with x_c within tol of v into idx; returns how many. */
static size_t face_nodes(const dtm_mesh *mesh, int c, double v, double tol, size_t *idx) {
  size_t n = 0;
  for (size_t a = 0; a < mesh->nnodes; a++)
    if (fabs(mesh->xyz[3 * a + c] - v) <= tol) idx[n++] = a;
  return n;
}

/* Join the nodes of the faces x_c = lo and x_c = hi; 0 when they do not match. */
static int match_faces(const dtm_mesh *mesh, int c, double lo, double hi, double tol, size_t *buf, size_t *parent) {
  size_t *a = buf, *b = buf + mesh->nnodes, *tmp = buf + 2 * mesh->nnodes;
  size_t na = face_nodes(mesh, c, lo, tol, a), nb = face_nodes(mesh, c, hi, tol, b);
  face_sort s = {mesh->xyz, c, tol};
  if (na != nb || !na) return 0;
  sort_face(&s, a, na, tmp), sort_face(&s, b, nb, tmp);
  for (size_t i = 0; i < na; i++) {
    if (by_other(&s, a[i], b[i])) return 0;
    size_t ra = root_of(parent, a[i]), rb = root_of(parent, b[i]);
    parent[ra > rb ? ra : rb] = ra > rb ? rb : ra;
  }
  return 1;
}

int dtm_wave_periodic_find(const dtm_mesh *mesh, dtm_wave_periodic *p) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, ext = 0;
  memset(p, 0, sizeof *p);
  for (size_t a = 0; a < mesh->nnodes; a++)
    for (int c = 0; c < 3; c++) lo[c] = fmin(lo[c], mesh->xyz[3 * a + c]), hi[c] = fmax(hi[c], mesh->xyz[3 * a + c]);
  for (int c = 0; c < mesh->dim; c++) ext = fmax(ext, hi[c] - lo[c]);
  size_t *buf = malloc((3 * mesh->nnodes + 1) * sizeof *buf);
  p->root = malloc((mesh->nnodes + 1) * sizeof *p->root);
  if (!buf || !p->root) return free(buf), dtm_wave_periodic_free(p), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t a = 0; a < mesh->nnodes; a++) p->root[a] = a;
  int ok = ext > 0;
  for (int c = 0; c < mesh->dim && ok; c++) {
    p->L[c] = hi[c] - lo[c];
    ok = match_faces(mesh, c, lo[c], hi[c], 1e-6 * ext, buf, p->root);
  }
  free(buf);
  if (!ok) return dtm_wave_periodic_free(p), DTM_OK;
  for (size_t a = 0; a < mesh->nnodes; a++) p->root[a] = root_of(p->root, a);
  p->periodic = 1;
  return DTM_OK;
}

void dtm_wave_periodic_free(dtm_wave_periodic *p) {
  free(p->root);
  p->root = NULL, p->periodic = 0;
}

int dtm_wave_periodic_fit(const dtm_wave_periodic *p, int dim, double k[3]) {
  int any = 0;
  for (int c = 0; c < dim; c++) {
    double m = round(k[c] * p->L[c] / (2 * 3.14159265358979323846));
    k[c] = 2 * 3.14159265358979323846 * m / p->L[c];
    any |= m != 0;
  }
  return any;
}
