/* The sparse symmetric matrices (dtm_csr, include/dtmap/operator.h) that
 * carry a mass matrix which is not diagonal (selective mass scaling) from
 * where it is assembled to where it is applied or factored: their product
 * and their release. */
#include <stdlib.h>
#include <string.h>

#include "dtmap/operator.h"
#include "spectral.h"

void dtm_csr_free(dtm_csr *m) {
  if (!m) return;
  free(m->rowptr);
  free(m->col);
  free(m->val);
  memset(m, 0, sizeof *m);
}

void dtm_csr_apply(const dtm_csr *m, const double *x, double *y) {
  for (size_t i = 0; i < m->n; i++) {
    double s = 0;
    for (size_t k = m->rowptr[i]; k < m->rowptr[i + 1]; k++) s += m->val[k] * x[m->col[k]];
    y[i] = s;
  }
}

double dtm_vec_dot(size_t n, const double *x, const double *y) {
  double s = 0;
  for (size_t i = 0; i < n; i++) s += x[i] * y[i];
  return s;
}
