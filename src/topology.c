/* Edge and facet tables of the element types (Gmsh node ordering), the
 * mean edge length used as an element's size, and facet measures. A
 * second-order type (tri6, quad8/9, tet10, hex20/27, prism15/18, pyr13/14)
 * has the edges and facets of its linear parent, on its corner nodes: Gmsh
 * numbers the corners first, in the parent's order, so the parent's tables
 * apply unchanged. Lengths are then chords between corners and facet
 * measures those of the flat corner polygons (mid-side nodes, and so any
 * curvature, are ignored). */
#include <math.h>

#include "dtmap/kernel.h"
#include "dtmap/topology.h"
#include "kernel/kernel_impl.h"

static const int line_e[][2] = {{0, 1}};
static const int tri_e[][2] = {{0, 1}, {1, 2}, {2, 0}};
static const int quad_e[][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
static const int tet_e[][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
static const int hex_e[][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                               {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
static const int prism_e[][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                 {5, 3}, {0, 3}, {1, 4}, {2, 5}};
static const int pyr_e[][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0},
                               {0, 4}, {1, 4}, {2, 4}, {3, 4}};

#define TABLE(t, out) (*(out) = t, (int)(sizeof t / sizeof t[0]))

int dtm_elem_edges(int type, const int (**edges)[2]) {
  switch (dtm_elem_parent(type)) {
  case DTM_LINE2: return TABLE(line_e, edges);
  case DTM_TRI3: return TABLE(tri_e, edges);
  case DTM_QUAD4: return TABLE(quad_e, edges);
  case DTM_TET4: return TABLE(tet_e, edges);
  case DTM_HEX8: return TABLE(hex_e, edges);
  case DTM_PRISM6: return TABLE(prism_e, edges);
  case DTM_PYR5: return TABLE(pyr_e, edges);
  default: *edges = 0; return 0;
  }
}

double dtm_elem_mean_edge(int type, const double *x) {
  const int(*ed)[2];
  int n = dtm_elem_edges(type, &ed);
  double sum = 0;
  for (int i = 0; i < n; i++) {
    const double *p = x + 3 * ed[i][0], *q = x + 3 * ed[i][1];
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    sum += sqrt(dx * dx + dy * dy + dz * dz);
  }
  return n ? sum / n : NAN;
}

/* Facets: node lists padded to 4, with their counts. */
static const int line_f[][4] = {{0}, {1}}, line_c[] = {1, 1};
static const int tri_f[][4] = {{0, 1}, {1, 2}, {2, 0}}, tri_c[] = {2, 2, 2};
static const int quad_f[][4] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}}, quad_c[] = {2, 2, 2, 2};
static const int tet_f[][4] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, tet_c[] = {3, 3, 3, 3};
static const int hex_f[][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                               {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}},
                 hex_c[] = {4, 4, 4, 4, 4, 4};
static const int prism_f[][4] = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}},
                 prism_c[] = {3, 3, 4, 4, 4};
static const int pyr_f[][4] = {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}},
                 pyr_c[] = {4, 3, 3, 3, 3};

#define FACETS(f, c) (*nodes = f, *count = c, (int)(sizeof f / sizeof f[0]))

int dtm_elem_facets(int type, const int (**nodes)[DTM_MAX_FACET_NODES], const int **count) {
  switch (dtm_elem_parent(type)) {
  case DTM_LINE2: return FACETS(line_f, line_c);
  case DTM_TRI3: return FACETS(tri_f, tri_c);
  case DTM_QUAD4: return FACETS(quad_f, quad_c);
  case DTM_TET4: return FACETS(tet_f, tet_c);
  case DTM_HEX8: return FACETS(hex_f, hex_c);
  case DTM_PRISM6: return FACETS(prism_f, prism_c);
  case DTM_PYR5: return FACETS(pyr_f, pyr_c);
  default: *nodes = 0, *count = 0; return 0;
  }
}

static void sub(const double *a, const double *b, double *d) {
  d[0] = a[0] - b[0], d[1] = a[1] - b[1], d[2] = a[2] - b[2];
}

/* Half the norm of the cross product of the diagonals: the exact area of a
 * planar quadrilateral (and of a triangle, with a degenerate diagonal). */
static double face_area(const double *p0, const double *p1, const double *p2, const double *p3) {
  double d1[3], d2[3];
  sub(p2, p0, d1);
  sub(p3, p1, d2);
  double c[3] = {d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2], d1[0] * d2[1] - d1[1] * d2[0]};
  return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

double dtm_elem_facet_measure(int type, int f, const double *x) {
  const int(*fn)[DTM_MAX_FACET_NODES];
  const int *fc;
  if (f < 0 || f >= dtm_elem_facets(type, &fn, &fc)) return NAN;
  const int *v = fn[f];
  if (fc[f] == 1) return 1.0;
  if (fc[f] == 2) {
    double d[3];
    sub(x + 3 * v[1], x + 3 * v[0], d);
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  }
  /* a triangle p0 p1 p2 is the quadrilateral p0 p1 p2 p0 */
  return face_area(x + 3 * v[0], x + 3 * v[1], x + 3 * v[2], x + 3 * v[fc[f] == 4 ? 3 : 0]);
}
