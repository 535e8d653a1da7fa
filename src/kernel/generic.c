/* The generic element bound: assemble the fully integrated element matrix,
 * lump the mass (or capacity) (row sums for linear types, HRZ for
 * second-order ones: lump.c) and take the largest eigenvalue of
 * M^-1/2 K M^-1/2, with the Jacobi solver for the small problems of the
 * linear types and by tridiagonalization (tridiag.c) for the larger ones
 * of second-order types. Works for every supported type; non-simplices
 * and second-order simplices always come here, linear simplices only for
 * cross-checks. No allocation: the element matrix (up to 81 x 81, 52 kB)
 * is on the stack.
 *
 * The fast path (dtm_elastic_lambda_at): the rule is the one the model
 * gives the element (its kept level when the caller knows it, else the
 * level search of curved.c), a straight-sided tri6 or tet10 takes its
 * matrices from reference tensors (affine.c), any other element is
 * integrated in one pass over the rule's table (dtm_elem_assemble: the
 * shape functions evaluated once per process, the Jacobian once per
 * point), and the top of the tridiagonal is found by Laguerre's iteration.
 * The earlier path, which set the element up, checked every point, then
 * summed the stiffness and the masses in separate passes and bisected, is
 * kept as dtm_elastic_lambda_reference and dtm_diffusion_lambda_reference:
 * tests/t521 checks that the two agree to 1e-12 relative.
 *
 * Four tet10 at a time (dtm_elastic_lambda_lanes), each goes into the
 * eigenvalue solver's packed lanes as its scaled matrix is formed: a
 * straight one from the reference tensors, a curved one from its Gram
 * tensor (what its level search left in the memo), with no 30 x 30
 * matrix, no second scaling pass and no packing between. The entries and
 * their order are those of the general path, which still takes any other
 * group (other types, an element refused), so the bits are the same
 * (tests/t951). */
#include <math.h>

#include "dtmap/error.h"
#include "assemble-impl.h"
#include "kernel-impl.h"

/* K = M^-1/2 K M^-1/2 in place, m the masses of the n / per nodes. */
static int lumped_scale(int n, int per, double *K, const double *m) {
  double r[DTM_K_DOF];
  for (int k = 0; k < n; k++) {
    if (!(m[k / per] > 0))
      return DTM_ERR(DTM_ERR_INPUT, "degenerate element: lumped mass of node %d is %g", k / per, m[k / per]);
    r[k] = 1 / sqrt(m[k / per]);
  }
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) K[i * n + j] *= r[i] * r[j];
  return DTM_OK;
}

static int lumped_eig_max(int n, int per, double *K, const double *m, double *lambda, int reference) {
  DTM_CHECK(lumped_scale(n, per, K, m));
  /* Jacobi for the small linear problems (up to quad4's 8 unknowns),
   * tridiagonalization for the rest (pyr5 15, prism6 18, hex8 24, and the
   * second-order types up to 81), where it is several times faster: hex8
   * went from about 230 us to tens of us; both are backward stable. */
  *lambda = n <= 12     ? dtm_eig_sym_max(n, K)
            : reference ? dtm_eig_sym_max_tridiag_bisect(n, K)
                        : dtm_eig_sym_max_tridiag(n, K);
  return DTM_OK;
}

int dtm_lumped_eig_max(int type, int n, int per, double *K, const double *m, double *lambda) {
  (void)type;
  return lumped_eig_max(n, per, K, m, lambda, 0);
}

/* The rule id (dtm_ref_rule_id) of the element in its frame: from its
 * kept level when level >= 0, else by the level search. */
static int rule_of(int type, int d, int nn, const double (*xl)[3], int model, int level) {
  if (level >= 0) return dtm_ref_rule_id(type, model, level);
  return dtm_elem_rule_choose(type, d, nn, xl, model, NULL, NULL);
}

/* K and the masses per unit density of the element with coordinates x
 * (moduli m, NULL: the Laplacian) in the model's rule; *d and *nn its
 * dimension and node count. */
static int matrices(int type, const double *x, int model, int level, const dtm_elastic_moduli *m, int *d, int *nn,
                    double *K, double *mass) {
  double xl[DTM_K_NODES][3], dj;
  DTM_CHECK(dtm_elem_info(type, d, nn));
  if (dtm_elem_local(type, x, xl))
    return DTM_ERR(DTM_ERR_INPUT, "degenerate or inverted %s element: its nodes span no %s", dtm_elem_name(type),
                   *d == 1 ? "line" : "plane");
  int id = rule_of(type, *d, *nn, (const double(*)[3])xl, model, level);
  if (id == 0 && dtm_affine_matrices(type, *d, *nn, (const double(*)[3])xl, m, K, mass)) return DTM_OK;
  const dtm_ref_table *t = dtm_ref_rule_table(type, id);
  if (!t) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int bad = dtm_elem_assemble(type, *d, *nn, (const double(*)[3])xl, t, m, K, mass, &dj);
  if (bad >= 0)
    return DTM_ERR(DTM_ERR_INPUT, "degenerate or inverted %s element: Jacobian determinant %g at integration point %d",
                   dtm_elem_name(type), dj, bad);
  return DTM_OK;
}

int dtm_elastic_lambda_at(int type, const dtm_elastic_moduli *m, const double *x, int level, double *lambda) {
  int d, nn;
  double K[DTM_K_DOF * DTM_K_DOF], mass[DTM_K_NODES];
  DTM_CHECK(matrices(type, x, m->integration, level, m, &d, &nn, K, mass));
  DTM_CHECK(dtm_form_check(type, d, m->form));
  for (int a = 0; a < nn; a++) mass[a] *= m->rho;
  return lumped_eig_max(nn * d, d, K, mass, lambda, 0);
}

/* 1 when element x of a lanes group is a tet10 the reference tensors
 * serve (the first steps of matrices(): its frame, its rule, the affine
 * check), with det J and J^-1; else 0 and matrices() takes it. */
static int affine_lane(int type, const double *x, int model, int level, double *dj, double Ji[3][3]) {
  double xl[DTM_K_NODES][3];
  if (type != DTM_TET10 || dtm_elem_local(type, x, xl)) return 0;
  return rule_of(type, 3, 10, (const double(*)[3])xl, model, level) == 0 &&
         dtm_affine_frame(type, 3, 10, (const double(*)[3])xl, dj, Ji);
}

/* Lane l of A from a tet10 integrated over its rule id (a curved one at
 * its kept level, or over the full rule where the curvature pass compares
 * models): its Gram tensor, as matrices() reads it, and the
 * entries its scaled stiffness would have, its largest |entry| into *top.
 * 0 (the lane unusable) where the element is refused on the way: the
 * general path below then names it. */
static int gram_lane(const dtm_elastic_moduli *m, const double (*xl)[3], int id, int l, dtm_v4d *A, double *top) {
  double U[DTM_K_DOF * DTM_K_DOF], mass[DTM_K_NODES], r[DTM_K_DOF], dj;
  const dtm_ref_table *t = dtm_ref_rule_table(DTM_TET10, id);
  if (!t || m->form != DTM_FORM_3D || dtm_elem_gram(DTM_TET10, 3, 10, xl, t, U, mass, &dj) >= 0) return 0;
  for (int b = 0; b < 10; b++) {
    mass[b] *= m->rho;
    if (!(mass[b] > 0)) return 0;
    for (int i = 0; i < 3; i++) r[3 * b + i] = 1 / sqrt(mass[b]);
  }
  *top = dtm_elem_gram_lane(10, m->lam, m->mu, U, r, l, A);
  return 1;
}

/* A group of tet10, each straight (the reference tensors) or integrated
 * over its rule's table (curved), straight into the packed lanes of the
 * eigenvalue solver: bitwise the general path's result without its
 * 30 x 30 matrices (the scaling and the largest entry taken as each entry
 * is formed). 0, with nothing given out, where an element is of neither
 * kind or is refused: the general path takes the group. */
static int packed_group(int count, const dtm_elastic_moduli *const *m, const double *const *x, const int *level,
                        double *lambda) {
  double dj[4], Ji[4][3][3], top[4], xl[4][DTM_K_NODES][3];
  int use[4] = {0, 0, 0, 0}, id[4];
  dtm_v4d A[30 * 31 / 2];
  for (int k = 0; k < count; k++) {
    if (dtm_elem_local(DTM_TET10, x[k], xl[k])) return 0;
    id[k] = rule_of(DTM_TET10, 3, 10, (const double(*)[3])xl[k], m[k]->integration, level[k]);
    use[k] = id[k] == 0 && dtm_affine_frame(DTM_TET10, 3, 10, (const double(*)[3])xl[k], &dj[k], Ji[k]);
  }
  if (!dtm_affine_elastic_pack(use, dj, (const double(*)[3][3])Ji, m, A, top)) return 0;
  for (int k = 0; k < count; k++)
    if (!use[k] && !gram_lane(m[k], (const double(*)[3])xl[k], id[k], k, A, &top[k])) return 0;
  dtm_packed_divide(count, A, top);
  dtm_eig_sym_max_tridiag_packed(30, A, top, count, lambda);
  return 1;
}

int dtm_elastic_lambda_lanes(int type, int count, const dtm_elastic_moduli *const *m, const double *const *x,
                             const int *level, double *lambda, int *failed) {
  int d = 3, nn = 10, n = 0, done = 0, err = DTM_OK, na = 0;
  if (type == DTM_TET10 && count > 0 && packed_group(count, m, x, level, lambda)) return DTM_OK;
  double K[4][DTM_K_LANE_DOF * DTM_K_LANE_DOF], mass[4][DTM_K_NODES], *a[4] = {K[0], K[1], K[2], K[3]};
  double dj[4], Ji[4][3][3], *aK[4], *am[4];
  const dtm_elastic_moduli *amod[4];
  for (int k = 0; k < count; k++, done++) {
    int r = DTM_OK;
    if (affine_lane(type, x[k], m[k]->integration, level[k], &dj[na], Ji[na])) { /* below, with the others */
      aK[na] = a[k], am[na] = mass[k], amod[na++] = m[k], n = 30;
      continue;
    }
    r = matrices(type, x[k], m[k]->integration, level[k], m[k], &d, &nn, a[k], mass[k]);
    if (!r) r = dtm_form_check(type, d, m[k]->form);
    n = nn * d;
    if (!r && n > DTM_K_LANE_DOF)
      r = DTM_ERR(DTM_ERR_INTERNAL, "%s has too many unknowns for the lanes", dtm_elem_name(type));
    for (int b = 0; !r && b < nn; b++) mass[k][b] *= m[k]->rho;
    if (!r) r = lumped_scale(n, d, a[k], mass[k]);
    if (r) {
      *failed = k, err = r;
      break;
    }
  }
  if (na) dtm_affine_elastic_lanes(na, dj, (const double(*)[3][3])Ji, amod, aK, am);
  for (int i = 0; i < na; i++) { /* as matrices() and the loop above: masses per unit density, then rho */
    for (int b = 0; b < 10; b++) am[i][b] *= amod[i]->rho;
    lumped_scale(30, 3, aK[i], am[i]); /* the masses are positive: det J is */
  }
  if (done) dtm_eig_sym_max_tridiag_lanes(n, a, done, lambda);
  return err;
}

int dtm_elastic_lambda_generic(int type, const dtm_elastic_moduli *m, const double *x, double *lambda) {
  return dtm_elastic_lambda_at(type, m, x, -1, lambda);
}

int dtm_diffusion_lambda_generic(int type, double alpha, const double *x, double *lambda) {
  int d, nn;
  double K[DTM_K_NODES * DTM_K_NODES], cap[DTM_K_NODES];
  DTM_CHECK(matrices(type, x, DTM_INTEGRATION_CONVERGED, -1, NULL, &d, &nn, K, cap));
  DTM_CHECK(lumped_eig_max(nn, 1, K, cap, lambda, 0));
  *lambda *= alpha;
  return DTM_OK;
}

int dtm_elastic_lambda_reference(int type, const dtm_elastic_moduli *m, const double *x, double *lambda) {
  dtm_elem_geom eg;
  double K[DTM_K_DOF * DTM_K_DOF], mass[DTM_K_NODES];
  DTM_CHECK(dtm_elem_prepare(type, x, m->integration, &eg));
  DTM_CHECK(dtm_form_check(type, eg.d, m->form));
  dtm_elem_stiffness(&eg, m, K);
  dtm_elem_mass(&eg, mass);
  for (int a = 0; a < eg.nn; a++) mass[a] *= m->rho;
  DTM_CHECK(lumped_eig_max(eg.nn * eg.d, eg.d, K, mass, lambda, 1));
  return DTM_OK;
}

int dtm_diffusion_lambda_reference(int type, double alpha, const double *x, double *lambda) {
  dtm_elem_geom eg;
  double K[DTM_K_NODES * DTM_K_NODES], cap[DTM_K_NODES];
  DTM_CHECK(dtm_elem_prepare(type, x, DTM_INTEGRATION_CONVERGED, &eg));
  dtm_elem_laplace(&eg, K);
  dtm_elem_mass(&eg, cap);
  DTM_CHECK(lumped_eig_max(eg.nn, 1, K, cap, lambda, 1));
  *lambda *= alpha;
  return DTM_OK;
}
