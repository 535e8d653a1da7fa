/* Eigenvalues of small symmetric matrices in closed form, for the simplex
 * kernels' hot path. The 3x3 solver is the trigonometric (Smith 1961)
 * solution of the characteristic cubic, set up from the shifted matrix
 * B = S - qI (q = tr S / 3) so that its scale p^2 = |B|^2/6 is a sum of
 * squares. Its weak spot is two nearly equal eigenvalues, where acos is
 * evaluated next to +-1 and the close pair can come out with an error
 * near sqrt(eps) of the matrix norm. There the well-separated eigenvalue is
 * still accurate; its eigenvector (a cross product of two rows of B - e I)
 * is used to deflate, and the close pair is recomputed from the 2x2
 * restriction, whose formula has no cancellation. Every eigenvalue then
 * comes out within a few eps of the largest magnitude, with no iteration
 * and no allocation.
 *
 * A close bottom pair is common (flat tetrahedra: one large eigenvalue, two
 * small) and deflating costs more than the rest, so dtm_eig3_top avoids
 * it: it returns the largest eigenvalue and the sum and product of the two
 * gaps s1 - s2, s1 - s3, which the trigonometric form gives accurately
 * whatever the split of the pair (see kernel_impl.h). */
#include <math.h>

#include "kernel-impl.h"

/* |r| above this means two eigenvalues are close: deflate. Below it the
 * trigonometric error is at most ~ eps/sqrt(1 - r^2) < 3 eps times the norm. */
#define CLOSE_PAIR 0.9

static const double PI = 3.14159265358979323846;

void dtm_eig2_sym(double a, double b, double c, double e[2]) {
  double m = 0.5 * (a + c), h = 0.5 * (a - c), r = sqrt(h * h + b * b);
  e[0] = m + r;
  e[1] = m - r;
}

/* y = B x for the symmetric B packed as in kernel_impl.h. */
static void mul(const double b[6], const double *x, double *y) {
  y[0] = b[0] * x[0] + b[3] * x[1] + b[4] * x[2];
  y[1] = b[3] * x[0] + b[1] * x[1] + b[5] * x[2];
  y[2] = b[4] * x[0] + b[5] * x[1] + b[2] * x[2];
}

/* Unit null vector of B - e I (e a simple eigenvalue of B): the longest
 * cross product of two of its rows. Returns -1 if none is usable. */
static int null_vector(const double b[6], double e, double *v) {
  double r[3][3] = {{b[0] - e, b[3], b[4]}, {b[3], b[1] - e, b[5]}, {b[4], b[5], b[2] - e}};
  double c[3][3], n[3];
  dtm_v3_cross(r[0], r[1], c[0]);
  dtm_v3_cross(r[0], r[2], c[1]);
  dtm_v3_cross(r[1], r[2], c[2]);
  for (int k = 0; k < 3; k++) n[k] = dtm_v3_dot(c[k], c[k]);
  int k = n[0] >= n[1] ? (n[0] >= n[2] ? 0 : 2) : (n[1] >= n[2] ? 1 : 2);
  if (!(n[k] > 0) || !isfinite(n[k])) return -1;
  double s = 1 / sqrt(n[k]);
  for (int i = 0; i < 3; i++) v[i] = c[k][i] * s;
  return 0;
}

/* The two eigenvalues of B restricted to the plane normal to unit v. */
static void restricted_pair(const double b[6], const double *v, double e[2]) {
  int k = fabs(v[0]) <= fabs(v[1]) ? (fabs(v[0]) <= fabs(v[2]) ? 0 : 2) : (fabs(v[1]) <= fabs(v[2]) ? 1 : 2);
  double ax[3] = {0, 0, 0}, u1[3], u2[3], y1[3], y2[3];
  ax[k] = 1;
  dtm_v3_cross(v, ax, u1);
  double s = 1 / sqrt(dtm_v3_dot(u1, u1));
  for (int i = 0; i < 3; i++) u1[i] *= s;
  dtm_v3_cross(v, u1, u2);
  mul(b, u1, y1);
  mul(b, u2, y2);
  dtm_eig2_sym(dtm_v3_dot(u1, y1), dtm_v3_dot(u1, y2), dtm_v3_dot(u2, y2), e);
}

static void sort3(double e[3]) {
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2 - i; j++)
      if (e[j] < e[j + 1]) {
        double t = e[j];
        e[j] = e[j + 1], e[j + 1] = t;
      }
}

/* Recompute the close pair from the separated eigenvalue e[sep] of the
 * shifted matrix b. */
static void deflate(const double b[6], int sep, double e[3]) {
  double v[3], pair[2];
  if (null_vector(b, e[sep], v)) return;
  restricted_pair(b, v, pair);
  if (sep == 0)
    e[1] = pair[0], e[2] = pair[1];
  else
    e[0] = pair[0], e[1] = pair[1];
  sort3(e);
}

/* The trigonometric set-up: b = S - q I, scale p (0 for S = q I) and
 * r = det(b / p) / 2 in [-1, 1]; the eigenvalues of b are 2 p cos(phi +
 * 2 pi k / 3), phi = acos(r) / 3. */
typedef struct {
  double q, p, r; /* shift, scale, cosine of 3 phi */
  double b[6];    /* shifted matrix */
} trig;

static void trig_setup(const double s[6], trig *t) {
  t->q = (s[0] + s[1] + s[2]) / 3;
  double *b = t->b;
  b[0] = s[0] - t->q, b[1] = s[1] - t->q, b[2] = s[2] - t->q;
  b[3] = s[3], b[4] = s[4], b[5] = s[5];
  double p2 = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2] + 2 * (b[3] * b[3] + b[4] * b[4] + b[5] * b[5])) / 6;
  t->p = sqrt(p2);
  t->r = 0;
  if (!(p2 > 0)) return;
  double det =
      b[0] * (b[1] * b[2] - b[5] * b[5]) - b[3] * (b[3] * b[2] - b[5] * b[4]) + b[4] * (b[3] * b[5] - b[1] * b[4]);
  double ip = 1 / t->p, r = 0.5 * det * ip * ip * ip;
  t->r = r < -1 ? -1 : (r > 1 ? 1 : r);
}

/* Eigenvalues of the shifted matrix, refined where a pair is close
 * (bottom pair only if refine_bottom). */
static void shifted_eigs(const trig *t, double e[3], int refine_bottom) {
  double phi = acos(t->r) / 3;
  e[0] = 2 * t->p * cos(phi);
  e[2] = 2 * t->p * cos(phi + 2 * PI / 3);
  e[1] = -e[0] - e[2];
  if (t->r < -CLOSE_PAIR)
    deflate(t->b, 2, e);
  else if (t->r > CLOSE_PAIR && refine_bottom)
    deflate(t->b, 0, e);
}

void dtm_eig3_sym(const double s[6], double e[3]) {
  trig t;
  trig_setup(s, &t);
  e[0] = e[1] = e[2] = 0;
  if (t.p > 0) shifted_eigs(&t, e, 1);
  for (int i = 0; i < 3; i++) e[i] += t.q;
}

void dtm_eig3_top(const double s[6], dtm_top3 *top) {
  trig t;
  trig_setup(s, &t);
  if (!(t.p > 0)) {
    top->s1 = t.q, top->tau = top->rho = 0;
  } else if (t.r < -CLOSE_PAIR) { /* close top pair: deflate */
    double e[3];
    shifted_eigs(&t, e, 0);
    top->s1 = t.q + e[0];
    top->tau = (e[0] - e[1]) + (e[0] - e[2]);
    top->rho = (e[0] - e[1]) * (e[0] - e[2]);
  } else { /* s1 - q = 2pc; gaps 2pc - 2p cos(phi +- 2pi/3) */
    double c = cos(acos(t.r) / 3);
    top->s1 = t.q + 2 * t.p * c;
    top->tau = 6 * t.p * c;
    top->rho = 3 * t.p * t.p * (2 * c - 1) * (2 * c + 1);
  }
}
