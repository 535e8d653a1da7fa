/* dtm_operator_apply on single elements of every supported type, against
 * the element matrices assembled in the test from K e_j (unit vectors):
 * symmetry, rigid-body modes (translations, infinitesimal rotations) and
 * constants in the null space, the exact energy of linear fields
 * (u = H x: u^T K u = V (lam tr(H)^2 + 2 mu |sym H|^2); phi = g.x:
 * phi^T K phi = k V |g|^2, since every type reproduces linear fields and
 * the full rules integrate det J exactly), the kernels' own element
 * matrices (kernel/assemble.h, 3D) and element eigenvalues
 * (dtm_kernel_elastic_lambda, dtm_kernel_diffusion_lambda; 2D elements
 * are given in a plane z = const and clockwise, so the operator's
 * orientation handling is exercised), the lumped diagonal, and the input
 * checks of dtm_operator_create. The whole group runs three times: the
 * operator keeping each element's points, keeping its element matrix
 * wherever it may (solid 3D types but the linear tet), and choosing
 * (dtm_operator_store); test_stored_matrices compares the two ways
 * directly.
 * Tolerances: 1e-12 of max |K_ij| for symmetry and for the agreement with
 * the kernels' matrices (both are sums of a few dozen O(max|K|) products
 * per entry); 1e-10 relative for rigid modes, as asked (the actual
 * residuals are ~1e-15, rounding of entries of size max|K| that cancel);
 * 1e-12 relative for linear-field energies and masses (exact quadrature,
 * a few dozen roundings); 1e-10 relative for the element eigenvalues
 * (Jacobi on both sides, but the kernels work in the element's own frame
 * and on simplices through a closed form). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/operator.h"
#include "assemble-impl.h"
#include "kernel-impl.h"
#include "spectral.h"

#define MAXN (3 * DTM_K_NODES) /* most unknowns of one element */

static const double E = 70e9, NU = 0.33, RHO = 2700;

static void near(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s: got %.17g, want %.17g (rel %.3g, tol %g)", what, got, want, (got - want) / want, rel);
}

/* Node coordinates (Gmsh order) of one element per type. */
static const double tet4[] = {0, 0, 0, 1, 0.1, 0.05, 0.2, 0.9, 0.1, 0.1, 0.3, 1.1};
static const double hex8[] = {0.05, -0.1, 0.02, 1.1,  0.05,  -0.05, 0.95, 1.12, 0.1, -0.08, 0.9,  0.0,
                              0.0,  0.1,  1.05, 1.15, -0.05, 0.92,  1.0,  0.96, 1.1, 0.1,   1.05, 0.97};
static const double prism6[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.05, 0.02, 1, 1.1, 0, 0.9, 0, 1.05, 1.1};
static const double pyr5[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0.1, 0.2, 1.2};
static const double tri3[] = {0, 0, 0.5, 0, 1, 0.5, 1, 0.2, 0.5};           /* clockwise */
static const double quad4[] = {0, 0, -2, 0, 1, -2, 1.2, 1.1, -2, 1, 0, -2}; /* clockwise */
static const double line2[] = {0.3, 0, 0, -0.2, 0, 0};                      /* reversed */

typedef struct {
  int type, dim, nn;
  const double *x;
} shape;

static const shape shapes[] = {
    {DTM_TET4, 3, 4, tet4}, {DTM_HEX8, 3, 8, hex8},   {DTM_PRISM6, 3, 6, prism6}, {DTM_PYR5, 3, 5, pyr5},
    {DTM_TRI3, 2, 3, tri3}, {DTM_QUAD4, 2, 4, quad4}, {DTM_LINE2, 1, 2, line2},
};

/* A mesh of one element (shifted by (1, 2, 3) in 3D). */
typedef struct {
  dtm_mesh m;
  dtm_block b;
  double xyz[3 * DTM_K_NODES];
  size_t conn[DTM_K_NODES], tag;
  int mat;
} one;

static void one_init(one *o, const shape *s) {
  memset(o, 0, sizeof *o);
  memcpy(o->xyz, s->x, 3 * (size_t)s->nn * sizeof(double));
  for (int a = 0; a < s->nn; a++) {
    o->conn[a] = (size_t)a;
    for (int i = 0; i < 3 && s->dim == 3; i++) o->xyz[3 * a + i] += i + 1;
  }
  o->tag = 42;
  o->b = (dtm_block){
      .type = s->type, .dim = s->dim, .nn = s->nn, .n = 1, .tags = &o->tag, .conn = o->conn, .mat = &o->mat};
  o->m = (dtm_mesh){.dim = s->dim, .nnodes = (size_t)s->nn, .xyz = o->xyz, .nblocks = 1, .blocks = &o->b};
}

static dtm_operator_coeffs elastic_coeffs(int dim) {
  dtm_operator_coeffs c = {.kind = DTM_OP_ELASTIC, .capacity = RHO};
  int f = dim == 3 ? DTM_FORM_3D : dim == 2 ? DTM_FORM_PLANE_STRAIN : DTM_FORM_BAR;
  assert_int_equal(dtm_elastic_moduli_init(f, E, NU, RHO, &c.mod), DTM_OK);
  return c;
}

static dtm_operator *make(const one *o, const dtm_operator_coeffs *c) {
  dtm_operator *op = NULL;
  dtm_error_clear();
  if (dtm_operator_create(&o->m, c->kind, c, NULL, NULL, 1, &op))
    fail_msg("%s: %s", dtm_elem_name(o->b.type), dtm_error_message());
  return op;
}

/* K[n][n] (row-major) from K e_j; returns max |K_ij|. */
static double assemble(const dtm_operator *op, double *K) {
  size_t n = dtm_operator_ndof(op);
  double e[MAXN] = {0}, col[MAXN], mx = 0;
  for (size_t j = 0; j < n; j++) {
    e[j] = 1;
    dtm_operator_apply(op, e, col);
    e[j] = 0;
    for (size_t i = 0; i < n; i++) K[i * n + j] = col[i], mx = fmax(mx, fabs(col[i]));
  }
  return mx;
}

static double quad_form(size_t n, const double *K, const double *u, double *ku) {
  double s = 0;
  for (size_t i = 0; i < n; i++) {
    ku[i] = 0;
    for (size_t j = 0; j < n; j++) ku[i] += K[i * n + j] * u[j];
    s += u[i] * ku[i];
  }
  return s;
}

static void check_symmetric(size_t n, const double *K, double mx, const char *name) {
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < i; j++)
      if (!(fabs(K[i * n + j] - K[j * n + i]) <= 1e-12 * mx))
        fail_msg("%s: K[%zu][%zu] = %g, K[%zu][%zu] = %g", name, i, j, K[i * n + j], j, i, K[j * n + i]);
}

/* Rigid mode r of a d-dimensional element (translations, then rotations
 * about axis k: u = e_k x (x - x0)). */
static int rigid_mode(const one *o, int d, int r, double *u) {
  int nn = o->b.nn, nrot = d == 3 ? 3 : d == 2 ? 1 : 0;
  if (r >= d + nrot) return 0;
  for (int a = 0; a < nn; a++) {
    const double *x = o->xyz + 3 * a;
    for (int i = 0; i < d; i++) u[a * d + i] = r < d ? (i == r) : 0;
    if (r < d) continue;
    int k = d == 2 ? 2 : r - d; /* axis */
    double w[3] = {0, 0, 0}, p[3] = {x[0] - 0.3, x[1] - 0.2, x[2] - 0.1};
    w[k] = 1;
    double c[3] = {w[1] * p[2] - w[2] * p[1], w[2] * p[0] - w[0] * p[2], w[0] * p[1] - w[1] * p[0]};
    for (int i = 0; i < d; i++) u[a * d + i] = c[i];
  }
  return 1;
}

static void check_rigid(const one *o, int d, size_t n, const double *K, const char *name) {
  double u[MAXN], ku[MAXN], fro = 0;
  for (size_t i = 0; i < n * n; i++) fro += K[i] * K[i];
  for (int r = 0; rigid_mode(o, d, r, u); r++) {
    double nu = 0, nk = 0;
    quad_form(n, K, u, ku);
    for (size_t i = 0; i < n; i++) nu += u[i] * u[i], nk += ku[i] * ku[i];
    if (!(sqrt(nk) <= 1e-10 * sqrt(fro * nu)))
      fail_msg("%s: rigid mode %d: |K r| = %g, |K| |r| = %g", name, r, sqrt(nk), sqrt(fro * nu));
  }
}

/* u = H x: u^T K u = V (lam tr(H)^2 + 2 mu |sym H|^2). */
static void check_linear(const one *o, int d, size_t n, const double *K, const dtm_operator_coeffs *c,
                         const char *name) {
  const double H[3][3] = {{0.3, -0.7, 0.2}, {0.4, 0.1, -0.5}, {0.9, 0.25, -0.35}};
  double u[MAXN], ku[MAXN], tr = 0, ss = 0;
  for (int a = 0; a < o->b.nn; a++)
    for (int i = 0; i < d; i++) {
      u[a * d + i] = 0;
      for (int j = 0; j < d; j++) u[a * d + i] += H[i][j] * o->xyz[3 * a + j];
    }
  for (int i = 0; i < d; i++) {
    tr += H[i][i];
    for (int j = 0; j < d; j++) ss += pow(0.5 * (H[i][j] + H[j][i]), 2);
  }
  double lam = d == 1 ? c->mod.modulus : c->mod.lam, mu = d == 1 ? 0 : c->mod.mu;
  double V = fabs(dtm_elem_measure(o->b.type, o->xyz));
  near(quad_form(n, K, u, ku), V * (lam * tr * tr + 2 * mu * ss), 1e-12, name);
}

/* Largest eigenvalue of M^-1/2 K M^-1/2 from the dense K. */
static double dense_lambda(const dtm_operator *op, size_t n, const double *K) {
  double *A = malloc(n * n * sizeof *A);
  const double *m = dtm_operator_mass(op);
  for (size_t i = 0; i < n; i++)
    for (size_t j = 0; j < n; j++) A[i * n + j] = K[i * n + j] / sqrt(m[i] * m[j]);
  double top = dtm_eig_sym_max((int)n, A);
  free(A);
  return top;
}

static void check_masses(const dtm_operator *op, const one *o, int nc, double cap) {
  double w[DTM_K_NODES], V = fabs(dtm_elem_measure(o->b.type, o->xyz));
  dtm_elem_lumped_weights(o->b.type, o->xyz, w);
  for (int a = 0; a < o->b.nn; a++)
    for (int i = 0; i < nc; i++) near(dtm_operator_mass(op)[a * nc + i], cap * V * w[a], 1e-12, "lumped mass");
}

/* The kernels' own element stiffness, in the element frame (3D only: the
 * frame of a 3D element is the global one). */
static void check_kernel_matrix(const one *o, size_t n, const double *K, double mx, const dtm_operator_coeffs *c) {
  dtm_elem_geom eg;
  double *Kr = malloc(n * n * sizeof *Kr);
  assert_int_equal(dtm_elem_prepare(o->b.type, o->xyz, DTM_INTEGRATION_CONVERGED, &eg), DTM_OK);
  dtm_elem_stiffness(&eg, &c->mod, Kr);
  for (size_t i = 0; i < n * n; i++)
    if (!(fabs(K[i] - Kr[i]) <= 1e-12 * mx))
      fail_msg("%s: K[%zu] = %.17g, kernel %.17g", dtm_elem_name(o->b.type), i, K[i], Kr[i]);
  free(Kr);
}

static void check_elastic(const one *o, int d) {
  const char *name = dtm_elem_name(o->b.type);
  dtm_operator_coeffs c = elastic_coeffs(d);
  dtm_operator *op = make(o, &c);
  size_t n = dtm_operator_ndof(op);
  assert_int_equal(n, (size_t)(o->b.nn * d));
  double *K = malloc(n * n * sizeof *K), lk;
  double mx = assemble(op, K);
  check_symmetric(n, K, mx, name);
  check_rigid(o, d, n, K, name);
  check_linear(o, d, n, K, &c, name);
  check_masses(op, o, d, RHO);
  if (d == 3) check_kernel_matrix(o, n, K, mx, &c);
  assert_int_equal(dtm_kernel_elastic_lambda(o->b.type, &c.mod, o->xyz, &lk), DTM_OK);
  near(dense_lambda(op, n, K), lk, 1e-10, name);
  free(K);
  dtm_operator_destroy(&op);
}

static void test_elastic_elements(void **state) {
  (void)state;
  for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
    one o;
    one_init(&o, &shapes[s]);
    check_elastic(&o, shapes[s].dim);
  }
}

static void check_diffusion(const one *o, int d) {
  const double cap = 2e6, k = 4.5, g[3] = {0.3, -1.2, 0.7};
  const char *name = dtm_elem_name(o->b.type);
  int nn = o->b.nn;
  dtm_operator_coeffs c = {.kind = DTM_OP_DIFFUSION, .capacity = cap, .conductivity = k};
  dtm_operator *op = make(o, &c);
  double K[DTM_K_NODES * DTM_K_NODES], mx = assemble(op, K), one_[DTM_K_NODES] = {0}, phi[DTM_K_NODES] = {0},
                                       kp[DTM_K_NODES] = {0}, g2 = 0, lk;
  check_symmetric((size_t)nn, K, mx, name);
  for (int a = 0; a < nn; a++) {
    one_[a] = 1, phi[a] = 0;
    for (int i = 0; i < d; i++) phi[a] += g[i] * o->xyz[3 * a + i];
  }
  quad_form((size_t)nn, K, one_, kp);
  for (int a = 0; a < nn; a++) assert_true(fabs(kp[a]) <= 1e-13 * mx);
  for (int i = 0; i < d; i++) g2 += g[i] * g[i];
  double V = fabs(dtm_elem_measure(o->b.type, o->xyz));
  near(quad_form((size_t)nn, K, phi, kp), k * V * g2, 1e-12, name);
  check_masses(op, o, 1, cap);
  assert_int_equal(dtm_kernel_diffusion_lambda(o->b.type, k / cap, o->xyz, &lk), DTM_OK);
  near(dense_lambda(op, (size_t)nn, K), lk, 1e-10, name);
  dtm_operator_destroy(&op);
}

static void test_diffusion_elements(void **state) {
  (void)state;
  for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
    one o;
    one_init(&o, &shapes[s]);
    check_diffusion(&o, shapes[s].dim);
  }
}

/* Second-order types, where the kernels support them (Gmsh codes 9 tri6,
 * 11 tet10): straight-sided elements with nodes at the edge midpoints, in
 * the order of the parent's edges (Gmsh's order for these two), through
 * the same checks; then the same elements curved (mid-edge nodes moved
 * by up to 0.06 of the edge), which the kernels and the operator
 * integrate with the same levelled rule (src/kernel/curved.c,
 * src/spectral/parts.c): the element eigenvalue and masses must agree to
 * the same tolerances (the full rules would differ by ~1e-3). */
static void test_second_order(void **state) {
  (void)state;
  static const struct {
    int type, parent;
    size_t shape;
  } t[] = {{9, DTM_TRI3, 4}, {11, DTM_TET4, 0}};
  for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
    int dim, nn;
    dtm_error_clear();
    if (dtm_elem_info(t[i].type, &dim, &nn)) {
      print_message("type %d not supported by the kernels yet: skipped\n", t[i].type);
      continue;
    }
    one o;
    one_init(&o, &shapes[t[i].shape]);
    const dtm_topology *tp = dtm_elem_topology(t[i].parent);
    for (int e = 0; e < tp->nedge; e++)
      for (int c = 0; c < 3; c++)
        o.xyz[3 * (o.b.nn + e) + c] = 0.5 * (o.xyz[3 * tp->edge[e][0] + c] + o.xyz[3 * tp->edge[e][1] + c]);
    assert_int_equal(o.b.nn + tp->nedge, nn);
    for (int a = 0; a < nn; a++) o.conn[a] = (size_t)a;
    o.b.type = t[i].type, o.b.nn = nn, o.m.nnodes = (size_t)nn;
    check_elastic(&o, dim);
    check_diffusion(&o, dim);
    /* curved: the operator integrates it with the kernel's levelled rule */
    for (int a = nn - tp->nedge; a < nn; a++)
      for (int c = 0; c < dim; c++) o.xyz[3 * a + c] += 0.06 * sin(1.7 * a + 2.3 * c);
    check_elastic(&o, dim);
    check_diffusion(&o, dim);
  }
}

/* The "calculix" model on a tet10, straight and curved: the operator
 * integrates it with CalculiX's 4-point rule and lumps it CalculiX's way
 * (src/kernel/lump.c), as the kernel does: its element eigenvalue equals the
 * kernel's to 1e-10 and its masses the model's weights times the 4-point
 * measure to 1e-12; the converged model differs by more than 1e-4 (t117
 * checks the model itself against closed forms). */
static void test_calculix(void **state) {
  (void)state;
  const dtm_topology *tp = dtm_elem_topology(DTM_TET4);
  one o;
  one_init(&o, &shapes[0]);
  for (int e = 0; e < 6; e++)
    for (int c = 0; c < 3; c++)
      o.xyz[3 * (4 + e) + c] = 0.5 * (o.xyz[3 * tp->edge[e][0] + c] + o.xyz[3 * tp->edge[e][1] + c]);
  for (int a = 0; a < 10; a++) o.conn[a] = (size_t)a;
  o.b.type = DTM_TET10, o.b.nn = 10, o.m.nnodes = 10;
  for (int bent = 0; bent < 2; bent++) {
    for (int a = 4; a < 10 && bent; a++)
      for (int c = 0; c < 3; c++) o.xyz[3 * a + c] += 0.06 * sin(1.7 * a + 2.3 * c);
    dtm_operator_coeffs c = elastic_coeffs(3);
    c.mod.integration = DTM_INTEGRATION_CALCULIX;
    dtm_operator *op = make(&o, &c);
    double K[30 * 30], w[10], lk, lc;
    double mx = assemble(op, K), V = dtm_elem_lumped_model(DTM_TET10, o.xyz, DTM_INTEGRATION_CALCULIX, w);
    check_symmetric(30, K, mx, "calculix tet10");
    for (int a = 0; a < 10; a++) near(dtm_operator_mass(op)[3 * a], RHO * V * w[a], 1e-12, "calculix lumped mass");
    assert_int_equal(dtm_kernel_elastic_lambda(DTM_TET10, &c.mod, o.xyz, &lk), DTM_OK);
    near(dense_lambda(op, 30, K), lk, 1e-10, "calculix tet10");
    c.mod.integration = DTM_INTEGRATION_CONVERGED;
    assert_int_equal(dtm_kernel_elastic_lambda(DTM_TET10, &c.mod, o.xyz, &lc), DTM_OK);
    assert_true(fabs(lc - lk) > 1e-4 * lk);
    dtm_operator_destroy(&op);
  }
}

/* Plane stress uses the lam the moduli give it; the bar sigma = E eps. */
static void test_plane_stress(void **state) {
  (void)state;
  one o;
  one_init(&o, &shapes[5]);
  dtm_operator_coeffs c = {.kind = DTM_OP_ELASTIC, .capacity = RHO};
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, E, NU, RHO, &c.mod), 0);
  dtm_operator *op = make(&o, &c);
  double K[64], lk;
  assemble(op, K);
  check_linear(&o, 2, 8, K, &c, "quad4 plane stress");
  check_rigid(&o, 2, 8, K, "quad4 plane stress");
  assert_int_equal(dtm_kernel_elastic_lambda(DTM_QUAD4, &c.mod, o.xyz, &lk), 0);
  near(dense_lambda(op, 8, K), lk, 1e-10, "quad4 plane stress lambda");
  dtm_operator_destroy(&op);
}

/* Membranes: tri3, quad4, tri6 and quad8 turned by the rotation R (rows
 * (2,3,6)/7, (3,-6,2)/7, (6,2,-3)/7, orthonormal in exact rationals) into
 * an oblique plane span 3D, so the operator has 3 unknowns per node and
 * acts in the element's own plane only. Checks: the in-plane linear
 * field u = R H R^T x (H a 2 x 2 field of the plane) has the plane-stress
 * energy t A (lam tr(H)^2 + 2 mu |sym H|^2) (1e-12, exact quadrature);
 * an out-of-plane field u = n phi(x) costs nothing (no stiffness across a
 * membrane: 1e-12 of max |K|); the six rigid modes of 3D are in the null
 * space (1e-10, as above); and the top eigenvalue equals the same element
 * in the xy plane (2 unknowns) and the kernel's element eigenvalue on the
 * turned element (1e-10, as for the eigenvalues above). The thickness
 * (section_factor) scales K and M alike. */
static const double R[3][3] = {{2.0 / 7, 3.0 / 7, 6.0 / 7}, {3.0 / 7, -6.0 / 7, 2.0 / 7}, {6.0 / 7, 2.0 / 7, -3.0 / 7}};

static void turn(one *o) {
  for (int a = 0; a < o->b.nn; a++) {
    double p[3] = {o->xyz[3 * a], o->xyz[3 * a + 1], 0}, q[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) q[i] += R[j][i] * p[j]; /* x = R^T p: the plane's axes are R's first two rows */
    for (int i = 0; i < 3; i++) o->xyz[3 * a + i] = q[i] + 0.1 * (i + 1);
  }
  o->m.dim = 2;
}

static void membrane_energy(const one *o, size_t n, const double *K, const dtm_operator_coeffs *c, double t) {
  const double H[2][2] = {{0.3, -0.7}, {0.4, 0.1}};
  double u[MAXN], ku[MAXN], mx = 0;
  for (int a = 0; a < o->b.nn; a++) {
    const double *x = o->xyz + 3 * a;
    double p[2] = {0, 0}, v[2];
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 3; j++) p[i] += R[i][j] * x[j];
    for (int i = 0; i < 2; i++) v[i] = H[i][0] * p[0] + H[i][1] * p[1];
    for (int i = 0; i < 3; i++) u[3 * a + i] = R[0][i] * v[0] + R[1][i] * v[1];
  }
  double tr = H[0][0] + H[1][1], ss = H[0][0] * H[0][0] + H[1][1] * H[1][1] + 0.5 * pow(H[0][1] + H[1][0], 2);
  double A = fabs(dtm_elem_measure(o->b.type, o->xyz));
  near(quad_form(n, K, u, ku), t * A * (c->mod.lam * tr * tr + 2 * c->mod.mu * ss), 1e-12, "membrane energy");
  for (size_t i = 0; i < n * n; i++) mx = fmax(mx, fabs(K[i]));
  for (int a = 0; a < o->b.nn; a++)
    for (int i = 0; i < 3; i++) u[3 * a + i] = R[2][i] * sin(3.0 * a + 1);
  quad_form(n, K, u, ku);
  for (size_t i = 0; i < n; i++)
    if (!(fabs(ku[i]) <= 1e-12 * mx)) fail_msg("membrane: out-of-plane force %g (max |K| %g)", ku[i], mx);
}

static void test_membranes_in_space(void **state) {
  (void)state;
  static const double tri6[] = {0, 0, 0, 1, 0.1, 0, 0.2, 0.9, 0, 0.5, 0.02, 0, 0.62, 0.52, 0, 0.08, 0.45, 0};
  static const double quad8[] = {0,   0,    0, 1,    0,    0, 1.1,  0.9,  0, 0,    1,   0,
                                 0.5, 0.03, 0, 1.04, 0.45, 0, 0.55, 0.97, 0, 0.02, 0.5, 0};
  const shape planar[] = {
      {DTM_TRI3, 2, 3, tri3}, {DTM_QUAD4, 2, 4, quad4}, {DTM_TRI6, 2, 6, tri6}, {DTM_QUAD8, 2, 8, quad8}};
  dtm_operator_coeffs c = {.kind = DTM_OP_ELASTIC, .capacity = RHO, .section_factor = 0.01};
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, E, NU, RHO, &c.mod), 0);
  for (int s = 0; s < 4; s++) {
    one o;
    double K[MAXN * MAXN], K2[MAXN * MAXN], lk;
    one_init(&o, &planar[s]);
    for (int a = 0; a < o.b.nn; a++) o.xyz[3 * a + 2] = 0;
    dtm_operator *flat = make(&o, &c);
    size_t n2 = dtm_operator_ndof(flat);
    assemble(flat, K2);
    double top2 = dense_lambda(flat, n2, K2);
    dtm_operator_destroy(&flat);
    turn(&o);
    dtm_operator *op = make(&o, &c);
    assert_int_equal(dtm_operator_ncomp(op), 3);
    size_t n = dtm_operator_ndof(op);
    double mx = assemble(op, K);
    check_symmetric(n, K, mx, dtm_elem_name(o.b.type));
    check_rigid(&o, 3, n, K, dtm_elem_name(o.b.type));
    membrane_energy(&o, n, K, &c, 0.01);
    check_masses(op, &o, 3, RHO * 0.01);
    near(dense_lambda(op, n, K), top2, 1e-10, "membrane lambda, turned vs flat");
    assert_int_equal(dtm_kernel_elastic_lambda(o.b.type, &c.mod, o.xyz, &lk), 0);
    near(dense_lambda(op, n, K), lk, 1e-10, "membrane lambda, operator vs kernel");
    dtm_operator_destroy(&op);
  }
}

static void expect_error(const one *o, const dtm_operator_coeffs *c, const char *text) {
  dtm_operator *op = NULL;
  dtm_error_clear();
  assert_int_equal(dtm_operator_create(&o->m, c->kind, c, NULL, NULL, 1, &op), DTM_ERR_INPUT);
  assert_null(op);
  if (!strstr(dtm_error_message(), text)) fail_msg("message '%s' lacks '%s'", dtm_error_message(), text);
}

static void test_errors(void **state) {
  (void)state;
  one o;
  one_init(&o, &shapes[4]); /* tri3 in z = 0.5 */
  dtm_operator_coeffs c2 = elastic_coeffs(2), c3 = elastic_coeffs(3);
  o.xyz[3 * 2 + 2] = 0.5 + 1e-12; /* rounding-level tilt: still a 2D mesh */
  dtm_operator *op = make(&o, &c2);
  assert_int_equal(dtm_operator_ncomp(op), 2);
  dtm_operator_destroy(&op);
  one_init(&o, &shapes[0]);
  o.conn[0] = 1, o.conn[1] = 0; /* inverted tet */
  expect_error(&o, &c3, "element 42 (tet4)");
  one_init(&o, &shapes[0]);
  memcpy(o.xyz + 9, o.xyz + 6, 3 * sizeof(double)); /* flat */
  expect_error(&o, &c3, "degenerate");
  one_init(&o, &shapes[1]);
  /* fold the hex: move a top node below the bottom face */
  o.xyz[3 * 6 + 2] = -3;
  expect_error(&o, &c3, "element 42 (hex8)");
  one_init(&o, &shapes[0]);
  o.b.type = 99; /* no such Gmsh type */
  expect_error(&o, &c3, "type 99");
  one_init(&o, &shapes[0]);
  for (int a = 0; a < 4; a++) o.xyz[3 * a + 2] = 0;
  o.m.dim = 2, o.b.dim = 2; /* a 3D type in a 2D mesh */
  expect_error(&o, &c2, "tet4");
  dtm_error_clear();
}

/* K (elastic or diffusion) and the damping product of one element with
 * Rayleigh beta, the operator keeping points (dtm_operator_store 0) or the
 * element matrix (2): kdense[n][n] from K e_j and damp = C u for a fixed u;
 * returns how many elements the operator stored. */
static size_t matrices(const one *o, const dtm_operator_coeffs *c, int store, double *kdense, double *damp) {
  double beta = 3e-7, e[MAXN] = {0}, col[MAXN];
  dtm_operator *op = NULL;
  dtm_operator_store = store;
  dtm_error_clear();
  if (dtm_operator_create(&o->m, c->kind, c, NULL, &beta, 1, &op))
    fail_msg("%s: %s", dtm_elem_name(o->b.type), dtm_error_message());
  dtm_operator_store = 1;
  size_t n = dtm_operator_ndof(op), stored = dtm_operator_stored(op);
  for (size_t j = 0; j < n; j++) {
    e[j] = 1;
    dtm_operator_apply(op, e, col);
    e[j] = sin(0.7 * (double)j + 0.2);
    for (size_t i = 0; i < n; i++) kdense[i * n + j] = col[i];
  }
  dtm_operator_apply_damping(op, e, damp);
  dtm_operator_destroy(&op);
  return stored;
}

/* The two ways of the operator on one element: the same K and damping
 * product to 1e-12 of max |K| (each entry is the same integral over the
 * same rule points, summed in another order: a few hundred roundings of
 * terms below max |K|), the damping product beta K u (|u_j| <= 1) to the
 * same relative tolerance of its bound beta n max |K|; the one with points
 * stores nothing, the other one element. */
static void check_stored(const one *o, const dtm_operator_coeffs *c, const char *what) {
  size_t n = (size_t)o->b.nn * (c->kind == DTM_OP_ELASTIC ? 3 : 1);
  double *kp = malloc(n * n * sizeof *kp), *ks = malloc(n * n * sizeof *ks), dp[MAXN], ds[MAXN], mx = 0;
  assert_int_equal(matrices(o, c, 0, kp, dp), 0);
  assert_int_equal(matrices(o, c, 2, ks, ds), 1);
  for (size_t i = 0; i < n * n; i++) mx = fmax(mx, fabs(kp[i]));
  for (size_t i = 0; i < n * n; i++)
    if (!(fabs(ks[i] - kp[i]) <= 1e-12 * mx))
      fail_msg("%s: K[%zu] = %.17g stored, %.17g from points", what, i, ks[i], kp[i]);
  for (size_t i = 0; i < n; i++)
    if (!(fabs(ds[i] - dp[i]) <= 1e-12 * 3e-7 * mx * (double)n))
      fail_msg("%s: damping product [%zu] = %.17g stored, %.17g from points", what, i, ds[i], dp[i]);
  free(kp), free(ks);
}

/* The tet4 of the shapes above as a straight-sided tet10 (mid-edge nodes
 * at the middles, in Gmsh's order of the edges). */
static void straight_tet10(one *o) {
  one_init(o, &shapes[0]);
  const dtm_topology *tp = dtm_elem_topology(DTM_TET4);
  for (int e = 0; e < tp->nedge; e++)
    for (int c = 0; c < 3; c++)
      o->xyz[3 * (4 + e) + c] = 0.5 * (o->xyz[3 * tp->edge[e][0] + c] + o->xyz[3 * tp->edge[e][1] + c]);
  for (int a = 0; a < 10; a++) o->conn[a] = (size_t)a;
  o->b.type = DTM_TET10, o->b.nn = 10, o->m.nnodes = 10;
}

/* Element matrices kept instead of points (issue 46: the curved parts of
 * the global estimate): every solid 3D type of the shapes above, a
 * straight and a strongly curved tet10, elastic and diffusion; the curved
 * tet10 settles at a level whose points (10 doubles each) take more memory
 * than its packed matrix (465), so the default keeps its matrix, and the
 * straight one (14 points) its points. */
static void test_stored_matrices(void **state) {
  (void)state;
  dtm_operator_coeffs ce = elastic_coeffs(3), cd = {.kind = DTM_OP_DIFFUSION, .capacity = 2e6, .conductivity = 4.5};
  for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
    if (shapes[s].dim != 3 || shapes[s].type == DTM_TET4) continue; /* linear simplices keep one point */
    one o;
    one_init(&o, &shapes[s]);
    check_stored(&o, &ce, dtm_elem_name(o.b.type));
    check_stored(&o, &cd, dtm_elem_name(o.b.type));
  }
  one o;
  straight_tet10(&o);
  double kd[30 * 30], dd[30];
  check_stored(&o, &ce, "straight tet10");
  assert_int_equal(matrices(&o, &ce, 1, kd, dd), 0);
  for (int a = 4; a < 10; a++)
    for (int c = 0; c < 3; c++) o.xyz[3 * a + c] += 0.15 * sin(1.7 * a + 2.3 * c);
  check_stored(&o, &ce, "curved tet10");
  check_stored(&o, &cd, "curved tet10, diffusion");
  assert_int_equal(matrices(&o, &ce, 1, kd, dd), 1);
}

/* The rule of a straight-sided tet10 (src/spectral/parts.c): its map is
 * affine, so the operator integrates it with the 4 points of a degree-2
 * rule, exact for its stiffness (the closed forms of test_second_order
 * hold for it, and it equals the kernel's 14-point matrix to 1e-12); with
 * a mid-edge node moved by 1e-12 of its edge (not affine, but straight for
 * the levels: below 1e-9) it takes the full rule's 14 points. */
static void test_affine_rule(void **state) {
  (void)state;
  one o;
  straight_tet10(&o);
  dtm_operator_coeffs c = elastic_coeffs(3);
  dtm_operator *op = make(&o, &c);
  assert_int_equal(dtm_operator_points(op), 4);
  dtm_operator_destroy(&op);
  o.xyz[3 * 4] += 1e-12;
  op = make(&o, &c);
  assert_int_equal(dtm_operator_points(op), 14);
  dtm_operator_destroy(&op);
}

/* The group once with the operator keeping points, once keeping element
 * matrices wherever it may, and once its own way: the closed forms above
 * hold for each. */
static int points_everywhere(void **state) {
  (void)state;
  dtm_operator_store = 0;
  return 0;
}

static int matrices_everywhere(void **state) {
  (void)state;
  dtm_operator_store = 2;
  return 0;
}

static int own_choice(void **state) {
  (void)state;
  dtm_operator_store = 1;
  return 0;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_elastic_elements),   cmocka_unit_test(test_diffusion_elements),
      cmocka_unit_test(test_second_order),       cmocka_unit_test(test_calculix),
      cmocka_unit_test(test_plane_stress),       cmocka_unit_test(test_errors),
      cmocka_unit_test(test_membranes_in_space),
  };
  const struct CMUnitTest stored[] = {cmocka_unit_test(test_stored_matrices), cmocka_unit_test(test_affine_rule)};
  int r = cmocka_run_group_tests_name("points", tests, points_everywhere, own_choice);
  r += cmocka_run_group_tests_name("element matrices", tests, matrices_everywhere, own_choice);
  r += cmocka_run_group_tests_name("the operator's choice", tests, own_choice, own_choice);
  return r + cmocka_run_group_tests_name("both ways", stored, own_choice, own_choice);
}
