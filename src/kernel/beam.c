/* Two-node 3D Timoshenko beam (structural.h): the section helpers (circle,
 * rectangle with Saint-Venant's torsion series), the beam frame from the
 * orientation vector, the local stiffness (axial E A/L, torsion G J_t/L,
 * bending E I/L on the rotation differences, shear k G A L gamma^2 with
 * the shear strain at the midpoint: reduced integration), the lumped
 * masses and the eigenvalue bounds through the shell's shared helpers.
 *
 * Frame unknowns per node (u, v, w, theta_x, theta_y, theta_z). Shear
 * strains at the midpoint, consistent with right-hand rotations (a rigid
 * rotation leaves them zero):
 *   e1-e2 plane: gamma_xy = (v1 - v0)/L - (theta_z0 + theta_z1)/2,
 *   e1-e3 plane: gamma_xz = (w1 - w0)/L + (theta_y0 + theta_y1)/2. */
#include <math.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/units.h"
#include "kernel-impl.h"
#include "structural.h"

#define ND 6
#define NB 12 /* unknowns of the element */

static const double PI = 3.14159265358979323846;

static int positive(double v) { return v > 0 && isfinite(v); }

int dtm_beam_section_circle(double r, dtm_beam_section *s) {
  char t[48];
  if (!positive(r))
    return DTM_ERR(DTM_ERR_INPUT, "beam: radius must be finite and > 0 (got %s)",
                   dtm_units_si_text(DTM_UNIT_LENGTH, r, 6, t, sizeof t));
  double r2 = r * r;
  s->area = PI * r2;
  s->iy = s->iz = PI * r2 * r2 / 4;
  s->jt = PI * r2 * r2 / 2;
  return DTM_OK;
}

/* Saint-Venant's torsion constant of an a x c rectangle, a >= c. */
static double rect_torsion(double a, double c) {
  double sum = 0;
  for (int n = 9999; n >= 1; n -= 2) { /* small terms first; the tail beyond is below 1e-17 */
    double n2 = (double)n * n;
    sum += tanh(n * PI * a / (2 * c)) / (n2 * n2 * n);
  }
  return a * c * c * c / 3 * (1 - 192 * c / (pow(PI, 5) * a) * sum);
}

int dtm_beam_section_rect(double b, double h, dtm_beam_section *s) {
  char tb[48], th[48];
  if (!positive(b) || !positive(h))
    return DTM_ERR(DTM_ERR_INPUT, "beam: rectangle sides must be finite and > 0 (got %s, %s)",
                   dtm_units_si_text(DTM_UNIT_LENGTH, b, 6, tb, sizeof tb),
                   dtm_units_si_text(DTM_UNIT_LENGTH, h, 6, th, sizeof th));
  s->area = b * h;
  s->iy = b * h * h * h / 12;
  s->iz = h * b * b * b / 12;
  s->jt = rect_torsion(fmax(b, h), fmin(b, h));
  return DTM_OK;
}

static int check_section(const dtm_beam_section *s) {
  char t1[48], t2[48], t3[48], t4[48];
  if (!positive(s->E) || !positive(s->rho))
    return DTM_ERR(DTM_ERR_INPUT, "beam: E and rho must be finite and > 0 (got %s, %s)",
                   dtm_units_si_text(DTM_UNIT_MODULUS, s->E, 6, t1, sizeof t1),
                   dtm_units_si_text(DTM_UNIT_DENSITY, s->rho, 6, t2, sizeof t2));
  if (!(s->nu > -1 && s->nu < 0.5))
    return DTM_ERR(DTM_ERR_INPUT, "beam: Poisson's ratio must lie in (-1, 0.5) (got %g)", s->nu);
  if (!positive(s->area) || !positive(s->iy) || !positive(s->iz) || !positive(s->jt))
    return DTM_ERR(DTM_ERR_INPUT, "beam: A, I_y, I_z, J_t must be finite and > 0 (got %s, %s, %s, %s)",
                   dtm_units_si_text(DTM_UNIT_AREA, s->area, 6, t1, sizeof t1),
                   dtm_units_si_text(DTM_UNIT_MOMENT, s->iy, 6, t2, sizeof t2),
                   dtm_units_si_text(DTM_UNIT_MOMENT, s->iz, 6, t3, sizeof t3),
                   dtm_units_si_text(DTM_UNIT_MOMENT, s->jt, 6, t4, sizeof t4));
  if (!(s->k_shear >= 0) || !isfinite(s->k_shear))
    return DTM_ERR(DTM_ERR_INPUT, "beam: shear correction must be finite and >= 0 (got %g)", s->k_shear);
  return DTM_OK;
}

/* Axes (rows e1, e2, e3) and length of the beam x[2][3]. */
static int beam_frame(const dtm_beam_section *s, const double *x, double axes[3][3], double *L) {
  double *e1 = axes[0], *e2 = axes[1], ref[3];
  dtm_v3_sub(x + 3, x, e1);
  *L = sqrt(dtm_v3_dot(e1, e1));
  if (!positive(*L)) return DTM_ERR(DTM_ERR_INPUT, "beam: zero-length element");
  for (int i = 0; i < 3; i++) e1[i] /= *L;
  int def = s->ref[0] == 0 && s->ref[1] == 0 && s->ref[2] == 0;
  for (int i = 0; i < 3; i++) ref[i] = def ? (i == (fabs(e1[2]) > 0.99 ? 1 : 2)) : s->ref[i];
  double r = sqrt(dtm_v3_dot(ref, ref)), p = dtm_v3_dot(ref, e1);
  for (int i = 0; i < 3; i++) e2[i] = ref[i] - p * e1[i];
  double n = sqrt(dtm_v3_dot(e2, e2));
  if (!(n > 1e-6 * r) || !isfinite(n))
    return DTM_ERR(DTM_ERR_INPUT, "beam: orientation vector (%g, %g, %g) is parallel to the beam", ref[0], ref[1],
                   ref[2]);
  for (int i = 0; i < 3; i++) e2[i] /= n;
  dtm_v3_cross(e1, e2, axes[2]);
  return DTM_OK;
}

/* K[NB][NB] += c [1 -1; -1 1] on unknowns i, j. */
static void add_pair(double *K, int i, int j, double c) {
  K[i * NB + i] += c, K[j * NB + j] += c, K[i * NB + j] -= c, K[j * NB + i] -= c;
}

/* K += f b b^T for b[NB] with entries on unknowns idx[4]. */
static void add_rank1(double *K, const int idx[4], const double b[4], double f) {
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) K[idx[i] * NB + idx[j]] += f * b[i] * b[j];
}

static void beam_stiffness(const dtm_beam_section *s, double L, double *K) {
  double G = s->E / (2 * (1 + s->nu)), k = s->k_shear > 0 ? s->k_shear : 5.0 / 6.0;
  memset(K, 0, sizeof(double) * NB * NB);
  add_pair(K, 0, ND + 0, s->E * s->area / L); /* axial */
  add_pair(K, 3, ND + 3, G * s->jt / L);      /* torsion */
  add_pair(K, 4, ND + 4, s->E * s->iy / L);   /* bending about e2 */
  add_pair(K, 5, ND + 5, s->E * s->iz / L);   /* bending about e3 */
  const int ixz[4] = {2, 4, ND + 2, ND + 4}, ixy[4] = {1, 5, ND + 1, ND + 5};
  const double bxz[4] = {-1 / L, 0.5, 1 / L, 0.5}, bxy[4] = {-1 / L, -0.5, 1 / L, -0.5};
  add_rank1(K, ixz, bxz, k * G * s->area * L);
  add_rank1(K, ixy, bxy, k * G * s->area * L);
}

/* Local diagonal masses m[NB]. */
static void beam_mass(const dtm_beam_section *s, double L, double *m) {
  double h = s->rho * L / 2;
  double imin = fmin(s->iy, s->iz);
  const double per[ND] = {s->area,
                          s->area,
                          s->area,
                          s->isotropic ? imin : s->iy + s->iz,
                          s->isotropic ? imin : s->iy,
                          s->isotropic ? imin : s->iz};
  for (int i = 0; i < NB; i++) m[i] = h * per[i % ND];
}

static int beam_local(const dtm_beam_section *s, const double *x, double axes[3][3], double *K, double *m) {
  double L;
  DTM_CHECK(check_section(s));
  DTM_CHECK(beam_frame(s, x, axes, &L));
  beam_stiffness(s, L, K);
  beam_mass(s, L, m);
  return DTM_OK;
}

static const int axial_comp[1] = {0}, transverse_comp[5] = {1, 2, 3, 4, 5};

int dtm_kernel_beam_lambda(const dtm_beam_section *sec, const double *x, dtm_beam_lambda *out) {
  double axes[3][3], K[NB * NB], m[NB], b[4];
  DTM_CHECK(beam_local(sec, x, axes, K, m));
  dtm_struct_bounds(2, K, m, 1, axial_comp, 5, transverse_comp, b);
  out->lambda_axial = b[0], out->lambda_physical = b[1], out->lambda_scaled = b[2], out->scale = b[3];
  return DTM_OK;
}

int dtm_kernel_beam_bounds(const dtm_beam_section *sec, const double *x, int need, double screen, double out[3],
                           double *m) {
  double axes[3][3], K[NB * NB];
  DTM_CHECK(beam_local(sec, x, axes, K, m));
  dtm_struct_bounds_fast(2, K, m, 1, axial_comp, 5, transverse_comp, need, screen, out);
  return DTM_OK;
}

int dtm_kernel_beam_masses(const dtm_beam_section *sec, const double *x, double *m) {
  double axes[3][3], K[NB * NB];
  return beam_local(sec, x, axes, K, m);
}

int dtm_kernel_beam_scale(const dtm_beam_section *sec, const double *x, double out[2], double *m) {
  double axes[3][3], K[NB * NB];
  DTM_CHECK(beam_local(sec, x, axes, K, m));
  dtm_struct_ref_scale(2, K, m, 1, axial_comp, 5, transverse_comp, out);
  return DTM_OK;
}

int dtm_kernel_beam_matrices(const dtm_beam_section *sec, const double *x, dtm_rotary_convention conv,
                             dtm_struct_matrices *out) {
  double K[NB * NB], M[NB * NB] = {0}, b[2];
  DTM_CHECK(beam_local(sec, x, out->axes, K, out->m));
  if (conv == DTM_ROTARY_SCALED) {
    dtm_struct_ref_scale(2, K, out->m, 1, axial_comp, 5, transverse_comp, b);
    if (!isfinite(b[1]))
      return DTM_ERR(DTM_ERR_INPUT, "beam: no finite rotary inertia scale reaches the target (k G >= E)");
    for (int i = 0; i < NB; i++) out->m[i] *= i % ND >= 3 ? b[1] : 1;
  }
  out->nn = 2;
  for (int i = 0; i < NB; i++) M[i * NB + i] = out->m[i];
  dtm_struct_to_global(2, (const double(*)[3])out->axes, K, out->K);
  dtm_struct_to_global(2, (const double(*)[3])out->axes, M, out->M);
  return DTM_OK;
}
