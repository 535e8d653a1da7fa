/* The Bloch analysis of src/cost/dispersion.c against closed forms.
 * - Bar (linear, lumped): omega_h h / c = 2 sin(k h / 2), so the
 *   semi-discrete error is sin(kh/2)/(kh/2) - 1, and with central
 *   differences sin(omega dt/2) = (c dt/h) sin(kh/2): at Courant number 1
 *   the two cancel exactly. Round-off only: 1e-12.
 * - Along a lattice axis every linear element type (quad4, hex8, tri3 cut
 *   along a diagonal, tet4 cut around the body diagonal) has the bar's
 *   relation for both branches: P with c_P, S with c_S (the stiffness of a
 *   wave uniform across the axis reduces to the 1D three-point stencil, and
 *   the lumped mass per node is the cell's). Jacobi round-off: 1e-10. The
 *   same for one polarisation at a time (dtm_dispersion_polarised).
 * - Every type converges to the exact speed: |err(kh/2)| < |err(kh)| / 3
 *   for kh = 0.4 (second order or better; tri6 S: 3.48), and the error at 10 cells per
 *   wavelength is below 5 % (lumped mass lags; tri3 is stiff in shear and
 *   leads by 4 % off the axes).
 * - The table interpolates err/(kh)^2, so at a point between its nodes it
 *   agrees with a direct evaluation to 2 % of the error.
 * - Bad arguments and unsupported types fail with DTM_ERR_INPUT (the
 *   measures skip such elements: t705 runs prisms and pyramids).
 * - The regular lattice: its tri3 cell holds equilateral triangles, so its
 *   table repeats every 60 degrees (8 of its 24 directions) to round-off,
 *   which the right-angled cell's does not (1e-9 of err / (k h)^2).
 * - Own shapes, normalised: along the long axis of 1 x 2 rectangles and
 *   1 x 1 x 2 boxes the table is the bar's relation at the long spacing
 *   over the lattice spacing V^(1/d), P and S (1e-10).
 * - Own shapes (src/cost/shapes.c): one tri3 with its point reflection
 *   tiles the plane, so a table built from the two right triangles of the
 *   cube lattice's cell, from their translates and scaled copies, or from
 *   one of them alone is the cube lattice's table, and one equilateral
 *   triangle (turned as the lattice's) gives the regular lattice's; the unit square and cube give the quad4
 *   and hex8 lattices' (one node class: the plane wave's Rayleigh quotient is the
 *   Bloch eigenvalue). Jacobi round-off: 1e-9 of err / (k h)^2. One
 *   element's dynamic matrix at small k is its area times the continuum's
 *   Christoffel matrix (lam + mu) k k^T + mu k^2 I to O(k^4): 1e-6 at
 *   k h = 1e-3 relative to the matrix. Unsupported types fail. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/mesh.h"

static const double ex[3] = {1, 0, 0};

static void bar_closed_form(void **state) {
  (void)state;
  for (double kh = 0.1; kh < 3.1; kh += 0.3) {
    double err[2];
    assert_int_equal(dtm_dispersion_space(DTM_LINE2, DTM_LATTICE_CUBE, 0, kh, ex, err), DTM_OK);
    double exact = sin(kh / 2) / (kh / 2) - 1;
    assert_true(fabs(err[0] - exact) < 1e-12);
    for (double cr = 0.2; cr <= 1.0; cr += 0.2) {
      /* x = omega_h dt / 2 = cr sin(kh/2); the closed form omega = (2/dt) asin(x) */
      double x = cr * sin(kh / 2), ref = 2 * asin(x) / (cr * kh) - 1;
      assert_true(fabs(dtm_dispersion_time(err[0], x) - ref) < 1e-12);
    }
    assert_true(fabs(dtm_dispersion_time(err[0], sin(kh / 2))) < 1e-12); /* Courant 1: exact */
  }
  assert_true(isnan(dtm_dispersion_time(0, 1.01)));
}

static void axis_is_bar(void **state) {
  (void)state;
  const int types[] = {DTM_QUAD4, DTM_HEX8, DTM_TRI3, DTM_TET4};
  const double r = 0.25 * 0.5 / 0.75; /* nu = 0.25 in 3D: mu / (lam + 2 mu) = 1/3 */
  for (int t = 0; t < 4; t++)
    for (double kh = 0.2; kh < 3.0; kh += 0.7) {
      double err[2], bar = sin(kh / 2) / (kh / 2) - 1;
      assert_int_equal(dtm_dispersion_space(types[t], DTM_LATTICE_CUBE, r, kh, ex, err), DTM_OK);
      if (fabs(err[0] - bar) > 1e-10 || fabs(err[1] - bar) > 1e-10)
        fail_msg("%s kh %g: P %.12g S %.12g bar %.12g", dtm_elem_name(types[t]), kh, err[0], err[1], bar);
      /* one polarisation at a time: P along x, S along y */
      double ey[3] = {0, 1, 0}, p, s;
      assert_int_equal(dtm_dispersion_polarised(types[t], DTM_LATTICE_CUBE, r, kh, ex, ex, 0, &p), DTM_OK);
      assert_int_equal(dtm_dispersion_polarised(types[t], DTM_LATTICE_CUBE, r, kh, ex, ey, 1, &s), DTM_OK);
      if (fabs(p - bar) > 1e-10 || fabs(s - bar) > 1e-10)
        fail_msg("%s kh %g polarised: P %.12g S %.12g bar %.12g", dtm_elem_name(types[t]), kh, p, s, bar);
    }
  double e;
  assert_int_equal(dtm_dispersion_polarised(DTM_TRI3, DTM_LATTICE_CUBE, 0, 1, ex, ex, 1, &e),
                   DTM_ERR_INPUT); /* no S at r = 0 */
}

static void converges(void **state) {
  (void)state;
  const int types[] = {DTM_LINE2, DTM_TRI3, DTM_TRI6, DTM_QUAD4, DTM_TET4, DTM_TET10, DTM_HEX8};
  const double n3[3] = {0.6, 0.48, 0.64}, n2[3] = {0.6, 0.8, 0}; /* unit, off the symmetry planes */
  for (int t = 0; t < 7; t++) {
    double e1[2], e2[2], e3[2], r = types[t] == DTM_LINE2 ? 0 : 0.3;
    int d, nn;
    dtm_elem_info(types[t], &d, &nn);
    const double *dir = d == 1 ? ex : d == 2 ? n2 : n3;
    assert_int_equal(dtm_dispersion_space(types[t], DTM_LATTICE_CUBE, r, 0.4, dir, e1), DTM_OK);
    assert_int_equal(dtm_dispersion_space(types[t], DTM_LATTICE_CUBE, r, 0.2, dir, e2), DTM_OK);
    assert_int_equal(dtm_dispersion_space(types[t], DTM_LATTICE_CUBE, r, 2 * 3.14159265358979323846 / 10, dir, e3),
                     DTM_OK);
    for (int m = 0; m < (r > 0 ? 2 : 1); m++) {
      if (!(fabs(e2[m]) < fabs(e1[m]) / 3))
        fail_msg("%s branch %d: err %g at kh 0.4, %g at 0.2", dtm_elem_name(types[t]), m, e1[m], e2[m]);
      if (!(fabs(e3[m]) < 0.05))
        fail_msg("%s branch %d: err %g at 10 per wavelength", dtm_elem_name(types[t]), m, e3[m]);
    }
  }
}

static void table_interpolates(void **state) {
  (void)state;
  dtm_dispersion t;
  assert_int_equal(dtm_dispersion_table(DTM_TRI3, DTM_LATTICE_CUBE, 0.3, &t), DTM_OK);
  assert_int_equal(t.ndir, 24);
  double kh = 0.83, worst = 0;
  for (int i = 0; i < t.ndir; i++) {
    double err[2];
    assert_int_equal(dtm_dispersion_space(DTM_TRI3, DTM_LATTICE_CUBE, 0.3, kh, t.dir[i], err), DTM_OK);
    if (fabs(err[1]) > fabs(worst)) worst = err[1];
  }
  double got = dtm_dispersion_worst(&t, 1, kh, 0);
  assert_true(fabs(got - worst) < 0.02 * fabs(worst));
  assert_true(isnan(dtm_dispersion_worst(&t, 1, 3.2, 0))); /* under 2 cells per wavelength */
}

/* The largest difference between two tables' entries relative to the largest entry. */
static double table_diff(const dtm_dispersion *a, const dtm_dispersion *b) {
  double d = 0, big = 0;
  for (int m = 0; m < 2; m++)
    for (int i = 0; i < a->ndir; i++)
      for (int j = 0; j < DTM_DISP_KH; j++)
        d = fmax(d, fabs(a->g[m][i][j] - b->g[m][i][j])), big = fmax(big, fabs(a->g[m][i][j]));
  return d / big;
}

static void regular_is_hexagonal(void **state) {
  (void)state;
  dtm_dispersion t[2];
  double asym[2] = {0};
  for (int shape = 0; shape < 2; shape++) {
    assert_int_equal(dtm_dispersion_table(DTM_TRI3, shape, 0.3, &t[shape]), DTM_OK);
    for (int m = 0; m < 2; m++)
      for (int i = 0; i + 8 < t[shape].ndir; i++) /* 8 directions: 60 degrees */
        for (int j = 0; j < DTM_DISP_KH; j++)
          asym[shape] = fmax(asym[shape], fabs(t[shape].g[m][i][j] - t[shape].g[m][i + 8][j]));
  }
  assert_true(asym[DTM_LATTICE_REGULAR] < 1e-9);
  assert_true(asym[DTM_LATTICE_CUBE] > 1e-3);
}

static void own_shapes_are_lattices(void **state) {
  (void)state;
  dtm_dispersion lat, own;
  /* the cube lattice's two right triangles, moved and scaled, and one alone */
  double right[] = {0, 0, 0, 1, 0,       0, 1, 1,    0, /* */ 5, 7,    0,    5, 8,
                    0, 6, 8, 0, /* */ 0, 0, 0, 2e-3, 0, 0,       2e-3, 2e-3, 0};
  assert_int_equal(dtm_dispersion_table(DTM_TRI3, DTM_LATTICE_CUBE, 0.3, &lat), DTM_OK);
  assert_int_equal(dtm_dispersion_table_shapes(DTM_TRI3, 0.3, right, 3, &own), DTM_OK);
  assert_int_equal(own.shape, DTM_LATTICE_OWN);
  assert_int_equal((int)own.samples, 3);
  assert_true(table_diff(&lat, &own) < 1e-9);
  assert_int_equal(dtm_dispersion_table_shapes(DTM_TRI3, 0.3, right + 9, 1, &own), DTM_OK);
  assert_true(table_diff(&lat, &own) < 1e-9);
  /* an equilateral triangle turned as the regular lattice's: an edge at -15 degrees */
  double c15 = cos(3.14159265358979323846 / 12), s15 = sin(3.14159265358979323846 / 12);
  double eq[] = {0, 0, 0, c15, -s15, 0, sqrt(0.5), sqrt(0.5), 0};
  assert_int_equal(dtm_dispersion_table(DTM_TRI3, DTM_LATTICE_REGULAR, 0.3, &lat), DTM_OK);
  assert_int_equal(dtm_dispersion_table_shapes(DTM_TRI3, 0.3, eq, 1, &own), DTM_OK);
  assert_true(table_diff(&lat, &own) < 1e-9);
  double sq[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  assert_int_equal(dtm_dispersion_table(DTM_QUAD4, DTM_LATTICE_CUBE, 0.3, &lat), DTM_OK);
  assert_int_equal(dtm_dispersion_table_shapes(DTM_QUAD4, 0.3, sq, 1, &own), DTM_OK);
  assert_true(table_diff(&lat, &own) < 1e-9);
  double cube[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  assert_int_equal(dtm_dispersion_table(DTM_HEX8, DTM_LATTICE_CUBE, 0.3, &lat), DTM_OK);
  assert_int_equal(dtm_dispersion_table_shapes(DTM_HEX8, 0.3, cube, 1, &own), DTM_OK);
  assert_true(table_diff(&lat, &own) < 1e-9);
}

/* Along the long axis of a lattice of rectangles (1 x 2) or boxes
 * (1 x 1 x 2), the own-shape table has the bar's relation for both
 * branches with the spacing 2 in units of the lattice spacing h = V^(1/d):
 * the table's normalisation of each element to its own h, checked. */
static void long_axis_is_bar(void **state) {
  (void)state;
  double rect[] = {0, 0, 0, 1, 0, 0, 1, 2, 0, 0, 2, 0};
  double box[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 2, 1, 0, 2, 1, 1, 2, 0, 1, 2};
  struct {
    int type, dir; /* the table's direction along the long axis: 90 degrees in 2D, z in 3D */
    double *x, s;  /* nodes; the long spacing over h */
  } c[2] = {{DTM_QUAD4, 12, rect, 2 / sqrt(2.0)}, {DTM_HEX8, 2, box, 2 / cbrt(2.0)}};
  for (int t = 0; t < 2; t++) {
    dtm_dispersion own;
    assert_int_equal(dtm_dispersion_table_shapes(c[t].type, 0.3, c[t].x, 1, &own), DTM_OK);
    assert_true(fabs(own.dir[c[t].dir][t ? 2 : 1] - 1) < 1e-15);
    for (int j = 0; j < DTM_DISP_KH; j++) {
      double kh = 3.14159265358979323846 * (j + 1) / DTM_DISP_KH, ks = kh * c[t].s;
      double bar = sin(ks / 2) / (ks / 2) - 1;
      if (!(ks < 2 * 3.14159265358979323846)) continue; /* past the long spacing's zone */
      for (int m = 0; m < 2; m++)
        if (fabs(own.g[m][c[t].dir][j] * kh * kh - bar) > 1e-10)
          fail_msg("%s kh %g branch %d: %.12g against the bar's %.12g", dtm_elem_name(c[t].type), kh, m,
                   own.g[m][c[t].dir][j] * kh * kh, bar);
    }
  }
}

static void element_is_christoffel(void **state) {
  (void)state;
  double x[] = {0.1, 0.2, 0, 1.3, 0.1, 0, 0.4, 0.9, 0}, lam = 2, mu = 1.5, kk = 1e-3, D[9];
  double n[3] = {0.6, 0.8, 0}, k[3] = {kk * n[0], kk * n[1], 0};
  double area = 0.5 * fabs((x[3] - x[0]) * (x[7] - x[1]) - (x[6] - x[0]) * (x[4] - x[1]));
  assert_int_equal(dtm_dispersion_element(DTM_TRI3, x, lam, mu, k, D), DTM_OK);
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      double c = area * ((lam + mu) * k[i] * k[j] + (i == j) * mu * kk * kk);
      assert_true(fabs(D[3 * i + j] - c) < 1e-6 * area * (lam + 2 * mu) * kk * kk);
    }
  double w[3];
  dtm_dispersion_branches(2, D, n, w); /* P first: (lam + 2 mu) k^2 area */
  assert_true(fabs(w[0] / (area * (lam + 2 * mu) * kk * kk) - 1) < 1e-6);
  assert_true(fabs(w[1] / (area * mu * kk * kk) - 1) < 1e-6);
  assert_int_equal(dtm_dispersion_element(DTM_TET10, x, lam, mu, k, D), DTM_ERR_INPUT); /* mid-edge nodes */
  /* a tetrahedron: its volume times the Christoffel matrix too */
  double xt[] = {0.1, 0.2, 0.05, 1.3, 0.1, 0.2, 0.4, 0.9, 0.1, 0.3, 0.4, 1.1}, k3[3] = {0.48e-3, 0.6e-3, 0.64e-3}, V;
  V = fabs(dtm_elem_measure(DTM_TET4, xt));
  assert_int_equal(dtm_dispersion_element(DTM_TET4, xt, lam, mu, k3, D), DTM_OK);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double c = V * ((lam + mu) * k3[i] * k3[j] + (i == j) * mu * kk * kk);
      assert_true(fabs(D[3 * i + j] - c) < 1e-6 * V * (lam + 2 * mu) * kk * kk);
    }
  assert_int_equal(dtm_dispersion_table_shapes(DTM_TRI3, 0.3, x, 0, NULL), DTM_ERR_INPUT);
  dtm_error_clear();
}

/* A box of n^3 unit cells, each cut into the six tetrahedra of the cube
 * lattice (around its main diagonal, the cells all alike), first or second
 * order (mid-edge nodes on a grid of half the spacing), with node jiggle
 * added to node `moved` (none when negative). */
static dtm_mesh *kuhn_box(int n, int order, long moved, double jiggle) {
  static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  static const int mid[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}}; /* Gmsh's tet10 edge order */
  int g = order * n + 1, nn = order == 1 ? 4 : 10; /* grid points per side at the finest spacing */
  dtm_mesh *m = calloc(1, sizeof *m);
  m->dim = 3, m->nnodes = (size_t)g * g * g, m->nblocks = 1;
  m->xyz = malloc(3 * m->nnodes * sizeof *m->xyz);
  for (size_t a = 0; a < m->nnodes; a++)
    for (int c = 0, r = (int)a; c < 3; c++, r /= g) m->xyz[3 * a + c] = (double)(r % g) / order;
  if (moved >= 0) m->xyz[3 * moved] += jiggle;
  dtm_block *b = m->blocks = calloc(1, sizeof *b);
  b->type = order == 1 ? DTM_TET4 : DTM_TET10, b->dim = 3, b->nn = nn, b->n = (size_t)6 * n * n * n;
  b->conn = malloc(b->n * (size_t)nn * sizeof *b->conn), b->mat = calloc(b->n, sizeof *b->mat);
  size_t e = 0;
  for (int cell = 0; cell < n * n * n; cell++)
    for (int t = 0; t < 6; t++, e++) {
      int v[4][3] = {{cell % n, cell / n % n, cell / n / n}};
      for (int s = 1; s < 4; s++) memcpy(v[s], v[s - 1], sizeof v[s]), v[s][perm[t][s - 1]]++;
      for (int a = 0; a < nn; a++) {
        int p[3];
        for (int c = 0; c < 3; c++)
          p[c] = a < 4 ? order * v[a][c] : v[mid[a - 4][0]][c] + v[mid[a - 4][1]][c]; /* order 2: doubled grid */
        b->conn[e * (size_t)nn + (size_t)a] = (size_t)p[0] + (size_t)g * ((size_t)p[1] + (size_t)g * (size_t)p[2]);
      }
    }
  return m;
}

static void kuhn_free(dtm_mesh *m) {
  free(m->xyz), free(m->blocks->conn), free(m->blocks->mat), free(m->blocks), free(m);
}

/* A structured mesh is recognised and predicted by its own lattice: the
 * box of cube-lattice cells gives that lattice's table (tet4: the plane-wave
 * sums of its node grid; tet10: the Bloch analysis of its cell, eight node
 * classes), to round-off (1e-9 of err / (k h)^2, as above); one node moved
 * by a tenth of a cell breaks it. */
static void structured_is_lattice(void **state) {
  (void)state;
  for (int order = 1; order <= 2; order++) {
    dtm_dispersion lat, mesh;
    int found = 0, type = order == 1 ? DTM_TET4 : DTM_TET10;
    dtm_mesh *m = kuhn_box(3, order, -1, 0);
    assert_int_equal(dtm_dispersion_table(type, DTM_LATTICE_CUBE, 0.3, &lat), DTM_OK);
    assert_int_equal(dtm_dispersion_table_mesh(m, type, 0, 0.3, &mesh, &found), DTM_OK);
    assert_int_equal(found, 1);
    assert_int_equal(mesh.shape, DTM_LATTICE_MESH);
    assert_true(fabs(mesh.per_cell - 6) < 1e-12);
    if (table_diff(&lat, &mesh) > 1e-9) fail_msg("%s: %g", dtm_elem_name(type), table_diff(&lat, &mesh));
    assert_int_equal(dtm_dispersion_table_mesh(m, type, 1, 0.3, &mesh, &found), DTM_OK); /* no element of material 1 */
    assert_int_equal(found, 0);
    kuhn_free(m);
    m = kuhn_box(3, order, order == 1 ? 21 : 3 * 49 + 2 * 7 + 3, 0.1); /* an interior vertex */
    assert_int_equal(dtm_dispersion_table_mesh(m, type, 0, 0.3, &mesh, &found), DTM_OK);
    assert_int_equal(found, 0);
    kuhn_free(m);
  }
}

/* The measured table (src/cost/measured.c) of Gmsh's unstructured
 * tetrahedra: the P wave lags in every direction by close to the same
 * amount (the meshes are isotropic for it: the three classes within 20 %
 * of each other at k h = 1), its error is quadratic at small k h (err /
 * (k h)^2 within 10 % between the first two points), the S wave of tet4
 * stiffens as nu nears 1/2 (it leads at nu = 0.45, lags at 0.3), and
 * outside the measured range of nu the table is the nearest end's. */
static void measured_table(void **state) {
  (void)state;
  const double r03 = 0.4 / 1.4, r045 = 0.1 / 1.1, r049 = 0.02 / 1.02; /* (1 - 2 nu) / (2 (1 - nu)) */
  dtm_dispersion t, t2;
  for (int type = DTM_TET4; type; type = type == DTM_TET4 ? DTM_TET10 : 0) {
    assert_int_equal(dtm_dispersion_table_measured(type, r03, &t), DTM_OK);
    assert_int_equal(t.ndir, 3);
    assert_int_equal(t.shape, DTM_LATTICE_MEASURED);
    assert_true(t.per_cell == 0); /* at the mean edge */
    double p[3];
    for (int i = 0; i < 3; i++) p[i] = dtm_dispersion_at(&t, 0, i, 1.0);
    for (int i = 0; i < 3; i++) {
      if (!(p[i] < 0 && fabs(p[i] / p[0] - 1) < 0.2))
        fail_msg("%s P class %d: %g (axis %g)", dtm_elem_name(type), i, p[i], p[0]);
      if (!(fabs(t.g[0][i][1] / t.g[0][i][0] - 1) < 0.1))
        fail_msg("%s P class %d not quadratic", dtm_elem_name(type), i);
    }
    assert_int_equal(dtm_dispersion_table_measured(type, r045, &t2), DTM_OK);
    assert_int_equal(dtm_dispersion_table_measured(type, r049, &t), DTM_OK);
    assert_true(table_diff(&t, &t2) < 1e-15); /* clamped */
  }
  assert_int_equal(dtm_dispersion_table_measured(DTM_TET4, r045, &t), DTM_OK);
  assert_true(dtm_dispersion_at(&t, 1, 0, 1.0) > 0);
  assert_int_equal(dtm_dispersion_table_measured(DTM_TET4, r03, &t), DTM_OK);
  assert_true(dtm_dispersion_at(&t, 1, 0, 1.0) < 0);
  assert_true(isnan(dtm_dispersion_at(&t, 1, 0, 3.2))); /* under 2 mean edges per wavelength */
  assert_int_equal(dtm_dispersion_table_measured(DTM_HEX8, r03, &t), DTM_ERR_INPUT);
  dtm_error_clear();
}

static void bad_input(void **state) {
  (void)state;
  double err[2];
  assert_int_equal(dtm_dispersion_space(DTM_TRI3, DTM_LATTICE_CUBE, 0.3, 0, ex, err), DTM_ERR_INPUT);
  assert_int_equal(dtm_dispersion_space(DTM_TRI3, DTM_LATTICE_CUBE, -1, 1, ex, err), DTM_ERR_INPUT);
  assert_int_equal(dtm_dispersion_space(DTM_PRISM6, DTM_LATTICE_CUBE, 0.3, 1, ex, err), DTM_ERR_INPUT);
  assert_true(!dtm_dispersion_has_model(DTM_PRISM6) && dtm_dispersion_has_model(DTM_TET10));
  dtm_error_clear();
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(bar_closed_form),
                                     cmocka_unit_test(axis_is_bar),
                                     cmocka_unit_test(converges),
                                     cmocka_unit_test(table_interpolates),
                                     cmocka_unit_test(regular_is_hexagonal),
                                     cmocka_unit_test(own_shapes_are_lattices),
                                     cmocka_unit_test(long_axis_is_bar),
                                     cmocka_unit_test(element_is_christoffel),
                                     cmocka_unit_test(structured_is_lattice),
                                     cmocka_unit_test(measured_table),
                                     cmocka_unit_test(bad_input)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
