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
 * The search keeps the best mesh (saved to a .msh without a name while it
 * remeshes on, and read back at the end): the one that meets the target
 * at least cost, else the largest step no dearer than the input. It tries
 * strategies from a table, in order, while the kept mesh falls short:
 * "try, measure, keep the best". The size field above, --max-iter rounds
 * at most; the input's own sizes scaled by the factor its shortfall
 * implies (what Mesh.MeshSizeFactor does: its grading around small
 * features and embedded entities kept); the uniform size the target
 * implies (at each node the size at which its own step reaches the target,
 * from the input's measured ratio of step to size, their median over the
 * spread of a fresh mesh, at least the input's median size scaled by its
 * shortfall); the scaled one climbs to coarser factors while it falls
 * short (3 remeshes at most) and stops when coarser does not raise the
 * step, the uniform one tries a list of sizes (uniform_factors, 5 at most)
 * and then, while its largest size falls short on refine's basis, coarser
 * by the shortfall (2 more at most, until coarser does not raise the step);
 * the scene's accuracy bounds clamp every size. Then the field floored at
 * the best uniform size (Mesh.MeshSizeMin), the field without its caps at
 * short curves, and, after a Gmsh refusal, the uniform size with Gmsh's
 * sizes from the curvature: one remesh each. A field equal to one tried
 * already is not remeshed again. A remesh Gmsh refuses or crashes in (it
 * runs in a child process, src/gmsh/contain.c) ends its strategy, not the
 * search. Before any remesh the search stops only when every element below
 * the target lies where an extrusion's Layers{} fix the node counts. The
 * stop is then decided from the meshes tried (decide_stop): shape-limited
 * or thickness-limited elements only when the uniform mesh at the target's
 * size still keeps them below the target, the accuracy bound when it
 * clamped the sizes tried, the budget when the size field was still rising,
 * else no mesh tried met it. When the mesh alone does not meet the target
 * and the caller allows it, point masses at the nodes that need them make
 * up the rest (refine_mass.c); when asked, the kept mesh scaled selectively
 * is the way beside them (refine_selective.c). The causes of a target not met come from
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

#define REMESH_LIMIT_MIN 120 /* s: a remesh may take at least this long, */
#define REMESH_LIMIT_X 20    /* ... and this many times round 0 (the input's meshing and analysis) */
#define GRADE 0.3            /* size slope of the field (m per m): a fresh mesh follows it */
#define MAX_GROWTH 1.5       /* of the calibration from one round to the next */
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

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The median of v[n] (n > 0; v is sorted). */
static double median(double *v, size_t n) {
  qsort(v, n, sizeof *v, cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
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
  r->strategy = kind == DTM_ROUND_INPUT ? "input" : NULL;
  dtm_analysis_layers(a, &r->layers);
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
  int field_end;                          /* FIELD_*: how the size-field strategy ended */
  int failed, crashed;                    /* remeshes Gmsh refused, crashed in */
  double uniform;                         /* the largest uniform size tried, m (0: none) */
  int uniform_capped;                     /* 1: an accuracy bound capped it */
  int uniform_rounds;                     /* uniform remeshes run */
  int nprints;                            /* fields the other strategies tried */
  double prints[DTM_REFINE_MAX_ROUNDS];   /* [nprints] a fingerprint of each */
} loop_state;

/* How the size-field strategy ended (the search then goes on). */
enum {
  FIELD_SPENT = 1, /* --max-iter remeshes run */
  FIELD_FLAT,      /* a remesh aimed higher left the step where it was */
  FIELD_NO_GAIN,   /* two remeshes in a row did not beat the kept mesh */
  FIELD_SAME,      /* the short curves and the grading gave the last field again */
  FIELD_SHAPE,     /* only shape-limited elements were below the target */
  FIELD_GMSH       /* Gmsh refused or crashed in its remesh */
};

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

/* One remesh of the current model with size[] at the input's nodes (and
 * Gmsh's own sizes o, NULL: none), and its analysis (a progress stage
 * "refine round N"). *gmsh_failed: Gmsh refused or crashed in it. */
static int remesh_with(dtm_refine_result *rr, const loop_state *st, int dim, const double *size,
                       const dtm_remesh_sizes *o, dtm_analysis **next, int *gmsh_failed, dtm_refine_round *info) {
  const dtm_mesh *m = dtm_analysis_mesh(st->input);
  char stage[64];
  snprintf(stage, sizeof stage, "refine round %d", rr->nrounds);
  dtm_progress_begin(stage);
  double t0 = dtm_wtime();
  int r = dtm_gmsh_remesh_sized(m, size, 1.0, dim, rr->scene.mesh_order, rr->nrounds - 1, rr->options.optimise, o);
  info->mesh_seconds = dtm_wtime() - t0;
  info->optimise = dtm_gmsh_optimisers(dim, rr->options.optimise);
  int analysed = r == DTM_OK ? analyse_current(rr, dim, next) : DTM_OK;
  *gmsh_failed = dtm_refine_remesh_failed(r, analysed);
  if (r == DTM_OK && analysed && *gmsh_failed) { /* the message names the scene's mesh: say whose it is */
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", dtm_error_message());
    dtm_error_clear();
    analysed = DTM_ERR(DTM_ERR_INPUT,
                       "Gmsh's mesh of this round cannot be analysed (a failed mesh, not the input's): %s", msg);
  }
  if (r == DTM_OK) r = analysed;
  dtm_progress_end();
  DTM_CHECK(r);
  return DTM_OK;
}

int dtm_refine_remesh_failed(int remeshed, int analysed) { return remeshed != DTM_OK || analysed == DTM_ERR_INPUT; }

/* A fingerprint of a field and Gmsh's sizes: two fields with the same one
 * are taken to be the same (the accuracy bounds clamp a uniform size and a
 * scaled one to the same field, which gives the same mesh). */
static double fingerprint(const double *size, size_t n, const dtm_remesh_sizes *o) {
  double f = o ? 7.0 * o->min_size + 13.0 * o->curvature : 0.0;
  for (size_t v = 0; v < n; v++)
    if (isfinite(size[v])) f += size[v] * (1.0 + (double)(v % 97) / 97.0);
  return f;
}

static int seen_field(loop_state *st, double f) {
  for (int i = 0; i < st->nprints; i++)
    if (st->prints[i] == f) return 1;
  if (st->nprints < DTM_REFINE_MAX_ROUNDS) st->prints[st->nprints++] = f;
  return 0;
}

/* One remesh of the size-field strategy: the input's field with
 * calibration c; SAME_FIELD, and no remesh, when the field is the last
 * remesh's. */
static int remesh(dtm_refine_result *rr, loop_state *st, int dim, double c, dtm_analysis **next, int *gmsh_failed,
                  dtm_refine_round *info) {
  const dtm_mesh *m = dtm_analysis_mesh(st->input);
  double *size = malloc((m->nnodes + 1) * sizeof *size), *floor = malloc((m->nnodes + 1) * sizeof *floor);
  int r = size && floor ? round_field(st->input, c, size, floor) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = round_counts(rr, st, c, floor, &info->counts);
  if (r == DTM_OK && same_field(st, size, m->nnodes, info->counts)) return free(size), free(floor), SAME_FIELD;
  if (r == DTM_OK) (void)seen_field(st, fingerprint(size, m->nnodes, NULL)); /* the other strategies skip it */
  if (r == DTM_OK) r = remesh_with(rr, st, dim, size, NULL, next, gmsh_failed, info);
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

/* Whether only shape-limited elements keep analysis a below the target. */
static int only_shape(const dtm_analysis *a) {
  size_t below = dtm_analysis_below_target(a);
  return below && shape_count(a) == below;
}

/* The layer curves of extrusions (Layers{}) whose structured entities hold
 * every element below the target on the input: no remesh changes their
 * node counts across the layers. structured[] are the (dim, tag) of the
 * entities the model meshes by extrusion or recombination (the model's
 * "recombined" cause). */
static int layers_hold(const dtm_refine_result *rr, const loop_state *st) {
  if (dtm_gmsh_counts_cap(st->st, rr->options.keep_counts)) return 1;
  if (!st->st || dtm_gmsh_fixed_curves(st->st, 0, NULL, 0) == 0) return 0;
  const dtm_cause *rec = NULL;
  for (int i = 0; i < st->nmodel; i++)
    if (!strcmp(st->model[i].kind, "recombined")) rec = &st->model[i];
  const dtm_analysis *a = st->input;
  const dtm_geo *g = dtm_analysis_geo(a);
  if (!rec || !g || !g->elem_entity) return 0;
  const double *local = dtm_analysis_local_step(a);
  double target = dtm_analysis_advice_target(a), safety = dtm_analysis_scene(a)->safety;
  int dim = dtm_analysis_mesh(a)->dim;
  size_t n = dtm_analysis_nelements(a), below = 0;
  for (size_t i = 0; i < n; i++) {
    if (!(safety * local[i] < target)) continue;
    int in = 0;
    for (int k = 0; k < rec->nent && k < DTM_CAUSE_ENTITIES; k++)
      in |= rec->dim[k] == dim && rec->tag[k] == g->elem_entity[i];
    if (!in) return 0;
    below++;
  }
  return below > 0;
}

/* The last mesh round before round i (the input at least). */
static int previous_mesh(const dtm_refine_result *rr, int i) {
  while (i > 0 && rr->rounds[i - 1].kind == DTM_ROUND_MASS) i--;
  return i > 0 ? i - 1 : 0;
}

/* Remeshes of the size-field strategy so far. */
static int field_rounds(const dtm_refine_result *rr) {
  int n = 0;
  for (int i = 1; i < rr->nrounds; i++) n += rr->rounds[i].strategy && !strcmp(rr->rounds[i].strategy, "field");
  return n;
}

/* Keep round i (analysis next) when it beats the kept one; the model now
 * holds its mesh. */
static void judge(dtm_refine_result *rr, loop_state *st, dtm_analysis *next) {
  int i = rr->nrounds - 1;
  release(&st->cur, st->input, rr->analysis);
  st->cur = next, st->model_round = i;
  if (better(rr, i)) {
    release(&rr->analysis, st->input, NULL);
    rr->analysis = next, rr->best = i;
  }
}

/* After field round i: how the strategy ends, 0 while it goes on. It ends
 * when it left the step where the round before had it (to STALL, the
 * scatter of a fresh mesh's worst element being some per cent) although
 * it aimed clearly higher, when neither it nor the remesh before it beat
 * the kept mesh (import2.geo and revolve2.geo spent their third round so),
 * or when it did not beat a kept mesh whose step shape-limited elements
 * cap. */
static int judge_field(const dtm_refine_result *rr, int kept_before) {
  int i = rr->nrounds - 1;
  int j = previous_mesh(rr, i);
  const dtm_refine_round *r = &rr->rounds[i], *p = &rr->rounds[j];
  if (met(rr, i)) return 0;
  if (rr->best != i && rr->rounds[kept_before].shape_limited) return FIELD_SHAPE;
  if (j > 0 && fabs(r->recommended / p->recommended - 1) < STALL && r->calibration > STALL_AIM * p->calibration)
    return FIELD_FLAT;
  if (j > 0 && rr->best != i && rr->best != j) return FIELD_NO_GAIN; /* two in a row beat nothing */
  return 0;
}

#define NO_ROW "Gmsh gave no mesh, so this remesh has no round of its own"

/* A remesh Gmsh refused or crashed in ends its strategy, not the search:
 * its message is kept as a cause (the first such), and the model holds no
 * round's mesh until the next remesh. Such a remesh makes no round (no
 * row in the table), so the cause names it by the last round made before
 * it, the number the table shows (the next round made takes the number
 * after that one). */
static void gmsh_failed(dtm_refine_result *rr, loop_state *st, const char *strategy) {
  int crash = dtm_error_code() == DTM_ERR_INTERNAL;
  if (!st->failed && !st->crashed) {
    dtm_cause *c = dtm_refine_new_cause(rr, crash ? "gmsh-crash" : "gmsh-refused");
    if (c && crash)
      snprintf(c->text, sizeof c->text, "%s (strategy %s; %s)", dtm_error_message(), strategy, NO_ROW);
    else if (c)
      snprintf(c->text, sizeof c->text, "remeshing after round %d (strategy %s; %s): %s", rr->nrounds - 1, strategy,
               NO_ROW, dtm_error_message());
  }
  dtm_error_clear();
  st->failed += !crash, st->crashed += crash;
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
  int last = -1, nfield = 0;
  for (int i = 1; i < rr->nrounds; i++)
    if (isfinite(rr->rounds[i].calibration)) last = i, nfield++;
  if (!nfield) return first_calibration(st->input);
  const dtm_refine_round *b = &rr->rounds[rr->best], *l = &rr->rounds[last];
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

/* Record a remesh round of strategy name from analysis next. */
static int add_round(dtm_refine_result *rr, dtm_analysis *next, double t0, const char *name,
                     const dtm_refine_round *info) {
  int i = rr->nrounds++;
  int rc = record(next, DTM_ROUND_MESH, dtm_wtime() - t0, rr, i);
  if (rc) return rc;
  rr->rounds[i].strategy = name, rr->rounds[i].counts = info->counts, rr->rounds[i].optimise = info->optimise;
  rr->rounds[i].mesh_seconds = info->mesh_seconds, rr->rounds[i].calibration = info->calibration;
  rr->rounds[i].uniform = info->uniform;
  return DTM_OK;
}

/* Whether the search has room for another remesh (the rounds array holds
 * the mass round too). */
static int room(const dtm_refine_result *rr) { return rr->nrounds < DTM_REFINE_MAX_ROUNDS - 1; }

/* The size-field strategy: each round remeshes from the input mesh's
 * size field, --max-iter rounds at most. */
static int field_strategy(dtm_refine_result *rr, loop_state *st, int dim) {
  if (only_shape(st->input)) return st->field_end = FIELD_SHAPE, DTM_OK; /* the field grows nothing else */
  for (;;) {
    if (met(rr, rr->best)) return DTM_OK;
    if (field_rounds(rr) >= rr->options.max_rounds || !room(rr)) return st->field_end = FIELD_SPENT, DTM_OK;
    double t0 = dtm_wtime(), c = next_calibration(rr, st);
    dtm_analysis *next = NULL;
    dtm_refine_round info = {0};
    int failed = 0, kept = rr->best;
    DTM_CHECK(save_best(rr, st));
    int r = remesh(rr, st, dim, c, &next, &failed, &info);
    if (r == SAME_FIELD) return st->field_end = FIELD_SAME, DTM_OK; /* no remesh: it would repeat the last */
    if (r && failed) return gmsh_failed(rr, st, "field"), st->field_end = FIELD_GMSH, DTM_OK;
    DTM_CHECK(r);
    info.calibration = c, info.uniform = NAN;
    int rc = add_round(rr, next, t0, "field", &info);
    if (rc) return dtm_analysis_destroy(&next), rc;
    learn_miss(rr, st);
    judge(rr, st, next);
    if ((st->field_end = judge_field(rr, kept))) return DTM_OK;
  }
}

/* The uniform size a target implies on the input, searched from the
 * coarser (easier) side: at each node the size at which its own step
 * reaches the target (the input's measured ratio of step to size), their
 * median, scaled by the spread of a fresh mesh's worst node below its
 * median (first_calibration); at least the input's median size scaled by
 * the input's shortfall (on CAD parts the worst node sits far below the
 * median, and the median estimate then asks a finer mesh than the input).
 * The scene's accuracy bounds clamp it where they apply (uniform_field). */
static int uniform_size(const dtm_refine_result *rr, const loop_state *st, double *h, double *med) {
  const dtm_analysis *a = st->input;
  const dtm_mesh *m = dtm_analysis_mesh(a);
  const double big = 1e6; /* the field at a calibration this large is c x need wherever no bound caps it */
  double *need = malloc((m->nnodes + 1) * sizeof *need), *cur = malloc((m->nnodes + 1) * sizeof *cur);
  int r = need && cur ? dtm_analysis_size_field(a, big, need) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = dtm_analysis_size_field(a, 0.0, cur);
  size_t n = 0, nc = 0;
  for (size_t v = 0; r == DTM_OK && v < m->nnodes; v++) {
    if (isfinite(need[v]) && need[v] > 0) need[n++] = need[v] / big;
    if (isfinite(cur[v]) && cur[v] > 0) cur[nc++] = cur[v];
  }
  double p = basis_exponent(a);
  *h = n ? median(need, n) * first_calibration(a) : NAN;
  *med = nc ? median(cur, nc) : NAN;
  if (nc) *h = fmax(*h, *med * pow(rr->target / rr->rounds[0].recommended * MIN_MARGIN, 1.0 / p));
  free(need), free(cur);
  DTM_CHECK(r);
  return isfinite(*h) && isfinite(*med) ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "no size reaches the target on the input");
}

#define BIG_CALIBRATION 1e6 /* the field at this calibration is the accuracy bound wherever there is one */

/* A size field of h at every node of the input (NaN where its field has
 * none), or with scaled, h times the input's own size there (its grading
 * kept: what Mesh.MeshSizeFactor does), clamped by the scene's accuracy
 * bounds (*capped: 1 when they clamped a node), with transfinite counts
 * planned for it. */
static int uniform_field(dtm_refine_result *rr, const loop_state *st, double h, int scaled, double *size, int *counts,
                         int *capped) {
  const dtm_analysis *a = st->input;
  size_t nn = dtm_analysis_mesh(a)->nnodes;
  double *cur = malloc((nn + 1) * sizeof *cur);
  int r = cur ? dtm_analysis_size_field(a, BIG_CALIBRATION, size) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = dtm_analysis_size_field(a, 0.0, cur);
  *capped = 0;
  for (size_t v = 0; r == DTM_OK && v < nn; v++) {
    double want = scaled ? h * cur[v] : h;
    if (size[v] < want) *capped = 1;
    size[v] = isnan(cur[v]) ? NAN : fmin(want, size[v]);
  }
  *counts = 0;
  if (r == DTM_OK && st->st && !rr->options.keep_counts)
    r = dtm_gmsh_counts_plan(st->st, dtm_analysis_geo(a), size, cur);
  if (r == DTM_OK && st->st && !rr->options.keep_counts) r = dtm_gmsh_counts_apply(st->st, counts);
  free(cur);
  return r;
}

/* One remesh of an alternative strategy with field size[] and Gmsh's
 * sizes o; 1 in *refused when Gmsh refused it. */
static int try_field(dtm_refine_result *rr, loop_state *st, int dim, const char *name, const double *size,
                     const dtm_remesh_sizes *o, dtm_refine_round *info, int *refused) {
  double t0 = dtm_wtime();
  *refused = 0;
  if (seen_field(st, fingerprint(size, dtm_analysis_mesh(st->input)->nnodes, o))) return SAME_FIELD;
  dtm_analysis *next = NULL;
  int failed = 0;
  DTM_CHECK(save_best(rr, st));
  int r = remesh_with(rr, st, dim, size, o, &next, &failed, info);
  *refused = r && failed;
  if (*refused) return gmsh_failed(rr, st, name), DTM_OK;
  DTM_CHECK(r);
  int rc = add_round(rr, next, t0, name, info);
  if (rc) return dtm_analysis_destroy(&next), rc;
  judge(rr, st, next);
  return DTM_OK;
}

/* The largest finite value of size[n] (0: none). */
static double field_max(const double *size, size_t n) {
  double m = 0;
  for (size_t v = 0; v < n; v++)
    if (isfinite(size[v])) m = fmax(m, size[v]);
  return m;
}

#define LADDER_TRIES 3      /* remeshes of a uniform or scaled strategy at most */
#define LADDER_GROW 1.1     /* a size after one that fell short: at least this much coarser */
#define LADDER_FLAT 1.02    /* a coarser try whose step rose less than this ends the ladder */
#define LADDER_MAX_GROW 2.0 /* ... and at most this much coarser (a try far short is a bad mesh, not a guide) */

/* One remesh at size x (uniform, or with scaled a factor on the input's
 * sizes), clamped by the accuracy bounds, with the largest size as Gmsh's
 * cap (where the new mesh leaves the old one the field has no value);
 * SAME_FIELD when the field was tried already. */
static int one_size(dtm_refine_result *rr, loop_state *st, int dim, const char *name, double x, int scaled,
                    double *size, int *refused) {
  dtm_refine_round info = {0};
  int capped = 0;
  size_t nn = dtm_analysis_mesh(st->input)->nnodes;
  info.calibration = scaled ? x : NAN, info.uniform = scaled ? NAN : x;
  DTM_CHECK(uniform_field(rr, st, x, scaled, size, &info.counts, &capped));
  st->uniform_capped |= capped; /* the accuracy bounds kept some nodes finer */
  dtm_remesh_sizes o = {0, 0, field_max(size, nn)};
  int r = try_field(rr, st, dim, name, size, &o, &info, refused);
  if (r == DTM_OK && !scaled) st->uniform = fmax(st->uniform, x), st->uniform_rounds += !*refused;
  return r;
}

/* A ladder of sizes: x (a uniform size, or with scaled a factor on the
 * input's sizes), then, while it falls short, coarser by the shortfall and
 * the margin (the accuracy bounds clamping it where they apply); it ends when a
 * coarser try did not raise the step (the geometry, not the size, holds
 * it). A size Gmsh refuses is tried coarser. */
static int ladder(dtm_refine_result *rr, loop_state *st, int dim, const char *name, double x, int scaled) {
  double p = basis_exponent(st->input), last = NAN;
  size_t nn = dtm_analysis_mesh(st->input)->nnodes;
  double *size = malloc((nn + 1) * sizeof *size);
  if (!size) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = DTM_OK;
  for (int t = 0; t < LADDER_TRIES && r == DTM_OK && room(rr) && !met(rr, rr->best); t++) {
    int refused = 0;
    r = one_size(rr, st, dim, name, x, scaled, size, &refused);
    if (r == SAME_FIELD) {
      r = DTM_OK;
      break; /* clamped to a field tried already */
    }
    if (r) break;
    double step = refused ? NAN : rr->rounds[rr->nrounds - 1].recommended;
    if (!refused && !(step > LADDER_FLAT * last) && t > 0) break; /* coarser did not help */
    if (!refused) last = isnan(last) ? step : fmax(last, step);
    double shortfall = refused ? 1.0 : rr->target / step;
    x *= fmin(LADDER_MAX_GROW, fmax(LADDER_GROW, pow(shortfall * MIN_MARGIN, 1.0 / p)));
  }
  free(size);
  return r;
}

/* The uniform sizes tried: the input's median size times these, from the
 * first at least the estimate over UNIFORM_BELOW (uniform_size), in turn
 * until one meets the target. The worst element of a fresh mesh is a
 * lottery from one size to the next (on real parts 1.25x met where 1.5x
 * did not, and 2x where 1.25x and 1.5x did not): the search tries each
 * size, from the finer (more accurate) side, rather than trusting a trend. */
static const double uniform_factors[] = {1.25, 1.5, 2.0, 3.0, 4.0, 6.0};
#define UNIFORM_TRIES 5   /* uniform remeshes at most */
#define UNIFORM_BELOW 1.6 /* the first size tried may lie this far below the estimate */
#define UNIFORM_REFUSED 2 /* refusals in a row that end the strategy */

#define UNIFORM_MORE 2 /* coarser sizes past the list at most, while the largest falls short */

/* The uniform round of the largest size (-1: none). */
static int largest_uniform(const dtm_refine_result *rr) {
  int b = -1;
  for (int i = 1; i < rr->nrounds; i++)
    if (rr->rounds[i].strategy && !strcmp(rr->rounds[i].strategy, "uniform") &&
        (b < 0 || rr->rounds[i].uniform > rr->rounds[b].uniform))
      b = i;
  return b;
}

double dtm_refine_uniform_next(const dtm_refine_result *rr, double exponent) {
  if (!rr || rr->nrounds < 1 || !(exponent > 0) || met(rr, rr->best)) return NAN;
  int u = largest_uniform(rr);
  if (u < 0 || u != dtm_refine_best_of(rr, "uniform")) return NAN; /* a coarser size already did not help */
  double step = rr->rounds[u].recommended;
  if (!(step > 0)) return NAN;
  double grow = pow(rr->target / step * MIN_MARGIN, 1.0 / exponent);
  return rr->rounds[u].uniform * fmin(LADDER_MAX_GROW, fmax(LADDER_GROW, grow));
}

/* Past the list: while the largest uniform size tried falls short on the
 * basis refine judges by (the recommended step of its round: the global
 * estimate with --posterior) and has the largest step of the uniform
 * rounds, coarser by that shortfall and the margin (dtm_refine_uniform_next,
 * as the ladder does), until a coarser size does not raise the step. A mesh
 * the list stopped just short of (a fresh mesh's worst element scatters by
 * a few per cent from one size to the next) is then found before a layer
 * or a shape is named as the cause. */
static int uniform_coarser(dtm_refine_result *rr, loop_state *st, int dim, double *size) {
  int r = DTM_OK;
  for (int t = 0; t < UNIFORM_MORE && r == DTM_OK && room(rr); t++) {
    double x = dtm_refine_uniform_next(rr, basis_exponent(st->input));
    if (isnan(x)) break;
    double step = rr->rounds[largest_uniform(rr)].recommended;
    int before = rr->nrounds, refused = 0;
    r = one_size(rr, st, dim, "uniform", x, 0, size, &refused);
    if (r == SAME_FIELD) return DTM_OK; /* the accuracy bounds clamp it: nothing coarser to try */
    if (r || refused || rr->nrounds == before) break;
    if (!(rr->rounds[rr->nrounds - 1].recommended > LADDER_FLAT * step)) break; /* coarser did not help */
  }
  return r;
}

/* The uniform strategy (see uniform_factors, then uniform_coarser). */
static int uniform_strategy(dtm_refine_result *rr, loop_state *st, int dim) {
  double h, med;
  DTM_CHECK(uniform_size(rr, st, &h, &med));
  size_t nn = dtm_analysis_mesh(st->input)->nnodes;
  double *size = malloc((nn + 1) * sizeof *size);
  if (!size) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = DTM_OK, tries = 0, refused_run = 0;
  size_t nf = sizeof uniform_factors / sizeof uniform_factors[0];
  for (size_t k = 0; k < nf && tries < UNIFORM_TRIES && r == DTM_OK && room(rr) && !met(rr, rr->best); k++) {
    double x = med * uniform_factors[k];
    if (x < h / UNIFORM_BELOW && k + 1 < nf) continue;
    int refused = 0;
    r = one_size(rr, st, dim, "uniform", x, 0, size, &refused);
    if (r == SAME_FIELD) r = DTM_OK; /* clamped to a field tried already: the next size */
    tries++, refused_run = refused ? refused_run + 1 : 0;
    if (refused_run >= UNIFORM_REFUSED) break;
  }
  if (r == DTM_OK && refused_run < UNIFORM_REFUSED) r = uniform_coarser(rr, st, dim, size);
  free(size);
  return r;
}

/* The scaled strategy: the input's own sizes times the factor its
 * shortfall implies (with the margin), as Mesh.MeshSizeFactor would: its
 * grading around small features and embedded entities is kept. */
static int scaled_strategy(dtm_refine_result *rr, loop_state *st, int dim) {
  double f = pow(rr->target / rr->rounds[0].recommended * MIN_MARGIN, 1.0 / basis_exponent(st->input));
  return ladder(rr, st, dim, "scaled", f, 1);
}

/* The field strategy's best calibration (the first one when it ran none). */
static double best_calibration(const dtm_refine_result *rr, const loop_state *st) {
  int b = -1;
  for (int i = 1; i < rr->nrounds; i++)
    if (rr->rounds[i].strategy && !strcmp(rr->rounds[i].strategy, "field") &&
        (b < 0 || rr->rounds[i].recommended > rr->rounds[b].recommended))
      b = i;
  return b > 0 ? rr->rounds[b].calibration : first_calibration(st->input);
}

/* The uniform size of the uniform round with the largest step (0: none). */
static double best_uniform(const dtm_refine_result *rr) {
  int b = -1;
  for (int i = 1; i < rr->nrounds; i++)
    if (rr->rounds[i].strategy && !strcmp(rr->rounds[i].strategy, "uniform") &&
        (b < 0 || rr->rounds[i].recommended > rr->rounds[b].recommended))
      b = i;
  return b > 0 ? rr->rounds[b].uniform : 0;
}

/* The size field capped differently: the field of the best calibration
 * without the caps at short model curves (graded only), or floored at the
 * largest uniform size tried (Mesh.MeshSizeMin): the small elements the
 * caps or the curves keep are what either lifts; the floor stays within
 * the scene's accuracy bounds. */
static int variant_strategy(dtm_refine_result *rr, loop_state *st, int dim, int floored) {
  const dtm_analysis *a = st->input;
  size_t nn = dtm_analysis_mesh(a)->nnodes;
  double c = best_calibration(rr, st) * MIN_MARGIN;
  double *size = malloc((nn + 1) * sizeof *size), *floor = malloc((nn + 1) * sizeof *floor);
  int r = size && floor ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"), refused = 0;
  dtm_refine_round info = {0};
  double h = best_uniform(rr);
  if (r == DTM_OK)
    r = dtm_analysis_size_field(a, BIG_CALIBRATION, size); /* the accuracy bounds: the floor stays below */
  for (size_t v = 0; r == DTM_OK && v < nn; v++)
    if (isfinite(size[v])) h = fmin(h, size[v]);
  dtm_remesh_sizes o = {floored ? h : 0, 0, 0};
  info.calibration = c, info.uniform = floored ? h : NAN;
  if (r == DTM_OK) r = dtm_analysis_size_field(a, c, size);
  if (r == DTM_OK) r = dtm_analysis_size_field(a, 0.0, floor);
  if (r == DTM_OK && floored) dtm_cap_at_features(dtm_analysis_geo(a), floor, size);
  if (r == DTM_OK) r = dtm_grade_sizes(dtm_analysis_mesh(a), GRADE, floor, size);
  if (r == DTM_OK) r = round_counts(rr, st, c, floor, &info.counts);
  if (r == DTM_OK) r = try_field(rr, st, dim, floored ? "field-floored" : "field-uncapped", size, &o, &info, &refused);
  free(size), free(floor);
  return r == SAME_FIELD ? DTM_OK : r;
}

/* Sizes from the curvature beside the largest uniform size tried: a
 * uniform mesh Gmsh refused on curved faces (a segment of a coarse facet
 * crossing another) often meshes with the curvature followed. */
#define CURVATURE_PER_2PI 12 /* elements per 2 pi of curvature */
static int curvature_strategy(dtm_refine_result *rr, loop_state *st, int dim) {
  size_t nn = dtm_analysis_mesh(st->input)->nnodes;
  double *size = malloc((nn + 1) * sizeof *size);
  if (!size) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  dtm_refine_round info = {0};
  dtm_remesh_sizes o = {0.25 * st->uniform, CURVATURE_PER_2PI, st->uniform};
  int refused = 0, capped = 0;
  info.calibration = NAN, info.uniform = st->uniform;
  int r = uniform_field(rr, st, st->uniform, 0, size, &info.counts, &capped);
  if (r == DTM_OK) r = try_field(rr, st, dim, "uniform-curvature", size, &o, &info, &refused);
  free(size);
  return r == SAME_FIELD ? DTM_OK : r;
}

/* The strategies refine tries, in order, while the kept mesh falls short
 * of the target: try, measure, keep the best (the cheapest that meets it,
 * else the largest step no dearer than the input). */
typedef struct {
  const char *name;
  int (*run)(dtm_refine_result *rr, loop_state *st, int dim);
  int (*wanted)(const loop_state *st); /* NULL: always */
} strategy;

static int uniform_tried(const loop_state *st) { return st->uniform_rounds > 0; }
static int gmsh_refused_some(const loop_state *st) { return st->uniform > 0 && (st->failed || st->crashed); }
static int floored_run(dtm_refine_result *rr, loop_state *st, int dim) { return variant_strategy(rr, st, dim, 1); }
static int uncapped_run(dtm_refine_result *rr, loop_state *st, int dim) { return variant_strategy(rr, st, dim, 0); }

static const strategy strategies[] = {
    {"field", field_strategy, NULL},               /* the calibrated size suggestion, --max-iter rounds */
    {"scaled", scaled_strategy, NULL},             /* the input's sizes times a factor */
    {"uniform", uniform_strategy, NULL},           /* the size the target implies everywhere */
    {"field-floored", floored_run, uniform_tried}, /* the field with Mesh.MeshSizeMin at that size */
    {"field-uncapped", uncapped_run, NULL},        /* the field without the caps at short curves */
    {"uniform-curvature", curvature_strategy, gmsh_refused_some}, /* after a refusal: curvature sizes too */
};

static int search(dtm_refine_result *rr, loop_state *st, int dim) {
  if (met(rr, 0)) return rr->stop = DTM_REFINE_MET, DTM_OK;
  if (layers_hold(rr, st)) return rr->stop = DTM_REFINE_LAYERS, DTM_OK;
  for (size_t k = 0; k < sizeof strategies / sizeof strategies[0]; k++) {
    if (met(rr, rr->best) || !room(rr)) break;
    if (strategies[k].wanted && !strategies[k].wanted(st)) continue;
    DTM_CHECK(strategies[k].run(rr, st, dim));
  }
  return DTM_OK;
}

/* Why the search ended short, from what the meshes tried showed: every
 * remesh refused; the budget of a field strategy still rising; the
 * accuracy bound capping the uniform size; elements the uniform mesh (the
 * coarser mesh at the target's size) still keeps below the target, all
 * across thin layers or all shape-limited; else no mesh tried met it. */
static void decide_stop(dtm_refine_result *rr, const loop_state *st) {
  if (rr->stop) return;
  if (met(rr, rr->best)) return (void)(rr->stop = DTM_REFINE_MET);
  int meshes = rr->nrounds - 1, u = dtm_refine_best_of(rr, "uniform");
  if (!meshes && (st->failed || st->crashed))
    return (void)(rr->stop = st->crashed ? DTM_REFINE_GMSH_CRASH : DTM_REFINE_GMSH_REFUSED);
  if (st->uniform_capped && rr->forced_by && rr->forced >= 0.5) return (void)(rr->stop = DTM_REFINE_ACCURACY);
  if (u < 0) return (void)(rr->stop = st->field_end == FIELD_SPENT ? DTM_REFINE_BUDGET : DTM_REFINE_STALLED);
  const dtm_refine_round *r = &rr->rounds[u];
  if (r->below && r->shape_limited == r->below)
    return (void)(rr->stop = r->layers ? DTM_REFINE_THICKNESS : DTM_REFINE_ONLY_SHAPE);
  int f = dtm_refine_best_of(rr, "field");
  if (st->field_end == FIELD_SPENT && f >= 0 && rr->rounds[f].recommended >= r->recommended)
    return (void)(rr->stop = DTM_REFINE_BUDGET);
  rr->stop = DTM_REFINE_STALLED;
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
  dtm_gmsh_remesh_limit((unsigned)fmax(REMESH_LIMIT_MIN, REMESH_LIMIT_X * rr->rounds[0].seconds));
  if (r == DTM_OK) r = search(rr, &st, dim);
  dtm_gmsh_remesh_limit(0);
  if (r == DTM_OK) decide_stop(rr, &st);
  rr->uniform = st.uniform, rr->uniform_rounds = st.uniform_rounds;
  if (r == DTM_OK && !met(rr, 0)) r = record_counts(rr, &st);
  if (r == DTM_OK) dtm_refine_collect_causes(rr, st.model, st.nmodel);
  release(&st.cur, st.input, rr->analysis);
  release(&st.input, rr->analysis, NULL);
  if (r == DTM_OK && rr->best != st.model_round) r = dtm_gmsh_restore_mesh(st.kept.tmp);
  if (r == DTM_OK) r = dtm_refine_selective_way(rr); /* before any point masses */
  if (r == DTM_OK && !met(rr, rr->best)) r = dtm_refine_mass_round(rr);
  if (r == DTM_OK && met(rr, rr->best)) dtm_refine_met_causes(rr); /* nothing about a stop */
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
  if (o->modes < 0 || (o->modes > 0 && !o->selective_mass))
    return DTM_ERR(DTM_ERR_INPUT, "%s: refine's modes price the selective mass way: ask for it too", s->path);
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
  if (rr->options.max_rounds > DTM_REFINE_MAX_ROUNDS - 14) rr->options.max_rounds = DTM_REFINE_MAX_ROUNDS - 14;
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
  dtm_refine_selective_free(*pr);
  free((*pr)->counts);
  free(*pr);
  *pr = NULL;
}

const char *dtm_refine_stop_text(int stop) {
  switch (stop) {
  case DTM_REFINE_MET: return "the target is met";
  case DTM_REFINE_ONLY_SHAPE:
    return "shape-limited elements stay below the target on a uniform mesh at or above the size it implies";
  case DTM_REFINE_BUDGET: return "the size-field rounds (--max-iter) are spent, and no other strategy met the target";
  case DTM_REFINE_SHAPE_CAP: return "shape-limited elements cap the step";
  case DTM_REFINE_THICKNESS:
    return "thin layers stay below the target on a uniform mesh at or above the size it implies";
  case DTM_REFINE_GMSH_REFUSED: return "Gmsh refused every remesh tried";
  case DTM_REFINE_GMSH_CRASH: return "Gmsh crashed in every remesh tried";
  case DTM_REFINE_LAYERS:
    return "every element below the target lies where the model fixes the node counts (extrusion Layers{}, or "
           "transfinite curves refine keeps): stopped before any remesh";
  case DTM_REFINE_STALLED: return "no mesh tried met the target";
  case DTM_REFINE_ACCURACY: return "the accuracy bounds forbid the uniform size that meets the target";
  default: return "not run";
  }
}
