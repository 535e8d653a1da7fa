/* The explicit time integration behind `dtmap verify`: run the scheme the
 * step is meant for on the whole mesh and watch an energy norm. Elastic
 * problems use central differences with the lumped mass, the damping force
 * taken on the lagged half-step velocity as fully explicit codes do,
 *   v_{n-1/2} = (u_n - u_{n-1}) / dt,
 *   u_{n+1} = 2 u_n - u_{n-1} - dt^2 M^-1 (K u_n + C v_{n-1/2}),
 * from rest (u_{-1} = u_0), with the norm sqrt(u_n^T K u_n + v^T M v) and
 * v = v_{n-1/2}; diffusion uses forward Euler u_{n+1} = u_n - dt M^-1 K u_n
 * with the norm sqrt(u^T M u). Dofs without mass are held at 0. The growth
 * is the largest norm over the second half of the run over the initial
 * one; a run is unstable when it exceeds 1e6 or a value is not finite, and
 * stops there. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/util.h"
#include "dtmap/operator.h"
#include "dtmap/progress.h"

#define GROWTH_LIMIT 1e6

typedef struct {
  const dtm_operator *op;
  size_t n;
  const double *m; /* lumped diagonal */
  double dt;
  double *u, *up;    /* u_n and u_{n-1} (elastic) */
  double *f, *v, *g; /* K u_n, v_{n-1/2}, C v */
  int elastic;
} vr_state;

/* f = K u_n and the energy norm of the current state. */
static double norm_now(vr_state *s) {
  double e = 0;
  if (!s->elastic) {
    for (size_t i = 0; i < s->n; i++) e += s->m[i] * s->u[i] * s->u[i];
    return sqrt(e);
  }
  dtm_operator_apply(s->op, s->u, s->f);
  for (size_t i = 0; i < s->n; i++) {
    double v = (s->u[i] - s->up[i]) / s->dt;
    e += s->u[i] * s->f[i] + s->m[i] * v * v;
  }
  return sqrt(fmax(e, 0));
}

/* u_{n+1} (f = K u_n already computed). */
static void step_elastic(vr_state *s) {
  size_t n = s->n;
  double dt = s->dt;
  for (size_t i = 0; i < n; i++) s->v[i] = (s->u[i] - s->up[i]) / dt;
  dtm_operator_apply_damping(s->op, s->v, s->g);
  for (size_t i = 0; i < n; i++) {
    double un = s->m[i] > 0 ? 2 * s->u[i] - s->up[i] - dt * dt * (s->f[i] + s->g[i]) / s->m[i] : 0;
    s->up[i] = s->u[i], s->u[i] = un;
  }
}

static void step_diffusion(vr_state *s) {
  dtm_operator_apply(s->op, s->u, s->f);
  for (size_t i = 0; i < s->n; i++) s->u[i] = s->m[i] > 0 ? s->u[i] - s->dt * s->f[i] / s->m[i] : 0;
}

/* The time loop: norms at n = 0 .. steps, growth over n >= steps / 2. */
int dtm_verify_sample(int n, int steps, double q, dtm_verify_result *r) {
  if (n >= steps / 2 || !(q <= GROWTH_LIMIT)) r->growth = fmax(r->growth, q);
  if (!(q <= GROWTH_LIMIT)) {
    r->unstable = 1;
    if (!isfinite(q)) r->growth = INFINITY;
    return 1;
  }
  return n == steps;
}

static void integrate(vr_state *s, int steps, double e0, dtm_verify_result *r) {
  for (int n = 0;; n++) {
    if (dtm_verify_sample(n, steps, n ? norm_now(s) / e0 : 1.0, r)) return;
    if (n % 16 == 0) dtm_progress_update((double)n / steps);
    if (s->elastic)
      step_elastic(s);
    else
      step_diffusion(s);
    r->steps = n + 1;
  }
}

static void vr_free(vr_state *s) { free(s->u), free(s->up), free(s->f), free(s->v), free(s->g); }

static int vr_init(vr_state *s, const double *u0) {
  size_t b = (s->n ? s->n : 1) * sizeof(double);
  s->u = malloc(b), s->up = malloc(b), s->f = malloc(b), s->v = malloc(b);
  s->g = malloc(b);
  if (!s->u || !s->up || !s->f || !s->v || !s->g) {
    vr_free(s);
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the verification run");
  }
  for (size_t i = 0; i < s->n; i++) {
    if (!isfinite(u0[i])) {
      vr_free(s);
      return DTM_ERR(DTM_ERR_INPUT, "the initial field is not finite at dof %zu", i);
    }
    s->u[i] = s->up[i] = s->m[i] > 0 ? u0[i] : 0;
  }
  return DTM_OK;
}

int dtm_verify_run(const dtm_operator *op, double dt, int steps, const double *u0, dtm_verify_result *r) {
  if (!r) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_verify_run: no result");
  memset(r, 0, sizeof *r);
  if (!op || !u0 || !(dt > 0) || !isfinite(dt) || steps < 1)
    return DTM_ERR(DTM_ERR_INPUT,
                   "verification needs dt > 0 (got %g), steps >= 1 (got "
                   "%d) and an initial field",
                   dt, steps);
  double t0 = dtm_wtime();
  vr_state s = {.op = op,
                .n = dtm_operator_ndof(op),
                .m = dtm_operator_mass(op),
                .dt = dt,
                .elastic = dtm_operator_kind(op) == DTM_OP_ELASTIC};
  DTM_CHECK(vr_init(&s, u0));
  double e0 = norm_now(&s);
  if (!(e0 > 0) || !isfinite(e0)) {
    vr_free(&s);
    return DTM_ERR(DTM_ERR_INPUT,
                   "the initial field has no energy (norm %g): nothing "
                   "to verify",
                   e0);
  }
  dtm_progress_begin("verify");
  integrate(&s, steps, e0, r);
  dtm_progress_end();
  vr_free(&s);
  r->seconds = dtm_wtime() - t0;
  return DTM_OK;
}
