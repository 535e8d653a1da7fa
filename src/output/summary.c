/* The terminal summary of an analysis, in the manner of an explicit solver's
 * starter listing: counts, the recommended step and its basis with the
 * element bound (the map's own minimum) labelled as such beside it,
 * the plausibility warnings right under the model line (before any figure
 * a unit error would make wrong), accuracy, the cost from that one step,
 * the shape-limited elements,
 * damping factors, the smallest elements, a histogram in octaves of the
 * recommended step (or the target) and the
 * warnings. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "output-impl.h"
#include "dtmap/operator.h"
#include "dtmap/util.h"
#include "report.h"

static const char *effect_name(const dtm_analysis *a, int k) { return dtm_analysis_effect(a, k)->name; }

static const char *type_name(const dtm_analysis *a, size_t i) {
  int b;
  size_t l;
  dtm_analysis_locate(a, i, &b, &l);
  return dtm_elem_name(dtm_analysis_mesh(a)->blocks[b].type);
}

static const char *group_name(const dtm_analysis *a, size_t i, char *lbl, size_t len) {
  return dtm_mesh_group_label(dtm_analysis_mesh(a), dtm_analysis_group(a, i), lbl, len);
}

/* One line per scene section: its groups and kind, element count, the
 * smallest element step and the anchor rule's smallest step. */
static void print_sections(const dtm_analysis *a, FILE *f) {
  const dtm_scene *s = dtm_analysis_scene(a);
  dtm_section_stats *st = calloc((size_t)s->nsections + 1, sizeof *st);
  if (!st) return;
  dtm_analysis_sections(a, st);
  for (int i = 0; i < s->nsections; i++) {
    const dtm_section *sec = &s->sections[i];
    fprintf(f, "%s", i ? "             " : "sections     ");
    for (int g = 0; g < sec->ngroups; g++) fprintf(f, "%s%s", g ? " " : "", sec->groups[g]);
    fprintf(f, "%s%s: %s", sec->ngroups ? "" : "(default)", sec->is_default && sec->ngroups ? " (default)" : "",
            dtm_section_kind_name(sec->kind));
    if (sec->area > 0) fprintf(f, ", A %.4g %s", sec->area, dtm_unit_label(s, DTM_UNIT_AREA));
    if (sec->thickness > 0 && sec->kind != DTM_SECTION_SOLID)
      fprintf(f, ", t %.4g %s", sec->thickness, dtm_unit_label(s, DTM_UNIT_LENGTH));
    fprintf(f, ", %zu elements", st[i].elements);
    if (isfinite(st[i].dt_min)) fprintf(f, ", element bound %.4e s", st[i].dt_min);
    if (isfinite(st[i].anchor_min)) fprintf(f, " (%s: %.4e s)", st[i].anchor, st[i].anchor_min);
    fprintf(f, "\n");
    if (!isfinite(st[i].dt_physical_min)) continue;
    if (sec->rotary == DTM_ROTARY_SCALED_INERTIA)
      fprintf(f,
              "             rotary inertia scaled (by up to %.4g) so that %s modes govern: the bound above and the "
              "step use it; with physical rotary inertia %.4e s (element %zu)\n",
              st[i].scale_max, sec->kind == DTM_SECTION_SHELL ? "membrane" : "axial", st[i].dt_physical_min,
              st[i].physical_element);
    else
      fprintf(f, "             physical rotary inertia (rotary=\"physical\"): the bound above and the step use it\n");
  }
  for (int i = 0; i < s->nsections; i++)
    if (isfinite(st[i].anchor_min)) {
      fprintf(f, "             element bound: dtmap's, 2/omega_max of each element (an eigenvalue bound, safe); in "
                 "brackets: the solver's length rule, not a bound\n");
      break;
    }
  free(st);
}

static void print_counts(const dtm_analysis *a, FILE *f) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  fprintf(f, "mesh         %zu elements (", dtm_analysis_nelements(a));
  for (int b = 0; b < m->nblocks; b++)
    fprintf(f, "%s%s %zu", b ? ", " : "", dtm_elem_name(m->blocks[b].type), m->blocks[b].n);
  int space = dtm_analysis_space_dim(a);
  fprintf(f, "), %zu nodes", m->nnodes);
  if (m->nodes_used && m->nodes_used < m->nnodes) fprintf(f, " (%zu in analysed elements)", m->nodes_used);
  if (dtm_analysis_planes(a) > 1)
    fprintf(f, ", analysed in %d parallel planes (each surface a plane problem in its own plane)\n",
            dtm_analysis_planes(a));
  else if (space > m->dim)
    fprintf(f, ", analysed in %dD (elements of dimension %d and below)\n", space, m->dim);
  else
    fprintf(f, ", analysed in %dD\n", m->dim);
  print_sections(a, f);
  const dtm_mesher_info *mi = dtm_analysis_mesher(a);
  if (!mi->reproducible)
    fprintf(f, "mesher       %s on %d thread%s: another run may number (and count) the elements differently\n",
            dtm_scene_algorithm_name(mi->algorithm), mi->threads, mi->threads == 1 ? "" : "s");
  fprintf(f, "effects     ");
  for (int k = 0; k < dtm_analysis_neffects(a); k++) fprintf(f, " [%d] %s", k, effect_name(a, k));
  fprintf(f, "\n");
}

static void print_where(const dtm_analysis *a, size_t i, FILE *f) {
  double c[3];
  char lbl[64];
  dtm_analysis_centroid(a, i, c);
  fprintf(f, "element %zu (%s) in '%s' at (%.4g, %.4g, %.4g) %s", dtm_analysis_tag(a, i), type_name(a, i),
          group_name(a, i, lbl, sizeof lbl), c[0], c[1], c[2], dtm_output_unit(a, DTM_UNIT_LENGTH));
}

/* What the factorisation cost, or what the refused one would have cost
 * against what it was allowed (src/analysis/global.c). */
static void print_factorisation(const dtm_global_info *g, FILE *f) {
  if (g->deterministic == DTM_CERT_PROVEN || g->certified == DTM_CERT_PROVEN)
    fprintf(f, "             factorisation of %.3g flops, %.3g MB, %.2f s\n", g->cert_predicted[0],
            g->cert_predicted[1] / 1e6, g->cert_seconds);
  else if (g->deterministic == DTM_CERT_TOO_DEAR && isfinite(g->cert_predicted[0]))
    fprintf(f,
            "             factorisation too dear: %.3g flops and %.3g MB predicted, %.3g flops allowed (%.2f s to "
            "predict)\n",
            g->cert_predicted[0], g->cert_predicted[1] / 1e6, g->cert_budget, g->cert_seconds);
  else if (g->deterministic == DTM_CERT_TOO_DEAR)
    fprintf(f, "             factorisation too dear: the mesh is too large to order, %.3g flops allowed (%.2f s)\n",
            g->cert_budget, g->cert_seconds);
}

/* Which proof holds for the global estimate, in words. */
static void print_certificate(const dtm_global_info *g, FILE *f) {
  const char *why = g->deterministic == DTM_CERT_TOO_DEAR      ? "factorisation too dear"
                    : g->deterministic == DTM_CERT_UNAVAILABLE ? "no factorisation for shells or beams"
                                                               : "no factorisation in a distributed run";
  if (g->certified == DTM_CERT_PROVEN)
    fprintf(f, "             bound proven: the factorisation shows no eigenvalue above theta + residual\n");
  else if (g->certified == DTM_CERT_PROBABLE)
    fprintf(f,
            "             bound probable (%s): the step %.4e s is at or below the exact step but with\n"
            "             probability %.0e (Kuczynski-Wozniakowski, %d steps, eps %.3g, n %.0f)\n",
            why, g->dt_certified, g->failure, g->iterations, g->eps, g->nbound);
  else
    fprintf(f, "             bound not proven (%s%s)\n", why,
            g->deterministic == DTM_CERT_TOO_DEAR || g->deterministic == DTM_CERT_UNAVAILABLE
                ? "; too few Lanczos steps for the probable bound"
                : "");
}

static void print_effect_minima(const dtm_analysis *a, FILE *f) {
  int ne = dtm_analysis_neffects(a);
  for (int k = 0; k < ne && ne > 1; k++) {
    if (!dtm_analysis_effect_dt(a, k)) continue;
    fprintf(f, "  %-10s %.4e s at ", effect_name(a, k), dtm_analysis_effect_min(a, k)->min);
    print_where(a, dtm_analysis_effect_min(a, k)->element, f);
    fprintf(f, "\n");
  }
  for (int k = 0; k < ne; k++) {
    const dtm_effect_min *pe = dtm_analysis_effect_min(a, k);
    if (isfinite(pe->nodal))
      fprintf(f, "nodal bound  %-10s %.4e s (%.2fx its element bound)\n", effect_name(a, k), pe->nodal,
              pe->nodal / pe->min);
  }
  for (int k = 0; k < ne; k++) {
    const dtm_global_info *g = dtm_analysis_global(a, k);
    if (!g) continue;
    fprintf(f, "global       %-10s dt in [%.4e, %.4e] s after %d Lanczos steps (%.2f s, seed %u), %s\n",
            effect_name(a, k), g->dt_low, g->dt_high, g->iterations, g->seconds, g->seed,
            g->converged ? "converged (an estimate at its tolerance)"
                         : "NOT converged: the nodal bound stays the basis");
    if (g->converged) print_certificate(g, f);
    if (g->converged) print_factorisation(g, f);
  }
}

static void print_min(const dtm_analysis *a, FILE *f) {
  const dtm_scene *s = dtm_analysis_scene(a);
  size_t el;
  double rec = dtm_analysis_recommended(a);
  if (dtm_analysis_recommended_certified(a))
    fprintf(f,
            "recommended  %.4e s = the probable bound's certified step, below safety %.2f x %.4e s (%s):\n"
            "             the step; cost, subcycling, mass scaling\n",
            rec, s->safety, dtm_analysis_basis_step(a), dtm_analysis_basis(a));
  else
    fprintf(f, "recommended  %.4e s = safety %.2f x %.4e s (%s): the step; cost, subcycling, mass scaling\n", rec,
            s->safety, dtm_analysis_basis_step(a), dtm_analysis_basis(a));
  fprintf(f, "             and verify all use it\n");
  fprintf(f, "elem. bound  %.4e s, the dt map's own minimum (a bound, not the step) at ", dtm_analysis_dt_min(a, &el));
  print_where(a, el, f);
  fprintf(f, ", limited by %s\n", effect_name(a, dtm_analysis_limiting(a)[el]));
  print_effect_minima(a, f);
  if (s->target > 0)
    fprintf(f, "target       %.4e s: %s\n", s->target,
            rec >= s->target ? "met" : "NOT met (see the size suggestion view)");
}

/* The point masses the mesh carries (refine's added mass, or read back). */
static void print_point_masses(const dtm_analysis *a, FILE *f) {
  const double *pm = dtm_analysis_point_masses(a);
  size_t nn = dtm_analysis_mesh(a)->nnodes, nodes = 0;
  double total = 0;
  for (size_t v = 0; pm && v < nn; v++) total += pm[v], nodes += pm[v] > 0;
  if (!pm) return;
  fprintf(f, "point masses %.4g %s at %zu node(s) (view '%s'): in the nodal bound, the global estimate and verify,\n",
          total, dtm_output_unit(a, DTM_UNIT_MASS), nodes, DTM_VIEW_NODE_MASS);
  fprintf(f, "             not in the element steps of the dt map\n");
}

static void print_smallest(const dtm_results *res, FILE *f) {
  const dtm_analysis *a = res->analysis;
  size_t *idx = NULL;
  int k = dtm_worst(a, dtm_results_top(res), &idx);
  char lbl[64], len[32];
  if (!k) {
    free(idx);
    return;
  }
  fprintf(f, "\n%d smallest element steps:\n  %4s %10s %-7s %-16s %-12s %-12s %s\n", k, "rank", "element", "type",
          "group", "dt (s)", (snprintf(len, sizeof len, "length (%s)", dtm_output_unit(a, DTM_UNIT_LENGTH)), len),
          "effect");
  for (int r = 0; r < k; r++) {
    size_t i = idx[r];
    fprintf(f, "  %4d %10zu %-7s %-16s %-12.4e %-12.4e %s\n", r + 1, dtm_analysis_tag(a, i), type_name(a, i),
            group_name(a, i, lbl, sizeof lbl), dtm_analysis_dt(a)[i], dtm_analysis_length(a)[i],
            effect_name(a, dtm_analysis_limiting(a)[i]));
  }
  free(idx);
}

static void print_conflict(const dtm_analysis *a, const dtm_accuracy *ac, FILE *f) {
  const dtm_scene *s = dtm_analysis_scene(a);
  size_t i = ac->cap_element;
  const dtm_effect_class *c = dtm_analysis_effect(a, dtm_analysis_hmax_by(a)[i]);
  fprintf(f,
          "conflict     resolving '%s' needs h <= %.4g %s (element %zu), which caps the step at %.4e s,\n"
          "             below the target %.4e s at %zu element(s)",
          c->indicator.view, dtm_analysis_hmax(a)[i], dtm_unit_label(s, DTM_UNIT_LENGTH), dtm_analysis_tag(a, i),
          ac->dt_cap, s->target, ac->conflicts);
  if (s->duration > 0)
    fprintf(f, ";\n             the duration %.4g s then costs %.4g element-steps", s->duration,
            (double)dtm_analysis_nelements(a) * s->duration / ac->dt_cap);
  fprintf(f, "\n");
}

static void print_accuracy(const dtm_analysis *a, FILE *f) {
  const double *h = dtm_analysis_size(a), *hmax = dtm_analysis_hmax(a);
  const int *by = dtm_analysis_hmax_by(a);
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    if (!dtm_analysis_resolution(a, k)) continue;
    size_t n = 0;
    for (size_t i = 0; i < dtm_analysis_nelements(a); i++) n += h[i] > hmax[i] && by[i] == k;
    fprintf(f, "accuracy     %s: %zu element(s) coarser than its accuracy bound (view '%s')\n", effect_name(a, k), n,
            dtm_analysis_effect(a, k)->indicator.view);
  }
  dtm_accuracy ac;
  dtm_analysis_accuracy(a, &ac);
  if (ac.conflicts) print_conflict(a, &ac, f);
}

/* What "below the target" counts, said where a count is printed: an
 * element's own safe step (dtm_analysis_local_step x safety) below the
 * advice target (dtm_analysis_below_target, refine's "below" column and the
 * histogram's bins under 1 count the same elements). */
#define BELOW_DEFINITION                                                                                               \
  "own safe step below the target: safety x the larger of its element step and the smallest nodal bound at its nodes"

static void print_cost(const dtm_analysis *a, const dtm_cost *c, FILE *f) {
  const dtm_subcycling *sc = &c->subcycling;
  double rec = dtm_analysis_recommended(a);
  fprintf(f, "subcycling   %d level(s) of the recommended step x 2^k:", sc->nlevels);
  for (int k = 0; k < sc->nlevels && k < 8; k++) fprintf(f, " %zu", sc->count[k]);
  fprintf(f, "%s; ideal speed-up %.2fx\n", sc->nlevels > 8 ? " ..." : "", sc->speedup);
  if (c->duration > 0)
    fprintf(f, "cost         %.4g s needs %.0f steps of %.4e s: %.4g element-steps (%.4g with subcycling)\n",
            c->duration, ceil(c->duration / rec), rec, c->element_steps, c->element_steps_subcycled);
  const dtm_mass_scaling *ms = c->mass;
  if (ms && ms->nodal)
    fprintf(f,
            "mass scaling to reach the target at the nodes: +%.3g%% mass (%.4g %s of %.4g %s); %zu element(s) have a "
            "node that receives mass, the %zu below the target among them (view 'added mass')\n",
            100.0 * ms->total_added / ms->total_mass, ms->total_added, dtm_output_unit(a, DTM_UNIT_MASS),
            ms->total_mass, dtm_output_unit(a, DTM_UNIT_MASS), ms->scaled, dtm_analysis_below_target(a));
  else if (ms)
    fprintf(f,
            "mass scaling to reach the target: +%.3g%% mass (%.4g %s of %.4g %s) on %zu element(s) (view 'added "
            "mass')\n",
            100.0 * ms->total_added / ms->total_mass, ms->total_added, dtm_output_unit(a, DTM_UNIT_MASS),
            ms->total_mass, dtm_output_unit(a, DTM_UNIT_MASS), ms->scaled);
}

#define SHAPE_LISTED 20 /* shape-limited elements printed */

static void print_shape(const dtm_results *r, FILE *f) {
  const dtm_analysis *a = r->analysis;
  size_t n, below = dtm_analysis_below_target(a);
  const dtm_shape_limited *sl = dtm_analysis_shape_limited(a, &n);
  if (!below) return;
  fprintf(f,
          "below target %zu element(s) (" BELOW_DEFINITION
          "; view 'below target [s]'); %zu of them shape-limited (no larger size lifts "
          "their step)%s\n",
          below, n, n ? " (view 'shape limited'):" : "");
  for (size_t j = 0; j < n && j < SHAPE_LISTED; j++) {
    char ft[200], rt[200];
    fprintf(f, "  ");
    print_where(a, sl[j].element, f);
    fprintf(f, ":\n    %s; a well-shaped element there reaches about %.4e s (an estimate, not a bound); remedy: %s\n",
            dtm_feature_text(a, &sl[j], ft, sizeof ft), sl[j].reach, dtm_remedy_text(r, &sl[j], rt, sizeof rt));
  }
  if (n > SHAPE_LISTED) fprintf(f, "  ... and %zu more (the report lists them)\n", n - SHAPE_LISTED);
  const dtm_mass_scaling *ms = r->cost ? r->cost->shape_mass : NULL;
  if (ms)
    fprintf(f, "  mass alternative for exactly these: +%.4g %s (%.3g%% of the model) at their nodes\n", ms->total_added,
            dtm_output_unit(a, DTM_UNIT_MASS), 100.0 * ms->total_added / ms->total_mass);
}

#define LAYERS_LISTED 4 /* layers printed (the report lists all) */

/* The remedies of layer k: the mass its elements need, and the layer as
 * its mid-surface (mid-line in 2D) at its own thickness. */
static void print_layer_remedies(const dtm_results *r, size_t k, const dtm_layer *l, FILE *f) {
  const dtm_mass_scaling *ms = r->cost ? r->cost->layer_mass : NULL;
  int g = l->group, slot = g >= 0 ? g : (ms ? ms->ngroups - 1 : 0);
  double added = dtm_layer_added_mass(r, k);
  if (ms && ms->group_mass[slot] > 0 && isfinite(added))
    fprintf(f, "               remedy: mass scaling at their nodes, +%.4g %s (+%.3g%% of the group's mass)\n", added,
            dtm_output_unit(r->analysis, DTM_UNIT_MASS), 100.0 * added / ms->group_mass[slot]);
  if (isfinite(l->shell_step) && dtm_analysis_mesh(r->analysis)->dim == 3)
    fprintf(f,
            "               remedy: model the layer as its mid-surface, <section kind=\"shell\" thickness=\"%.3g\"/>: "
            "about %.4e s by LS-DYNA's rule at its present size %.3g %s\n",
            l->thickness, l->shell_step, l->size, dtm_output_unit(r->analysis, DTM_UNIT_LENGTH));
  else if (isfinite(l->shell_step))
    fprintf(f,
            "               remedy: model the layer as its mid-line, <section kind=\"beam\" width=\"1\" "
            "height=\"%.3g\"/> (per unit thickness, as the plane elements): about %.4e s by LS-DYNA's rule at its "
            "present size %.3g %s\n",
            l->thickness, l->shell_step, l->size, dtm_output_unit(r->analysis, DTM_UNIT_LENGTH));
}

/* Each layer whose thickness caps elements below the target (smallest
 * reach first, at most LAYERS_LISTED): its own thickness, how many, the
 * best step any mesh of it reaches, and its remedies with their costs;
 * subcycling once for all. */
static void print_layers(const dtm_results *r, FILE *f) {
  const dtm_analysis *a = r->analysis;
  size_t n;
  const dtm_layer *ly = dtm_analysis_layers(a, &n);
  const char *L = dtm_output_unit(a, DTM_UNIT_LENGTH);
  if (n && !ly[0].at_minimum)
    fprintf(f,
            "thickness    %zu layer(s) cap elements below the target at their own thickness (view 'thickness "
            "limited'): a well-shaped element across each falls short of the target on its own (an estimate, not a "
            "bound: a fresh mesh's nodal bound there may lie above it; refine tries):\n",
            n);
  for (size_t k = 0; k < n && k < LAYERS_LISTED; k++) {
    char lbl[64], fc[96];
    const char *gl = dtm_mesh_group_label(dtm_analysis_mesh(a), ly[k].group, lbl, sizeof lbl);
    dtm_layer_faces_text(&ly[k], fc, sizeof fc);
    if (ly[k].at_minimum) {
      double rec = dtm_analysis_recommended(a);
      fprintf(
          f,
          "thickness    the smallest steps lie where '%s' is %.4g %s thin, %s (%zu of the elements within 10%% of "
          "the smallest step): a well-shaped element across that thickness reaches about %.4e s there (an estimate, "
          "not a bound%s)\n",
          gl, ly[k].thickness, L, fc, ly[k].elements, ly[k].reach,
          ly[k].reach < rec ? ", which this mesh's recommended step already beats: not a bound" : "");
      continue; /* no target: nothing to remedy */
    }
    fprintf(f, "  layer %zu   '%s' %s: %zu element(s), %.4g %s thick; an element across it reaches about %.4e s\n",
            k + 1, gl, fc, ly[k].elements, ly[k].thickness, L, ly[k].reach);
    print_layer_remedies(r, k, &ly[k], f);
  }
  if (n > LAYERS_LISTED) fprintf(f, "  ... and %zu more layer(s) (the report lists them)\n", n - LAYERS_LISTED);
  if (n && !ly[0].at_minimum && r->cost && r->cost->subcycling.speedup > 1)
    fprintf(f, "  remedy: subcycling, the rest of the mesh on larger steps (ideal speed-up %.2fx)\n",
            r->cost->subcycling.speedup);
}

void dtm_summary_advice(const dtm_results *r, FILE *f) {
  print_shape(r, f);
  print_layers(r, f);
}

static void print_damping(const dtm_analysis *a, FILE *f) {
  dtm_damping_row *rows = NULL;
  int n = 0;
  if (dtm_damping_rows(a, &rows, &n) == DTM_OK)
    for (int j = 0; j < n; j++)
      fprintf(f, "damping      %-10s x %.4f on '%s' at omega %.4g rad/s (elements: %.4f to %.4f)\n",
              effect_name(a, rows[j].effect), rows[j].factor, dtm_analysis_scene(a)->materials[rows[j].mat].m.name,
              rows[j].omega, rows[j].emin, rows[j].emax);
  free(rows);
}

static void print_zones(const dtm_analysis *a, FILE *f) {
  dtm_zone_row *rows = NULL;
  int n = 0;
  if (dtm_zone_rows(a, &rows, &n) == DTM_OK)
    for (int j = 0; j < n; j++)
      fprintf(f, "cohesive     '%s': process zone R = %.4g %s, h_max = R/N = %.4g %s\n",
              dtm_analysis_scene(a)->materials[rows[j].mat].m.name, rows[j].R, dtm_output_unit(a, DTM_UNIT_LENGTH),
              rows[j].hmax, dtm_output_unit(a, DTM_UNIT_LENGTH));
  free(rows);
}

/* The plausibility warnings (a density, a wave speed, a model's size that
 * look like a unit error), right under the model line: before any figure
 * they would make wrong. Returns how many. */
static int print_plausibility(const dtm_analysis *a, FILE *f) {
  dtm_warnings w = {0, {{0}}};
  dtm_output_plausibility_warnings(a, &w);
  for (int j = 0; j < w.n; j++) fprintf(f, "WARNING: %s\n", w.text[j]);
  return w.n;
}

/* The other warnings, at the end (dtm_output_warnings gives the
 * plausibility ones first: the first `shown` are printed already). */
static void print_warnings(const dtm_results *r, int shown, FILE *f) {
  dtm_warnings w;
  dtm_output_warnings(r, &w);
  if (w.n > shown) fputc('\n', f);
  for (int j = shown; j < w.n; j++) fprintf(f, "WARNING: %s\n", w.text[j]);
}

#define HIST_BINS 16 /* octaves shown at most; the last takes every larger step */

static void print_hist_title(const dtm_analysis *a, int aimed, double ref, FILE *f) {
  const dtm_scene *s = dtm_analysis_scene(a);
  if (!aimed) {
    fprintf(f, "\ndt in multiples of the recommended step %.4e s (each element's step / it):\n", ref);
    return;
  }
  fprintf(f,
          "\ndt in multiples of the target %.4e s (each element's own safe step / it: safety x the larger of its "
          "element step and the smallest nodal bound at its nodes; below 1: the %zu element(s) below the target)",
          ref, dtm_analysis_below_target(a));
  if (fabs(ref / s->target - 1) > 1e-12) fprintf(f, " (the scene's %.4e s carried to the nodal bound)", s->target);
  fputs(":\n", f);
}

/* The histogram in octaves of a reference step. With a target, it bins
 * each element's own safe step (safety x local step) over the advice
 * target, so that its bins under 1 hold exactly the elements below the
 * target; else each element's step (the dt map) over the recommended step,
 * so that its bins read as "how many times the step the run takes". Bins
 * run from the smallest element's octave up; the last gathers what lies
 * above. */
static void print_histogram(const dtm_analysis *a, FILE *f) {
  size_t nel = dtm_analysis_nelements(a);
  int aimed = dtm_analysis_advice_target(a) > 0;
  double ref = aimed ? dtm_analysis_advice_target(a) : dtm_analysis_recommended(a), small = INFINITY, big = -INFINITY;
  if (!(ref > 0) || !isfinite(ref)) return;
  const double *dt = dtm_analysis_dt(a), *own = dtm_analysis_local_step(a), safety = dtm_analysis_scene(a)->safety;
  for (size_t i = 0; i < nel; i++) {
    double v = aimed ? safety * own[i] : dt[i];
    if (v < small) small = v; /* NaN: skipped, as fmin skips it */
    if (isfinite(v) && v > big) big = v;
  }
  if (!isfinite(small)) return;
  /* the largest octave is the largest value's: log2 and the division keep the order */
  int lo = dtm_octave(small / ref), hi = dtm_octave(big / ref);
  hi = hi > lo ? hi : lo;
  int last = hi - lo < HIST_BINS ? hi - lo : HIST_BINS - 1;
  size_t count[HIST_BINS] = {0}, most = 1;
#pragma omp parallel for schedule(static) reduction(+ : count[:HIST_BINS])
  for (size_t i = 0; i < nel; i++) {
    double v = aimed ? safety * own[i] : dt[i];
    if (!isfinite(v)) continue; /* no effect limits this element */
    int d = dtm_octave(v / ref) - lo;
    if (aimed && v < ref && lo + d >= 0) d = -1 - lo; /* below the target by a rounding: the bin under 1 */
    count[d < 0 ? 0 : d > last ? last : d]++;
  }
  for (int d = 0; d <= last; d++) most = count[d] > most ? count[d] : most;
  print_hist_title(a, aimed, ref, f);
  for (int d = 0; d <= last; d++) {
    int bar = (int)(40.0 * (double)count[d] / (double)most + 0.5);
    char bin[64];
    if (d == last && last < hi - lo)
      snprintf(bin, sizeof bin, "[%g, inf)", ldexp(1.0, lo + d));
    else
      snprintf(bin, sizeof bin, "[%g, %g)", ldexp(1.0, lo + d), ldexp(1.0, lo + d + 1));
    fprintf(f, "  %-18s %10zu %5.1f%% ", bin, count[d], 100.0 * count[d] / nel);
    for (int c = 0; c < bar; c++) fputc('#', f);
    fputc('\n', f);
  }
}

void dtm_summary_print(const dtm_results *r, void *stream) {
  FILE *f = stream;
  print_counts(r->analysis, f);
  dtm_summary_model(r->analysis, f);
  int shown = print_plausibility(r->analysis, f);
  print_min(r->analysis, f);
  print_point_masses(r->analysis, f);
  print_damping(r->analysis, f);
  print_zones(r->analysis, f);
  print_accuracy(r->analysis, f);
  if (r->cost) print_cost(r->analysis, r->cost, f);
  if (r->cost) dtm_summary_measures(r->analysis, r->cost, f);
  if (r->modes) dtm_summary_modes(r->analysis, r->modes, f);
  print_shape(r, f);
  print_layers(r, f);
  print_smallest(r, f);
  print_histogram(r->analysis, f);
  dtm_summary_selective_mass(r, f);
  print_warnings(r, shown, f);
}
