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

#include "dtmap/units.h"
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

/* Put the last cause first: the stop's own cause leads the list. */
static void to_front(dtm_refine_result *rr) {
  if (rr->ncauses < 2) return;
  dtm_cause c = rr->causes[rr->ncauses - 1];
  memmove(&rr->causes[1], &rr->causes[0], (size_t)(rr->ncauses - 1) * sizeof c);
  rr->causes[0] = c;
}

int dtm_refine_best_of(const dtm_refine_result *rr, const char *name) {
  int b = -1;
  for (int i = 1; i < rr->nrounds; i++)
    if (rr->rounds[i].strategy && !strcmp(rr->rounds[i].strategy, name) &&
        (b < 0 || rr->rounds[i].recommended > rr->rounds[b].recommended))
      b = i;
  return b;
}

static int count_of(const dtm_refine_result *rr, const char *name) {
  int n = 0;
  for (int i = 1; i < rr->nrounds; i++) n += rr->rounds[i].strategy && !strcmp(rr->rounds[i].strategy, name);
  return n;
}

/* "the size field (N remesh(es), best X s)" and the like into buf. */
static void tried_text(const dtm_refine_result *rr, char *buf, size_t len) {
  static const char *const names[][2] = {{"field", "the size field"},
                                         {"scaled", "the input's sizes scaled"},
                                         {"uniform", "uniform sizes"},
                                         {"field-floored", "the field floored at the uniform size"},
                                         {"field-uncapped", "the field without the caps at short curves"},
                                         {"uniform-curvature", "a uniform size with curvature sizes"}};
  buf[0] = '\0';
  for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
    int n = count_of(rr, names[k][0]), b = dtm_refine_best_of(rr, names[k][0]);
    if (!n) continue;
    size_t at = strlen(buf);
    snprintf(buf + at, len - at, "%s%s (%d remesh(es), best %.4g s)", at ? ", " : "", names[k][1], n,
             rr->rounds[b].recommended);
  }
}

/* The step of the uniform round u as a phrase. */
static void uniform_text(const dtm_refine_result *rr, int u, char *buf, size_t len) {
  snprintf(buf, len, "a uniform mesh of %.4g %s (round %d, %zu elements, %.4g s)", rr->rounds[u].uniform,
           dtm_units_name(rr->scene.units, DTM_UNIT_LENGTH), u, rr->rounds[u].elements, rr->rounds[u].recommended);
}

/* How many more rounds the last two field rounds predict at their rate of
 * rise. */
static void budget_cause(dtm_refine_result *rr, const char *tried) {
  int il = -1, ip = -1;
  dtm_cause *c = dtm_refine_new_cause(rr, "budget");
  if (!c) return;
  for (int i = rr->nrounds - 1; i > 0; i--)
    if (rr->rounds[i].strategy && !strcmp(rr->rounds[i].strategy, "field")) {
      if (il < 0)
        il = i;
      else if (ip < 0)
        ip = i;
    }
  if (ip < 0) ip = 0;
  if (il < 0) il = 0;
  double last = rr->rounds[il].recommended, rise = last / rr->rounds[ip].recommended,
         kept = rr->rounds[rr->best].recommended;
  int more = rise > 1.001 && last < rr->target ? (int)ceil(log(rr->target / last) / log(rise)) : 0;
  int spent = rr->options.max_rounds;
  if (more)
    snprintf(c->text, sizeof c->text,
             "the %d size-field round(s) of --max-iter are spent with %.4g s kept of the %.4g s target; they "
             "raised the step x%.3f per round, which predicts %d more (--max-iter %d); tried: %s",
             spent, kept, rr->target, rise, more, spent + more, tried);
  else
    snprintf(c->text, sizeof c->text,
             "the %d size-field round(s) of --max-iter are spent with %.4g s kept of the %.4g s target (%.1f %% "
             "short); the worst element of a fresh mesh scatters from one remesh to the next, so another round "
             "may or may not meet it; tried: %s",
             spent, kept, rr->target, 100.0 * (1.0 - kept / rr->target), tried);
}

/* The stop's own cause, from the meshes tried (see decide_stop in
 * refine.c), first in the list. */
static void stop_cause(dtm_refine_result *rr) {
  char tried[400], ut[160];
  int u = dtm_refine_best_of(rr, "uniform");
  const dtm_refine_round *b = &rr->rounds[rr->best];
  dtm_cause *c = NULL;
  tried_text(rr, tried, sizeof tried);
  if (u > 0) uniform_text(rr, u, ut, sizeof ut);
  switch (rr->stop) {
  case DTM_REFINE_ONLY_SHAPE:
    if ((c = dtm_refine_new_cause(rr, "shape-limited")))
      snprintf(c->text, sizeof c->text,
               "on %s, at or above the size the target implies, the %zu element(s) below the target are all "
               "limited by their shape (a small angle or thin feature of the model), not by their size",
               ut, rr->rounds[u].below);
    break;
  case DTM_REFINE_THICKNESS:
    if ((c = dtm_refine_new_cause(rr, "thickness")))
      snprintf(c->text, sizeof c->text,
               "on %s, at or above the size the target implies, %zu layer(s) still cap the step of the elements "
               "below the target: no mesh of those layers reached it; the layers and their remedies are in the "
               "summary",
               ut, rr->rounds[u].layers);
    break;
  case DTM_REFINE_ACCURACY:
    if ((c = dtm_refine_new_cause(rr, "accuracy")))
      snprintf(c->text, sizeof c->text,
               "the accuracy bound%s%s%s keeps the mesh finer than the target needs: it clamped the uniform and "
               "scaled sizes refine tried (to the field of a mesh tried already where they became one); tried: %s",
               rr->forced_by ? " '" : "s", rr->forced_by ? rr->forced_by : "", rr->forced_by ? "'" : "", tried);
    break;
  case DTM_REFINE_BUDGET: budget_cause(rr, tried); break;
  case DTM_REFINE_STALLED:
    if ((c = dtm_refine_new_cause(rr, "stalled")))
      snprintf(c->text, sizeof c->text,
               "no strategy met the target: %s; the best mesh has %.4g s, %.1f %% short, with %zu element(s) "
               "below the target (%zu shape-limited)",
               tried, b->recommended, 100.0 * (1.0 - b->recommended / rr->target), b->below, b->shape_limited);
    break;
  case DTM_REFINE_GMSH_REFUSED:
  case DTM_REFINE_GMSH_CRASH: return; /* Gmsh's own words are the cause, added when it failed */
  case DTM_REFINE_LAYERS: return;     /* the fixed counts, moved first by the caller */
  default: return;
  }
  to_front(rr);
}

/* On a stop by fixed layers, their cause goes first, saying that every
 * element below the target lies where they are. */
static void layers_first(dtm_refine_result *rr) {
  for (int i = 0; i < rr->ncauses; i++) {
    if (strcmp(rr->causes[i].kind, "fixed-node-count")) continue;
    dtm_cause c = rr->causes[i];
    size_t at = strlen(c.text);
    snprintf(c.text + at, sizeof c.text - at,
             "; every one of the %zu element(s) below the target lies in the entities these counts make, so no "
             "remesh was run: %s lift their step",
             rr->rounds[0].below,
             rr->options.keep_counts ? "fewer nodes on these curves (or refine without --keep-counts)"
                                     : "fewer layers, thicker ones,");
    memmove(&rr->causes[1], &rr->causes[0], (size_t)i * sizeof c);
    rr->causes[0] = c;
    return;
  }
  dtm_cause *c = dtm_refine_new_cause(rr, "fixed-node-count");
  if (c) snprintf(c->text, sizeof c->text, "%s", dtm_refine_stop_text(DTM_REFINE_LAYERS)), to_front(rr);
}

void dtm_refine_mass_cause(dtm_refine_result *rr) {
  dtm_cause *c = dtm_refine_new_cause(rr, "mass-limit");
  if (c && rr->mass_least)
    snprintf(c->text, sizeof c->text,
             "point masses need %.3g %% of the model's mass to meet the target on the kept mesh, more than the "
             "%.3g %% allowed (--max-added-mass): the least share a search found (dtmap's mass rule scaled down "
             "until the global estimate with the masses just meets the target)",
             rr->mass_needed, rr->options.max_added_mass);
  else if (c)
    snprintf(c->text, sizeof c->text,
             "dtmap's mass rule (each node below the target given the least mass that lifts its own bound to it) "
             "adds %.3g %% of the model's mass to meet the target on the kept mesh, more than the %.3g %% allowed "
             "(--max-added-mass); that is what the rule adds, not the least share that meets the target",
             rr->mass_needed, rr->options.max_added_mass);
}

void dtm_refine_collect_causes(dtm_refine_result *rr, const dtm_cause *model, int nmodel) {
  if (rr->rounds[rr->best].recommended < rr->target) {
    add_causes(rr, model, nmodel, 0);
    stop_cause(rr);
    if (rr->stop == DTM_REFINE_LAYERS) layers_first(rr);
    dtm_cause *c;
    if (rr->stop != DTM_REFINE_ACCURACY && rr->forced_by && rr->forced >= 0.5 &&
        (c = dtm_refine_new_cause(rr, "accuracy")))
      snprintf(c->text, sizeof c->text, "the accuracy bound '%s' forbids the coarser size (about %.0f more elements)",
               rr->forced_by, rr->forced);
    if (!rr->ncauses && (c = dtm_refine_new_cause(rr, "stalled")))
      snprintf(c->text, sizeof c->text, "%s", dtm_refine_stop_text(rr->stop));
  }
  add_causes(rr, model, nmodel, 1);
}

void dtm_refine_met_causes(dtm_refine_result *rr) {
  int n = 0;
  for (int i = 0; i < rr->ncauses; i++)
    if (!strcmp(rr->causes[i].kind, "size-options")) rr->causes[n++] = rr->causes[i];
  rr->ncauses = n;
  rr->stop = DTM_REFINE_MET;
}
