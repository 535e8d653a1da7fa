/* The element's own frame. Every element is moved so that node 0 is the
 * origin, which keeps the Jacobian accurate far from the mesh origin. 2D
 * elements may lie in any plane of space and 1D elements along any line,
 * so before any integration their nodes are expressed in an orthonormal
 * frame of that plane or line. The plane of a 2D element is the one normal
 * to the Newell vector sum (x_i - x_0) x (x_{i+1} - x_0) over its corner
 * nodes (the first 3 or 4 in Gmsh's order; mid-side nodes do not go round
 * the polygon in sequence, so they are left out): the plane of a flat
 * element, the mean plane of a warped quadrangle. Its first axis is the
 * projected edge 0-1. Every node, mid-side ones included, is then
 * projected on it. The frame's orientation follows the node order,
 * so a 2D element is never "inverted" as a whole: a collinear triangle is
 * degenerate, and a quadrangle whose Jacobian changes sign is caught by
 * dtm_map_first_bad. */
#include <math.h>
#include <string.h>

#include "kernel-impl.h"

static int unit(double *a) {
  double n = sqrt(dtm_v3_dot(a, a));
  if (!(n > 0) || !isfinite(n)) return -1;
  for (int i = 0; i < 3; i++) a[i] /= n;
  return 0;
}

static int frame1(const double *x, double (*xl)[3]) {
  double t[3];
  dtm_v3_sub(x + 3, x, t);
  memset(xl, 0, sizeof(double[2][3]));
  xl[1][0] = sqrt(dtm_v3_dot(t, t));
  return xl[1][0] > 0 && isfinite(xl[1][0]) ? 0 : -1;
}

int dtm_elem_plane_axes(int nc, const double *x, double axes[3][3]) {
  double *n = axes[2], *e1 = axes[0], r[3], s[3], c[3];
  n[0] = n[1] = n[2] = 0;
  for (int a = 1; a + 1 < nc; a++) {
    dtm_v3_sub(x + 3 * a, x, r);
    dtm_v3_sub(x + 3 * (a + 1), x, s);
    dtm_v3_cross(r, s, c);
    for (int i = 0; i < 3; i++) n[i] += c[i];
  }
  if (unit(n)) return -1;
  dtm_v3_sub(x + 3, x, e1);
  double h = dtm_v3_dot(e1, n);
  for (int i = 0; i < 3; i++) e1[i] -= h * n[i];
  if (unit(e1)) return -1;
  dtm_v3_cross(n, e1, axes[1]);
  return 0;
}

static int frame2(int nc, int nn, const double *x, double (*xl)[3]) {
  double ax[3][3], r[3];
  if (dtm_elem_plane_axes(nc, x, ax)) return -1;
  for (int a = 0; a < nn; a++) {
    dtm_v3_sub(x + 3 * a, x, r);
    xl[a][0] = dtm_v3_dot(r, ax[0]), xl[a][1] = dtm_v3_dot(r, ax[1]), xl[a][2] = 0;
  }
  return 0;
}

int dtm_elem_local(int type, const double *x, double (*xl)[3]) {
  int d, nn;
  if (dtm_elem_info(type, &d, &nn)) return -1;
  if (d == 1) return frame1(x, xl);
  if (d == 2) {
    int nc;
    dtm_elem_info(dtm_elem_parent(type), NULL, &nc);
    return frame2(nc, nn, x, xl);
  }
  for (int a = 0; a < nn; a++) dtm_v3_sub(x + 3 * a, x, xl[a]);
  return 0;
}
