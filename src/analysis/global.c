/* The global estimate behind --posterior: for every spectral effect, build
 * its matrix-free operator (with the scene's damping as element Rayleigh
 * coefficients) and run Lanczos on M^-1/2 K M^-1/2. Ritz values approach
 * lambda_max from below, so theta alone would give a step that is too
 * large; the step dtmap vouches for uses theta + residual, and only when
 * converged; otherwise the nodal bound stays the basis. An eigenvalue lies
 * within the residual of theta, but not necessarily the top one: when the
 * top of the spectrum is clustered (refine's point masses equalise the
 * limiting modes) Lanczos can converge on the second. So the bound is
 * certified where that is affordable (dtm_lanczos_max_certified: the
 * factorisation of sigma I - A proves every eigenvalue below sigma, and a
 * refuted bound sends Lanczos on, stricter); where it is not, a mesh with
 * point masses runs Lanczos to tol * 1e-4 instead (not a proof), and the
 * probable layer (dtm_lanczos_max_probable) goes on until the
 * Kuczynski-Wozniakowski bound's eps_k is at most 1 - safety^2 (waves;
 * 1 - safety for diffusion, whose step goes as 1 / lambda): then
 * lambda_max <= theta / (1 - eps_k) with probability at least 1 - 1e-12
 * for any spectrum, and its step (dt_certified, mapped from lambda to dt
 * by step_of like every other estimate) is at least safety x the global
 * step, so dtm_recommend can take the smaller of the two (at safety 1,
 * eps_k cannot reach 0 and Lanczos runs its maxit steps: the recommended
 * step is then the certified one). The global step itself (theta +
 * residual) stays an estimate with its tolerance. The caller
 * decides whether a converged estimate may be the basis at all (run
 * --posterior), so that verify, which needs the modes, checks exactly the
 * step run reports, and refine's mass round estimates through here too.
 * Damping enters through the smallest factor of the effect's materials at
 * the top frequency.
 * Curved second-order elements: the operator integrates each at the rule
 * level its search kept (src/kernel/curved.c), and the model the step is
 * for is the converged integration, which no level reaches exactly. The
 * remaining quadrature error is bounded and taken off the step rather
 * than driven below the Lanczos margin by more levels: the strongly
 * curved elements that need it (Gmsh's cone demo at order 2: Jacobian
 * ratio 0.09, levels 14-15 for 1e-8) would cost 3,375 points each in
 * every operator product, and levels stop at 8. The safe side is
 * theta + residual + quad, quad the largest element's remaining change of
 * its mass-scaled stiffness (dtm_analysis_quadrature_margin, curvature.c:
 * by the partition of the lumped masses the assembled top eigenvalue moves
 * by at most that), itself estimated from the level search's last changes
 * (curved.c): an estimate, not a proof, checked against an independent
 * converged integration (t342). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"

#define LANCZOS_SEED 20261121u
/* The certificate of the bound (src/spectral/certify.c, CHOLMOD) is made
 * when CHOLMOD's analysis predicts a factorisation within the run's own
 * cost: at most CERT_TIMES x the wall time of the run before it (reading
 * the mesh, the element map, the nodal bound) at CERT_RATE flop/s, and
 * never less than CERT_FLOOR flops, within certify.c's memory cap.
 * CERT_RATE is the whole certificate's rate on one core here (ordering,
 * probing, factorisation and margin, with Debian's single-threaded
 * OpenBLAS under CHOLMOD): predicted flops over CPU seconds, 7.9e9 to
 * 8.4e9 on boxes of 22,026 and 36,813 unknowns, 2.2e10 at 105,912 where
 * the factorisation's kernels dominate (docs/certificate.md). CERT_FLOOR
 * is a second at that rate, about a whole run's time for a mesh of 1e4 to
 * 1e5 unknowns (0.5-1 s, most of it outside the phases the budget counts):
 * every box up to about 22,000 unknowns in 3D, slender parts further.
 * Above it the certificate is "too dear" and the summary gives CHOLMOD's
 * predicted flops and bytes against the flops allowed. */
#define CERT_RATE 8e9
#define CERT_TIMES 1.0
#define CERT_FLOOR 8e9

/* DTMAP_BENCH_CERT_BUDGET (flops) replaces it, for bench/certify_reach.py's
 * factorisations past the budget and for tests/t307 (a probable report). */
double dtm_analysis_cert_budget(const dtm_analysis *a) {
  const char *bench = getenv("DTMAP_BENCH_CERT_BUDGET");
  if (bench && *bench) return atof(bench);
  double t = a->timings[DTM_T_MESH] + a->timings[DTM_T_EXTRACT] + a->timings[DTM_T_EFFECTS] + a->timings[DTM_T_NODAL];
  return fmax(CERT_FLOOR, CERT_TIMES * CERT_RATE * t);
}

unsigned dtm_analysis_seed(const dtm_analysis *a) { return a->lanczos_seed ? a->lanczos_seed : LANCZOS_SEED; }

/* Rayleigh coefficients of material i from the scene's damping effects. */
static int material_rayleigh(const dtm_analysis *a, int i, double omega, double *al, double *be) {
  *al = *be = 0;
  for (int j = 0; j < a->neffects && omega > 0; j++) {
    const dtm_effect *mj = &a->effects[j];
    double aj = 0, bj = 0;
    if (!(mj->cls->role & DTM_ROLE_MODIFIES_WAVES) || !mj->cls->rayleigh) continue;
    DTM_CHECK(mj->cls->rayleigh(mj->state, &a->scene->materials[i].m, omega, &aj, &bj));
    *al += aj, *be += bj;
  }
  return DTM_OK;
}

typedef struct {
  dtm_operator_coeffs *c; /* [nslots] per material and section (dtm_analysis_slot) */
  double *al, *be;        /* [nslots] */
  char *used;             /* [nslots] */
} material_table;

static void slots_used(const dtm_analysis *a, char *used) {
  for (int b = 0; b < a->mesh->nblocks; b++)
    for (size_t e = 0; e < a->mesh->blocks[b].n; e++) used[dtm_analysis_slot(a, &a->mesh->blocks[b], e)] = 1;
}

static int fill_table(const dtm_analysis *a, int k, double omega, material_table *t) {
  int nm = a->scene->nmaterials;
  slots_used(a, t->used);
  for (int i = 0; i < dtm_analysis_nslots(a); i++) {
    if (!t->used[i]) continue;
    DTM_CHECK(dtm_analysis_coefficients(a, k, i, &t->c[i]));
    if (t->c[i].kind == DTM_OP_ELASTIC) DTM_CHECK(material_rayleigh(a, i % nm, omega, &t->al[i], &t->be[i]));
  }
  return DTM_OK;
}

int dtm_analysis_operator(const dtm_analysis *a, int k, double omega_top, dtm_operator **op) {
  size_t nm = (size_t)dtm_analysis_nslots(a) + 1;
  material_table t = {calloc(nm, sizeof *t.c), calloc(nm, sizeof(double)), calloc(nm, sizeof(double)), calloc(nm, 1)};
  int r =
      (t.c && t.al && t.be && t.used) ? fill_table(a, k, omega_top, &t) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int kind = DTM_OP_NONE;
  for (int i = 0; i < dtm_analysis_nslots(a); i++)
    if (t.used[i]) kind = t.c[i].kind;
  dtm_operator_kept kept = {(const dtm_section_bounds *const *)a->rot, (const unsigned char *const *)a->level};
  if (r == DTM_OK)
    r = dtm_operator_create_kept(a->mesh, kind, t.c, t.al, t.be, a->scene->nmaterials, a->scene->nsections, &kept, op);
  free(t.c), free(t.al), free(t.be), free(t.used);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

/* Smallest damping factor over the used materials (of every part) at
 * omega. */
static int damping_factor(const dtm_analysis *a, double omega, double *fac) {
  char *used = calloc((size_t)a->scene->nmaterials + 1, 1);
  int r = used ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (used) dtm_mesh_materials_used(a->mesh, a->scene->nmaterials, used);
  *fac = 1.0;
  for (int j = 0; j < a->neffects && r == DTM_OK; j++) {
    const dtm_effect *mj = &a->effects[j];
    if (!(mj->cls->role & DTM_ROLE_MODIFIES_WAVES)) continue;
    for (int i = 0; i < a->scene->nmaterials && r == DTM_OK; i++) {
      double f = 1.0;
      if (used[i]) r = mj->cls->wave_factor(mj->state, &a->scene->materials[i].m, omega, &f);
      *fac = fmin(*fac, f);
    }
  }
  free(used);
  return dtm_x_reduce(a, r, fac, 1, DTM_X_MIN);
}

/* Steps from an eigenvalue estimate lam of effect k. */
static int step_of(const dtm_analysis *a, int k, double lam, double *dt) {
  if (!dtm_analysis_is_wave(a, k)) return *dt = 2.0 / lam, DTM_OK;
  double f = 1.0;
  DTM_CHECK(damping_factor(a, sqrt(lam), &f));
  *dt = 2.0 / sqrt(lam) * f;
  return DTM_OK;
}

/* Point masses make clustered tops the rule (they equalise the limiting
 * modes): without a certificate, Lanczos then goes to a stricter tolerance. */
static int has_point_masses(const dtm_analysis *a) {
  for (size_t v = 0; a->mesh->node_mass && v < a->mesh->nnodes; v++)
    if (a->mesh->node_mass[v] > 0) return 1;
  return 0;
}

/* The probable bound's step (NaN when there is none). */
static int certified_step(dtm_analysis *a, int k, const dtm_lanczos_result *lr, dtm_global_info *g) {
  g->deterministic = lr->deterministic, g->eps = lr->eps, g->failure = lr->failure;
  g->nbound = lr->nbound, g->seed = lr->seed, g->dt_certified = NAN;
  if (lr->certified != DTM_CERT_PROBABLE) return DTM_OK;
  return step_of(a, k, lr->bound + g->quad_err, &g->dt_certified); /* the converged model's, as dt_low */
}

static int estimate_effect(dtm_analysis *a, int k, double tol, int maxit, int want_mode) {
  dtm_global_info *g = &a->global[k];
  dtm_operator *op = NULL;
  dtm_lanczos_result lr;
  memset(&lr, 0, sizeof lr);
  unsigned seed = dtm_analysis_seed(a);
  double budget = dtm_analysis_cert_budget(a); /* the certificate's flops, read once for the call and the report */
  /* the eps at which safety x the step of theta is the probable bound's step:
     dt ~ lambda^-1/2 for waves, lambda^-1 for diffusion */
  double safety = a->scene->safety, eps_target = dtm_analysis_is_wave(a, k) ? 1 - safety * safety : 1 - safety;
  int r = dtm_analysis_operator(a, k, 0.0, &op);
  if (a->x) /* the whole mesh's operator, of which op is this part's share */
    r = a->x->eigen(a->x->ctx, r, op, tol, maxit, seed, &lr);
  else if (r == DTM_OK)
    r = dtm_lanczos_max_probable(op, tol, maxit, seed, want_mode, budget, has_point_masses(a), eps_target, &lr);
  dtm_operator_destroy(&op);
  DTM_CHECK(r);
  double quad = 0; /* the converged integration's eigenvalue is at most theta + residual + quad */
  DTM_CHECK(dtm_x_reduce(a, dtm_analysis_quadrature_margin(a, k, &quad), &quad, 1, DTM_X_MAX));
  *g = (dtm_global_info){.done = 1,
                         .theta = lr.theta,
                         .residual = lr.residual,
                         .iterations = lr.iterations,
                         .converged = lr.converged,
                         .seconds = lr.seconds,
                         .dt_low = NAN,
                         .dt_high = NAN,
                         .omega_top = sqrt(lr.theta + lr.residual),
                         .mode = lr.mode,
                         .certified = lr.certified,
                         .cert_predicted = {lr.cert_predicted[0], lr.cert_predicted[1]},
                         .cert_budget = budget,
                         .cert_seconds = lr.cert_seconds,
                         .quad_err = quad};
  DTM_CHECK(step_of(a, k, lr.theta + lr.residual + quad, &g->dt_low));
  DTM_CHECK(step_of(a, k, lr.theta, &g->dt_high));
  DTM_CHECK(certified_step(a, k, &lr, g));
  g->seed = seed; /* also for a distributed run */
  a->per_effect[k].global = g->converged ? g->dt_low : NAN;
  a->per_effect[k].certified = g->converged ? g->dt_certified : NAN;
  return DTM_OK;
}

/* The advice again when the global basis moved its target (recommend.c):
 * the size suggestion and the elements below the target. */
static int readvise(dtm_analysis *a) {
  double t0 = dtm_wtime();
  free(a->size_node), free(a->forced);
  a->size_node = NULL, a->forced = NULL;
  DTM_CHECK(dtm_size_suggest(a));
  DTM_CHECK(dtm_x_agree(a, dtm_shape_classify(a)));
  a->timings[DTM_T_ADVICE] += dtm_wtime() - t0;
  return DTM_OK;
}

static void global_free(dtm_analysis *a) {
  for (int k = 0; a->global && k < a->neffects; k++) free(a->global[k].mode);
  free(a->global);
  a->global = NULL;
}

int dtm_analysis_estimate_global(dtm_analysis *a, double tol, int maxit, unsigned flags) {
  double t0 = dtm_wtime(), advised = a->advice_target;
  int want_modes = (flags & DTM_GLOBAL_MODES) != 0;
  global_free(a); /* an earlier estimate (after the masses changed) */
  a->global = calloc((size_t)a->neffects + 1, sizeof *a->global);
  DTM_CHECK(dtm_x_agree(a, a->global ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory")));
  for (int k = 0; k < a->neffects; k++)
    if (a->dt_effect[k] && a->effects[k].cls->coefficients) DTM_CHECK(estimate_effect(a, k, tol, maxit, want_modes));
  a->global_basis = (flags & DTM_GLOBAL_BASIS) != 0;
  dtm_recommend(a);
  a->timings[DTM_T_GLOBAL] = dtm_wtime() - t0;
  return a->advice_target != advised ? readvise(a) : DTM_OK;
}
