/* The generic element bound: assemble the fully integrated element matrix,
 * lump the mass (or capacity) (row sums for linear types, HRZ for
 * second-order ones: lump.c) and take the largest eigenvalue of
 * M^-1/2 K M^-1/2, with the Jacobi solver for the small problems of the
 * linear types and by tridiagonalization (tridiag.c) for the larger ones
 * of second-order types. Works for every supported type; non-simplices
 * and second-order simplices always come here, linear simplices only for
 * cross-checks. No allocation: the element matrix (up to 81 x 81, 52 kB)
 * is on the stack. */
#include <math.h>

#include "dtmap/error.h"
#include "assemble-impl.h"
#include "kernel-impl.h"

int dtm_lumped_eig_max(int type, int n, int per, double *K, const double *m, double *lambda) {
  double r[DTM_K_DOF];
  for (int k = 0; k < n; k++) {
    if (!(m[k / per] > 0))
      return DTM_ERR(DTM_ERR_INPUT, "degenerate element: lumped mass of node %d is %g", k / per, m[k / per]);
    r[k] = 1 / sqrt(m[k / per]);
  }
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) K[i * n + j] *= r[i] * r[j];
  /* Jacobi for the small linear problems (up to quad4's 8 unknowns),
   * tridiagonalization for the rest (pyr5 15, prism6 18, hex8 24, and the
   * second-order types up to 81), where it is several times faster: hex8
   * went from about 230 us to tens of us; both are backward stable. */
  (void)type;
  *lambda = n <= 12 ? dtm_eig_sym_max(n, K) : dtm_eig_sym_max_tridiag(n, K);
  return DTM_OK;
}

int dtm_elastic_lambda_generic(int type, const dtm_elastic_moduli *m, const double *x, double *lambda) {
  dtm_elem_geom eg;
  double K[DTM_K_DOF * DTM_K_DOF], mass[DTM_K_NODES];
  DTM_CHECK(dtm_elem_prepare(type, x, m->integration, &eg));
  DTM_CHECK(dtm_form_check(type, eg.d, m->form));
  dtm_elem_stiffness(&eg, m, K);
  dtm_elem_mass(&eg, mass);
  for (int a = 0; a < eg.nn; a++) mass[a] *= m->rho;
  DTM_CHECK(dtm_lumped_eig_max(type, eg.nn * eg.d, eg.d, K, mass, lambda));
  return DTM_OK;
}

int dtm_diffusion_lambda_generic(int type, double alpha, const double *x, double *lambda) {
  dtm_elem_geom eg;
  double K[DTM_K_NODES * DTM_K_NODES], cap[DTM_K_NODES];
  DTM_CHECK(dtm_elem_prepare(type, x, DTM_INTEGRATION_CONVERGED, &eg));
  dtm_elem_laplace(&eg, K);
  dtm_elem_mass(&eg, cap);
  DTM_CHECK(dtm_lumped_eig_max(type, eg.nn, 1, K, cap, lambda));
  *lambda *= alpha;
  return DTM_OK;
}
