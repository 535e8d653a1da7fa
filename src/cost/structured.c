/* A structured mesh: its elements are a few shapes repeated on one lattice
 * (Gmsh's transfinite and extruded meshes, a box cut into cells). Its
 * dispersion is then computed exactly from its own cells, leading waves
 * included, not taken from the measured mean of unstructured meshes
 * (src/cost/measured.c). Two kinds, for the elements of one type and
 * material:
 * - a grid of one node class (types whose nodes are all corners: tet4,
 *   prism6, ...): every node lies on one lattice and the elements are at
 *   most DTM_DISP_MAX_SHAPES shapes. The plane wave p exp(i k.x) on the
 *   nodes is then a Bloch mode of each cell pattern, and the Rayleigh
 *   quotient of the summed element matrices (src/cost/shapes.c, each shape
 *   counted as often as it occurs) is its frequency: exact when the cells
 *   are all alike, and within round-off of a simulation on Gmsh's
 *   transfinite tetrahedra, which cut neighbouring cells differently
 *   (tests/t613-tet-accuracy.py);
 * - a lattice (any type, second-order ones included): the elements are
 *   the translates of at most DTM_DISP_MAX_EL shapes, one of each per cell,
 *   by one lattice; Bloch analysis of that cell (src/cost/dispersion.c).
 * Recognition:
 * - each element's shape key: its nodes relative to its lexicographically
 *   first corner, quantised to 1e-6 of the first element's mean edge and
 *   sorted; an unstructured mesh has more shapes than allowed within its
 *   first few elements, so the check costs nothing there;
 * - the lattice: the shortest independent vectors among the key's node
 *   offsets (a grid) or among the differences between the first corners of
 *   the elements of the first key (a lattice; in 3D successive minima are
 *   a basis); every element's corner must lie on it (a grid: relative to
 *   the first element; a lattice: to its key's first element, and one
 *   element of each key must fill the cell). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dispersion-impl.h"
#include "dtmap/cost.h"
#include "dtmap/kernel.h"
#include "dtmap/topology.h"
#include "reference.h"

typedef struct {
  long long q[DTM_DISP_MAX_NN][3]; /* the nodes relative to the first corner, quantised and sorted */
  double o[3];                     /* the first corner, m */
} shape_key;

/* The shapes met so far. */
typedef struct {
  int type, d, nn, nv;                /* element type, dimension, nodes, corners */
  double tol;                         /* the quantum, m */
  int n;                              /* shapes */
  shape_key key[DTM_DISP_MAX_SHAPES]; /* the first element of each */
  dtm_disp_structure *out;            /* its nodes (x) and counts */
  double *corner;                     /* [count[0]][3] the first corners of the first shape's elements, m */
  int failed;                         /* out of memory */
} shape_set;

/* Quantised coordinates of one point within round-off of another: 2 quanta
 * apart at most (a value near a quantum's edge rounds either way). */
#define NEAR 2

/* a before b, lexicographically, coordinates within NEAR being equal (the
 * nodes of an element are many quanta apart, so this orders them). */
static int lex_less(const long long *a, const long long *b) {
  for (int c = 0; c < 3; c++)
    if (llabs(a[c] - b[c]) > NEAR) return a[c] < b[c];
  return 0;
}

/* Whether two keys are one shape. */
static int same_key(const shape_key *a, const shape_key *b, int nn) {
  for (int n = 0; n < nn; n++)
    for (int c = 0; c < 3; c++)
      if (llabs(a->q[n][c] - b->q[n][c]) > NEAR) return 0;
  return 1;
}

/* The key of the element with nodes x[nn][3]. */
static void key_of(const shape_set *S, const double *x, shape_key *k) {
  long long abs[DTM_DISP_MAX_NN][3];
  int first = 0;
  for (int a = 0; a < S->nv; a++)
    for (int c = 0; c < 3; c++) abs[a][c] = llround(x[3 * a + c] / S->tol);
  for (int a = 1; a < S->nv; a++)
    if (lex_less(abs[a], abs[first])) first = a;
  for (int a = 0; a < S->nn; a++)
    for (int c = 0; c < 3; c++) k->q[a][c] = llround((x[3 * a + c] - x[3 * first + c]) / S->tol);
  for (int a = 1; a < S->nn; a++) /* insertion sort: at most ten nodes */
    for (int b = a; b > 0 && lex_less(k->q[b], k->q[b - 1]); b--) {
      long long t[3] = {k->q[b][0], k->q[b][1], k->q[b][2]};
      memcpy(k->q[b], k->q[b - 1], sizeof t), memcpy(k->q[b - 1], t, sizeof t);
    }
  memcpy(k->o, x + 3 * first, sizeof k->o);
}

/* Index of key k among S's, adding it (nodes x); -1 when S is full. */
static int key_index(shape_set *S, const shape_key *k, const double *x) {
  for (int i = 0; i < S->n; i++)
    if (same_key(&S->key[i], k, S->nn)) return i;
  if (S->n == DTM_DISP_MAX_SHAPES) return -1;
  S->key[S->n] = *k;
  memcpy(S->out->x[S->n], x, sizeof(double) * 3 * (size_t)S->nn);
  S->out->count[S->n] = 0;
  return S->n++;
}

/* Pass over the elements of type and material mat (no section): fn(user,
 * nodes) for each, stopping at the first nonzero return, which it returns. */
static int each_element(const dtm_mesh *mesh, int type, int mat, int (*fn)(void *, const double *), void *user) {
  double x[3 * DTM_MAX_NODES];
  for (int b = 0; b < mesh->nblocks; b++) {
    const dtm_block *bl = &mesh->blocks[b];
    for (size_t e = 0; bl->type == type && e < bl->n; e++) {
      if (bl->mat[e] != mat || (bl->section && bl->section[e] >= 0)) continue;
      dtm_mesh_gather_one(mesh, bl, e, x);
      int r = fn(user, x);
      if (r) return r;
    }
  }
  return 0;
}

/* First pass: count the shapes, keep the first shape's corners. */
static int add_shape(void *user, const double *x) {
  shape_set *S = user;
  shape_key k;
  if (!(S->tol > 0)) S->tol = 1e-6 * dtm_elem_mean_edge(S->type, x);
  key_of(S, x, &k);
  int i = key_index(S, &k, x);
  if (i < 0) return 1;
  size_t c = (size_t)S->out->count[0];
  if (i == 0 && !(c & (c + 1))) { /* 0, 1, 3, 7, ...: grow to twice */
    double *p = realloc(S->corner, 2 * (c + 1) * 3 * sizeof *p);
    if (!p) return S->failed = 1;
    S->corner = p;
  }
  if (i == 0) memcpy(S->corner + 3 * c, k.o, sizeof k.o);
  S->out->count[i]++;
  return 0;
}

/* A lattice's vectors (the columns of B) and its inverse. */
typedef struct {
  const shape_set *S; /* the shapes */
  int d;              /* dimension */
  int grid;           /* 1: every node on the lattice (relative to the first corner met) */
  double B[3][3];     /* columns: the vectors, m */
  double Bi[3][3];    /* its inverse */
  int nb;             /* vectors found */
} lattice_scan;

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Whether v is independent of the first nb vectors of B (relative 1e-6). */
static int independent(const lattice_scan *L, const double *v) {
  double vv = dot3(v, v), a[3] = {L->B[0][0], L->B[1][0], L->B[2][0]}, b[3] = {L->B[0][1], L->B[1][1], L->B[2][1]},
         c[3];
  if (!(vv > 0) || L->nb == 0) return vv > 0;
  if (L->nb == 1) return cross3(a, v, c), dot3(c, c) > 1e-12 * dot3(a, a) * vv;
  cross3(a, b, c);
  return dot3(c, v) * dot3(c, v) > 1e-12 * dot3(c, c) * vv;
}

/* The candidate vectors: a grid's node offsets within its shapes, a
 * lattice's differences between the first shape's corners; *n of them
 * into v (owned by the caller). */
static double *candidates(const lattice_scan *L, size_t *n) {
  const shape_set *S = L->S;
  size_t m = L->grid ? (size_t)S->n * (size_t)S->nn : (size_t)S->out->count[0];
  double *v = malloc((m + 1) * 3 * sizeof *v);
  *n = 0;
  for (size_t i = 0; v && i < m; i++, (*n)++)
    for (int c = 0; c < 3; c++)
      v[3 * i + c] = L->grid ? (double)S->key[i / (size_t)S->nn].q[i % (size_t)S->nn][c] * S->tol
                             : S->corner[3 * i + c] - S->corner[c];
  return v;
}

/* Whether v is a whole combination of the vectors (1e-6). */
static int whole(const lattice_scan *L, const double *v) {
  for (int i = 0; i < 3; i++) {
    double f = dot3(L->Bi[i], v);
    if (fabs(f - round(f)) > 1e-6) return 0;
  }
  return 1;
}

/* The shortest independent candidates as the lattice's vectors; 0 when they span less than the space. */
static int find_vectors(lattice_scan *L) {
  size_t n;
  double *v = candidates(L, &n);
  int ok = v != NULL;
  for (L->nb = 0; ok && L->nb < L->d; L->nb++) {
    double best = INFINITY;
    size_t pick = 0;
    for (size_t i = 0; i < n; i++)
      if (dot3(v + 3 * i, v + 3 * i) < best && independent(L, v + 3 * i)) best = dot3(v + 3 * i, v + 3 * i), pick = i;
    ok = isfinite(best);
    for (int c = 0; ok && c < 3; c++) L->B[c][L->nb] = v[3 * pick + c];
  }
  for (int j = L->d; j < 3; j++) /* a plane mesh: the rest of space */
    for (int c = 0; c < 3; c++) L->B[c][j] = c == j;
  double det = ok ? dtm_mat_det(3, L->B) : 0;
  ok = ok && fabs(det) > 0;
  if (ok) dtm_mat_inverse(3, L->B, det, L->Bi);
  for (size_t i = 0; ok && L->grid && i < n; i++) ok = whole(L, v + 3 * i); /* every offset on the grid */
  free(v);
  return ok;
}

/* Second pass: the element's first corner lies on the lattice, relative to
 * the first element's (a grid) or to its key's first element's (a lattice). */
static int on_lattice(void *user, const double *x) {
  lattice_scan *L = user;
  shape_key k;
  key_of(L->S, x, &k);
  for (int i = 0; i < L->S->n; i++)
    if (L->grid || same_key(&k, &L->S->key[i], L->S->nn)) {
      double v[3] = {k.o[0] - L->S->key[i].o[0], k.o[1] - L->S->key[i].o[1], k.o[2] - L->S->key[i].o[2]};
      return !whole(L, v);
    }
  return 1;
}

/* The patch: one element of each key in cell units, the cell scaled to
 * volume 1; DTM_ERR_INPUT when they do not fill it. */
static int build_patch(const shape_set *S, const lattice_scan *L, dtm_disp_lattice *P) {
  double vol = fabs(dtm_mat_det(3, L->B)), s = pow(vol, 1.0 / S->d), cell[3][3], sum = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) cell[i][j] = i < S->d ? L->B[i][j] / s : L->B[i][j];
  DTM_CHECK(dtm_disp_lattice_begin(P, S->type, cell));
  for (int k = 0; k < S->n; k++) {
    double f[3 * DTM_DISP_MAX_NN], y[3];
    for (int a = 0; a < S->nn; a++) {
      for (int c = 0; c < 3; c++) y[c] = S->out->x[k][3 * a + c] - S->key[0].o[c];
      for (int i = 0; i < 3; i++) f[3 * a + i] = dot3(L->Bi[i], y);
    }
    sum += fabs(dtm_elem_measure(S->type, S->out->x[k]));
    DTM_CHECK(dtm_disp_lattice_add(P, f));
  }
  return fabs(sum / vol - 1) < 1e-6 ? DTM_OK : DTM_ERR_INPUT;
}

/* Whether the counted shapes are one of each per cell of a lattice. */
static int as_lattice(const dtm_mesh *mesh, int mat, shape_set *S, lattice_scan *L) {
  int ok = S->n <= DTM_DISP_MAX_EL;
  for (int i = 1; ok && i < S->n; i++) ok = S->out->count[i] == S->out->count[0];
  L->grid = 0;
  return ok && find_vectors(L) && !each_element(mesh, S->type, mat, on_lattice, L);
}

/* Whether every node lies on one lattice (types whose nodes are all corners). */
static int as_grid(const dtm_mesh *mesh, int mat, shape_set *S, lattice_scan *L) {
  L->grid = 1;
  return dtm_elem_parent(S->type) == S->type && find_vectors(L) && !each_element(mesh, S->type, mat, on_lattice, L);
}

int dtm_disp_structure_find(const dtm_mesh *mesh, int type, int mat, dtm_disp_structure *s) {
  shape_set *S = calloc(1, sizeof *S);
  lattice_scan L = {.S = S};
  memset(s, 0, sizeof *s);
  if (!S) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  S->type = type, S->out = s;
  int ok = !dtm_elem_info(type, &S->d, &S->nn) && S->nn <= DTM_DISP_MAX_NN && S->d >= 2 &&
           !dtm_elem_info(dtm_elem_parent(type), &L.d, &S->nv);
  ok = ok && !each_element(mesh, type, mat, add_shape, S) && S->n > 0;
  int rc = S->failed ? DTM_ERR(DTM_ERR_INTERNAL, "out of memory") : DTM_OK;
  if (ok && !rc && as_grid(mesh, mat, S, &L))
    s->nshapes = S->n;
  else if (ok && !rc && as_lattice(mesh, mat, S, &L)) {
    s->lattice = malloc(sizeof *s->lattice);
    if (!s->lattice) rc = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    if (s->lattice && build_patch(S, &L, s->lattice) != DTM_OK) {
      dtm_error_clear(); /* a cell beyond the patch's limits: not a lattice dtmap models */
      free(s->lattice), s->lattice = NULL;
    }
  }
  free(S->corner);
  free(S);
  return rc;
}

void dtm_disp_structure_free(dtm_disp_structure *s) {
  free(s->lattice);
  s->lattice = NULL, s->nshapes = 0;
}

int dtm_dispersion_table_mesh(const dtm_mesh *mesh, int type, int mat, double r, dtm_dispersion *t, int *found) {
  dtm_disp_structure st;
  *found = 0;
  DTM_CHECK(dtm_disp_structure_find(mesh, type, mat, &st));
  int rc = DTM_OK;
  if (st.lattice)
    rc = dtm_disp_lattice_table(st.lattice, r, t), t->samples = (size_t)st.lattice->nel;
  else if (st.nshapes) { /* the shapes' nodes packed as x[n][nn][3] */
    double x[DTM_DISP_MAX_SHAPES * 3 * DTM_DISP_MAX_NN];
    int d, nn;
    dtm_elem_info(type, &d, &nn);
    for (int k = 0; k < st.nshapes; k++) memcpy(x + (size_t)k * 3 * nn, st.x[k], sizeof(double) * 3 * (size_t)nn);
    rc = dtm_disp_table_weighted(type, r, x, st.count, (size_t)st.nshapes, t);
  }
  if ((st.lattice || st.nshapes) && rc == DTM_OK) t->shape = DTM_LATTICE_MESH, *found = 1;
  dtm_disp_structure_free(&st);
  return rc;
}
