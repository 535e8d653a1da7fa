/* Why refine stopped short of its target, as causes a user can act on,
 * most specific first: Gmsh's failure (named where it happened), the
 * elements no size lifts when they ended the loop (thin layers, shapes),
 * what the model holds that decides sizes (found on the input mesh by
 * src/gmsh/causes.c), a spent budget with the rounds its trend predicts,
 * and the size options refine lifted (named even when the target is met);
 * then, when point masses would meet it but need more than allowed, how
 * much they need. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "study-impl.h"

dtm_cause *dtm_refine_new_cause(dtm_refine_result *rr, const char *kind) {
  if (rr->ncauses >= DTM_REFINE_MAX_CAUSES) return NULL;
  dtm_cause *c = &rr->causes[rr->ncauses++];
  memset(c, 0, sizeof *c);
  snprintf(c->kind, sizeof c->kind, "%s", kind);
  return c;
}

static void add_causes(dtm_refine_result *rr, const dtm_cause *c, int n, int size_options) {
  for (int i = 0; i < n && rr->ncauses < DTM_REFINE_MAX_CAUSES; i++)
    if ((strcmp(c[i].kind, "size-options") == 0) == size_options) rr->causes[rr->ncauses++] = c[i];
}

static size_t shape_count(const dtm_analysis *a) {
  size_t ns;
  dtm_analysis_shape_limited(a, &ns);
  return ns;
}

/* The elements no size suggestion lifts, and an accuracy bound. */
static void analysis_causes(dtm_refine_result *rr, const dtm_analysis *a) {
  size_t nl = 0, ns = shape_count(a);
  dtm_cause *c;
  if (dtm_analysis_layers(a, &nl) && nl && (c = dtm_refine_new_cause(rr, "thickness")))
    snprintf(c->text, sizeof c->text,
             "%zu layer(s) are too thin for the target: the thickness caps their elements' step whatever the size", nl);
  if (ns && (c = dtm_refine_new_cause(rr, "shape-limited")))
    snprintf(c->text, sizeof c->text,
             "%zu element(s) below the target are limited by their shape (a small angle or thin feature of the "
             "model), not by their size: a larger size does not lift them",
             ns);
  if (rr->forced_by && rr->forced >= 0.5 && (c = dtm_refine_new_cause(rr, "accuracy")))
    snprintf(c->text, sizeof c->text, "the accuracy bound '%s' forbids the coarser size (about %.0f more elements)",
             rr->forced_by, rr->forced);
}

/* The last mesh round and the one before it. */
static void last_meshes(const dtm_refine_result *rr, int *last, int *prev) {
  *last = *prev = -1;
  for (int i = rr->nrounds - 1; i >= 0; i--)
    if (rr->rounds[i].kind != DTM_ROUND_MASS) {
      if (*last < 0)
        *last = i;
      else if (*prev < 0)
        *prev = i;
    }
  if (*prev < 0) *prev = *last;
}

/* How many more rounds the last two predict at their rate of rise. */
static void budget_cause(dtm_refine_result *rr) {
  int il, ip;
  dtm_cause *c = dtm_refine_new_cause(rr, "budget");
  if (!c) return;
  last_meshes(rr, &il, &ip);
  double last = rr->rounds[il].recommended, rise = last / rr->rounds[ip].recommended,
         kept = rr->rounds[rr->best].recommended;
  int more = rise > 1.001 && last < rr->target ? (int)ceil(log(rr->target / last) / log(rise)) : 0, spent = il;
  if (rr->stop != DTM_REFINE_BUDGET)
    snprintf(c->text, sizeof c->text, "%s", dtm_refine_stop_text(rr->stop));
  else if (more)
    snprintf(c->text, sizeof c->text,
             "the round budget (%d remesh(es)) is spent with %.4g s kept of the %.4g s target; the last rounds raised "
             "the step x%.3f per round, which predicts %d more round(s) (--max-iter %d)",
             spent, kept, rr->target, rise, more, spent + more);
  else
    snprintf(c->text, sizeof c->text,
             "the round budget (%d remesh(es)) is spent with %.4g s kept of the %.4g s target (%.1f %% short); the "
             "last round did not raise the step (x%.3f): the worst element of a fresh mesh scatters from one remesh "
             "to the next, so the trend predicts nothing and another round may or may not meet it",
             spent, kept, rr->target, 100.0 * (1.0 - kept / rr->target), rise);
}

/* A stall: the same elements keep the step whatever the size field. */
static void stall_cause(dtm_refine_result *rr) {
  dtm_cause *c = dtm_refine_new_cause(rr, "stalled");
  if (c) snprintf(c->text, sizeof c->text, "%s", dtm_refine_stop_text(DTM_REFINE_STALLED));
}

void dtm_refine_mass_cause(dtm_refine_result *rr) {
  dtm_cause *c = dtm_refine_new_cause(rr, "mass-limit");
  if (c)
    snprintf(c->text, sizeof c->text,
             "point masses at the nodes need %.3g %% of the model's mass to meet the target on the kept mesh, more "
             "than the %.3g %% allowed (--max-added-mass)",
             rr->mass_needed, rr->options.max_added_mass);
}

void dtm_refine_collect_causes(dtm_refine_result *rr, const dtm_cause *model, int nmodel) {
  int by_elements = rr->stop == DTM_REFINE_THICKNESS || rr->stop == DTM_REFINE_ONLY_SHAPE ||
                    rr->stop == DTM_REFINE_SHAPE_CAP; /* the elements ended the loop: they come first */
  if (rr->rounds[rr->best].recommended < rr->target) {
    if (by_elements) analysis_causes(rr, rr->analysis);
    add_causes(rr, model, nmodel, 0);
    if (!by_elements) analysis_causes(rr, rr->analysis);
    if (rr->stop == DTM_REFINE_BUDGET) budget_cause(rr);
    if (rr->stop == DTM_REFINE_STALLED) stall_cause(rr);
  }
  add_causes(rr, model, nmodel, 1);
}
