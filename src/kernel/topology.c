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
#include "kernel-impl.h"

/* The tables live in the kernel's element catalogue (dtm_elem_topology),
 * which already maps a second-order type to its linear parent. */
int dtm_elem_edges(int type, const int (**edges)[2]) {
  const dtm_topology *t = dtm_elem_topology(type);
  *edges = t ? (const int(*)[2])t->edge : NULL;
  return t ? t->nedge : 0;
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

int dtm_elem_facets(int type, const int (**nodes)[DTM_MAX_FACET_NODES], const int **count) {
  const dtm_topology *t = dtm_elem_topology(type);
  *nodes = t ? (const int(*)[DTM_MAX_FACET_NODES])t->facet : NULL;
  *count = t ? t->facet_nn : NULL;
  return t ? t->nfacet : 0;
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
