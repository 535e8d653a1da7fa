/* The refine loop behind `dtmap refine`. The size field of the input mesh
 * (dtm_analysis_size_field: the current size where a node meets the
 * target, the larger size that reaches it elsewhere, accuracy bounds on
 * top) drives a fresh mesh
 * of the same geometry as its only size source (dtm_gmsh_remesh, with
 * Gmsh's optimisers in 3D), and the new mesh is analysed. Only nodes below
 * the target grow, so the element count falls and the step rises: the run
 * gets cheaper, unless an accuracy bound asks for smaller elements.
 * A fresh mesh has a spread of element shapes, and its worst nodes sit
 * below its typical ones (on Gmsh meshes of uniform size the smallest
 * nodal step is about 0.78 of the median in 3D, 0.8 in 2D; after a remesh
 * with a graded field the worst node of the bundled scenes sat at 0.70-0.75
 * (2D) and 0.81-0.83 (3D) of the field's nominal target). The size that
 * reaches the target is therefore scaled by a calibration c: the first
 * round uses 1/0.72 (2D) or 1/0.8 (3D), and each later one corrects c by
 * the shortfall it measured, c <- c (target / recommended)^(1/p) x 1.02
 * (at least x 1.08, as the worst node of a fresh mesh scatters by about
 * 5 % from one mesh to the next; at most x 1.5), p the size exponent of
 * the effect that sets the step.
 * The field is capped at the length of the model curves a node lies on and
 * graded (slope 0.3), so that the mesher can follow it.
 * Every round remeshes the geometry (which stays loaded) with the size field
 * of the input mesh, so the rounds are a one-dimensional search over c; a
 * round that fell short is followed by a coarser one. The loop keeps the
 * best mesh (saved to a temporary .msh while it remeshes on, and read back
 * at the end) and stops as soon as the target is met, a round makes the run
 * more expensive than the input mesh without meeting the target, or only
 * shape-limited elements remain below the target (or cap it, and a round
 * around them did not beat the kept mesh). A remesh that Gmsh refuses or
 * crashes in (it runs in a child process, src/gmsh/contain.c) ends the loop
 * too, and the kept mesh is read back. When the target is not met, the
 * result names the causes: Gmsh's failure, what the model holds that decides
 * sizes (found on the input mesh, src/gmsh/causes.c), the elements no size
 * lifts, an accuracy bound, and a spent budget with the rounds its trend
 * predicts. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/gmsh.h"
#include "dtmap/progress.h"
#include "dtmap/cost.h"
#include "dtmap/refine.h"
#include "dtmap/util.h"
#include "study-impl.h"

#define GRADE 0.3       /* size slope of the field (m per m): a fresh mesh follows it */
#define MAX_GROWTH 1.5  /* of the calibration from one round to the next */
#define MIN_GROWTH 1.08 /* above the round-to-round scatter of a fresh mesh's worst node (+-5 %) */

/* Size exponent of the effect whose step is the recommendation's basis. */
static double basis_exponent(const dtm_analysis *a) {
  int best = -1;
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    if (dtm_analysis_effect_dt(a, k) &&
        (best < 0 || dtm_analysis_effect_min(a, k)->safe < dtm_analysis_effect_min(a, best)->safe))
      best = k;
  return best >= 0 ? dtm_analysis_effect(a, best)->exponent : 1.0;
}

/* The worst node of a remesh over the field's nominal target, measured on
 * the bundled scenes' first rounds (2D 0.70-0.75, 3D 0.81-0.83). */
static double first_calibration(const dtm_analysis *a) {
  int dim = dtm_analysis_mesh(a)->dim;
  double spread = dim == 3 ? 0.8 : dim == 2 ? 0.72 : 1.0;
  return pow(1.0 / spread, 1.0 / basis_exponent(a));
}

double dtm_refine_cost(const dtm_refine_round *r) { return isnan(r->element_steps) ? r->rate : r->element_steps; }

/* The round's accuracy: the worst phase-speed error at the frequency of
 * round 0 (rr->frequency, 0 before it is known) and whether every measure
 * is inside its band. */
static int record_accuracy(const dtm_analysis *a, dtm_refine_result *rr, dtm_refine_round *r) {
  dtm_measures *m = NULL;
  DTM_CHECK(dtm_measures_compute(a, rr->frequency, NULL, &m));
  r->phase_error = NAN, r->in_band = 1, r->unresolved = 0;
  for (int k = 0; k < m->n; k++) {
    r->in_band &= m->m[k].in_band;
    if (m->m[k].kind != DTM_MEASURE_PHASE) continue;
    r->phase_error = m->m[k].worst, r->unresolved = m->m[k].unresolved;
    if (!(rr->frequency > 0)) rr->frequency = m->m[k].f;
  }
  dtm_measures_destroy(&m);
  return DTM_OK;
}

static int record(const dtm_analysis *a, double seconds, dtm_refine_result *rr, dtm_refine_round *r) {
  size_t ns;
  double rec = dtm_analysis_recommended(a), d = dtm_analysis_scene(a)->duration;
  size_t n = dtm_analysis_nelements(a);
  dtm_analysis_shape_limited(a, &ns);
  *r = (dtm_refine_round){n,       dtm_analysis_dt_min(a, NULL),
                          rec,     d > 0 ? (double)n * ceil(d / rec) : NAN,
                          n / rec, dtm_analysis_below_target(a),
                          ns,      seconds,
                          NAN,     0,
                          0};
  return record_accuracy(a, rr, r);
}

static int met(const dtm_refine_result *rr, int i) { return rr->rounds[i].recommended >= rr->target; }

/* Whether round i beats the kept round. */
static int better(const dtm_refine_result *rr, int i) {
  const dtm_refine_round *r = &rr->rounds[i], *b = &rr->rounds[rr->best];
  if (met(rr, i)) return !met(rr, rr->best) || dtm_refine_cost(r) < dtm_refine_cost(b);
  return !met(rr, rr->best) && r->recommended > b->recommended && dtm_refine_cost(r) <= dtm_refine_cost(&rr->rounds[0]);
}

/* The size field of a round: the calibrated suggestion, capped at the
 * model's short curves, graded, never below the current size (the field
 * with c = 0). */
static int round_field(const dtm_analysis *a, double c, double *size, double *floor) {
  DTM_CHECK(dtm_analysis_size_field(a, c, size));
  DTM_CHECK(dtm_analysis_size_field(a, 0.0, floor));
  dtm_cap_at_features(dtm_analysis_geo(a), floor, size);
  return dtm_grade_sizes(dtm_analysis_mesh(a), GRADE, floor, size);
}

/* One remesh of the current model from analysis a with calibration c, and
 * its analysis (a progress stage "refine round N"). */
static int remesh(const dtm_refine_result *rr, const dtm_analysis *a, int dim, double c, dtm_analysis **next,
                  int *gmsh_failed) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  double *size = malloc((m->nnodes + 1) * sizeof *size), *floor = malloc((m->nnodes + 1) * sizeof *floor);
  char stage[64];
  snprintf(stage, sizeof stage, "refine round %d", rr->nrounds);
  dtm_progress_begin(stage);
  int r = size && floor ? round_field(a, c, size, floor) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = dtm_gmsh_remesh(m, size, 1.0, dim, rr->scene.mesh_order, rr->nrounds);
  *gmsh_failed = r != DTM_OK && size && floor;
  if (r == DTM_OK) r = dtm_analysis_current(&rr->scene, dim, next);
  dtm_progress_end();
  free(size), free(floor);
  DTM_CHECK(r);
  return DTM_OK;
}

/* The loop's state: the input, last and kept (rr->analysis) analyses (two
 * or three of them may be the same), the Gmsh model's round, and where the
 * kept mesh is saved. */
typedef struct {
  dtm_analysis *input;                    /* round 0: every round's size field comes from it */
  dtm_analysis *cur;                      /* the last round's analysis */
  int model_round;                        /* the round the Gmsh model holds */
  char dir[256];                          /* temporary directory of the saved mesh ("" until made) */
  char path[300];                         /* dir/best.msh */
  int saved;                              /* round saved in path, -1: none */
  int nmodel;                             /* causes the model holds (found on round 0's mesh) */
  dtm_cause model[DTM_REFINE_MAX_CAUSES]; /* [nmodel] those causes */
} loop_state;

/* Destroy *a unless another role still holds it. */
static void release(dtm_analysis **a, const dtm_analysis *o1, const dtm_analysis *o2) {
  if (*a != o1 && *a != o2) dtm_analysis_destroy(a);
  *a = NULL;
}

/* Save the kept mesh before remeshing it away. */
static int save_best(const dtm_refine_result *rr, loop_state *st) {
  if (rr->best != st->model_round || st->saved == rr->best) return DTM_OK;
  if (!st->dir[0]) {
    const char *tmp = getenv("TMPDIR");
    snprintf(st->dir, sizeof st->dir, "%s/dtmap-refine-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    if (!mkdtemp(st->dir)) return st->dir[0] = 0, DTM_ERR(DTM_ERR_INTERNAL, "cannot make a temporary directory");
    snprintf(st->path, sizeof st->path, "%s/best.msh", st->dir);
  }
  DTM_CHECK(dtm_gmsh_save_mesh(st->path));
  st->saved = rr->best;
  return DTM_OK;
}

/* Whether only shape-limited elements keep analysis a below the target. */
static int only_shape(const dtm_analysis *a) {
  size_t ns, below = dtm_analysis_below_target(a);
  dtm_analysis_shape_limited(a, &ns);
  return below && ns == below;
}

static size_t shape_count(const dtm_analysis *a) {
  size_t ns;
  dtm_analysis_shape_limited(a, &ns);
  return ns;
}

/* Stop before another round: the kept mesh meets the target, or only
 * shape-limited elements keep it or the last mesh below it, or the budget
 * is spent. */
static int should_stop(dtm_refine_result *rr, const loop_state *st, int max_rounds) {
  size_t nl;
  if (met(rr, rr->best)) return rr->stop = DTM_REFINE_MET;
  if (dtm_analysis_layers(st->cur, &nl) && nl) return rr->stop = DTM_REFINE_THICKNESS;
  if (only_shape(rr->analysis) || only_shape(st->cur)) return rr->stop = DTM_REFINE_ONLY_SHAPE;
  if (rr->nrounds - 1 >= max_rounds) return rr->stop = DTM_REFINE_BUDGET;
  return 0;
}

/* After round i: keep it if better; stop when it made the run more
 * expensive than the input without meeting the target, or when it did not
 * beat the kept mesh while shape-limited elements cap the step. */
static int judge_round(dtm_refine_result *rr, loop_state *st, dtm_analysis *next) {
  int i = rr->nrounds - 1;
  const dtm_refine_round *input = &rr->rounds[0], *r = &rr->rounds[i];
  release(&st->cur, st->input, rr->analysis);
  st->cur = next, st->model_round = i;
  if (better(rr, i)) {
    release(&rr->analysis, st->input, NULL);
    rr->analysis = next, rr->best = i;
  } else if (shape_count(rr->analysis)) {
    return rr->stop = DTM_REFINE_SHAPE_CAP; /* remeshing around them did not help */
  }
  if (!met(rr, i) && dtm_refine_cost(r) > dtm_refine_cost(input)) return rr->stop = DTM_REFINE_COST_ROSE;
  return 0;
}

/* A remesh Gmsh refused or crashed in ends the loop, not the run: its
 * message becomes the first cause, and the kept mesh is read back. */
static void gmsh_failed(dtm_refine_result *rr, loop_state *st) {
  int crash = dtm_error_code() == DTM_ERR_INTERNAL;
  dtm_cause *c = &rr->causes[rr->ncauses++];
  memset(c, 0, sizeof *c);
  snprintf(c->kind, sizeof c->kind, crash ? "gmsh-crash" : "gmsh-refused");
  if (crash)
    snprintf(c->text, sizeof c->text, "%s", dtm_error_message());
  else
    snprintf(c->text, sizeof c->text, "remeshing round %d: %s", rr->nrounds, dtm_error_message());
  dtm_error_clear();
  rr->stop = crash ? DTM_REFINE_GMSH_CRASH : DTM_REFINE_GMSH_REFUSED;
  st->model_round = -1; /* the model holds no round's mesh */
}

/* Each round remeshes from the input mesh's size field; the calibration
 * grows by the shortfall of the last round, a one-dimensional search. */
static int rounds(dtm_refine_result *rr, loop_state *st, int dim, int max_rounds) {
  double c = first_calibration(st->input);
  while (!should_stop(rr, st, max_rounds)) {
    double t0 = dtm_wtime(), last = rr->rounds[rr->nrounds - 1].recommended;
    dtm_analysis *next = NULL;
    if (rr->nrounds > 1)
      c *= fmin(MAX_GROWTH, fmax(MIN_GROWTH, 1.02 * pow(rr->target / last, 1.0 / basis_exponent(st->cur))));
    int failed = 0;
    DTM_CHECK(save_best(rr, st));
    int r = remesh(rr, st->input, dim, c, &next, &failed);
    if (r && failed) return gmsh_failed(rr, st), DTM_OK;
    DTM_CHECK(r);
    int rc = record(next, dtm_wtime() - t0, rr, &rr->rounds[rr->nrounds++]);
    if (rc) return dtm_analysis_destroy(&next), rc;
    if (judge_round(rr, st, next)) break;
  }
  return DTM_OK;
}

static void input_accuracy(dtm_refine_result *rr, const dtm_analysis *a) {
  dtm_accuracy ac;
  dtm_analysis_accuracy(a, &ac);
  rr->forced = ac.forced;
  rr->forced_by = ac.forced_by >= 0 ? dtm_analysis_effect(a, ac.forced_by)->indicator.view : NULL;
}

/* What the model holds that decides sizes (src/gmsh/causes.c), found on
 * the input mesh with the nominal size suggestion (calibration 1). */
static int model_causes(const dtm_refine_result *rr, loop_state *st) {
  const dtm_mesh *m = dtm_analysis_mesh(st->input);
  double *size = malloc((m->nnodes + 1) * sizeof *size);
  if (!size) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = dtm_analysis_size_field(st->input, 1.0, size);
  if (r == DTM_OK)
    r = dtm_gmsh_size_causes(&rr->scene, m, dtm_analysis_geo(st->input), size, st->model, DTM_REFINE_MAX_CAUSES,
                             &st->nmodel);
  free(size);
  DTM_CHECK(r);
  return DTM_OK;
}

static void add_causes(dtm_refine_result *rr, const dtm_cause *c, int n, int size_options) {
  for (int i = 0; i < n && rr->ncauses < DTM_REFINE_MAX_CAUSES; i++)
    if ((strcmp(c[i].kind, "size-options") == 0) == size_options) rr->causes[rr->ncauses++] = c[i];
}

static dtm_cause *new_cause(dtm_refine_result *rr, const char *kind) {
  if (rr->ncauses >= DTM_REFINE_MAX_CAUSES) return NULL;
  dtm_cause *c = &rr->causes[rr->ncauses++];
  memset(c, 0, sizeof *c);
  snprintf(c->kind, sizeof c->kind, "%s", kind);
  return c;
}

/* The elements no size suggestion lifts, and an accuracy bound. */
static void analysis_causes(dtm_refine_result *rr) {
  size_t nl = 0, ns = shape_count(rr->analysis);
  dtm_cause *c;
  if (dtm_analysis_layers(rr->analysis, &nl) && nl && (c = new_cause(rr, "thickness")))
    snprintf(c->text, sizeof c->text,
             "%zu layer(s) are too thin for the target: the thickness caps their elements' step whatever the size", nl);
  if (ns && (c = new_cause(rr, "shape-limited")))
    snprintf(c->text, sizeof c->text,
             "%zu element(s) below the target are limited by their shape (a small angle or thin feature of the "
             "model), not by their size: a larger size does not lift them",
             ns);
  if (rr->forced_by && rr->forced >= 0.5 && (c = new_cause(rr, "accuracy")))
    snprintf(c->text, sizeof c->text, "the accuracy bound '%s' forbids the coarser size (about %.0f more elements)",
             rr->forced_by, rr->forced);
}

/* How many more rounds the last two predict at their rate of rise. */
static void budget_cause(dtm_refine_result *rr) {
  int n = rr->nrounds;
  dtm_cause *c = new_cause(rr, rr->stop == DTM_REFINE_BUDGET ? "budget" : "cost-rose");
  if (!c) return;
  double last = rr->rounds[n - 1].recommended, prev = n > 1 ? rr->rounds[n - 2].recommended : last, rise = last / prev,
         kept = rr->rounds[rr->best].recommended;
  int more = rise > 1.001 && last < rr->target ? (int)ceil(log(rr->target / last) / log(rise)) : 0;
  if (rr->stop != DTM_REFINE_BUDGET)
    snprintf(c->text, sizeof c->text, "%s", dtm_refine_stop_text(rr->stop));
  else if (more)
    snprintf(c->text, sizeof c->text,
             "the round budget (%d remesh(es)) is spent with %.4g s kept of the %.4g s target; the last rounds raised "
             "the step x%.3f per round, which predicts %d more round(s) (--max-iter %d)",
             n - 1, kept, rr->target, rise, more, n - 1 + more);
  else
    snprintf(c->text, sizeof c->text,
             "the round budget (%d remesh(es)) is spent with %.4g s kept of the %.4g s target (%.1f %% short); the "
             "last round did not raise the step (x%.3f): the worst element of a fresh mesh scatters from one remesh "
             "to the next, so the trend predicts nothing and another round may or may not meet it",
             n - 1, kept, rr->target, 100.0 * (1.0 - kept / rr->target), rise);
}

/* The causes, most specific first: Gmsh's failure (already there), the
 * elements no size lifts when they ended the loop, what the model holds,
 * those elements otherwise, a spent budget or a dearer round, and the size
 * options refine lifted (named even when the target is met). */
static void collect_causes(dtm_refine_result *rr, const loop_state *st) {
  int by_elements = rr->stop == DTM_REFINE_THICKNESS || rr->stop == DTM_REFINE_ONLY_SHAPE ||
                    rr->stop == DTM_REFINE_SHAPE_CAP; /* the elements ended the loop: they come first */
  if (!met(rr, rr->best)) {
    if (by_elements) analysis_causes(rr);
    add_causes(rr, st->model, st->nmodel, 0);
    if (!by_elements) analysis_causes(rr);
    if (rr->stop == DTM_REFINE_BUDGET || rr->stop == DTM_REFINE_COST_ROSE) budget_cause(rr);
  }
  add_causes(rr, st->model, st->nmodel, 1);
}

static int refine_loop(dtm_refine_result *rr, int max_rounds) {
  double t0 = dtm_wtime();
  static loop_state st0; /* zero: no cause yet */
  loop_state st = st0;
  st.saved = -1;
  int dim;
  DTM_CHECK(dtm_gmsh_load(&rr->scene, &dim));
  DTM_CHECK(dtm_analysis_current(&rr->scene, dim, &rr->analysis));
  st.input = st.cur = rr->analysis;
  DTM_CHECK(record(rr->analysis, dtm_wtime() - t0, rr, &rr->rounds[rr->nrounds++]));
  input_accuracy(rr, rr->analysis);
  int r = model_causes(rr, &st);
  if (r == DTM_OK) r = rounds(rr, &st, dim, max_rounds);
  if (r == DTM_OK) collect_causes(rr, &st);
  release(&st.cur, st.input, rr->analysis);
  release(&st.input, rr->analysis, NULL);
  if (r == DTM_OK && rr->best != st.model_round) r = dtm_gmsh_restore_mesh(st.path);
  if (st.dir[0]) unlink(st.path), rmdir(st.dir);
  return r;
}

int dtm_refine_run(const dtm_scene *s, double target, int max_rounds, dtm_refine_result **out) {
  if (!s->geometry) return DTM_ERR(DTM_ERR_INPUT, "%s: refine needs a <geometry>, not a <mesh>", s->path);
  if (!(target > 0) || !isfinite(target))
    return DTM_ERR(DTM_ERR_INPUT, "%s: refine needs a positive target step, got %g s", s->path, target);
  dtm_refine_result *rr = calloc(1, sizeof *rr);
  if (!rr) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  rr->target = target;
  rr->scene = *s;
  rr->scene.target = target;
  if (max_rounds > DTM_REFINE_MAX_ROUNDS - 1) max_rounds = DTM_REFINE_MAX_ROUNDS - 1;
  int r = refine_loop(rr, max_rounds);
  if (r) {
    dtm_refine_destroy(&rr);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = rr;
  return DTM_OK;
}

void dtm_refine_destroy(dtm_refine_result **pr) {
  if (!*pr) return;
  dtm_analysis_destroy(&(*pr)->analysis);
  free(*pr);
  *pr = NULL;
}

const char *dtm_refine_stop_text(int stop) {
  switch (stop) {
  case DTM_REFINE_MET: return "the target is met";
  case DTM_REFINE_COST_ROSE: return "the last round cost more than the input without meeting the target";
  case DTM_REFINE_ONLY_SHAPE: return "only shape-limited elements remain below the target";
  case DTM_REFINE_BUDGET: return "the round budget is spent";
  case DTM_REFINE_SHAPE_CAP:
    return "shape-limited elements cap the step: a round around them did not improve on the kept mesh";
  case DTM_REFINE_THICKNESS:
    return "elements that the thickness of their layer caps are below the target: no mesh of that layer reaches it";
  case DTM_REFINE_GMSH_REFUSED: return "Gmsh refused a remesh";
  case DTM_REFINE_GMSH_CRASH: return "Gmsh crashed in a remesh";
  default: return "not run";
  }
}
