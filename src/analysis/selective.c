/* Selective mass scaling of an analysed model (include/dtmap/selective.h):
 * the elastic effect's undamped element steps (the analysis keeps them
 * per effect, dtm_analysis_effect_dt_undamped) give each element's beta
 * for the element target T / safety, so that the recommended step
 * (safety x the scaled model's global step) can reach T; the operator of
 * that effect without damping carries the lumped masses the added masses
 * are built from (src/spectral/sms.c); the scaled model's global step is
 * Lanczos on (K, M_s) with the certificate's budget and the probable
 * layer's eps as the global estimate's (global.c). Damping is left out of
 * the scaled model's step: the scaled elements' frequencies fall, and
 * with them a stiffness-proportional damping's reduction of the step, so
 * the undamped figure is the one the scaling is judged on.
 * The solver's cost: an explicit solver with M_s solves M_s a = f - K u
 * every step. The iterations of Jacobi PCG at DTM_SMS_SOLVER_RTOL are
 * counted on right-hand sides K u for random u (the stiffness forces of
 * a field with every wavelength), and each costs about one product with
 * the assembled M_s, timed here against one product with K on this mesh:
 * the time per step grows by 1 + iterations x that ratio. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "dtmap/selective.h"
#include "dtmap/util.h"

#define COST_DRAWS 3        /* right-hand sides the CG iterations are averaged over */
#define CG_MAXIT 10000      /* iterations of one solve at most */
#define TIMING_SECONDS 0.05 /* each product is repeated for at least this long */

/* The first wave effect with an element map and an operator. */
static int wave_effect(const dtm_analysis *a) {
  for (int k = 0; k < a->neffects; k++)
    if (a->dt_effect[k] && a->effects[k].cls->coefficients && dtm_analysis_is_wave(a, k)) return k;
  return -1;
}

static int check(const dtm_analysis *a, double target, int *k) {
  const char *path = a->scene->path;
  if (!(target > 0) || !isfinite(target))
    return DTM_ERR(DTM_ERR_INPUT, "%s: selective mass scaling needs a target step > 0", path);
  if (a->x) return DTM_ERR(DTM_ERR_INPUT, "%s: selective mass scaling runs on one whole mesh, without mpirun", path);
  if (dtm_analysis_has_rotations(a))
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s: selective mass scaling of shells and beams is not supported (their rotations "
                   "would need a form of their own)",
                   path);
  if ((*k = wave_effect(a)) < 0)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s: selective mass scaling needs an elastic (wave) effect; this scene has none "
                   "(diffusion only?)",
                   path);
  return DTM_OK;
}

/* beta per element, the smallest steps before and after, and where the
 * largest beta is. */
static void factors(const dtm_analysis *a, int k, dtm_selective_mass *o, double *beta) {
  const double *dt = dtm_analysis_effect_dt_undamped(a, k);
  size_t n = a->nel;
  dtm_sms_beta(n, dt, o->element_target, beta);
  o->dt_input = o->element_min = INFINITY, o->beta_element = (size_t)-1;
  for (size_t i = 0; i < n; i++) {
    double after;
    if (!(dt[i] > 0) || !isfinite(dt[i])) continue;
    dtm_sms_element_steps(1, dt + i, beta + i, &after);
    o->dt_input = fmin(o->dt_input, dt[i]), o->element_min = fmin(o->element_min, after);
  }
}

static size_t global_index(const dtm_analysis *a, int block, size_t local) {
  size_t i = 0;
  for (int b = 0; b < block; b++) i += a->mesh->blocks[b].n;
  return i + local;
}

/* Seconds of one call of the product f (K or M_s) on x. */
static double time_product(const dtm_operator *op, const dtm_csr *ms, const double *x, double *y) {
  int reps = 0;
  double t0 = dtm_wtime(), t;
  do {
    if (ms)
      dtm_csr_apply(ms, x, y);
    else
      dtm_operator_apply(op, x, y);
    reps++;
  } while ((t = dtm_wtime() - t0) < TIMING_SECONDS);
  return t / reps;
}

/* The CG iterations per solve at the solver's tolerance and the products'
 * cost ratio. */
static int solver_cost(const dtm_operator *op, const dtm_sms *s, unsigned seed, dtm_selective_mass *o) {
  size_t n = dtm_operator_ndof(op);
  dtm_csr ms = {0};
  double *u = malloc((n + 1) * sizeof *u), *f = malloc((n + 1) * sizeof *f), *x = malloc((n + 1) * sizeof *x);
  int r = u && f && x ? dtm_sms_assemble(s, 0, &ms) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  long total = 0;
  for (int d = 0; d < COST_DRAWS && r == DTM_OK; d++) {
    int it = 0;
    dtm_operator_draw(op, seed + 1000u * (unsigned)(d + 1), -1, 1, u);
    dtm_operator_apply(op, u, f);
    r = dtm_sms_solve(&ms, f, DTM_SMS_SOLVER_RTOL, CG_MAXIT, x, &it);
    total += it;
  }
  if (r == DTM_OK) {
    o->cg_iterations = (double)total / COST_DRAWS;
    o->product_ratio = time_product(op, &ms, u, x) / time_product(op, NULL, u, x);
    o->runtime_factor = 1 + o->cg_iterations * o->product_ratio;
  }
  free(u), free(f), free(x);
  dtm_csr_free(&ms);
  return r;
}

/* The undamped operator of effect k and the added masses of beta. */
static int build(const dtm_analysis *a, int k, const double *beta, dtm_operator **op, dtm_sms **s) {
  int r = dtm_analysis_operator(a, k, 0.0, op);
  if (r == DTM_OK && dtm_operator_kind(*op) != DTM_OP_ELASTIC)
    r = DTM_ERR(DTM_ERR_INPUT, "%s: selective mass scaling needs an elastic effect", a->scene->path);
  if (r == DTM_OK) r = dtm_sms_create(*op, a->mesh, (const unsigned char *const *)a->level, beta, s);
  return r;
}

static int scaled(const dtm_analysis *a, int k, double tol, int maxit, const double *beta, dtm_selective_mass *o) {
  dtm_operator *op = NULL;
  dtm_sms *s = NULL;
  double safety = a->scene->safety;
  int r = build(a, k, beta, &op, &s);
  if (r == DTM_OK) dtm_sms_stats_get(s, &o->stats);
  if (r == DTM_OK && o->stats.beta_block >= 0)
    o->beta_element = global_index(a, o->stats.beta_block, o->stats.beta_local);
  if (r == DTM_OK)
    r = dtm_sms_lambda_max(op, s, tol, maxit, dtm_analysis_seed(a), dtm_analysis_cert_budget(a), 1 - safety * safety,
                           &o->global);
  if (r == DTM_OK) r = solver_cost(op, s, dtm_analysis_seed(a), o);
  dtm_sms_destroy(&s);
  dtm_operator_destroy(&op);
  return r;
}

/* The field verify starts from: uniform in [-1, 1] per dof, from the seed. */
static int run_verify(const dtm_operator *op, const dtm_sms *s, unsigned seed, double dt, int steps,
                      dtm_verify_result *vr, double *cg_mean) {
  size_t n = dtm_operator_ndof(op);
  double *u0 = malloc((n + 1) * sizeof *u0);
  if (!u0) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  dtm_operator_draw(op, seed, -1, 1, u0);
  int r = dtm_sms_verify_run(op, s, dt, steps, u0, vr, cg_mean);
  free(u0);
  return r;
}

/* The operator and scaled mass of m, made again from a's element steps. */
static int rebuild(const dtm_analysis *a, const dtm_selective_mass *m, dtm_operator **op, dtm_sms **s) {
  double *beta = malloc((a->nel + 1) * sizeof *beta);
  if (!beta) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  dtm_sms_beta(a->nel, dtm_analysis_effect_dt_undamped(a, m->effect), m->element_target, beta);
  int r = build(a, m->effect, beta, op, s);
  free(beta);
  return r;
}

int dtm_analysis_selective_verify(const dtm_analysis *a, const dtm_selective_mass *m, double dt, int steps,
                                  dtm_verify_result *vr, double *cg_mean) {
  dtm_operator *op = NULL;
  dtm_sms *s = NULL;
  int r = rebuild(a, m, &op, &s);
  if (r == DTM_OK) r = run_verify(op, s, dtm_analysis_seed(a), dt, steps, vr, cg_mean);
  dtm_sms_destroy(&s);
  dtm_operator_destroy(&op);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_analysis_selective_added(const dtm_analysis *a, const dtm_selective_mass *m, dtm_csr *out) {
  dtm_operator *op = NULL;
  dtm_sms *s = NULL;
  memset(out, 0, sizeof *out);
  int r = rebuild(a, m, &op, &s);
  if (r == DTM_OK) r = dtm_sms_assemble(s, 1, out);
  dtm_sms_destroy(&s);
  dtm_operator_destroy(&op);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_analysis_selective_mass(const dtm_analysis *a, double target, double tol, int maxit, dtm_selective_mass *out) {
  double t0 = dtm_wtime();
  int k = -1;
  memset(out, 0, sizeof *out);
  DTM_CHECK(check(a, target, &k));
  double *beta = malloc((a->nel + 1) * sizeof *beta);
  if (!beta) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  out->target = target, out->effect = k, out->element_target = target / a->scene->safety;
  factors(a, k, out, beta);
  int r = scaled(a, k, tol > 0 ? tol : 1e-4, maxit > 0 ? maxit : 400, beta, out);
  free(beta);
  out->recommended = a->scene->safety * out->global.dt;
  int vouched = out->global.certified == DTM_CERT_PROVEN || out->global.certified == DTM_CERT_PROBABLE;
  out->target_met = vouched && out->recommended >= target * (1 - 1e-12);
  out->seconds = dtm_wtime() - t0;
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
