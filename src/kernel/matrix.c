/* The small dense algebra of element maps: determinant, Hadamard bound and
 * inverse of a d x d Jacobian (d = 1, 2, 3) stored in a 3 x 3 array. Shared
 * by the kernel's map (map.c) and the global operator (src/spectral/), so
 * both judge an element's validity the same way. */
#include <math.h>

#include "reference.h"

double dtm_mat_det(int d, const double J[3][3]) {
  if (d == 1) return J[0][0];
  if (d == 2) return J[0][0] * J[1][1] - J[0][1] * J[1][0];
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

double dtm_mat_hadamard(int d, const double J[3][3]) {
  double h = 1;
  for (int j = 0; j < d; j++) {
    double c = 0;
    for (int i = 0; i < d; i++) c += J[i][j] * J[i][j];
    h *= sqrt(c);
  }
  return h;
}

void dtm_mat_inverse(int d, const double J[3][3], double dj, double K[3][3]) {
  if (d == 1) {
    K[0][0] = 1 / dj;
  } else if (d == 2) {
    K[0][0] = J[1][1] / dj, K[0][1] = -J[0][1] / dj;
    K[1][0] = -J[1][0] / dj, K[1][1] = J[0][0] / dj;
  } else {
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
      for (int j = 0; j < 3; j++) { /* unrolled: the indices are constants */
        int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
        K[i][j] = (J[i1][j1] * J[i2][j2] - J[i1][j2] * J[i2][j1]) / dj;
      }
  }
}
