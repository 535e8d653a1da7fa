/* Closed-form element bound of the linear simplices (line2, tri3, tet4) for
 * isotropic elasticity with row-sum lumped mass rho V / (d + 1).
 *
 * Derivation. Ke = V G^T C G, where G maps nodal displacements u_a to the
 * displacement gradient H = sum_a u_a g_a^T and C is the quadratic form
 * lam (tr H)^2 + 2 mu |sym H|^2. The nonzero eigenvalues of Me^-1 Ke are
 * those of (d+1)/rho C^(1/2) (G G^T) C^(1/2), and G G^T = I (x) S with
 * S = sum_a g_a g_a^T. In the eigenbasis of S (eigenvalues s_i, w_i =
 * sqrt(s_i)), C acting on H W (W = diag(w)) splits into
 *   - the "normal" block on diagonal H: 2 mu diag(s) + lam w w^T, and
 *   - one "shear" pair per i < j, with eigenvalue mu (s_i + s_j).
 * So lambda = (d+1)/rho * max(lambda_max(2 mu diag(s) + lam w w^T),
 * mu (s_1 + s_2)). DESIGN.md quotes only the first term: it dominates
 * whenever lam >= 0 (it is >= 2 mu s_max >= mu (s_i + s_j)); the shear term
 * matters only for auxetic materials (nu < 0), so it is kept. A bar has no
 * lam or mu: its 1x1 block is modulus * s with s = 2/L^2, so lambda =
 * 4E/(rho L^2) and dt = 2/sqrt(lambda) = L/c.
 *
 * Numerics (tet4, the hot path; no allocation, no Jacobi).
 *  - nu >= 0.045 (lam >= 0.1 mu): the top of the normal block is the
 *    largest root of its characteristic polynomial, whose coefficients are
 *    the invariants of S, by Halley's iteration from an upper bound
 *    (normal_top3_poly): no transcendental function at all.
 *  - 0 <= nu < 0.045: that root is too close to the next for the
 *    polynomial, so S's spectrum is taken from dtm_eig3_top (one acos, one
 *    cos) and the top is t = 2 mu s1 + u, u the root of the secular
 *    equation, written with the gaps e_i = s1 - s_i (i = 2, 3) as the
 *    convex function
 *      F(u) = u - lam s1 - lam sum_i s_i u / (u + 2 mu e_i)
 *           = u - lam s1 - lam u (u sigma + 2 mu kappa) / D(u),
 *      D(u) = u^2 + 2 mu tau u + 4 mu^2 rho = prod_i (u + 2 mu e_i),
 *    with tau = e2 + e3, rho = e2 e3, sigma = s2 + s3, kappa = e2 s3 +
 *    e3 s2: symmetric in (s2, s3), so a close bottom pair need not be
 *    split. The root is found on the cubic G = D F (the characteristic
 *    polynomial of the normal block shifted by 2 mu s1), convex right of
 *    its largest root: Newton from the upper bound u = lam tr S decreases
 *    monotonically to the root, so stopping early errs high. Since G'(u) =
 *    D F' >= D / 3 there, rounding in the coefficients moves the root by a
 *    few eps of (u + lam s1).
 *  - nu < 0: the plain eigenvalues of S and of the normal block, plus the
 *    shear term.
 * Against a long-double reference on the same coordinates the result is
 * within ~1e-14 on well-shaped tetrahedra, for every branch. On extreme
 * slivers both this and the assembled path lose ~eps times the aspect
 * ratio, because det J itself is computed with cancellation. */
#include <math.h>

#include "dtmap/error.h"
#include "kernel-impl.h"

/* u for lam > 0 (see above): the largest root of G = D F, a monic cubic
 * whose other roots are <= 0 (interlacing), Horner-evaluated. */
static double secular_root(double mu, double lam, const dtm_top3 *t) {
  double m2 = 2 * mu, L = lam * t->s1, T = m2 * t->tau, R = m2 * m2 * t->rho;
  double sigma = 2 * t->s1 - t->tau, K = m2 * (t->s1 * t->tau - 2 * t->rho);
  double a2 = T - L - lam * sigma, a1 = R - L * T - lam * K, a0 = -L * R;
  double u = L + lam * sigma; /* lam tr S >= root */
  for (int it = 0; it < 100; it++) {
    double g = ((u + a2) * u + a1) * u + a0, gp = (3 * u + 2 * a2) * u + a1;
    if (!(g > 0 && gp > 0)) break; /* at the root to rounding */
    double step = g / gp;
    u -= step;
    /* Quadratic convergence: what is left is ~ step^2 / u, below eps once
     * step < 1e-9 u, and it is an overestimate (we come from above). */
    if (step < 1e-9 * u) break;
  }
  return u;
}

/* lambda_max of the normal block for tet4 when lam >= LAM_FAST mu: the
 * largest root of its characteristic polynomial
 *   P(t) = t^3 - (2mu+lam) I1 t^2 + 4mu(mu+lam) I2 t - 4mu^2(2mu+3lam) I3
 * (I1, I2, I3 the invariants of S), by Halley's iteration from the upper
 * bound 2 mu (q + 2p) + lam I1 (q + 2p = tr S/3 + sqrt(2/3 |S - qI|^2) >=
 * s1, Samuelson; exact for S = qI, at most ~17% high otherwise). The other
 * roots are <= 2 mu s1 <= t1 - lam s1, so P'(t1) >= (lam s1)^2 and the
 * rounding of the invariants (a few eps of |S|^k) moves t1 by ~ eps
 * ((2mu + lam)/lam)^2 relative: < 1e-13 for lam >= 0.1 mu (nu >= 0.045).
 * Below that the gap closes and the secular path is used. Halley converges
 * cubically, so the iteration stops fully converged (not merely from
 * above): its error is the rounding error just stated. */
#define LAM_FAST 0.1

static double normal_top3_poly(double mu, double lam, const double S[6]) {
  double I1 = S[0] + S[1] + S[2], q = I1 / 3;
  double b0 = S[0] - q, b1 = S[1] - q, b2 = S[2] - q;
  double off = S[3] * S[3] + S[4] * S[4] + S[5] * S[5];
  double p = sqrt((b0 * b0 + b1 * b1 + b2 * b2 + 2 * off) / 6);
  double I2 = S[0] * S[1] + S[0] * S[2] + S[1] * S[2] - off;
  double I3 =
      S[0] * (S[1] * S[2] - S[5] * S[5]) - S[3] * (S[3] * S[2] - S[5] * S[4]) + S[4] * (S[3] * S[5] - S[1] * S[4]);
  double c2 = (2 * mu + lam) * I1, c1 = 4 * mu * (mu + lam) * I2;
  double c0 = 4 * mu * mu * (2 * mu + 3 * lam) * I3;
  double t = 2 * mu * (q + 2 * p) + lam * I1;
  for (int it = 0; it < 100; it++) {
    double g = ((t - c2) * t + c1) * t - c0, gp = (3 * t - 2 * c2) * t + c1;
    double step = 2 * g * gp / (2 * gp * gp - g * (6 * t - 2 * c2)); /* Halley */
    t -= step;
    /* The first two steps run unconditionally (no exit branch to
     * mispredict); from within 17% of the root, cubic convergence then
     * leaves ~1e-6 or less, and one more step brings it below 1e-17. */
    if (it >= 1 && !(fabs(step) >= 1e-6 * t)) break;
  }
  return t;
}

/* lambda_max of the normal block for tet4 (lam >= 0). */
static double normal_top3(double mu, double lam, const double S[6]) {
  if (lam >= LAM_FAST * mu) return normal_top3_poly(mu, lam, S);
  dtm_top3 t;
  dtm_eig3_top(S, &t);
  double s1 = fmax(t.s1, 0);
  return 2 * mu * s1 + (lam > 0 ? secular_root(mu, lam, &t) : 0);
}

/* Any sign of lam, from the full spectrum s (sorted, d = 2 or 3). */
static double normal_top_full(int d, double mu, double lam, const double *s) {
  double w[3], a[6], e[3];
  for (int i = 0; i < d; i++) w[i] = sqrt(s[i]);
  if (d == 2) {
    dtm_eig2_sym((2 * mu + lam) * s[0], lam * w[0] * w[1], (2 * mu + lam) * s[1], e);
    return e[0];
  }
  for (int i = 0; i < 3; i++) a[i] = (2 * mu + lam) * s[i];
  a[3] = lam * w[0] * w[1], a[4] = lam * w[0] * w[2], a[5] = lam * w[1] * w[2];
  dtm_eig3_sym(a, e);
  return e[0];
}

/* lambda_max(C (I (x) S)) from S packed (d = 2 or 3). */
static double block_top(int d, const dtm_elastic_moduli *m, const double S[6]) {
  double s[3];
  if (d == 3 && m->lam >= 0) return normal_top3(m->mu, m->lam, S);
  if (d == 3)
    dtm_eig3_sym(S, s);
  else
    dtm_eig2_sym(S[0], S[3], S[1], s);
  for (int i = 0; i < d; i++) s[i] = fmax(s[i], 0); /* rounding on slivers */
  return fmax(normal_top_full(d, m->mu, m->lam, s), m->mu * (s[0] + s[1]));
}

int dtm_elastic_lambda_simplex(int type, const dtm_elastic_moduli *m, const double *x, double *lambda) {
  int d;
  double S[6], scale, vol;
  DTM_CHECK(dtm_simplex_metric(type, x, &d, S, &scale, &vol));
  double top = d == 1 ? m->modulus * S[0] : block_top(d, m, S);
  *lambda = (d + 1) / m->rho * scale * top; /* top is linear in S */
  return DTM_OK;
}
