/* Three-component vector helpers shared by the kernel files (and the
 * topology module): difference, dot and cross products. */
#ifndef DTM_KERNEL_VEC3_H
#define DTM_KERNEL_VEC3_H

static inline void dtm_v3_sub(const double *a, const double *b, double *c) {
  for (int i = 0; i < 3; i++) c[i] = a[i] - b[i];
}

static inline double dtm_v3_dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static inline void dtm_v3_cross(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

#endif
