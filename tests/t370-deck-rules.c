/* The solvers' own element rules a deck prints beside dtmap's step
 * (src/deck/rules.c), against closed forms:
 * - LS-DYNA: the shortest altitude of the regular tetrahedron of edge h is
 *   h sqrt(2/3), of the unit right tetrahedron 1/sqrt(3) (to its slanted
 *   face); V/A_max of an a x b x c brick is its smallest side; the shell
 *   length L_s is 2A/L_max = sqrt(3)/2 h on the equilateral triangle and
 *   A/L_max = b on an a x b rectangle (a > b);
 * - CalculiX: V/3 over the largest face, h sqrt(2/3)/9, on the regular
 *   tetrahedron and on the straight tet10 built on it (its det J at the
 *   centroid and 6-node faces); 8 det J over the largest face, the smallest side, on a
 *   brick; the triangle extruded by t, min(t/2, A/(2 L_max)); the
 *   rectangle extruded, min(t, A/L_max); the beam box, min(L, a, b);
 * - the wave speeds at nu = 0.25: c_d^2 = 1.2 E/rho, c_p^2 = E/(0.9375 rho);
 * - numbers written into fixed columns keep the most digits that fit and
 *   read back exactly when all 17 fit.
 * Tolerance 1e-14 relative: a handful of roundings in each formula. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deck-impl.h"

static void near(double got, double want, const char *what) {
  if (!(fabs(got - want) <= 1e-14 * fabs(want))) fail_msg("%s: %.17g, want %.17g", what, got, want);
}

static const double H = 0.37; /* an edge that is not a power of two */

/* The regular tetrahedron of edge H. */
static void regular_tet(double *x) {
  const double v[12] = {0, 0, 0, H, 0, 0, H / 2, H * sqrt(3.0) / 2, 0, H / 2, H * sqrt(3.0) / 6, H * sqrt(2.0 / 3)};
  memcpy(x, v, sizeof v);
}

/* An a x b x c brick in Gmsh's node order. */
static void brick(double a, double b, double c, double *x) {
  const double v[24] = {0, 0, 0, a, 0, 0, a, b, 0, 0, b, 0, 0, 0, c, a, 0, c, a, b, c, 0, b, c};
  memcpy(x, v, sizeof v);
}

static void lsdyna_rules(void **unused) {
  double x[24];
  regular_tet(x);
  near(deck_tet_min_altitude(x), H * sqrt(2.0 / 3), "regular tet altitude");
  const double right[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  near(deck_tet_min_altitude(right), 1 / sqrt(3.0), "right tet altitude");
  brick(0.3, 0.7, 0.2, x);
  near(deck_hex_volume_area(x), 0.2, "brick V/A_max");
  const double tri[9] = {0, 0, 0, H, 0, 0, H / 2, H * sqrt(3.0) / 2, 0};
  near(deck_shell_length(tri, 3), sqrt(3.0) / 2 * H, "equilateral L_s");
  const double rect[12] = {0, 0, 0, 0.5, 0, 0, 0.5, 0.2, 0, 0, 0.2, 0};
  near(deck_shell_length(rect, 4), 0.2, "rectangle L_s");
  (void)unused;
}

static void calculix_rules(void **unused) {
  double x[24];
  regular_tet(x);
  near(deck_ccx_length(DTM_TET4, x, 0, 0, 0), H * sqrt(2.0 / 3) / 9, "tet: V/3 / A_max");
  static const int ends[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}}; /* Gmsh's tet10 edges */
  double x10[30];
  memcpy(x10, x, 12 * sizeof *x);
  for (int e = 0; e < 6; e++)
    for (int k = 0; k < 3; k++) x10[3 * (4 + e) + k] = (x[3 * ends[e][0] + k] + x[3 * ends[e][1] + k]) / 2;
  near(deck_ccx_length(DTM_TET10, x10, 0, 0, 0), H * sqrt(2.0 / 3) / 9, "straight tet10: det J / 18 / A_max");
  brick(0.3, 0.7, 0.2, x);
  near(deck_ccx_length(DTM_HEX8, x, 0, 0, 0), 0.2, "brick: 8 det J / A_max");
  const double tri[9] = {0, 0, 0, H, 0, 0, H / 2, H * sqrt(3.0) / 2, 0};
  near(deck_ccx_length(DTM_TRI3, tri, 1.0, 0, 0), sqrt(3.0) / 8 * H, "thick wedge: A/(2 L_max)");
  near(deck_ccx_length(DTM_TRI3, tri, 0.01, 0, 0), 0.005, "thin wedge: t/2");
  const double rect[12] = {0, 0, 0, 0.5, 0, 0, 0.5, 0.2, 0, 0, 0.2, 0};
  near(deck_ccx_length(DTM_QUAD4, rect, 1.0, 0, 0), 0.2, "thick brick: A/L_max");
  near(deck_ccx_length(DTM_QUAD4, rect, 0.05, 0, 0), 0.05, "thin brick: t");
  const double line[6] = {0, 0, 0, 0.3, 0.4, 0};
  near(deck_ccx_length(DTM_LINE2, line, 0, 0.04, 0.01), 0.01, "beam box: min(L, a, b)");
  near(deck_ccx_length(DTM_LINE2, line, 0, 0.9, 0.8), 0.5, "short beam box: L");
  near(deck_ccx_elemfac("C3D4"), 1.0, "C3D4 elemfac");
  near(deck_ccx_elemfac("C3D10"), 0.3, "C3D10 elemfac");
  near(deck_ccx_elemfac("B31"), 0.125, "B31 (C3D8I) elemfac");
  (void)unused;
}

/* A regular polygon of nc corners about the origin in z = 0 (circumradius
 * r) whose corner normals lean out by theta: n = cos(theta) z + sin(theta)
 * x / r. Its layer's top face is the polygon scaled by 1 + s, s = t
 * sin(theta) / (2 r); each side face is a planar isosceles trapezoid of
 * parallel sides L (1 -+ s) and height sqrt((2 rho s)^2 + (t cos(theta))^2)
 * (rho the inradius); the volume weight is A t cos(theta) / 2 (wedge: det
 * J at the centroid / 2) or A t cos(theta) (brick: 8 det J at the centre),
 * since the normals' mean is cos(theta) z. */
static double leaning(int nc, double t, double theta, double *x, double *n) {
  const double PI = 3.14159265358979323846;
  double r = 0.03, L = 2 * r * sin(PI / nc), rho = r * cos(PI / nc), A = nc * r * rho * sin(PI / nc);
  for (int a = 0; a < nc; a++) {
    double c = cos(2 * PI * a / nc), d = sin(2 * PI * a / nc);
    x[3 * a] = r * c, x[3 * a + 1] = r * d, x[3 * a + 2] = 0;
    n[3 * a] = sin(theta) * c, n[3 * a + 1] = sin(theta) * d, n[3 * a + 2] = cos(theta);
  }
  double s = t * sin(theta) / (2 * r), hs = sqrt(4 * rho * rho * s * s + t * t * cos(theta) * cos(theta));
  double w = A * t * cos(theta) / (nc == 3 ? 2 : 1);
  return w / fmax(A * (1 + s) * (1 + s), L * hs);
}

/* The layers of shells and membranes along their corner normals
 * (deck_ccx_layer_length): with every normal the face's, the flat
 * extrusion of deck_ccx_length; with normals leaning out, the closed form
 * of leaning() on a thin layer (the top face the largest) and a thick one
 * (a side face). */
static void calculix_layers(void **unused) {
  const double tri[9] = {0, 0, 0, H, 0, 0, H / 2, H * sqrt(3.0) / 2, 0};
  const double rect[12] = {0, 0, 0, 0.5, 0, 0, 0.5, 0.2, 0, 0, 0.2, 0};
  const double up[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  near(deck_ccx_layer_length(DTM_TRI3, tri, up, 1.0), sqrt(3.0) / 8 * H, "flat thick wedge");
  near(deck_ccx_layer_length(DTM_TRI3, tri, up, 0.01), 0.005, "flat thin wedge");
  near(deck_ccx_layer_length(DTM_QUAD4, rect, up, 1.0), 0.2, "flat thick brick");
  near(deck_ccx_layer_length(DTM_QUAD4, rect, up, 0.05), 0.05, "flat thin brick");
  double x[12], n[12], want;
  for (int nc = 3; nc <= 4; nc++)
    for (double t = 0.002; t < 0.5; t *= 50) {
      want = leaning(nc, t, 0.2, x, n);
      near(deck_ccx_layer_length(nc == 3 ? DTM_TRI3 : DTM_QUAD4, x, n, t), want,
           nc == 3 ? "leaning wedge" : "leaning brick");
    }
  (void)unused;
}

static void speeds(void **unused) {
  const double E = 60e9, rho = 2700;
  near(deck_speed_3d(E, 0.25, rho), sqrt(1.2 * E / rho), "c_d");
  near(deck_speed_plate(E, 0.25, rho), sqrt(E / (0.9375 * rho)), "c_p");
  near(deck_speed_bar(E, rho), sqrt(E / rho), "c_bar");
  (void)unused;
}

static void numbers(void **unused) {
  const double v[] = {0.1, -1.0 / 3, 2.1e11, 6.02214076e23, -4.4e-8, 7850, 0.0056311600582221472};
  char b[40];
  for (size_t i = 0; i < sizeof v / sizeof *v; i++) {
    deck_number(v[i], 24, b);
    if (strtod(b, NULL) != v[i]) fail_msg("%.17g written in 24 columns as '%s'", v[i], b);
    for (int w = 9; w <= 20; w++) {
      deck_number(v[i], w, b);
      if ((int)strlen(b) > w) fail_msg("%.17g in %d columns: '%s'", v[i], w, b);
      if (fabs(strtod(b, NULL) - v[i]) > 1e-3 * fabs(v[i])) fail_msg("%.17g in %d columns: '%s'", v[i], w, b);
    }
  }
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(lsdyna_rules), cmocka_unit_test(calculix_rules),
                                     cmocka_unit_test(calculix_layers), cmocka_unit_test(speeds),
                                     cmocka_unit_test(numbers)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
