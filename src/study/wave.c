/* `dtmap verify --accuracy` in the library: proof by simulation of the
 * predicted phase-speed error. A plane wave u0 = p cos(k.x) (p the
 * polarisation: along k for P, across it for S) with zero velocity is put
 * on the nodes of the host material (the material of the largest volume)
 * and integrated undamped by central differences with the lumped mass,
 *   u_1 = u_0 - dt^2/2 M^-1 K u_0,  u_{n+1} = 2 u_n - u_{n-1} - dt^2 M^-1 K u_n,
 * at the step given, for several periods:
 * - on a periodic sample (src/study/periodic.c: the mesh of a box whose
 *   opposite faces carry the same nodes, made one unknown), the whole
 *   plane wave, its wave vector the nearest that fits the box, for 12
 *   periods (or --periods): no boundary is met;
 * - on any other mesh, a packet under a Gaussian window of width sigma
 *   about the host's centre (a quarter of the free distance d, half the
 *   smallest extent of its box, but at most (d - 3 lambda) / 2 so that the
 *   run covers 3 periods, and at least a wavelength), run until its part
 *   above e^-2 of the peak could reach the boundary; when the mesh cannot
 *   hold that at the frequency asked, the default frequency is raised to
 *   the lowest that fits (a frequency given with --freq is refused);
 * - with --periods on a bounded mesh, the whole plane wave, boundary
 *   included.
 * Its projection on the plane-wave mode,
 *   q_n = sum_a m_a (p.u_a) cos(k.x_a) / sum_a m_a,
 * picks the Fourier component k of the field: on a lattice one cosine at
 * the Bloch frequency; on an unstructured mesh the coherent wave (a sharp
 * peak) plus a spread of higher frequencies from the elements'
 * fluctuations. The measured frequency is that of the coherent wave: the
 * largest peak of the Hann-windowed spectrum of q, refined by the least-
 * squares fit of one sinusoid (exact for a single oscillation, whatever the
 * run's length); the mean frequency of q (its Rayleigh quotient) would be
 * too stiff there. A straight line through the zero crossings is kept as a
 * second figure. The measured error is omega / (c k) - 1; the prediction is
 * the same wave's from the measures' model (dtm_measures_phase_along). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "dtmap/cost.h"
#include "dtmap/kernel.h"
#include "dtmap/operator.h"
#include "dtmap/verify.h"
#include "wave-impl.h"

#define PI 3.14159265358979323846
#define PACKET_PERIODS 3    /* a packet runs at least this many periods */
#define PERIODIC_PERIODS 12 /* the whole wave on a periodic sample, by default */

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
 * about the centre x0 of the host's bounding box; the free distance is
 * half its smallest extent (set here), sigma is chosen by plan_packet. */
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
  const size_t *root; /* [nnodes] a periodic sample's node classes (NULL: none) */
  double *mc;         /* [n] the mass of each unknown's class (m without classes) */
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

/* Each unknown's class mass: the sum over the nodes of its class. */
static void class_mass(wave_state *s, size_t nnodes) {
  memcpy(s->mc, s->m, s->n * sizeof *s->mc);
  for (size_t a = 0; s->root && a < nnodes; a++)
    for (int c = 0; c < s->nc && s->root[a] != a; c++)
      s->mc[s->root[a] * (size_t)s->nc + c] += s->m[a * (size_t)s->nc + c];
}

/* One step (f = K u_n computed here); first: the zero-velocity start. A
 * class's forces are summed on its root, which steps; its other nodes copy it. */
static void wave_step(wave_state *s, double dt, int first) {
  size_t nn = s->n / (size_t)s->nc;
  dtm_operator_apply(s->op, s->u, s->f);
  for (size_t a = 0; s->root && a < nn; a++)
    for (int c = 0; c < s->nc && s->root[a] != a; c++)
      s->f[s->root[a] * (size_t)s->nc + c] += s->f[a * (size_t)s->nc + c];
  for (size_t i = 0; i < s->n; i++) {
    if (s->root && s->root[i / (size_t)s->nc] != i / (size_t)s->nc) continue;
    double acc = s->mc[i] > 0 ? s->f[i] / s->mc[i] : 0;
    double un = first ? s->u[i] - 0.5 * dt * dt * acc : 2 * s->u[i] - s->up[i] - dt * dt * acc;
    s->up[i] = s->u[i], s->u[i] = s->mc[i] > 0 ? un : 0;
  }
  for (size_t a = 0; s->root && a < nn; a++)
    for (int c = 0; c < s->nc && s->root[a] != a; c++) {
      size_t i = a * (size_t)s->nc + c, r = s->root[a] * (size_t)s->nc + c;
      s->up[i] = s->up[r], s->u[i] = s->u[r];
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

/* The least-squares fit of A cos(omega t) + B sin(omega t) to q over
 * [n0, n1) (t = n dt): its energy in *energy, the phase of A - i B. */
static double fit_phase(const double *q, int n0, int n1, double dt, double omega, double *energy) {
  double cc = 0, ss = 0, cs = 0, qc = 0, qs = 0;
  for (int n = n0; n < n1; n++) {
    double c = cos(omega * n * dt), s = sin(omega * n * dt);
    cc += c * c, ss += s * s, cs += c * s, qc += q[n] * c, qs += q[n] * s;
  }
  double det = cc * ss - cs * cs, A = det > 0 ? (qc * ss - qs * cs) / det : 0,
         B = det > 0 ? (qs * cc - qc * cs) / det : 0;
  if (energy) *energy = A * qc + B * qs;
  return atan2(-B, A);
}

/* The frequency of the largest peak of the Hann-windowed spectrum of q
 * over [0.3, 2] omega0; refined by golden section on the energy of the fit
 * of one sinusoid within a grid step, then twice by the drift of the fitted
 * phase between the two halves of the run (the energy's maximum is flat:
 * its location is known to sqrt(round-off) only; the phase's drift is not).
 * Exact for a single oscillation, whatever the run's length. */
static double tone_omega(const double *q, int nq, double dt, double omega0) {
  double step = 2 * PI / (8 * nq * dt), best = -1, w1 = omega0;
  for (double w = 0.3 * omega0; w <= 2 * omega0; w += step) {
    double re = 0, im = 0;
    for (int n = 0; n < nq; n++) {
      double h = 0.5 - 0.5 * cos(2 * PI * n / (nq - 1));
      re += h * q[n] * cos(w * n * dt), im += h * q[n] * sin(w * n * dt);
    }
    if (re * re + im * im > best) best = re * re + im * im, w1 = w;
  }
  double a = w1 - step, b = w1 + step, g = 0.5 * (sqrt(5.0) - 1), ec, ed;
  for (int it = 0; it < 60 && b - a > 1e-12 * w1; it++) {
    double c = b - g * (b - a), d = a + g * (b - a);
    fit_phase(q, 0, nq, dt, c, &ec), fit_phase(q, 0, nq, dt, d, &ed);
    if (ec > ed)
      b = d;
    else
      a = c;
  }
  double w = 0.5 * (a + b);
  for (int it = 0; it < 2; it++) {
    double drift = fit_phase(q, nq / 2, nq, dt, w, NULL) - fit_phase(q, 0, nq / 2, dt, w, NULL);
    w += remainder(drift, 2 * PI) / (0.5 * nq * dt);
  }
  return w;
}

static void wave_free(wave_state *s) { free(s->u), free(s->up), free(s->f), free(s->w), free(s->mc); }

static int wave_alloc(wave_state *s) {
  size_t b = (s->n ? s->n : 1) * sizeof(double);
  s->u = malloc(b), s->up = malloc(b), s->f = malloc(b), s->w = malloc(b), s->mc = malloc(b);
  if (s->u && s->up && s->f && s->w && s->mc) return DTM_OK;
  wave_free(s);
  return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the wave run");
}

/* Integrate for r->duration (window win, classes root) and measure omega into r. */
static int wave_run(const dtm_operator *op, const dtm_mesh *mesh, const char *on, const wave_window *win,
                    const size_t *root, double dt, dtm_wave_result *r) {
  wave_state s = {
      .op = op, .n = dtm_operator_ndof(op), .nc = dtm_operator_ncomp(op), .m = dtm_operator_mass(op), .root = root};
  DTM_CHECK(wave_alloc(&s));
  double k[3] = {r->k * r->dir[0], r->k * r->dir[1], r->k * r->dir[2]};
  class_mass(&s, mesh->nnodes);
  wave_start(&s, mesh, on, win, k, r->pol);
  int nq = (int)ceil(r->duration / dt) + 1;
  double *q = malloc((size_t)nq * sizeof *q), t0 = dtm_wtime();
  if (!q) return wave_free(&s), DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the wave run");
  for (int n = 0; n < nq; n++) {
    q[n] = project(&s);
    if (n + 1 < nq) wave_step(&s, dt, n == 0);
  }
  r->omega_crossings = crossing_omega(q, nq, dt, &r->crossings);
  r->omega = tone_omega(q, nq, dt, r->speed * r->k);
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

/* The wave on a periodic sample: the nearest wave vector that fits the
 * box (a wavelength along the direction's largest component when it
 * rounds to none), the whole wave for w->periods (default 12) periods. */
static void plan_periodic(const dtm_mesh *mesh, const dtm_wave_spec *w, const dtm_wave_periodic *pp,
                          dtm_wave_result *r) {
  double k[3] = {r->k * w->dir[0], r->k * w->dir[1], r->k * w->dir[2]};
  if (!dtm_wave_periodic_fit(pp, mesh->dim, k)) {
    int c = fabs(w->dir[1]) > fabs(w->dir[0]) ? 1 : 0;
    c = fabs(w->dir[2]) > fabs(w->dir[c]) ? 2 : c;
    k[c] = copysign(2 * PI / pp->L[c], w->dir[c]);
  }
  r->k = sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
  for (int c = 0; c < 3; c++) r->dir[c] = k[c] / r->k;
  r->f = r->speed * r->k / (2 * PI), r->periodic = 1;
  r->duration = (w->periods > 0 ? w->periods : PERIODIC_PERIODS) * 2 * PI / (r->speed * r->k);
}

/* The packet on a bounded mesh: a window of at least a wavelength that
 * leaves PACKET_PERIODS periods before the boundary; the default frequency
 * is raised until the mesh holds that, a given one is refused. */
static int plan_packet(const dtm_mesh *mesh, const char *on, const dtm_wave_spec *w, wave_window *win,
                       dtm_wave_result *r) {
  window_of(mesh, on, win);
  double d = win->distance, lam = 2 * PI / r->k;
  if (d < (PACKET_PERIODS + 2) * lam) {
    double fmin = (PACKET_PERIODS + 2) * r->speed / d;
    if (!w->raise)
      return DTM_ERR(DTM_ERR_INPUT,
                     "verify --accuracy: at %.4g Hz the mesh's free distance (%.3g m, half its smallest extent) "
                     "holds a packet for %.2g periods; %d need %.4g Hz or more (or a periodic sample: a box meshed "
                     "with periodic faces)",
                     w->f, d, fmax(d / lam - 2, 0), PACKET_PERIODS, fmin);
    r->f = fmin, r->k = 2 * PI * fmin / r->speed, lam = 2 * PI / r->k;
  }
  win->sigma = fmin(d / 4, (d - PACKET_PERIODS * lam) / 2);
  r->duration = (d - 2 * win->sigma) / r->speed;
  return DTM_OK;
}

/* The frequency, wave vector, window and duration of the run into r and win. */
static int plan(const dtm_mesh *mesh, const char *on, const dtm_wave_spec *w, const dtm_wave_periodic *pp,
                wave_window *win, dtm_wave_result *r) {
  r->f = w->f, r->k = 2 * PI * w->f / r->speed;
  memcpy(r->dir, w->dir, sizeof r->dir);
  win->sigma = 0;
  if (pp->periodic) return plan_periodic(mesh, w, pp, r), DTM_OK;
  if (w->periods > 0) return r->duration = w->periods * 2 * PI / (r->speed * r->k), DTM_OK;
  return plan_packet(mesh, on, w, win, r);
}

/* Whether every node of the mesh is on the host (a periodic sample must be the host alone). */
static int all_on(const dtm_mesh *mesh, const char *on) {
  for (size_t a = 0; a < mesh->nnodes; a++)
    if (!on[a]) return 0;
  return 1;
}

/* Plan, predict and run the wave of analysis a (operator op, host nodes on). */
static int wave_measure(const dtm_analysis *a, const dtm_operator *op, const char *on, double dt,
                        const dtm_wave_spec *w, dtm_wave_result *r) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  dtm_wave_periodic pp = {0};
  wave_window win = {{0, 0, 0}, 0, 0};
  if (mesh->dim >= 2 && all_on(mesh, on)) DTM_CHECK(dtm_wave_periodic_find(mesh, &pp));
  int rc = plan(mesh, on, w, &pp, &win, r);
  polarisation(w->mode, dtm_analysis_space_dim(a), r->dir, r->pol);
  if (!rc) rc = dtm_measures_phase_along(a, r->f, dt, r->dir, r->pol, w->mode, r->material, &r->predicted);
  if (!rc && r->predicted.unresolved && r->f != w->f)
    rc = DTM_ERR(DTM_ERR_INPUT,
                 "verify --accuracy: the mesh is too small for a packet: at %.4g Hz, the lowest at which one runs %d "
                 "periods, %zu host elements have fewer than 2 per wavelength (mesh finer, or a periodic sample: a "
                 "box meshed with periodic faces)",
                 r->f, PACKET_PERIODS, r->predicted.unresolved);
  r->sigma = win.sigma;
  if (!rc) rc = wave_run(op, mesh, on, &win, pp.periodic ? pp.root : NULL, dt, r);
  dtm_wave_periodic_free(&pp);
  return rc;
}

/* The mesh's phase-speed measure as `run` reports it, into *m (kind 0: none). */
static int mesh_measure(const dtm_analysis *a, dtm_measure *m) {
  dtm_measures *ms = NULL;
  memset(m, 0, sizeof *m);
  DTM_CHECK(dtm_measures_compute(a, 0, NULL, &ms));
  for (int k = 0; k < ms->n; k++)
    if (ms->m[k].kind == DTM_MEASURE_PHASE) *m = ms->m[k];
  dtm_measures_destroy(&ms);
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
  r->speed = r->predicted.speed; /* the branch's exact speed in the host */
  char *on = calloc(mesh->nnodes + 1, 1);
  dtm_operator *op = NULL;
  int rc = on ? dtm_analysis_operator(a, elastic_effect(a), 0, &op) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (rc == DTM_OK && dtm_operator_ncomp(op) < mesh->dim) rc = DTM_ERR(DTM_ERR_INPUT, "verify --accuracy: no plane");
  if (rc == DTM_OK) host_nodes(mesh, r->material, on), rc = wave_measure(a, op, on, dt, w, r);
  dtm_operator_destroy(&op);
  free(on);
  DTM_CHECK(rc);
  DTM_CHECK(mesh_measure(a, &r->mesh));
  r->measured = r->omega / (r->speed * r->k) - 1;
  r->agreement = (r->measured - r->predicted.mean) / fabs(r->predicted.mean);
  return DTM_OK;
}
