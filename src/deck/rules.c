/* The solvers' own element-by-element step rules, as their documents and
 * sources give them, so that a deck can show the solver's estimate beside
 * dtmap's step (and LS-DYNA's TSSFAC can make its estimate equal dtmap's):
 * - LS-DYNA (keyword manual, *CONTROL_TIMESTEP; theory manual, time step
 *   control): solids L/c_d with L the shortest altitude of a tetrahedron
 *   or V/A_max of a hexahedron; shells and 2D solids L_s/c with
 *   L_s = (1 + b) A / max(L_1, L_2, L_3, (1 - b) L_4), b = 1 for
 *   triangles, 0 for quadrangles; beams and trusses L/sqrt(E/rho).
 * - CalculiX 2.20 (calcstabletimeincvol.f): 0.8 (its safety) x the
 *   critical omega dt of the time scheme (1.96 with ALPHA = 0) / 2 x
 *   h x elemfac / c_d, h the smallest over the element's faces of its
 *   volume weight over the face's area, on the solid CalculiX integrates:
 *   a tetrahedron's volume weight is V/3 (the 1-point rule: weight 1/6 x
 *   det J), a hexahedron's 8 det J at its centre, a wedge's V/2; 2D
 *   elements are extruded into wedges and bricks of the section's
 *   thickness t (gen3delem.f), 1D ones into bricks of the section's sides;
 *   elemfac is 0.3 for second order, 0.5 for C3D8R, 0.125 for C3D8I
 *   (beams, trusses, S4 shells), else 1. Face areas are integrated at
 *   their centres, as CalculiX does. A shell's or membrane's layer is
 *   built along the normals CalculiX gives its corners (gen3dnor.f; the
 *   writer computes them), so on a curved shell its faces and volume are
 *   not those of the flat extrusion. */
#include <math.h>
#include <string.h>

#include "deck-impl.h"

double deck_speed_3d(double E, double nu, double rho) { return sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho)); }
double deck_speed_plate(double E, double nu, double rho) { return sqrt(E / (rho * (1 - nu * nu))); }
double deck_speed_bar(double E, double rho) { return sqrt(E / rho); }

static void sub(const double *a, const double *b, double *d) {
  for (int k = 0; k < 3; k++) d[k] = a[k] - b[k];
}

static void cross(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

static double norm(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

static double dist(const double *a, const double *b) {
  double d[3];
  sub(a, b, d);
  return norm(d);
}

/* Area of the triangle p, q, r. */
static double tri_area(const double *p, const double *q, const double *r) {
  double u[3], v[3], n[3];
  sub(q, p, u), sub(r, p, v), cross(u, v, n);
  return 0.5 * norm(n);
}

/* Area of the bilinear quadrangle p0..p3 at its centre (4 |x_xi x x_eta|):
 * half the cross product of its diagonals. */
static double quad_area(const double *p0, const double *p1, const double *p2, const double *p3) {
  double d1[3], d2[3], n[3];
  sub(p2, p0, d1), sub(p3, p1, d2), cross(d1, d2, n);
  return 0.5 * norm(n);
}

static double tet_volume(const double *x) {
  double u[3], v[3], w[3], n[3];
  sub(x + 3, x, u), sub(x + 6, x, v), sub(x + 9, x, w), cross(u, v, n);
  return fabs(n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) / 6;
}

static const int tet_faces[4][3] = {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {0, 2, 3}};
static const int hex_faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

static double tet_max_face(const double *x) {
  double mx = 0;
  for (int f = 0; f < 4; f++)
    mx = fmax(mx, tri_area(x + 3 * tet_faces[f][0], x + 3 * tet_faces[f][1], x + 3 * tet_faces[f][2]));
  return mx;
}

static double hex_max_face(const double *x) {
  double mx = 0;
  for (int f = 0; f < 6; f++) {
    const int *q = hex_faces[f];
    mx = fmax(mx, quad_area(x + 3 * q[0], x + 3 * q[1], x + 3 * q[2], x + 3 * q[3]));
  }
  return mx;
}

double deck_tet_min_altitude(const double *x) { return 3 * tet_volume(x) / tet_max_face(x); }

double deck_hex_volume_area(const double *x) { return fabs(dtm_elem_measure(DTM_HEX8, x)) / hex_max_face(x); }

double deck_shell_length(const double *x, int nc) {
  double mx = 0;
  for (int i = 0; i < nc; i++) mx = fmax(mx, dist(x + 3 * i, x + 3 * ((i + 1) % nc)));
  if (nc == 3) return 2 * tri_area(x, x + 3, x + 6) / mx;
  return quad_area(x, x + 3, x + 6, x + 9) / mx;
}

/* 8 det J of a hexahedron at its centre (Gmsh's node order). */
static double hex_centre_volume(const double *x) {
  static const int s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                              {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  double J[3][3] = {{0}};
  for (int a = 0; a < 8; a++)
    for (int i = 0; i < 3; i++)
      for (int k = 0; k < 3; k++) J[i][k] += s[a][i] * x[3 * a + k] / 8;
  double c[3];
  cross(J[1], J[2], c);
  return 8 * fabs(J[0][0] * c[0] + J[0][1] * c[1] + J[0][2] * c[2]);
}

/* Longest side of the first nc corners, in order. */
static double longest_side(const double *x, int nc) {
  double mx = 0;
  for (int i = 0; i < nc; i++) mx = fmax(mx, dist(x + 3 * i, x + 3 * ((i + 1) % nc)));
  return mx;
}

/* The mid-edge node of edge (i, j) of a tet10 in Gmsh's order. */
static int tet10_mid(int i, int j) {
  static const int mid[4][4] = {{-1, 4, 6, 7}, {4, -1, 5, 9}, {6, 5, -1, 8}, {7, 9, 8, -1}};
  return mid[i][j];
}

/* d/dL_k - d/dL_0 of the tet10's map at its centroid (corners drop out:
 * d(L(2L - 1))/dL = 0 at L = 1/4; mid-edge 4 L_i L_j gives L_i + L_j's
 * derivative), into g[3]. */
static void tet10_tangent(const double *x, int k, double *g) {
  static const int ends[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  for (int c = 0; c < 3; c++) g[c] = 0;
  for (int e = 0; e < 6; e++) {
    int d = (ends[e][0] == k) + (ends[e][1] == k) - (ends[e][0] == 0) - (ends[e][1] == 0);
    for (int c = 0; c < 3; c++) g[c] += d * x[3 * (4 + e) + c];
  }
}

/* The area CalculiX gives face (a, b, c) of a tet10: its 6-node triangle
 * at the centroid, 0.5 |x_s x x_t|, x_s = (b - a)/3 + 4/3 (m_bc - m_ca),
 * x_t = (c - a)/3 + 4/3 (m_bc - m_ab). */
static double tet10_face(const double *x, int a, int b, int c) {
  const double *pa = x + 3 * a, *pb = x + 3 * b, *pc = x + 3 * c;
  const double *ab = x + 3 * tet10_mid(a, b), *bc = x + 3 * tet10_mid(b, c), *ca = x + 3 * tet10_mid(c, a);
  double s[3], t[3], n[3];
  for (int k = 0; k < 3; k++)
    s[k] = (pb[k] - pa[k]) / 3 + 4 * (bc[k] - ca[k]) / 3, t[k] = (pc[k] - pa[k]) / 3 + 4 * (bc[k] - ab[k]) / 3;
  cross(s, t, n);
  return 0.5 * norm(n);
}

/* CalculiX's length of a tet10: det J at the centroid / 6 (its 1-point
 * weight) / 3 over the largest face. */
static double tet10_length(const double *x) {
  double g[3][3], c[3], amax = 0;
  for (int k = 1; k <= 3; k++) tet10_tangent(x, k, g[k - 1]);
  cross(g[1], g[2], c);
  for (int f = 0; f < 4; f++) amax = fmax(amax, tet10_face(x, tet_faces[f][0], tet_faces[f][1], tet_faces[f][2]));
  return fabs(g[0][0] * c[0] + g[0][1] * c[1] + g[0][2] * c[2]) / 6 / 3 / amax;
}

double deck_ccx_length(int type, const double *x, double t, double a, double b) {
  int parent = dtm_elem_parent(type);
  if (type == DTM_TET10) return tet10_length(x);
  if (parent == DTM_TET4) return tet_volume(x) / 3 / tet_max_face(x);
  if (parent == DTM_HEX8) return hex_centre_volume(x) / hex_max_face(x);
  if (parent == DTM_LINE2) return fmin(dist(x, x + 3), fmin(a, b));
  if (parent == DTM_TRI3) return fmin(t / 2, tri_area(x, x + 3, x + 6) / (2 * longest_side(x, 3)));
  if (parent == DTM_QUAD4) return fmin(t, quad_area(x, x + 3, x + 6, x + 9) / longest_side(x, 4));
  return NAN;
}

/* The layer CalculiX builds from the nc-corner 2D element x, each corner
 * moved by -t/2 and +t/2 along its normal n[nc][3], into y[2 nc][3]. */
static void expand(const double *x, const double *n, int nc, double t, double *y) {
  for (int a = 0; a < nc; a++)
    for (int k = 0; k < 3; k++)
      y[3 * a + k] = x[3 * a + k] - t / 2 * n[3 * a + k], y[3 * (a + nc) + k] = x[3 * a + k] + t / 2 * n[3 * a + k];
}

/* The wedge y[6][3] (the first triangle at zeta = -1): its volume weight,
 * det J at (1/3, 1/3, 0) / 2 (shape6w, weight 1), over its largest face,
 * the triangles' areas and the quadrangles' at their centres. */
static double wedge_length(const double *y) {
  double xs[3], xe[3], xz[3] = {0, 0, 0}, c[3], amax;
  for (int k = 0; k < 3; k++) {
    xs[k] = (y[3 + k] + y[12 + k] - y[k] - y[9 + k]) / 2, xe[k] = (y[6 + k] + y[15 + k] - y[k] - y[9 + k]) / 2;
    for (int a = 0; a < 3; a++) xz[k] += (y[3 * (a + 3) + k] - y[3 * a + k]) / 6;
  }
  cross(xs, xe, c);
  amax = fmax(tri_area(y, y + 3, y + 6), tri_area(y + 9, y + 12, y + 15));
  for (int i = 0; i < 3; i++) {
    int j = (i + 1) % 3;
    amax = fmax(amax, quad_area(y + 3 * i, y + 3 * j, y + 3 * (j + 3), y + 3 * (i + 3)));
  }
  return fabs(c[0] * xz[0] + c[1] * xz[1] + c[2] * xz[2]) / 2 / amax;
}

double deck_ccx_layer_length(int type, const double *x, const double *n, double t) {
  double y[24];
  int nc = dtm_elem_parent(type) == DTM_TRI3 ? 3 : 4;
  expand(x, n, nc, t, y);
  return nc == 3 ? wedge_length(y) : hex_centre_volume(y) / hex_max_face(y);
}

double deck_ccx_elemfac(const char *elem) {
  static const struct {
    const char *elem; /* CalculiX's element (as the deck names it) */
    double fac;       /* elemfac of the solid it becomes */
  } facs[] = {{"C3D10", 0.3}, {"C3D8R", 0.5}, {"CPE4R", 0.5},  {"CPS4R", 0.5}, {"S4R", 0.5},  {"M3D4R", 0.5},
              {"S4", 0.125},  {"B31", 0.125}, {"T3D2", 0.125}, {"CPE6", 0.3},  {"CPS6", 0.3}, {"S6", 0.3},
              {"M3D6", 0.3},  {"CPE8", 0.3},  {"CPS8", 0.3},   {"C3D20", 0.3}};
  for (size_t i = 0; i < sizeof facs / sizeof *facs; i++)
    if (!strcmp(elem, facs[i].elem)) return facs[i].fac;
  return 1.0;
}
