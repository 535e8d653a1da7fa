/* A well-shaped element of every supported type with a given mean edge
 * length h: the equilateral triangle, the regular tetrahedron, the square,
 * the cube, the right prism on an equilateral triangle with square sides,
 * the pyramid on a square whose eight edges are all h, and the bar. Their
 * second-order nodes sit where Gmsh's reference nodes map under the same
 * affine map (mid-edges, face and cell centres). The advice compares an
 * element's step with that of the well-shaped element of its size, to tell
 * a step limited by shape from one limited by size. */
#include <math.h>

#include "dtmap/error.h"
#include "kernel-impl.h"

/* Affine image of reference node p (Gmsh's u, v, w) for the parent type. */
static void map_node(int parent, double h, const double p[3], double x[3]) {
  const double s3 = sqrt(3.0), u = p[0], v = p[1], w = p[2];
  x[0] = x[1] = x[2] = 0;
  switch (parent) {
  case DTM_LINE2: x[0] = 0.5 * (u + 1) * h; break;
  case DTM_TRI3:
  case DTM_PRISM6:
    x[0] = (u + 0.5 * v) * h, x[1] = 0.5 * s3 * v * h;
    if (parent == DTM_PRISM6) x[2] = 0.5 * (w + 1) * h;
    break;
  case DTM_QUAD4:
  case DTM_HEX8:
    x[0] = 0.5 * (u + 1) * h, x[1] = 0.5 * (v + 1) * h;
    if (parent == DTM_HEX8) x[2] = 0.5 * (w + 1) * h;
    break;
  case DTM_TET4:
    x[0] = (u + 0.5 * v + 0.5 * w) * h, x[1] = (0.5 * s3 * v + s3 / 6 * w) * h, x[2] = sqrt(2.0 / 3.0) * w * h;
    break;
  case DTM_PYR5: x[0] = 0.5 * u * h, x[1] = 0.5 * v * h, x[2] = w * h / sqrt(2.0); break;
  default: break;
  }
}

int dtm_elem_regular(int type, double h, double *x) {
  int d, nn;
  DTM_CHECK(dtm_elem_info(type, &d, &nn));
  int parent = dtm_elem_parent(type);
  for (int a = 0; a < nn; a++) {
    double p[3];
    dtm_ref_node_uvw(type, a, p);
    map_node(parent, h, p, x + 3 * a);
  }
  return DTM_OK;
}
