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
