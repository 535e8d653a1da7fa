/* dtm_kernel_elastic_lambda: the element bound lambda_max(Me^-1 Ke) of
 * isotropic linear elasticity with lumped mass (row sums for linear types,
 * HRZ for second-order ones). Checks the type and the formulation, then
 * takes the closed form on linear simplices (elastic_simplex.c) and the
 * assembled eigenproblem otherwise (generic.c), second-order simplices
 * included. dtm_kernel_elastic_lambda_at skips the level search of a
 * curved element whose level the caller kept. */
#include "dtmap/error.h"
#include "kernel-impl.h"

int dtm_kernel_elastic_lambda_at(int type, const dtm_elastic_moduli *m, const double *x, int level, double *lambda) {
  if (type == DTM_TET4 && m->form == DTM_FORM_3D) /* the hot path */
    DTM_CHECK(dtm_elastic_lambda_simplex(type, m, x, lambda));
  else {
    int d;
    DTM_CHECK(dtm_elem_info(type, &d, NULL));
    DTM_CHECK(dtm_form_check(type, d, m->form));
    if (dtm_elem_is_simplex(type))
      DTM_CHECK(dtm_elastic_lambda_simplex(type, m, x, lambda));
    else
      DTM_CHECK(dtm_elastic_lambda_at(type, m, x, level < 0 ? -1 : level, lambda));
  }
  return DTM_OK;
}

int dtm_kernel_elastic_lambda(int type, const dtm_elastic_moduli *m, const double *x, double *lambda) {
  return dtm_kernel_elastic_lambda_at(type, m, x, -1, lambda);
}

int dtm_kernel_lanes_off = 0;

/* 1 when the elements of type under formulation form go to the lanes of
 * dtm_elastic_lambda_lanes: the generic path with the Householder
 * reduction (more than 12 unknowns) and at most DTM_K_LANE_DOF. */
static int lanes_take(int type, const dtm_elastic_moduli *m) {
  int d, nn;
  if (type == DTM_TET4 || dtm_kernel_lanes_off || dtm_elem_info(type, &d, &nn) || dtm_elem_is_simplex(type)) return 0;
  if (!(d == 3 ? m->form == DTM_FORM_3D
               : d == 2 && (m->form == DTM_FORM_PLANE_STRAIN || m->form == DTM_FORM_PLANE_STRESS)))
    return 0; /* the one-element call raises the mismatch */
  return nn * d > 12 && nn * d <= DTM_K_LANE_DOF;
}

int dtm_kernel_elastic_lambda_lanes(int type, int count, const dtm_elastic_moduli *const *m, const double *const *x,
                                    const int *level, double *lambda, int *failed) {
  int take = count >= 1 && count <= DTM_KERNEL_LANES;
  for (int k = 0; take && k < count; k++) take = lanes_take(type, m[k]);
  if (take) {
    int lv[DTM_KERNEL_LANES];
    for (int k = 0; k < count; k++) lv[k] = level && level[k] >= 0 ? level[k] : -1;
    return dtm_elastic_lambda_lanes(type, count, m, x, lv, lambda, failed);
  }
  for (int k = 0; k < count; k++) {
    int r = dtm_kernel_elastic_lambda_at(type, m[k], x[k], level ? level[k] : -1, &lambda[k]);
    if (r) return *failed = k, r;
  }
  return DTM_OK;
}
