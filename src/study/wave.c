/* `dtmap verify --accuracy` in the library: proof by simulation of the
 * predicted phase-speed error. A plane wave u0 = p cos(k.x) (p the
 * polarisation: along k for P, across it for S) with zero velocity is put
 * on the nodes of the host material (the material of the largest volume)
 * under a Gaussian window (a packet, see wave_window; or, given a number
 * of periods, everywhere on the host) and integrated undamped by central
 * differences with the lumped mass,
 *   u_1 = u_0 - dt^2/2 M^-1 K u_0,  u_{n+1} = 2 u_n - u_{n-1} - dt^2 M^-1 K u_n,
 * at the step given. Its projection on the plane-wave mode,
 *   q_n = sum_a m_a (p.u_a) cos(k.x_a) / sum_a m_a,
 * picks the single Fourier component k of the field: on a translation-
 * invariant mesh (a lattice) it oscillates at exactly the discrete
 * frequency of k whatever the window, until the wave meets the boundary;
 * the packet's run stops before that. (The whole plane wave on a bounded
 * mesh is not an eigenmode: the boundary mixes in the frequencies of
 * nearby wave numbers, a spread of about c pi / size.) Its zero crossings,
 * linearly interpolated, are fitted by a straight line over all of them:
 * half a period per crossing, so omega = pi / slope, and the measured
 * error is omega / (c k) - 1. The prediction is the mass-weighted mean of
 * the host elements' lattice errors for the same direction, branch,
 * frequency and step (dtm_measures_phase_along). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "dtmap/cost.h"
#include "dtmap/kernel.h"
#include "dtmap/operator.h"
#include "dtmap/verify.h"

#define PI 3.14159265358979323846

/* The material of the largest volume (the host of the wave). */
static int host_material(const dtm_mesh *mesh, int nmat) {
  double *v = calloc((size_t)nmat + 1, sizeof *v), x[3 * DTM_MAX_NODES];
  int best = -1;
  if (!v) return -1;
  for (int b = 0; b < mesh->nblocks; b++)
    for (size_t e = 0; e < mesh->blocks[b].n; e++) {
      const dtm_block *bl = &mesh->blocks[b];
      if (bl->mat[e] < 0 || bl->dim != mesh->dim) continue;
      for (int j = 0; j < bl->nn; j++) memcpy(x + 3 * j, mesh->xyz + 3 * bl->conn[e * bl->nn + j], 3 * sizeof *x);
      v[bl->mat[e]] += fabs(dtm_elem_measure(bl->type, x));
    }
  for (int m = 0; m < nmat; m++)
    if (v[m] > 0 && (best < 0 || v[m] > v[best])) best = m;
  free(v);
  return best;
}

/* on[nnodes] = 1 for the nodes of the host's elements. */
static void host_nodes(const dtm_mesh *mesh, int host, char *on) {
  for (int b = 0; b < mesh->nblocks; b++)
    for (size_t e = 0; e < mesh->blocks[b].n; e++)
      for (int j = 0; mesh->blocks[b].mat[e] == host && j < mesh->blocks[b].nn; j++)
        on[mesh->blocks[b].conn[e * mesh->blocks[b].nn + j]] = 1;
}

/* The polarisation of branch mode along n in nc components: n itself (P)
 * or the in-plane normal (2D) / a unit vector normal to n (3D) (S). */
static void polarisation(int mode, int nc, const double n[3], double p[3]) {
  memcpy(p, n, 3 * sizeof *p);
  if (!mode) return;
  if (nc == 2) {
    p[0] = -n[1], p[1] = n[0], p[2] = 0;
    return;
  }
  double a[3] = {0, 0, 0}, len;
  a[fabs(n[0]) < 0.9 ? 0 : 1] = 1;
  p[0] = a[1] * n[2] - a[2] * n[1], p[1] = a[2] * n[0] - a[0] * n[2], p[2] = a[0] * n[1] - a[1] * n[0];
  len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  for (int c = 0; c < 3; c++) p[c] /= len;
}

/* The packet's window over the host's nodes: a Gaussian of width sigma
 * about the mass-free centroid x0 of the host's nodes, sigma a quarter of
 * the free distance (half the smallest extent of their bounding box); the
 * free time is (distance - 2 sigma) / c: until then no part of the wave
 * above e^-2 of its peak has met the boundary. */
typedef struct {
  double x0[3];    /* centre, m */
  double sigma;    /* width, m (0: no window, the whole host) */
  double distance; /* free distance from x0 to the box's nearest side, m */
} wave_window;

static void window_of(const dtm_mesh *mesh, const char *on, wave_window *w) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t a = 0; a < mesh->nnodes; a++)
    for (int c = 0; c < 3 && on[a]; c++)
      lo[c] = fmin(lo[c], mesh->xyz[3 * a + c]), hi[c] = fmax(hi[c], mesh->xyz[3 * a + c]);
  w->distance = INFINITY;
  for (int c = 0; c < 3; c++) {
    w->x0[c] = 0.5 * (lo[c] + hi[c]);
    if (c < mesh->dim) w->distance = fmin(w->distance, 0.5 * (hi[c] - lo[c]));
  }
  w->sigma = w->distance / 4;
}

static double window_at(const wave_window *w, const double *x) {
  if (!(w->sigma > 0)) return 1;
  double r2 = 0;
  for (int c = 0; c < 3; c++) r2 += (x[c] - w->x0[c]) * (x[c] - w->x0[c]);
  return exp(-r2 / (2 * w->sigma * w->sigma));
}

typedef struct {
  const dtm_operator *op;
  size_t n;           /* dofs */
  int nc;             /* components per node */
  const double *m;    /* lumped mass [n] */
  double *u, *up, *f; /* u_n, u_{n-1}, K u_n */
  double *w;          /* projection weights [n]: m_a p_c cos(k.x_a) / sum m_a (0 off the host) */
} wave_state;

/* u0 and the projection weights from the wave vector k and polarisation p. */
static void wave_start(wave_state *s, const dtm_mesh *mesh, const char *on, const wave_window *win, const double k[3],
                       const double p[3]) {
  double msum = 0;
  for (size_t a = 0; a < mesh->nnodes; a++) {
    const double *x = mesh->xyz + 3 * a;
    double cs = cos(k[0] * x[0] + k[1] * x[1] + k[2] * x[2]);
    for (int c = 0; c < s->nc; c++) {
      size_t i = a * (size_t)s->nc + c;
      s->u[i] = on[a] && s->m[i] > 0 ? p[c] * cs * window_at(win, x) : 0;
      s->w[i] = on[a] ? s->m[i] * p[c] * cs : 0;
      msum += on[a] && c == 0 ? s->m[i] : 0;
    }
  }
  for (size_t i = 0; i < s->n; i++) s->w[i] /= msum;
}

static double project(const wave_state *s) {
  double q = 0;
  for (size_t i = 0; i < s->n; i++) q += s->w[i] * s->u[i];
  return q;
}

/* One step (f = K u_n computed here); first: the zero-velocity start. */
static void wave_step(wave_state *s, double dt, int first) {
  dtm_operator_apply(s->op, s->u, s->f);
  for (size_t i = 0; i < s->n; i++) {
    double acc = s->m[i] > 0 ? s->f[i] / s->m[i] : 0;
    double un = first ? s->u[i] - 0.5 * dt * dt * acc : 2 * s->u[i] - s->up[i] - dt * dt * acc;
    s->up[i] = s->u[i], s->u[i] = s->m[i] > 0 ? un : 0;
  }
}

/* Straight-line fit of the zero crossings of q[0..nq) (step dt): omega =
 * pi / slope; NaN with fewer than 4 crossings. */
static double crossing_omega(const double *q, int nq, double dt, int *ncross) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int j = 0;
  for (int n = 0; n + 1 < nq; n++) {
    if (!((q[n] > 0 && q[n + 1] <= 0) || (q[n] < 0 && q[n + 1] >= 0))) continue;
    double t = (n + q[n] / (q[n] - q[n + 1])) * dt;
    sx += j, sy += t, sxx += (double)j * j, sxy += j * t, j++;
  }
  *ncross = j;
  if (j < 4) return NAN;
  double slope = (j * sxy - sx * sy) / (j * sxx - sx * sx);
  return PI / slope;
}

/* The least-squares frequency of the recurrence q_{n+1} + q_{n-1} =
 * 2 cos(omega dt) q_n over the run: exact for a single oscillation, and
 * usable over less than a period. */
static double recurrence_omega(const double *q, int nq, double dt) {
  double num = 0, den = 0;
  for (int n = 1; n + 1 < nq; n++) num += q[n] * (q[n + 1] + q[n - 1]), den += 2 * q[n] * q[n];
  double c = den > 0 ? num / den : NAN;
  return c >= -1 && c <= 1 ? acos(c) / dt : NAN;
}

static void wave_free(wave_state *s) { free(s->u), free(s->up), free(s->f), free(s->w); }

static int wave_alloc(wave_state *s) {
  size_t b = (s->n ? s->n : 1) * sizeof(double);
  s->u = malloc(b), s->up = malloc(b), s->f = malloc(b), s->w = malloc(b);
  if (s->u && s->up && s->f && s->w) return DTM_OK;
  wave_free(s);
  return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the wave run");
}

/* Integrate spec->periods periods and measure omega into r. */
static int wave_run(const dtm_operator *op, const dtm_mesh *mesh, const char *on, const dtm_wave_spec *w, double dt,
                    const double k[3], dtm_wave_result *r) {
  wave_state s = {.op = op, .n = dtm_operator_ndof(op), .nc = dtm_operator_ncomp(op), .m = dtm_operator_mass(op)};
  DTM_CHECK(wave_alloc(&s));
  double p[3];
  polarisation(w->mode, s.nc, w->dir, p);
  wave_window win = {{0, 0, 0}, 0, 0};
  if (!(w->periods > 0)) window_of(mesh, on, &win);
  wave_start(&s, mesh, on, &win, k, p);
  double T = w->periods > 0 ? w->periods * 2 * PI / (r->speed * r->k) : (win.distance - 2 * win.sigma) / r->speed;
  int nq = (int)ceil(T / dt) + 1;
  r->sigma = win.sigma, r->duration = T;
  double *q = malloc((size_t)nq * sizeof *q), t0 = dtm_wtime();
  if (!q) return wave_free(&s), DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the wave run");
  for (int n = 0; n < nq; n++) {
    q[n] = project(&s);
    if (n + 1 < nq) wave_step(&s, dt, n == 0);
  }
  r->omega_crossings = crossing_omega(q, nq, dt, &r->crossings);
  r->omega = recurrence_omega(q, nq, dt);
  r->steps = nq - 1, r->seconds = dtm_wtime() - t0;
  free(q), wave_free(&s);
  return DTM_OK;
}

static int elastic_effect(const dtm_analysis *a) {
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    if (!strcmp(dtm_analysis_effect(a, k)->name, "elastic")) return k;
  return -1;
}

static int check_spec(const dtm_analysis *a, const dtm_wave_spec *w, double dt) {
  double len = sqrt(w->dir[0] * w->dir[0] + w->dir[1] * w->dir[1] + w->dir[2] * w->dir[2]);
  if (elastic_effect(a) < 0)
    return DTM_ERR(DTM_ERR_INPUT, "%s: verify --accuracy: the scene has no elastic effect",
                   dtm_analysis_scene(a)->path);
  if (!(w->f > 0) || !isfinite(w->f) || !(dt > 0) || !isfinite(dt) || !(w->periods == 0 || w->periods >= 2) ||
      (w->mode != 0 && w->mode != 1) || fabs(len - 1) > 1e-9)
    return DTM_ERR(
        DTM_ERR_INPUT,
        "verify --accuracy: needs f > 0 (got %g Hz), dt > 0 (got %g s), periods 0 or >= 2 (got %g), branch P "
        "or S and a unit direction (length %g)",
        w->f, dt, w->periods, len);
  return DTM_OK;
}

int dtm_verify_wave(const dtm_analysis *a, double dt, const dtm_wave_spec *w, dtm_wave_result *r) {
  memset(r, 0, sizeof *r);
  DTM_CHECK(check_spec(a, w, dt));
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  r->material = host_material(mesh, dtm_analysis_scene(a)->nmaterials);
  if (r->material < 0) return DTM_ERR(DTM_ERR_INPUT, "verify --accuracy: no element has a material");
  polarisation(w->mode, dtm_analysis_space_dim(a), w->dir, r->pol);
  DTM_CHECK(dtm_measures_phase_along(a, w->f, dt, w->dir, r->pol, w->mode, r->material, &r->predicted));
  r->speed = r->predicted.speed, r->k = 2 * PI * w->f / r->speed;
  char *on = calloc(mesh->nnodes + 1, 1);
  dtm_operator *op = NULL;
  int rc = on ? dtm_analysis_operator(a, elastic_effect(a), 0, &op) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (rc == DTM_OK && dtm_operator_ncomp(op) < mesh->dim) rc = DTM_ERR(DTM_ERR_INPUT, "verify --accuracy: no plane");
  if (rc == DTM_OK) {
    double k[3] = {r->k * w->dir[0], r->k * w->dir[1], r->k * w->dir[2]};
    host_nodes(mesh, r->material, on);
    rc = wave_run(op, mesh, on, w, dt, k, r);
  }
  dtm_operator_destroy(&op);
  free(on);
  DTM_CHECK(rc);
  r->measured = r->omega / (r->speed * r->k) - 1;
  r->agreement = (r->measured - r->predicted.mean) / fabs(r->predicted.mean);
  return DTM_OK;
}
