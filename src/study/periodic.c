/* A periodic sample for `verify --accuracy` (src/study/wave.c): a mesh of a
 * box whose opposite faces carry the same nodes (Gmsh's periodic meshes,
 * `Periodic Surface` or gmsh.model.mesh.setPeriodic, and structured meshes
 * of a box) tiles space when each node on a face is made one unknown with
 * its image on the opposite face. A plane wave whose wave vector fits the
 * box then meets no boundary and runs for as many periods as asked: the
 * measurement a phase speed needs (the packet on a bounded mesh only runs
 * until its window meets the boundary).
 * The faces are matched, dimension by dimension, on a grid of cells of the
 * matching tolerance over the two other coordinates: the nodes of the far
 * face are sorted by their cell (whole numbers: a total order whatever the
 * nodes' order), and each node of the near face takes the nearest unmatched
 * node within the tolerance among the far nodes of its cell and of the eight
 * around it (a twin within the tolerance is at most one cell away on each
 * axis). The result does not depend on the order of the nodes (a sort whose
 * "equal within the tolerance" is not transitive did: issue 45). Twins are
 * joined by union-find, so that edge and corner nodes end up in one class
 * with all their images. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "wave-impl.h"

/* A node of a face and its cell over the two coordinates other than the normal. */
typedef struct {
  int64_t cell[2]; /* floor((x - box lo) / tol) on the two other axes */
  size_t node;     /* the mesh node */
} face_node;

/* The matching of one pair of faces. */
typedef struct {
  const dtm_mesh *mesh;
  int axis[2];      /* the coordinates other than the faces' normal */
  const double *lo; /* [3] the box's lower corner, m */
  double tol;       /* m: the cell's side and the largest gap between twins */
  face_node *far;   /* [nfar] the far face's nodes, sorted by cell */
  size_t nfar;      /* nodes on the far face */
  char *taken;      /* [nfar] 1 once matched */
} face_match;

static int by_cell(const void *pa, const void *pb) {
  const face_node *a = pa, *b = pb;
  for (int j = 0; j < 2; j++)
    if (a->cell[j] != b->cell[j]) return a->cell[j] < b->cell[j] ? -1 : 1;
  return (a->node > b->node) - (a->node < b->node);
}

static face_node node_cell(const face_match *m, size_t node) {
  face_node f = {{0, 0}, node};
  for (int j = 0; j < 2; j++)
    f.cell[j] = (int64_t)floor((m->mesh->xyz[3 * node + m->axis[j]] - m->lo[m->axis[j]]) / m->tol);
  return f;
}

/* The first far node whose cell is not below (cu, cv). */
static size_t first_in(const face_match *m, int64_t cu, int64_t cv) {
  size_t lo = 0, hi = m->nfar;
  face_node key = {{cu, cv}, 0};
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (by_cell(&m->far[mid], &key) < 0)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

/* The largest gap (m) between node a and far node b on the other axes. */
static double gap(const face_match *m, size_t a, size_t b) {
  const double *x = m->mesh->xyz;
  return fmax(fabs(x[3 * a + m->axis[0]] - x[3 * b + m->axis[0]]), fabs(x[3 * a + m->axis[1]] - x[3 * b + m->axis[1]]));
}

/* The index in m->far of the unmatched twin of near node a nearest within tol, or m->nfar. */
static size_t twin_of(const face_match *m, size_t a) {
  face_node c = node_cell(m, a);
  size_t best = m->nfar;
  double best_gap = INFINITY;
  for (int du = -1; du <= 1; du++)
    for (int dv = -1; dv <= 1; dv++)
      for (size_t i = first_in(m, c.cell[0] + du, c.cell[1] + dv);
           i < m->nfar && m->far[i].cell[0] == c.cell[0] + du && m->far[i].cell[1] == c.cell[1] + dv; i++) {
        double g = gap(m, a, m->far[i].node);
        if (!m->taken[i] && g <= m->tol && g < best_gap) best = i, best_gap = g;
      }
  return best;
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

/* Join every node of near[n] to its twin among m's far nodes; 0 when one has none. */
static int join_twins(face_match *m, const size_t *near, size_t n, size_t *parent) {
  for (size_t i = 0; i < n; i++) {
    size_t t = twin_of(m, near[i]);
    if (t == m->nfar) return 0;
    m->taken[t] = 1;
    size_t ra = root_of(parent, near[i]), rb = root_of(parent, m->far[t].node);
    parent[ra > rb ? ra : rb] = ra > rb ? rb : ra;
  }
  return 1;
}

/* Join the nodes of the faces x_c = lo[c] and x_c = hi; 0 when they do not
 * match (buf: 2 nnodes; -1 on running out of memory). */
static int match_faces(const dtm_mesh *mesh, int c, const double *lo, double hi, double tol, size_t *buf,
                       size_t *parent) {
  size_t *a = buf, *b = buf + mesh->nnodes;
  size_t na = face_nodes(mesh, c, lo[c], tol, a), nb = face_nodes(mesh, c, hi, tol, b);
  if (na != nb || !na) return 0;
  face_match m = {mesh, {(c + 1) % 3, (c + 2) % 3}, lo, tol, malloc(nb * sizeof(face_node)), nb, calloc(nb, 1)};
  int ok = m.far && m.taken ? 1 : -1;
  if (ok > 0) {
    for (size_t i = 0; i < nb; i++) m.far[i] = node_cell(&m, b[i]);
    qsort(m.far, nb, sizeof *m.far, by_cell);
    ok = join_twins(&m, a, na, parent);
  }
  free(m.far), free(m.taken);
  return ok;
}

int dtm_wave_periodic_find(const dtm_mesh *mesh, dtm_wave_periodic *p) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, ext = 0;
  memset(p, 0, sizeof *p);
  for (size_t a = 0; a < mesh->nnodes; a++)
    for (int c = 0; c < 3; c++) lo[c] = fmin(lo[c], mesh->xyz[3 * a + c]), hi[c] = fmax(hi[c], mesh->xyz[3 * a + c]);
  for (int c = 0; c < mesh->dim; c++) ext = fmax(ext, hi[c] - lo[c]);
  size_t *buf = malloc((2 * mesh->nnodes + 1) * sizeof *buf);
  p->root = malloc((mesh->nnodes + 1) * sizeof *p->root);
  if (!buf || !p->root) return free(buf), dtm_wave_periodic_free(p), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t a = 0; a < mesh->nnodes; a++) p->root[a] = a;
  int ok = ext > 0;
  for (int c = 0; c < mesh->dim && ok > 0; c++) {
    p->L[c] = hi[c] - lo[c];
    ok = match_faces(mesh, c, lo, hi[c], 1e-6 * ext, buf, p->root);
  }
  free(buf);
  if (ok < 0) return dtm_wave_periodic_free(p), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
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
