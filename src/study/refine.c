/* The refine loop behind `dtmap refine`. Round 0 analyses the scene's own
 * mesh on the basis the caller chose (the nodal bound, or the global
 * estimate of run --posterior, whose advice holds the nodal steps to the
 * target scaled by the bound over the global step: src/analysis/
 * recommend.c); an input that already meets the target is kept as it is.
 * Otherwise the size field of the input mesh (dtm_analysis_size_field:
 * the current size where a node meets the target, the larger size that
 * reaches it elsewhere, accuracy bounds on top) drives a fresh mesh of the
 * same geometry as its only size source (dtm_gmsh_remesh, with Gmsh's
 * optimisers), the node counts of the model's transfinite curves set from
 * the same field (src/gmsh/counts.c), and the new mesh is analysed. Only
 * nodes below the target grow, so the element count falls and the step
 * rises: the run gets cheaper, unless an accuracy bound asks for smaller
 * elements.
 * A fresh mesh has a spread of element shapes, and its worst nodes sit
 * below its typical ones (on Gmsh meshes of uniform size the smallest
 * nodal step is about 0.78 of the median in 3D, 0.8 in 2D). The size that
 * reaches the target is therefore scaled by a calibration c, the margin
 * aimed past the target: the first round uses 1/0.72 (2D) or 1/0.8 (3D);
 * each later one corrects the calibration of the best round so far by its
 * shortfall and by the largest miss seen so far (how far a round fell from
 * the step its calibration predicted: the scatter of a fresh mesh's worst
 * element), at least 5 % past the target and 5 % above every calibration
 * tried, so that a loop within a few per cent of the target aims past it
 * by that scatter instead of creeping up to it, and never repeats a field.
 * The field is capped at the length of the model curves a node lies on and
 * graded (slope 0.3), so that the mesher can follow it.
 * The loop keeps the best mesh (saved to a .msh without a name while it
 * remeshes on, and read back at the end) and stops as soon as the target is met,
 * only shape-limited elements remain below the target (or cap
 * it, and a round around them did not beat the kept mesh), a remesh left
 * the step where it was, or the budget is spent. A round that costs more
 * than the input without meeting the target does not end the loop: it is
 * not kept, and the next aims from the best round and the miss seen (the
 * first remesh of a fresh mesh from the suggestion can come out worse;
 * extrude.geo and simple3.geo meet the target in their second or third
 * round). It stops before its
 * first remesh when no remesh can change what limits the step: every
 * element below the target limited by its shape or by the thickness of
 * its layer, or elements in extrusions whose layer count the model fixes.
 * A thin layer among other elements below the target is tried by one
 * remesh: the best step a fresh mesh reaches across it is an estimate
 * (src/analysis/shape.c), and on Gmsh's demos it proved short of what a
 * remesh reached on 2 of 17 such models on the nodal bound and 4 of 17 on
 * the global estimate (docs/refine-survey.md); the loop stops as soon as a
 * round does not beat the kept mesh. A remesh that Gmsh refuses or crashes in
 * (it runs in a child process, src/gmsh/contain.c) ends the loop too, and
 * the kept mesh is read back. When the mesh alone does not meet the target
 * and the caller allows it, point masses at the nodes that need them make
 * up the rest (refine_mass.c). The causes of a target not met come from
 * refine_causes.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/gmsh.h"
#include "dtmap/progress.h"
#include "dtmap/refine.h"
#include "dtmap/util.h"
#include "study-impl.h"

#define GRADE 0.3      /* size slope of the field (m per m): a fresh mesh follows it */
#define MAX_GROWTH 1.5 /* of the calibration from one round to the next */
#define MIN_MARGIN                                                                                                     \
  1.05                 /* aim at least this far past the target once a round fell short: the worst node of a           \
                          fresh mesh scatters by about 5 % from one mesh to the next */
#define STALL 2e-3     /* a remesh whose step is within this of the last one's left it where it was */
#define STALL_AIM 1.05 /* ... when it aimed at least this much higher */

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

/* Round i of kind from analysis a, after seconds. */
static int record(const dtm_analysis *a, int kind, double seconds, dtm_refine_result *rr, int i) {
  size_t ns;
  double rec = dtm_analysis_recommended(a), d = dtm_analysis_scene(a)->duration;
  size_t n = dtm_analysis_nelements(a);
  dtm_refine_round *r = &rr->rounds[i];
  dtm_analysis_shape_limited(a, &ns);
  memset(r, 0, sizeof *r);
  r->kind = kind, r->basis = dtm_analysis_basis(a), r->gap = rr->target / rec - 1.0, r->calibration = NAN;
  r->elements = n, r->dt_min = dtm_analysis_dt_min(a, NULL), r->recommended = rec;
  r->element_steps = d > 0 ? (double)n * ceil(d / rec) : NAN, r->rate = n / rec;
  r->below = dtm_analysis_below_target(a), r->shape_limited = ns, r->seconds = seconds;
  return record_accuracy(a, rr, r);
}

static int met(const dtm_refine_result *rr, int i) { return rr->rounds[i].recommended >= rr->target; }

/* Whether round i beats the kept round. */
static int better(const dtm_refine_result *rr, int i) {
  const dtm_refine_round *r = &rr->rounds[i], *b = &rr->rounds[rr->best];
  if (met(rr, i)) return !met(rr, rr->best) || dtm_refine_cost(r) < dtm_refine_cost(b);
  return !met(rr, rr->best) && r->recommended > b->recommended && dtm_refine_cost(r) <= dtm_refine_cost(&rr->rounds[0]);
}

/* The loop's state: the input, last and kept (rr->analysis) analyses (two
 * or three of them may be the same), the Gmsh model's round, where the
 * kept mesh is saved, what the model holds, and the calibrations so far. */
typedef struct {
  dtm_analysis *input;                    /* round 0: every round's size field comes from it */
  dtm_analysis *cur;                      /* the last round's analysis */
  int model_round;                        /* the round the Gmsh model holds */
  dtm_atomic kept;                        /* the saved mesh: a file without a name, saved and read by kept.tmp */
  int saved;                              /* round saved in kept, -1: none */
  int nmodel;                             /* causes the model holds (found on round 0's mesh) */
  dtm_cause model[DTM_REFINE_MAX_CAUSES]; /* [nmodel] those causes */
  dtm_structure *st;                      /* the model's fixed node counts (NULL: none found) */
  double miss;                            /* the largest miss so far: predicted over measured step, >= 1 */
  double *field;                          /* [nnodes] the last remesh's size field (NULL: none yet) */
  int field_counts;                       /* the transfinite counts set with it */
} loop_state;

/* The size field of a round: the calibrated suggestion, capped at the
 * model's short curves, graded, never below the current size (the field
 * with c = 0), which goes into floor. */
static int round_field(const dtm_analysis *a, double c, double *size, double *floor) {
  DTM_CHECK(dtm_analysis_size_field(a, c, size));
  DTM_CHECK(dtm_analysis_size_field(a, 0.0, floor));
  dtm_cap_at_features(dtm_analysis_geo(a), floor, size);
  return dtm_grade_sizes(dtm_analysis_mesh(a), GRADE, floor, size);
}

/* Whether some effect of analysis a has a global estimate. */
static int has_global(const dtm_analysis *a) {
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    if (dtm_analysis_global(a, k)) return 1;
  return 0;
}

/* The analysis of the mesh the Gmsh model holds, on the caller's basis:
 * with the global estimate, which some effect must have. */
static int analyse_current(const dtm_refine_result *rr, int dim, dtm_analysis **next) {
  DTM_CHECK(dtm_analysis_current(&rr->scene, dim, next));
  if (!rr->options.global) return DTM_OK;
  int r = dtm_analysis_estimate_global(*next, rr->options.tol, rr->options.lanczos_max, DTM_GLOBAL_BASIS);
  if (r == DTM_OK && !has_global(*next))
    r = DTM_ERR(DTM_ERR_INPUT,
                "%s: refining on the global estimate (--posterior) needs an effect that has one (elastic, thermal, "
                "hydraulic); none of the scene's effects has: refine without --posterior, on the nodal or element "
                "bound",
                rr->scene.path);
  if (r) dtm_analysis_destroy(next);
  return r;
}

/* The transfinite counts of a round (unless the caller keeps the model's),
 * set on the Gmsh model; *n gets how many differ from the model's. A
 * structured mesh has no spread of shapes to allow for: its counts follow
 * the field with the calibration over the first round's (1 in round 1). */
static int round_counts(dtm_refine_result *rr, const loop_state *st, double c, const double *floor, int *n) {
  const dtm_analysis *a = st->input;
  *n = 0;
  if (!st->st || rr->options.keep_counts) return DTM_OK;
  double *size = malloc((dtm_analysis_mesh(a)->nnodes + 1) * sizeof *size);
  int r =
      size ? dtm_analysis_size_field(a, c / first_calibration(a), size) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = dtm_gmsh_counts_plan(st->st, dtm_analysis_geo(a), size, floor);
  if (r == DTM_OK) r = dtm_gmsh_counts_apply(st->st, n);
  free(size);
  return r;
}

/* Whether the field size[] (with counts transfinite counts) is the one the
 * last remesh had: the model's short curves and the grading capped every
 * node the calibration would move, and the same field gives the same mesh. */
static int same_field(const loop_state *st, const double *size, size_t n, int counts) {
  if (!st->field || counts != st->field_counts) return 0;
  for (size_t v = 0; v < n; v++)
    if (!(size[v] == st->field[v]) && !(isnan(size[v]) && isnan(st->field[v]))) return 0;
  return 1;
}

/* Keep the field of this remesh for the next round's comparison (taking
 * size over). */
static void keep_field(loop_state *st, double **size, int counts) {
  free(st->field);
  st->field = *size, st->field_counts = counts, *size = NULL;
}

#define SAME_FIELD (-1) /* remesh(): the field is the last one's; nothing was remeshed (not a DTM code) */

/* One remesh of the current model from the input's field with calibration
 * c, and its analysis (a progress stage "refine round N"); SAME_FIELD, and
 * no remesh, when the field is the last remesh's. */
static int remesh(dtm_refine_result *rr, loop_state *st, int dim, double c, dtm_analysis **next, int *gmsh_failed,
                  dtm_refine_round *info) {
  const dtm_mesh *m = dtm_analysis_mesh(st->input);
  double *size = malloc((m->nnodes + 1) * sizeof *size), *floor = malloc((m->nnodes + 1) * sizeof *floor);
  char stage[64];
  snprintf(stage, sizeof stage, "refine round %d", rr->nrounds);
  int r = size && floor ? round_field(st->input, c, size, floor) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = round_counts(rr, st, c, floor, &info->counts);
  if (r == DTM_OK && same_field(st, size, m->nnodes, info->counts)) return free(size), free(floor), SAME_FIELD;
  dtm_progress_begin(stage);
  double t0 = dtm_wtime();
  if (r == DTM_OK) r = dtm_gmsh_remesh(m, size, 1.0, dim, rr->scene.mesh_order, rr->nrounds, rr->options.optimise);
  info->mesh_seconds = dtm_wtime() - t0;
  info->optimise = dtm_gmsh_optimisers(dim, rr->options.optimise);
  *gmsh_failed = r != DTM_OK && size && floor;
  if (r == DTM_OK) r = analyse_current(rr, dim, next);
  dtm_progress_end();
  if (r == DTM_OK) keep_field(st, &size, info->counts);
  free(size), free(floor);
  DTM_CHECK(r);
  return DTM_OK;
}

/* Destroy *a unless another role still holds it. */
static void release(dtm_analysis **a, const dtm_analysis *o1, const dtm_analysis *o2) {
  if (*a != o1 && *a != o2) dtm_analysis_destroy(a);
  *a = NULL;
}

/* Save the kept mesh before remeshing it away. */
static int save_best(const dtm_refine_result *rr, loop_state *st) {
  if (rr->best != st->model_round || st->saved == rr->best) return DTM_OK;
  if (st->kept.fd < 0) DTM_CHECK(dtm_scratch_named(&st->kept, "dtmap-refine", ".msh"));
  DTM_CHECK(dtm_gmsh_save_mesh(st->kept.tmp));
  st->saved = rr->best;
  return DTM_OK;
}

static size_t shape_count(const dtm_analysis *a) {
  size_t ns;
  dtm_analysis_shape_limited(a, &ns);
  return ns;
}

/* The stop for shape-limited elements that no remesh lifts: their layers'
 * thickness when thin layers are among them, else the given one. */
static int shape_stop(const dtm_analysis *a, int otherwise) {
  size_t nl = 0;
  return dtm_analysis_layers(a, &nl) && nl ? DTM_REFINE_THICKNESS : otherwise;
}

/* Whether only shape-limited elements keep analysis a below the target. */
static int only_shape(const dtm_analysis *a) {
  size_t below = dtm_analysis_below_target(a);
  return below && shape_count(a) == below;
}

/* Stop before another round: the kept mesh meets the target, or what
 * limits the step is beyond a remesh (fixed extrusions, elements below the
 * target all limited by their shape or their layer's thickness), or the
 * budget is spent. */
static int should_stop(dtm_refine_result *rr, const loop_state *st) {
  if (met(rr, rr->best)) return rr->stop = DTM_REFINE_MET;
  if (rr->nrounds == 1 && dtm_gmsh_counts_cap(st->st, rr->options.keep_counts)) return rr->stop = DTM_REFINE_LAYERS;
  if (only_shape(rr->analysis) || only_shape(st->cur)) return rr->stop = shape_stop(st->cur, DTM_REFINE_ONLY_SHAPE);
  if (rr->nrounds - 1 >= rr->options.max_rounds) return rr->stop = DTM_REFINE_BUDGET;
  return 0;
}

/* The last mesh round before round i (the input at least). */
static int previous_mesh(const dtm_refine_result *rr, int i) {
  while (i > 0 && rr->rounds[i - 1].kind == DTM_ROUND_MASS) i--;
  return i > 0 ? i - 1 : 0;
}

/* After round i: keep it if better; stop when it did not beat the kept
 * mesh while shape-limited elements cap the step, when neither it nor the
 * remesh before it beat the kept mesh (the rounds scatter around a step
 * that what the model fixes holds: import2.geo and revolve2.geo spent
 * their third round so), or when it
 * left the step where the round before had it (to STALL, the scatter of a
 * fresh mesh's worst element being some per cent) although it aimed
 * clearly higher: the same elements limit it whatever the field. */
static int judge_round(dtm_refine_result *rr, loop_state *st, dtm_analysis *next) {
  int i = rr->nrounds - 1;
  int j = previous_mesh(rr, i);
  const dtm_refine_round *r = &rr->rounds[i], *p = &rr->rounds[j];
  release(&st->cur, st->input, rr->analysis);
  st->cur = next, st->model_round = i;
  if (better(rr, i)) {
    release(&rr->analysis, st->input, NULL);
    rr->analysis = next, rr->best = i;
  } else if (shape_count(rr->analysis)) {
    return rr->stop = shape_stop(rr->analysis, DTM_REFINE_SHAPE_CAP); /* remeshing around them did not help */
  }
  if (met(rr, i)) return 0;
  if (i > 1 && fabs(r->recommended / p->recommended - 1) < STALL && r->calibration > STALL_AIM * p->calibration)
    return rr->stop = DTM_REFINE_STALLED;
  if (j > 0 && rr->best != i && rr->best != j) return rr->stop = DTM_REFINE_STALLED; /* two in a row beat nothing */
  return 0;
}

/* A remesh Gmsh refused or crashed in ends the loop, not the run: its
 * message becomes the first cause, and the kept mesh is read back. */
static void gmsh_failed(dtm_refine_result *rr, loop_state *st) {
  int crash = dtm_error_code() == DTM_ERR_INTERNAL;
  dtm_cause *c = dtm_refine_new_cause(rr, crash ? "gmsh-crash" : "gmsh-refused");
  if (c && crash)
    snprintf(c->text, sizeof c->text, "%s", dtm_error_message());
  else if (c)
    snprintf(c->text, sizeof c->text, "remeshing round %d: %s", rr->nrounds, dtm_error_message());
  dtm_error_clear();
  rr->stop = crash ? DTM_REFINE_GMSH_CRASH : DTM_REFINE_GMSH_REFUSED;
  st->model_round = -1; /* the model holds no round's mesh */
}

/* The calibration of the next round: the first one from the spread of a
 * fresh mesh (on the global basis the advice target already holds the
 * nodal steps to it); later ones from the kept round's (the best so far),
 * corrected by its shortfall and by the largest miss seen so far, and at
 * least MIN_MARGIN past the target; and MIN_MARGIN above every calibration
 * tried so far (the same field gives the same mesh: a round must try a new
 * one). */
static double next_calibration(const dtm_refine_result *rr, const loop_state *st) {
  if (rr->nrounds == 1) return first_calibration(st->input);
  const dtm_refine_round *b = &rr->rounds[rr->best], *l = &rr->rounds[rr->nrounds - 1];
  const dtm_refine_round *base = isfinite(b->calibration) ? b : l;
  double p = basis_exponent(st->cur), short_by = rr->target / base->recommended, tried = 0;
  double grow = pow(fmax(short_by, 1.0) * fmax(st->miss, MIN_MARGIN), 1.0 / p);
  for (int i = 1; i < rr->nrounds; i++)
    if (isfinite(rr->rounds[i].calibration)) tried = fmax(tried, rr->rounds[i].calibration);
  return fmax(base->calibration * fmin(MAX_GROWTH, grow), tried * pow(MIN_MARGIN, 1.0 / p));
}

/* After a round of calibration c that raised the step from the previous
 * round's by a factor less than c over the previous calibration predicted
 * (the step grows as the size, to the power p), how far it missed. */
static void learn_miss(const dtm_refine_result *rr, loop_state *st) {
  int i = rr->nrounds - 1, j = previous_mesh(rr, i);
  const dtm_refine_round *r = &rr->rounds[i], *p = &rr->rounds[j];
  if (!isfinite(p->calibration) || !isfinite(r->calibration)) return;
  double predicted = p->recommended * pow(r->calibration / p->calibration, basis_exponent(st->cur));
  if (predicted > r->recommended) st->miss = fmax(st->miss, predicted / r->recommended);
}

/* Each round remeshes from the input mesh's size field. */
static int rounds(dtm_refine_result *rr, loop_state *st, int dim) {
  while (!should_stop(rr, st)) {
    double t0 = dtm_wtime(), c = next_calibration(rr, st);
    dtm_analysis *next = NULL;
    dtm_refine_round info = {0};
    int failed = 0;
    DTM_CHECK(save_best(rr, st));
    int r = remesh(rr, st, dim, c, &next, &failed, &info);
    if (r == SAME_FIELD) return rr->stop = DTM_REFINE_STALLED, DTM_OK; /* no remesh: it would repeat the last */
    if (r && failed) return gmsh_failed(rr, st), DTM_OK;
    DTM_CHECK(r);
    int i = rr->nrounds++;
    int rc = record(next, DTM_ROUND_MESH, dtm_wtime() - t0, rr, i);
    if (rc) return dtm_analysis_destroy(&next), rc;
    rr->rounds[i].calibration = c, rr->rounds[i].counts = info.counts, rr->rounds[i].optimise = info.optimise;
    rr->rounds[i].mesh_seconds = info.mesh_seconds;
    learn_miss(rr, st);
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
 * the input mesh with the nominal size suggestion (calibration 1), and
 * which of its node counts refine can set (src/gmsh/counts.c). */
static int model_causes(const dtm_refine_result *rr, loop_state *st) {
  const dtm_mesh *m = dtm_analysis_mesh(st->input);
  const dtm_geo *g = dtm_analysis_geo(st->input);
  double *size = malloc((m->nnodes + 1) * sizeof *size), *cur = malloc((m->nnodes + 1) * sizeof *cur);
  int r = size && cur ? dtm_analysis_size_field(st->input, 1.0, size) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = dtm_analysis_size_field(st->input, 0.0, cur);
  if (r == DTM_OK) r = dtm_gmsh_structure(g, size, cur, &st->st);
  if (r == DTM_OK)
    r = dtm_gmsh_size_causes(&rr->scene, m, g, size, st->st, rr->options.keep_counts, st->model, DTM_REFINE_MAX_CAUSES,
                             &st->nmodel);
  free(size), free(cur);
  DTM_CHECK(r);
  return DTM_OK;
}

/* The counts refine set for the kept mesh, for the report. */
static int record_counts(dtm_refine_result *rr, const loop_state *st) {
  if (!st->st || rr->rounds[rr->best].kind == DTM_ROUND_INPUT || !rr->rounds[rr->best].counts) return DTM_OK;
  return dtm_gmsh_counts_list(st->st, &rr->counts, &rr->ncounts);
}

/* Round 0 (the scene's own mesh, on the caller's basis), the remeshes,
 * the causes, and the masses. */
static int refine_loop(dtm_refine_result *rr) {
  double t0 = dtm_wtime();
  static loop_state st0; /* zero: no cause yet */
  loop_state st = st0;
  st.saved = -1, st.miss = 1.0, st.kept.fd = -1;
  int dim;
  DTM_CHECK(dtm_gmsh_load(&rr->scene, &dim));
  DTM_CHECK(analyse_current(rr, dim, &rr->analysis));
  st.input = st.cur = rr->analysis;
  DTM_CHECK(record(rr->analysis, DTM_ROUND_INPUT, dtm_wtime() - t0, rr, rr->nrounds++));
  input_accuracy(rr, rr->analysis);
  int r = met(rr, 0) ? DTM_OK : model_causes(rr, &st);
  if (r == DTM_OK) r = rounds(rr, &st, dim);
  if (r == DTM_OK && !met(rr, 0)) r = record_counts(rr, &st);
  if (r == DTM_OK) dtm_refine_collect_causes(rr, st.model, st.nmodel);
  release(&st.cur, st.input, rr->analysis);
  release(&st.input, rr->analysis, NULL);
  if (r == DTM_OK && rr->best != st.model_round) r = dtm_gmsh_restore_mesh(st.kept.tmp);
  if (r == DTM_OK && !met(rr, rr->best)) r = dtm_refine_mass_round(rr);
  dtm_atomic_abort(&st.kept);
  dtm_gmsh_structure_destroy(&st.st);
  free(st.field);
  return r;
}

static int check_options(const dtm_scene *s, const dtm_refine_options *o) {
  if (!s->geometry) return DTM_ERR(DTM_ERR_INPUT, "%s: refine needs a <geometry>, not a <mesh>", s->path);
  if (!(o->target > 0) || !isfinite(o->target))
    return DTM_ERR(DTM_ERR_INPUT, "%s: refine needs a positive target step, got %g s", s->path, o->target);
  if (!isnan(o->max_added_mass) && !(o->max_added_mass >= 0 && o->max_added_mass <= 100))
    return DTM_ERR(DTM_ERR_INPUT, "%s: the added mass allowed must be 0 to 100 %% of the model's mass, got %g", s->path,
                   o->max_added_mass);
  return DTM_OK;
}

int dtm_refine_run(const dtm_scene *s, const dtm_refine_options *o, dtm_refine_result **out) {
  DTM_CHECK(check_options(s, o));
  dtm_refine_result *rr = calloc(1, sizeof *rr);
  if (!rr) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  rr->options = *o;
  if (!(rr->options.tol > 0)) rr->options.tol = 1e-4;
  if (!(rr->options.lanczos_max > 0)) rr->options.lanczos_max = 400;
  if (!rr->options.optimise) rr->options.optimise = DTM_REFINE_OPTIMISE;
  if (rr->options.max_rounds > DTM_REFINE_MAX_ROUNDS - 2) rr->options.max_rounds = DTM_REFINE_MAX_ROUNDS - 2;
  rr->target = o->target, rr->mass_needed = NAN;
  rr->scene = *s;
  rr->scene.target = o->target;
  int r = refine_loop(rr);
  if (r) {
    dtm_refine_destroy(&rr);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  rr->element_bound = s->safety * dtm_analysis_dt_min(rr->analysis, NULL);
  *out = rr;
  return DTM_OK;
}

void dtm_refine_destroy(dtm_refine_result **pr) {
  if (!*pr) return;
  dtm_analysis_destroy(&(*pr)->analysis);
  free((*pr)->counts);
  free(*pr);
  *pr = NULL;
}

const char *dtm_refine_stop_text(int stop) {
  switch (stop) {
  case DTM_REFINE_MET: return "the target is met";
  case DTM_REFINE_ONLY_SHAPE: return "only shape-limited elements remain below the target";
  case DTM_REFINE_BUDGET: return "the round budget is spent";
  case DTM_REFINE_SHAPE_CAP:
    return "shape-limited elements cap the step: a round around them did not improve on the kept mesh";
  case DTM_REFINE_THICKNESS:
    return "elements that the thickness of their layer caps are below the target: no mesh of that layer reaches it";
  case DTM_REFINE_GMSH_REFUSED: return "Gmsh refused a remesh";
  case DTM_REFINE_GMSH_CRASH: return "Gmsh crashed in a remesh";
  case DTM_REFINE_LAYERS:
    return "elements below the target lie where the model fixes the node counts (extrusion layers, or transfinite "
           "curves refine keeps): no remesh changes them";
  case DTM_REFINE_STALLED:
    return "a remesh aimed higher left the step where it was, or two remeshes in a row did not beat the kept mesh, "
           "or the model's short curves and the grading cap the field where it would grow: the same elements limit "
           "the step whatever the size field";
  default: return "not run";
  }
}
