/* The explicit time integration of a selectively scaled model (`dtmap
 * verify --selective-mass`): central differences with the scaled mass,
 *   M_s (u_{n+1} - 2 u_n + u_{n-1}) = -dt^2 K u_n,
 * from rest (u_{-1} = u_0), each step one product with K and one Jacobi
 * PCG solve with the assembled M_s to DTM_SMS_LANCZOS_RTOL (tight, so
 * that the scheme run is the one with the exact M_s: a solver's looser
 * tolerance would add its own error to what is verified), and the norm
 * sqrt(u_n^T K u_n + v^T M_s v) with v = (u_n - u_{n-1}) / dt. The scheme is
 * stable exactly when dt^2 lambda_max(K, M_s) < 4. Undamped; the growth
 * is the largest norm over the second half of the run over the initial
 * one, unstable past 1e6 or at a value that is not finite (then it
 * stops), as dtm_verify_run for the lumped model (integrate.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/sms.h"
#include "dtmap/util.h"
#include "spectral.h"

#define CG_MAXIT 10000

typedef struct {
  const dtm_operator *op;
  dtm_csr ms;
  size_t n;
  double dt;
  double *u, *up, *f, *a, *w; /* u_n, u_{n-1}, K u_n, the acceleration, work */
  long cg;                    /* CG iterations in all */
} sv_state;

static double norm_now(sv_state *s) {
  double e = 0;
  dtm_operator_apply(s->op, s->u, s->f);
  for (size_t i = 0; i < s->n; i++) s->w[i] = (s->u[i] - s->up[i]) / s->dt;
  dtm_csr_apply(&s->ms, s->w, s->a);
  for (size_t i = 0; i < s->n; i++) e += s->u[i] * s->f[i] + s->w[i] * s->a[i];
  return sqrt(fmax(e, 0));
}

/* u_{n+1} (f = K u_n already computed). */
static int step(sv_state *s) {
  int it = 0;
  for (size_t i = 0; i < s->n; i++) s->w[i] = -s->f[i];
  DTM_CHECK(dtm_sms_solve(&s->ms, s->w, DTM_SMS_LANCZOS_RTOL, CG_MAXIT, s->a, &it));
  s->cg += it;
  for (size_t i = 0; i < s->n; i++) {
    double un = 2 * s->u[i] - s->up[i] + s->dt * s->dt * s->a[i];
    s->up[i] = s->u[i], s->u[i] = un;
  }
  return DTM_OK;
}

static int integrate(sv_state *s, int steps, double e0, dtm_verify_result *r) {
  for (int n = 0;; n++) {
    if (dtm_verify_sample(n, steps, n ? norm_now(s) / e0 : 1.0, r)) return DTM_OK;
    DTM_CHECK(step(s));
    r->steps = n + 1;
  }
}

static void sv_free(sv_state *s) {
  free(s->u), free(s->up), free(s->f), free(s->a), free(s->w);
  dtm_csr_free(&s->ms);
}

static int sv_init(sv_state *s, const dtm_sms *sms, const double *u0) {
  size_t b = (s->n + 1) * sizeof(double);
  s->u = malloc(b), s->up = malloc(b), s->f = malloc(b), s->a = malloc(b), s->w = malloc(b);
  if (!s->u || !s->up || !s->f || !s->a || !s->w) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  DTM_CHECK(dtm_sms_assemble(sms, 0, &s->ms));
  const double *m = dtm_operator_mass(s->op);
  for (size_t i = 0; i < s->n; i++) {
    if (!isfinite(u0[i])) return DTM_ERR(DTM_ERR_INPUT, "the initial field is not finite at dof %zu", i);
    s->u[i] = s->up[i] = m[i] > 0 ? u0[i] : 0;
  }
  return DTM_OK;
}

int dtm_sms_verify_run(const dtm_operator *op, const dtm_sms *sms, double dt, int steps, const double *u0,
                       dtm_verify_result *r, double *cg_mean) {
  memset(r, 0, sizeof *r);
  if (!(dt > 0) || !isfinite(dt) || steps < 1)
    return DTM_ERR(DTM_ERR_INPUT, "verification needs dt > 0 (got %g) and steps >= 1 (got %d)", dt, steps);
  double t0 = dtm_wtime();
  sv_state s = {.op = op, .n = dtm_operator_ndof(op), .dt = dt};
  int rc = sv_init(&s, sms, u0);
  double e0 = rc == DTM_OK ? norm_now(&s) : 0;
  if (rc == DTM_OK && (!(e0 > 0) || !isfinite(e0)))
    rc = DTM_ERR(DTM_ERR_INPUT, "the initial field has no energy (norm %g): nothing to verify", e0);
  if (rc == DTM_OK) rc = integrate(&s, steps, e0, r);
  if (cg_mean) *cg_mean = r->steps ? (double)s.cg / r->steps : NAN;
  sv_free(&s);
  r->seconds = dtm_wtime() - t0;
  return rc;
}
