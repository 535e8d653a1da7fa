/* Flat facet Reissner-Mindlin shell on tri3 and quad4 (structural.h): the
 * element frame (Newell normal of the corners, first axis along the
 * projected edge 0-1, as dtm_elem_local), the local stiffness as membrane
 * (plane stress) + bending + transverse shear on the unknowns (u, v, w,
 * theta_x, theta_y, theta_z) of each node in that frame, the lumped masses,
 * and the eigenvalue bounds of both rotary-inertia conventions. Also the
 * helpers the beam shares (dense blocks, the rotary scale, the rotation to
 * global axes).
 *
 * Mindlin kinematics in the frame: the fibre rotations beta_x = theta_y,
 * beta_y = -theta_x (right-hand rotations about the local axes),
 * curvatures k = (beta_x,x, beta_y,y, beta_x,y + beta_y,x), shear strains
 * gamma = (w,x + beta_x, w,y + beta_y). quad4: membrane and bending 2x2
 * Gauss, shear at the centre. tri3: membrane and bending constant; shear
 * MITC3: gamma_h = sum over edges e = (i, j) of c_e phi_e, with
 * c_e = w_j - w_i + d . (beta_i + beta_j)/2 (d = x_j - x_i) the integral
 * of the tangential shear strain along the edge and
 * phi_e = N_i grad N_j - N_j grad N_i its Whitney (Nedelec) basis field,
 * integrated with the 3-point degree-2 rule (exact). */
#include <math.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/units.h"
#include "kernel-impl.h"
#include "structural.h"

#define ND 6 /* unknowns per node */

typedef struct {
  int type, nn;
  double axes[3][3]; /* rows e1, e2, normal */
  double xl[4][3];   /* nodes in the frame, node 0 at the origin, z = 0 */
  dtm_qrule q;       /* full rule: tri3 3-point, quad4 2x2 */
  double E, nu, rho, t, k;
} shell_elem;

/* ---- dense helpers shared with beam.c ---- */

/* lambda_max(diag(m)^-1/2 K diag(m)^-1/2); fast: the eigenvalue by
 * dtm_struct_eig_max instead of the bisection. */
static double lumped_max(int n, const double *K, const double *m, int fast) {
  double a[DTM_STRUCT_DOF * DTM_STRUCT_DOF], r[DTM_STRUCT_DOF];
  for (int i = 0; i < n; i++) r[i] = 1 / sqrt(m[i]);
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) a[i * n + j] = K[i * n + j] * r[i] * r[j];
  /* Householder + bisection: 2 to 9 times faster than cyclic Jacobi from
   * 6 unknowns up (bench: 3.4 against 6.7 us at 6, 5.4 against 27 us at 9),
   * to the same digits */
  if (n < 6) return dtm_eig_sym_max(n, a);
  return fast ? dtm_struct_eig_max(n, a) : dtm_eig_sym_max_tridiag(n, a);
}

double dtm_struct_lumped_max(int n, const double *K, const double *m) { return lumped_max(n, K, m, 0); }

/* In-place Cholesky of the SPD a[n][n] (lower triangle); -1 if not SPD. */
static int cholesky(int n, double *a) {
  for (int j = 0; j < n; j++) {
    double d = a[j * n + j];
    for (int k = 0; k < j; k++) d -= a[j * n + k] * a[j * n + k];
    if (!(d > 0) || !isfinite(d)) return -1;
    a[j * n + j] = sqrt(d);
    for (int i = j + 1; i < n; i++) {
      double s = a[i * n + j];
      for (int k = 0; k < j; k++) s -= a[i * n + k] * a[j * n + k];
      a[i * n + j] = s / a[j * n + j];
    }
  }
  return 0;
}

/* Solve L L^T x = b in place (b[n], L from cholesky). */
static void chol_solve(int n, const double *L, double *b) {
  for (int i = 0; i < n; i++) {
    for (int k = 0; k < i; k++) b[i] -= L[i * n + k] * b[k];
    b[i] /= L[i * n + i];
  }
  for (int i = n - 1; i >= 0; i--) {
    for (int k = i + 1; k < n; k++) b[i] -= L[k * n + i] * b[k];
    b[i] /= L[i * n + i];
  }
}

/* S[nr][nr] = K_rr + K_rt A^-1 K_tr over the index lists it[nt], ir[nr],
 * with L the Cholesky factor of A[nt][nt]. */
static void schur(int n, const double *K, int nt, const int *it, int nr, const int *ir, const double *L, double *S) {
  double X[DTM_STRUCT_DOF][DTM_STRUCT_DOF]; /* [nr][nt]: A^-1 K_tr, column by column */
  for (int c = 0; c < nr; c++) {
    for (int i = 0; i < nt; i++) X[c][i] = K[it[i] * n + ir[c]];
    chol_solve(nt, L, X[c]);
  }
  for (int r = 0; r < nr; r++)
    for (int c = 0; c < nr; c++) {
      double s = K[ir[r] * n + ir[c]];
      for (int i = 0; i < nt; i++) s += 0.5 * (K[it[i] * n + ir[r]] * X[c][i] + K[it[i] * n + ir[c]] * X[r][i]);
      S[r * nr + c] = s;
    }
}

static double rotary_scale(int n, const double *K, const double *m, const int *rot, double target, int fast) {
  int it[DTM_STRUCT_DOF], ir[DTM_STRUCT_DOF], nt = 0, nr = 0;
  double A[DTM_STRUCT_DOF * DTM_STRUCT_DOF], S[DTM_STRUCT_DOF * DTM_STRUCT_DOF], mr[DTM_STRUCT_DOF];
  for (int i = 0; i < n; i++) {
    if (rot[i])
      mr[nr] = m[i], ir[nr++] = i;
    else
      it[nt++] = i;
  }
  for (int i = 0; i < nt; i++)
    for (int j = 0; j < nt; j++) A[i * nt + j] = (i == j ? target * m[it[i]] : 0) - K[it[i] * n + it[j]];
  if (cholesky(nt, A)) return INFINITY;
  if (nr == 0) return 1;
  schur(n, K, nt, it, nr, ir, A, S);
  return fmax(1, lumped_max(nr, S, mr, fast) / target);
}

double dtm_struct_rotary_scale(int n, const double *K, const double *m, const int *rot, double target) {
  return rotary_scale(n, K, m, rot, target, 0);
}

/* Ks[ns][ns] = K[idx][idx] of the n x n K. */
static void extract(int n, const double *K, int ns, const int *idx, double *Ks) {
  for (int i = 0; i < ns; i++)
    for (int j = 0; j < ns; j++) Ks[i * ns + j] = K[idx[i] * n + idx[j]];
}

void dtm_struct_to_global(int nn, const double axes[3][3], const double *Kl, double *Kg) {
  int n = ND * nn;
  for (int A = 0; A < 2 * nn; A++)
    for (int B = 0; B < 2 * nn; B++) {
      double W[3][3]; /* Kl_AB R, R = axes: R^T Kl_AB R in two 3 x 3 products */
      for (int p = 0; p < 3; p++)
        for (int j = 0; j < 3; j++) {
          const double *row = Kl + (3 * A + p) * n + 3 * B;
          W[p][j] = row[0] * axes[0][j] + row[1] * axes[1][j] + row[2] * axes[2][j];
        }
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
          Kg[(3 * A + i) * n + 3 * B + j] = axes[0][i] * W[0][j] + axes[1][i] * W[1][j] + axes[2][i] * W[2][j];
    }
}

/* Largest eigenvalue of the block of per-node components comp[nc] (with
 * masses m, rotational ones times s) of the n = ND nn local problem;
 * idx/rot receive the block's unknowns. */
static double block_max(int nn, const double *K, const double *m, int nc, const int *comp, double s, int fast) {
  int idx[DTM_STRUCT_DOF] = {0}, nb = nn * nc;
  double Kb[DTM_STRUCT_DOF * DTM_STRUCT_DOF], mb[DTM_STRUCT_DOF];
  for (int i = 0; i < nb; i++) idx[i] = ND * (i / nc) + comp[i % nc];
  extract(ND * nn, K, nb, idx, Kb);
  for (int i = 0; i < nb; i++) mb[i] = m[idx[i]] * (idx[i] % ND >= 3 ? s : 1);
  return lumped_max(nb, Kb, mb, fast);
}

/* The scale s of the transverse block comp[nc] (rotations: comp >= 3). */
static double block_scale(int nn, const double *K, const double *m, int nc, const int *comp, double target, int fast) {
  int idx[DTM_STRUCT_DOF] = {0}, rot[DTM_STRUCT_DOF] = {0}, nb = nn * nc;
  double Kb[DTM_STRUCT_DOF * DTM_STRUCT_DOF], mb[DTM_STRUCT_DOF];
  for (int i = 0; i < nb; i++) idx[i] = ND * (i / nc) + comp[i % nc], rot[i] = comp[i % nc] >= 3;
  extract(ND * nn, K, nb, idx, Kb);
  for (int i = 0; i < nb; i++) mb[i] = m[idx[i]];
  return rotary_scale(nb, Kb, mb, rot, target, fast);
}

/* Whether one Cholesky factorisation proves T M - K positive definite on
 * the block comp[nc] (physical masses): then no eigenvalue of the block
 * exceeds T (Sylvester's law of inertia). */
static int block_below(int nn, const double *K, const double *m, int nc, const int *comp, double target) {
  int idx[DTM_STRUCT_DOF] = {0}, nb = nn * nc;
  double Kb[DTM_STRUCT_DOF * DTM_STRUCT_DOF];
  for (int i = 0; i < nb; i++) idx[i] = ND * (i / nc) + comp[i % nc];
  extract(ND * nn, K, nb, idx, Kb);
  for (int i = 0; i < nb; i++)
    for (int j = 0; j < nb; j++) Kb[i * nb + j] = (i == j ? target * m[idx[i]] : 0) - Kb[i * nb + j];
  return cholesky(nb, Kb) == 0;
}

/* The three bounds and s from the local K and m of an element whose
 * reference block comp_ref (membrane, axial) does not couple with the
 * transverse block comp_tr. */
void dtm_struct_bounds(int nn, const double *K, const double *m, int nref, const int *comp_ref, int ntr,
                       const int *comp_tr, double out[4]) {
  double lref = block_max(nn, K, m, nref, comp_ref, 1, 0);
  double s = block_scale(nn, K, m, ntr, comp_tr, lref, 0);
  int ntt = 0;
  while (ntt < ntr && comp_tr[ntt] < 3) ntt++; /* translational components come first */
  out[0] = lref;
  out[1] = fmax(lref, block_max(nn, K, m, ntr, comp_tr, 1, 0));
  out[2] = fmax(lref, isfinite(s) ? block_max(nn, K, m, ntr, comp_tr, s, 0) : block_max(nn, K, m, ntt, comp_tr, 1, 0));
  out[3] = s;
}

void dtm_struct_physical(int nn, const double *K, const double *m, int nref, const int *comp_ref, int ntr,
                         const int *comp_tr, double out[3]) {
  dtm_struct_ref_scale(nn, K, m, nref, comp_ref, ntr, comp_tr, out);
  out[2] = fmax(out[0], block_max(nn, K, m, ntr, comp_tr, 1, 0));
}

void dtm_struct_ref_scale(int nn, const double *K, const double *m, int nref, const int *comp_ref, int ntr,
                          const int *comp_tr, double out[2]) {
  out[0] = block_max(nn, K, m, nref, comp_ref, 1, 0);
  out[1] = block_scale(nn, K, m, ntr, comp_tr, out[0], 0);
}

/* s of the block comp[nc] by the Schur complement as rotary_scale, and
 * 1 without its eigenproblem when one Cholesky factorisation proves
 * T M_r - S positive definite (then every eigenvalue of the block is
 * below T, which *below records). */
static double scale_certified(int nn, const double *K, const double *m, int nc, const int *comp, double target,
                              int *below) {
  int idx[DTM_STRUCT_DOF] = {0}, it[DTM_STRUCT_DOF], ir[DTM_STRUCT_DOF], nt = 0, nr = 0, nb = nn * nc;
  double Kb[DTM_STRUCT_DOF * DTM_STRUCT_DOF], A[DTM_STRUCT_DOF * DTM_STRUCT_DOF], S[DTM_STRUCT_DOF * DTM_STRUCT_DOF];
  double mt[DTM_STRUCT_DOF], mr[DTM_STRUCT_DOF];
  for (int i = 0; i < nb; i++) idx[i] = ND * (i / nc) + comp[i % nc];
  extract(ND * nn, K, nb, idx, Kb);
  for (int i = 0; i < nb; i++) {
    if (idx[i] % ND >= 3)
      mr[nr] = m[idx[i]], ir[nr++] = i;
    else
      mt[nt] = m[idx[i]], it[nt++] = i;
  }
  *below = 0;
  for (int i = 0; i < nt; i++)
    for (int j = 0; j < nt; j++) A[i * nt + j] = (i == j ? target * mt[i] : 0) - Kb[it[i] * nb + it[j]];
  if (cholesky(nt, A)) return INFINITY;
  schur(nb, Kb, nt, it, nr, ir, A, S);
  double C[DTM_STRUCT_DOF * DTM_STRUCT_DOF];
  for (int i = 0; i < nr * nr; i++) C[i] = -S[i];
  for (int i = 0; i < nr; i++) C[i * nr + i] += target * mr[i];
  if (cholesky(nr, C) == 0) return *below = 1, 1.0;
  return fmax(1, lumped_max(nr, S, mr, 1) / target);
}

/* dtm_struct_bounds_fast from the reference eigenvalue lref. */
static void bounds_from(int nn, const double *K, const double *m, double lref, int ntr, const int *comp_tr, int need,
                        double screen, double out[3]) {
  int below = 0;
  out[0] = lref;
  if (need & DTM_STRUCT_NEED_SCALE)
    out[1] = scale_certified(nn, K, m, ntr, comp_tr, lref, &below);
  else
    out[1] = NAN, below = block_below(nn, K, m, ntr, comp_tr, lref);
  if (below) { /* no transverse eigenvalue above T */
    out[1] = 1, out[2] = lref;
    return;
  }
  out[2] = NAN;
  if (!(need & DTM_STRUCT_NEED_PHYSICAL)) return;
  /* below the screen: not wanted. s T bounds it for free: S(sigma), the
   * Schur complement at sigma, decreases as sigma grows, so sigma M - K is
   * positive semidefinite from sigma = s T up; else one factorisation */
  if (screen > lref && isfinite(out[1]) && out[1] * lref < screen * (1 - 1e-12)) return;
  if (screen > lref && block_below(nn, K, m, ntr, comp_tr, screen)) return;
  out[2] = fmax(lref, block_max(nn, K, m, ntr, comp_tr, 1, 1));
}

void dtm_struct_bounds_fast(int nn, const double *K, const double *m, int nref, const int *comp_ref, int ntr,
                            const int *comp_tr, int need, double screen, double out[3]) {
  bounds_from(nn, K, m, block_max(nn, K, m, nref, comp_ref, 1, 1), ntr, comp_tr, need, screen, out);
}

/* ---- the shell ---- */

static int check_section(const dtm_shell_section *s) {
  char t1[48], t2[48];
  if (!(s->E > 0) || !isfinite(s->E) || !(s->rho > 0) || !isfinite(s->rho))
    return DTM_ERR(DTM_ERR_INPUT, "shell: E and rho must be finite and > 0 (got %s, %s)",
                   dtm_units_si_text(DTM_UNIT_MODULUS, s->E, 6, t1, sizeof t1),
                   dtm_units_si_text(DTM_UNIT_DENSITY, s->rho, 6, t2, sizeof t2));
  if (!(s->nu > -1 && s->nu < 0.5))
    return DTM_ERR(DTM_ERR_INPUT, "shell: Poisson's ratio must lie in (-1, 0.5) (got %g)", s->nu);
  if (!(s->thickness > 0) || !isfinite(s->thickness))
    return DTM_ERR(DTM_ERR_INPUT, "shell: thickness must be finite and > 0 (got %s)",
                   dtm_units_si_text(DTM_UNIT_LENGTH, s->thickness, 6, t1, sizeof t1));
  if (!(s->k_shear >= 0) || !isfinite(s->k_shear))
    return DTM_ERR(DTM_ERR_INPUT, "shell: shear correction must be finite and >= 0 (got %g)", s->k_shear);
  return DTM_OK;
}

/* Frame and local coordinates of the nn corners x[nn][3]. */
static int shell_frame(int nn, const double *x, shell_elem *e) {
  double r[3];
  if (dtm_elem_plane_axes(nn, x, e->axes)) return -1;
  for (int a = 0; a < nn; a++) {
    dtm_v3_sub(x + 3 * a, x, r);
    e->xl[a][0] = dtm_v3_dot(r, e->axes[0]), e->xl[a][1] = dtm_v3_dot(r, e->axes[1]), e->xl[a][2] = 0;
  }
  return 0;
}

static int shell_setup(int type, const dtm_shell_section *sec, const double *x, shell_elem *e) {
  if (type != DTM_TRI3 && type != DTM_QUAD4)
    return DTM_ERR(DTM_ERR_INPUT, "shell: element type %d is not tri3 (2) or quad4 (3)", type);
  DTM_CHECK(check_section(sec));
  e->type = type, e->nn = type == DTM_TRI3 ? 3 : 4;
  e->E = sec->E, e->nu = sec->nu, e->rho = sec->rho, e->t = sec->thickness;
  e->k = sec->k_shear > 0 ? sec->k_shear : 5.0 / 6.0;
  if (shell_frame(e->nn, x, e)) return DTM_ERR(DTM_ERR_INPUT, "shell: degenerate element (no plane)");
  dtm_ref_rule(type, &e->q);
  double dj;
  int k = dtm_map_first_bad(type, 2, e->nn, (const double(*)[3])e->xl, &e->q, &dj);
  if (k >= 0) return DTM_ERR(DTM_ERR_INPUT, "shell: degenerate or inverted element (det J = %g at point %d)", dj, k);
  return DTM_OK;
}

/* Unknowns a strain of each kind involves, per node (the others' columns
 * of its B are zero): membrane u, v; bending theta_x, theta_y; transverse
 * shear w, theta_x, theta_y. */
static const int membrane_dofs[] = {0, 1}, bending_dofs[] = {3, 4}, shear_dofs[] = {2, 3, 4};

/* K[n][n] += w B^T D B for B[nr][n] and D[nr][nr], whose nonzero columns
 * are the unknowns dofs[nd] of each of the nn = n / 6 nodes: the sums of
 * the full product without its terms with a zero column, which only added
 * zeros, each entry's terms in the same order (a third to a ninth of the
 * work). B's and D B's nonzero columns are packed first (bc, dbc). */
static void add_btdb(int n, int nr, const double *B, const double *D, double w, double *restrict K, const int *dofs,
                     int nd) {
  double bc[3][DTM_STRUCT_DOF], dbc[3][DTM_STRUCT_DOF];
  int col[DTM_STRUCT_DOF], nc = 0;
  for (int a = 0; a < n / ND; a++)
    for (int k = 0; k < nd; k++) col[nc++] = ND * a + dofs[k];
  for (int r = 0; r < nr; r++)
    for (int jj = 0; jj < nc; jj++) bc[r][jj] = B[r * n + col[jj]];
  for (int r = 0; r < nr; r++)
    for (int jj = 0; jj < nc; jj++) {
      dbc[r][jj] = 0;
      for (int c = 0; c < nr; c++) dbc[r][jj] += D[r * nr + c] * bc[c][jj];
    }
  for (int ii = 0; ii < nc; ii++) {
    double *row = K + col[ii] * n;
    for (int r = 0; r < nr; r++) {
      if (bc[r][ii] == 0) continue;
      double f = w * bc[r][ii];
      for (int jj = 0; jj < nc; jj++) row[col[jj]] += f * dbc[r][jj];
    }
  }
}

/* Plane-stress matrix times f: f E/(1-nu^2) [1 nu 0; nu 1 0; 0 0 (1-nu)/2]. */
static void plane_stress(double E, double nu, double f, double D[9]) {
  double c = f * E / (1 - nu * nu);
  double v[9] = {c, c * nu, 0, c * nu, c, 0, 0, 0, c * (1 - nu) / 2};
  memcpy(D, v, sizeof v);
}

/* Membrane and bending at every point of the full rule. */
static void add_membrane_bending(const shell_elem *e, double *K) {
  int n = ND * e->nn;
  double N[DTM_K_NODES], g[DTM_K_NODES][3], dv, Dm[9], Db[9];
  plane_stress(e->E, e->nu, e->t, Dm);
  plane_stress(e->E, e->nu, e->t * e->t * e->t / 12, Db);
  for (int k = 0; k < e->q.n; k++) {
    double Bm[3 * DTM_STRUCT_DOF] = {0}, Bb[3 * DTM_STRUCT_DOF] = {0}; /* [3][n] */
    dtm_map_eval(e->type, 2, e->nn, (const double(*)[3])e->xl, e->q.p[k], e->q.w[k], N, g, &dv);
    for (int a = 0; a < e->nn; a++) {
      int u = ND * a, v = u + 1, tx = u + 3, ty = u + 4;
      Bm[u] = g[a][0], Bm[n + v] = g[a][1], Bm[2 * n + u] = g[a][1], Bm[2 * n + v] = g[a][0];
      Bb[ty] = g[a][0], Bb[n + tx] = -g[a][1], Bb[2 * n + ty] = g[a][1], Bb[2 * n + tx] = -g[a][0];
    }
    add_btdb(n, 3, Bm, Dm, dv, K, membrane_dofs, 2);
    add_btdb(n, 3, Bb, Db, dv, K, bending_dofs, 2);
  }
}

/* quad4 shear at the centre (weight 4). */
static void add_shear_quad(const shell_elem *e, double *K) {
  int n = ND * e->nn;
  double N[DTM_K_NODES], g[DTM_K_NODES][3], dv, p[3] = {0, 0, 0}, Bs[2 * DTM_STRUCT_DOF] = {0}; /* Bs[2][n] */
  double kgt = e->k * e->E / (2 * (1 + e->nu)) * e->t, Ds[4] = {kgt, 0, 0, kgt};
  dtm_map_eval(e->type, 2, e->nn, (const double(*)[3])e->xl, p, 4, N, g, &dv);
  for (int a = 0; a < e->nn; a++) {
    int w = ND * a + 2, tx = w + 1, ty = w + 2;
    Bs[w] = g[a][0], Bs[ty] = N[a], Bs[n + w] = g[a][1], Bs[n + tx] = -N[a];
  }
  add_btdb(n, 2, Bs, Ds, dv, K, shear_dofs, 3);
}

/* tri3 MITC3 shear: Bs[2][n] at a point with N[3] and gradients g[3][3]. */
static void mitc3_b(const shell_elem *e, const double *N, const double (*g)[3], double *Bs) {
  int n = ND * 3;
  for (int ed = 0; ed < 3; ed++) {
    int i = ed, j = (ed + 1) % 3;
    double dx = e->xl[j][0] - e->xl[i][0], dy = e->xl[j][1] - e->xl[i][1];
    for (int r = 0; r < 2; r++) {
      double phi = N[i] * g[j][r] - N[j] * g[i][r], *b = Bs + r * n;
      b[ND * j + 2] += phi, b[ND * i + 2] -= phi;
      b[ND * i + 4] += phi * dx / 2, b[ND * j + 4] += phi * dx / 2;
      b[ND * i + 3] -= phi * dy / 2, b[ND * j + 3] -= phi * dy / 2;
    }
  }
}

static void add_shear_tri(const shell_elem *e, double *K) {
  double N[DTM_K_NODES], g[DTM_K_NODES][3], dv;
  double kgt = e->k * e->E / (2 * (1 + e->nu)) * e->t, Ds[4] = {kgt, 0, 0, kgt};
  for (int k = 0; k < e->q.n; k++) {
    double Bs[2 * DTM_STRUCT_DOF] = {0};
    dtm_map_eval(e->type, 2, 3, (const double(*)[3])e->xl, e->q.p[k], e->q.w[k], N, g, &dv);
    mitc3_b(e, N, (const double(*)[3])g, Bs);
    add_btdb(ND * 3, 2, Bs, Ds, dv, K, shear_dofs, 3);
  }
}

/* Local diagonal masses m[ND nn]: rho t integral N_a, J_a = t^2/12 m_a. */
static void shell_mass(const shell_elem *e, double *m) {
  double ma[4], t2 = e->t * e->t / 12;
  dtm_lumped_mass(e->type, 2, e->nn, (const double(*)[3])e->xl, &e->q, ma);
  for (int a = 0; a < e->nn; a++)
    for (int i = 0; i < ND; i++) m[ND * a + i] = e->rho * e->t * ma[a] * (i < 3 ? 1 : t2);
}

/* The fast tri3: bending (constant: one point with the whole area) and
 * MITC3 shear, without the membrane block (its eigenvalue comes from the
 * plane-stress closed form, dtm_kernel_shell_bounds), from the constant gradients of the linear shape
 * functions, N at the rule's points in barycentric form, det J = 2 A, and
 * the row-sum masses A/3 (what the generic evaluation gives, to
 * rounding). */
static void tri3_fast(const shell_elem *e, double *K, double *m) {
  const double(*xl)[3] = (const double(*)[3])e->xl;
  double dj = xl[1][0] * xl[2][1] - xl[2][0] * xl[1][1], g[3][3] = {{0}}, Db[9], Bb[3 * 18] = {0};
  g[1][0] = xl[2][1] / dj, g[1][1] = -xl[2][0] / dj, g[2][0] = -xl[1][1] / dj, g[2][1] = xl[1][0] / dj;
  g[0][0] = -g[1][0] - g[2][0], g[0][1] = -g[1][1] - g[2][1];
  plane_stress(e->E, e->nu, e->t * e->t * e->t / 12, Db);
  for (int a = 0; a < 3; a++) {
    int tx = ND * a + 3, ty = tx + 1;
    Bb[ty] = g[a][0], Bb[18 + tx] = -g[a][1], Bb[36 + ty] = g[a][1], Bb[36 + tx] = -g[a][0];
  }
  add_btdb(18, 3, Bb, Db, dj / 2, K, bending_dofs, 2);
  /* MITC3 shear as C^T G C: the edge integrals c = C u (C[3][18], see
   * mitc3_b) and G the Gram matrix of the three Whitney fields times k G t */
  double kgt = e->k * e->E / (2 * (1 + e->nu)) * e->t, G[9] = {0}, C[3 * 18] = {0};
  for (int k = 0; k < e->q.n; k++) {
    double N[3] = {1 - e->q.p[k][0] - e->q.p[k][1], e->q.p[k][0], e->q.p[k][1]}, phi[2][3], w = e->q.w[k] * dj * kgt;
    for (int ed = 0; ed < 3; ed++)
      for (int r = 0; r < 2; r++) phi[r][ed] = N[ed] * g[(ed + 1) % 3][r] - N[(ed + 1) % 3] * g[ed][r];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) G[3 * a + b] += w * (phi[0][a] * phi[0][b] + phi[1][a] * phi[1][b]);
  }
  for (int ed = 0; ed < 3; ed++) {
    int i = ed, j = (ed + 1) % 3;
    double dx = xl[j][0] - xl[i][0], dy = xl[j][1] - xl[i][1], *c = C + 18 * ed;
    c[ND * j + 2] = 1, c[ND * i + 2] = -1;
    c[ND * i + 4] = c[ND * j + 4] = dx / 2;
    c[ND * i + 3] = c[ND * j + 3] = -dy / 2;
  }
  add_btdb(18, 3, C, G, 1, K, shear_dofs, 3);
  for (int a = 0; a < 3; a++)
    for (int i = 0; i < ND; i++) m[ND * a + i] = e->rho * e->t * (dj / 6) * (i < 3 ? 1 : e->t * e->t / 12);
}

/* Local K[ND nn][ND nn] and m[ND nn] (fast: a tri3 by tri3_fast). */
static int shell_local_with(int type, const dtm_shell_section *sec, const double *x, shell_elem *e, double *K,
                            double *m, int fast) {
  DTM_CHECK(shell_setup(type, sec, x, e));
  memset(K, 0, sizeof(double) * ND * e->nn * ND * e->nn);
  if (fast && type == DTM_TRI3) return tri3_fast(e, K, m), DTM_OK;
  add_membrane_bending(e, K);
  if (type == DTM_QUAD4)
    add_shear_quad(e, K);
  else
    add_shear_tri(e, K);
  shell_mass(e, m);
  return DTM_OK;
}

static int shell_local(int type, const dtm_shell_section *sec, const double *x, shell_elem *e, double *K, double *m) {
  return shell_local_with(type, sec, x, e, K, m, 0);
}

static const int membrane_comp[2] = {0, 1}, transverse_comp[3] = {2, 3, 4}; /* w first: see dtm_struct_bounds */

int dtm_kernel_shell_lambda(int type, const dtm_shell_section *sec, const double *x, dtm_shell_lambda *out) {
  shell_elem e;
  double K[DTM_STRUCT_DOF * DTM_STRUCT_DOF], m[DTM_STRUCT_DOF], b[4];
  DTM_CHECK(shell_local(type, sec, x, &e, K, m));
  dtm_struct_bounds(e.nn, K, m, 2, membrane_comp, 3, transverse_comp, b);
  out->lambda_membrane = b[0], out->lambda_physical = b[1], out->lambda_scaled = b[2], out->scale = b[3];
  return DTM_OK;
}

int dtm_kernel_shell_physical(int type, const dtm_shell_section *sec, const double *x, double out[3], double *m,
                              int *nn) {
  shell_elem e;
  double K[DTM_STRUCT_DOF * DTM_STRUCT_DOF];
  DTM_CHECK(shell_local(type, sec, x, &e, K, m));
  dtm_struct_physical(e.nn, K, m, 2, membrane_comp, 3, transverse_comp, out);
  *nn = e.nn;
  return DTM_OK;
}

int dtm_kernel_shell_scale(int type, const dtm_shell_section *sec, const double *x, double out[2], double *m, int *nn) {
  shell_elem e;
  double K[DTM_STRUCT_DOF * DTM_STRUCT_DOF];
  DTM_CHECK(shell_local(type, sec, x, &e, K, m));
  dtm_struct_ref_scale(e.nn, K, m, 2, membrane_comp, 3, transverse_comp, out);
  *nn = e.nn;
  return DTM_OK;
}

int dtm_kernel_shell_bounds(int type, const dtm_shell_section *sec, const double *x, int need, double screen,
                            double out[3], double *m, int *nn) {
  shell_elem e;
  double K[DTM_STRUCT_DOF * DTM_STRUCT_DOF];
  DTM_CHECK(shell_local_with(type, sec, x, &e, K, m, 1));
  if (type == DTM_TRI3) { /* the membrane eigenvalue of the plane-stress kernel (t cancels; structural.h) */
    dtm_elastic_moduli mod;
    double lref;
    DTM_CHECK(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, sec->E, sec->nu, sec->rho, &mod));
    DTM_CHECK(dtm_kernel_elastic_lambda(DTM_TRI3, &mod, (const double *)e.xl, &lref));
    bounds_from(e.nn, K, m, lref, 3, transverse_comp, need, screen, out);
  } else
    dtm_struct_bounds_fast(e.nn, K, m, 2, membrane_comp, 3, transverse_comp, need, screen, out);
  *nn = e.nn;
  return DTM_OK;
}

int dtm_kernel_shell_masses(int type, const dtm_shell_section *sec, const double *x, double *m, int *nn) {
  shell_elem e;
  DTM_CHECK(shell_setup(type, sec, x, &e));
  shell_mass(&e, m);
  *nn = e.nn;
  return DTM_OK;
}

int dtm_kernel_shell_matrices(int type, const dtm_shell_section *sec, const double *x, dtm_rotary_convention conv,
                              dtm_struct_matrices *out) {
  shell_elem e;
  double K[DTM_STRUCT_DOF * DTM_STRUCT_DOF], b[2];
  DTM_CHECK(shell_local(type, sec, x, &e, K, out->m));
  int n = ND * e.nn;
  if (conv == DTM_ROTARY_SCALED) {
    dtm_struct_ref_scale(e.nn, K, out->m, 2, membrane_comp, 3, transverse_comp, b);
    if (!isfinite(b[1]))
      return DTM_ERR(DTM_ERR_INPUT, "shell: no finite rotary inertia scale reaches the target (k G too large)");
    for (int i = 0; i < n; i++) out->m[i] *= i % ND >= 3 ? b[1] : 1;
  }
  out->nn = e.nn;
  memcpy(out->axes, e.axes, sizeof e.axes);
  dtm_struct_to_global(e.nn, (const double(*)[3])e.axes, K, out->K);
  memset(out->M, 0, sizeof(double) * n * n);
  for (int i = 0; i < n; i++) out->M[i * n + i] = out->m[i];
  return DTM_OK;
}
