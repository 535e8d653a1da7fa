/* dtm_kernel_diffusion_lambda: the element bound lambda_max(Ce^-1 Ke) of
 * scalar diffusion with lumped capacity (row sums for linear types, HRZ
 * for second-order ones). On a linear simplex Ke = alpha V G G^T and
 * Ce = V/(d+1) I, so lambda = (d+1) alpha lambda_max(G G^T) = (d+1) alpha
 * s_max, s_max the largest eigenvalue of S = G^T G, exactly. Other types,
 * tri6 and tet10 included, solve the nn x nn problem (generic.c). */
#include <math.h>

#include "dtmap/error.h"
#include "dtmap/units.h"
#include "kernel-impl.h"

static int simplex(int type, double alpha, const double *x, double *lambda) {
  int d;
  double S[6], scale, vol, s[2];
  dtm_top3 t;
  DTM_CHECK(dtm_simplex_metric(type, x, &d, S, &scale, &vol));
  if (d == 3)
    dtm_eig3_top(S, &t), s[0] = t.s1;
  else if (d == 2)
    dtm_eig2_sym(S[0], S[3], S[1], s);
  else
    s[0] = S[0];
  *lambda = (d + 1) * alpha * scale * s[0];
  return DTM_OK;
}

int dtm_kernel_diffusion_lambda(int type, double alpha, const double *x, double *lambda) {
  char t[48];
  if (!isfinite(alpha) || !(alpha > 0))
    return DTM_ERR(DTM_ERR_INPUT, "diffusivity must be finite and > 0 (got %s)",
                   dtm_units_si_text(DTM_UNIT_DIFFUSIVITY, alpha, 6, t, sizeof t));
  DTM_CHECK(dtm_elem_info(type, NULL, NULL));
  if (dtm_elem_is_simplex(type))
    DTM_CHECK(simplex(type, alpha, x, lambda));
  else
    DTM_CHECK(dtm_diffusion_lambda_generic(type, alpha, x, lambda));
  return DTM_OK;
}
