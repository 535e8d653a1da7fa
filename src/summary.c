/* The terminal summary of an analysis, in the manner of an explicit solver's
 * starter listing: counts, the smallest step and where it is, the
 * recommendation, the ten smallest elements, and a histogram by decade. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/analysis.h"
#include "dtmap/cost.h"

#define NSMALL 10

static void print_counts(const dtm_analysis *a, FILE *f) {
  fprintf(f, "mesh         %zu elements (", a->nel);
  for (int b = 0; b < a->mesh->nblocks; b++)
    fprintf(f, "%s%s %zu", b ? ", " : "", dtm_elem_name(a->mesh->blocks[b].type), a->mesh->blocks[b].n);
  fprintf(f, "), %zu nodes, analysed in %dD\n", a->mesh->nnodes, a->mesh->dim);
  fprintf(f, "effects     ");
  for (int k = 0; k < a->neffects; k++) fprintf(f, " [%d] %s", k, a->effects[k].cls->name);
  fprintf(f, "\n");
}

static void print_where(const dtm_analysis *a, size_t i, FILE *f) {
  double c[3];
  char lbl[64];
  int b;
  size_t l;
  dtm_analysis_locate(a, i, &b, &l);
  dtm_analysis_centroid(a, i, c);
  fprintf(f, "element %zu (%s) in '%s' at (%.4g, %.4g, %.4g)", dtm_analysis_tag(a, i),
          dtm_elem_name(a->mesh->blocks[b].type),
          dtm_mesh_group_label(a->mesh, dtm_analysis_group(a, i), lbl, sizeof lbl), c[0], c[1], c[2]);
}

static void print_min(const dtm_analysis *a, FILE *f) {
  fprintf(f, "dt min       %.4e s at ", a->dt_min);
  print_where(a, a->el_min, f);
  fprintf(f, ", limited by %s\n", a->effects[a->limiting[a->el_min]].cls->name);
  for (int k = 0; k < a->neffects && a->neffects > 1; k++) {
    if (!a->dt_effect[k]) continue;
    fprintf(f, "  %-10s %.4e s at ", a->effects[k].cls->name, a->per_effect[k].min);
    print_where(a, a->per_effect[k].element, f);
    fprintf(f, "\n");
  }
  for (int k = 0; k < a->neffects; k++)
    if (isfinite(a->per_effect[k].nodal))
      fprintf(f, "nodal bound  %-10s %.4e s (%.2fx its element bound)\n", a->effects[k].cls->name,
              a->per_effect[k].nodal, a->per_effect[k].nodal / a->per_effect[k].min);
  for (int k = 0; a->global && k < a->neffects; k++) {
    const dtm_global_info *g = &a->global[k];
    if (!g->done) continue;
    fprintf(f, "global       %-10s dt in [%.4e, %.4e] s after %d Lanczos steps (%.2f s), %s\n", a->effects[k].cls->name,
            g->dt_low, g->dt_high, g->iterations, g->seconds,
            g->converged ? "converged" : "NOT converged: the nodal bound stays the basis");
  }
  fprintf(f, "recommended  %.4e s = safety %.2f x %.4e s (%s)\n", a->recommended, a->scene->safety,
          a->recommended / a->scene->safety, a->basis);
  if (a->scene->target > 0)
    fprintf(f, "target       %.4e s: %s\n", a->scene->target,
            a->recommended >= a->scene->target ? "met" : "NOT met (see the size suggestion view)");
}

/* Indices of the k smallest dt, ascending, by a bounded insertion. */
static int smallest(const dtm_analysis *a, size_t *idx) {
  int k = 0;
  for (size_t i = 0; i < a->nel; i++) {
    if (k == NSMALL && a->dt[i] >= a->dt[idx[k - 1]]) continue;
    int j = k < NSMALL ? k++ : NSMALL - 1;
    while (j > 0 && a->dt[idx[j - 1]] > a->dt[i]) idx[j] = idx[j - 1], j--;
    idx[j] = i;
  }
  return k;
}

static void print_smallest(const dtm_analysis *a, FILE *f) {
  size_t idx[NSMALL];
  int k = smallest(a, idx);
  char lbl[64];
  fprintf(f, "\n%d smallest steps:\n  %4s %10s %-7s %-16s %-12s %-12s %s\n", k, "rank", "element", "type", "group",
          "dt (s)", "length (m)", "effect");
  for (int r = 0; r < k; r++) {
    size_t i = idx[r], l;
    int b;
    dtm_analysis_locate(a, i, &b, &l);
    fprintf(f, "  %4d %10zu %-7s %-16s %-12.4e %-12.4e %s\n", r + 1, dtm_analysis_tag(a, i),
            dtm_elem_name(a->mesh->blocks[b].type),
            dtm_mesh_group_label(a->mesh, dtm_analysis_group(a, i), lbl, sizeof lbl), a->dt[i], a->len[i],
            a->effects[a->limiting[i]].cls->name);
  }
}

static void print_accuracy(const dtm_analysis *a, FILE *f) {
  for (int k = 0; k < a->neffects; k++) {
    if (!a->resolution[k]) continue;
    size_t n = 0;
    for (size_t i = 0; i < a->nel; i++) n += a->h[i] > a->hmax[i] && a->hmax_by[i] == k;
    fprintf(f, "accuracy     %s: %zu element(s) coarser than its accuracy bound (view '%s')\n", a->effects[k].cls->name,
            n, a->effects[k].cls->accuracy_view);
  }
  if (!a->conflicts) return;
  size_t i = a->cap_element;
  const dtm_effect_class *c = a->effects[a->hmax_by[i]].cls;
  fprintf(f,
          "conflict     resolving '%s' needs h <= %.4g m (element %zu), which caps the step at %.4e s,\n"
          "             below the target %.4e s at %zu element(s)",
          c->accuracy_view, a->hmax[i], dtm_analysis_tag(a, i), a->dt_accuracy_cap, a->scene->target, a->conflicts);
  if (a->scene->duration > 0)
    fprintf(f, ";\n             the duration %.4g s then costs %.4g element-steps", a->scene->duration,
            (double)a->nel * a->scene->duration / a->dt_accuracy_cap);
  fprintf(f, "\n");
}

static void print_cost(const dtm_analysis *a, FILE *f) {
  const dtm_subcycling *sc = a->subcycling;
  fprintf(f, "subcycling   %d level(s) of dt_min x 2^k:", sc->nlevels);
  for (int k = 0; k < sc->nlevels && k < 8; k++) fprintf(f, " %zu", sc->count[k]);
  fprintf(f, "%s; ideal speed-up %.2fx\n", sc->nlevels > 8 ? " ..." : "", sc->speedup);
  if (a->scene->duration > 0)
    fprintf(f, "cost         %.4g s needs %.0f steps of %.4e s: %.4g element-steps (%.4g with subcycling)\n",
            a->scene->duration, ceil(a->scene->duration / a->recommended), a->recommended, dtm_cost_element_steps(a),
            dtm_cost_element_steps_subcycled(a));
  const dtm_mass_scaling *ms = a->mass_scaling;
  if (ms)
    fprintf(f, "mass scaling to reach the target: +%.3g%% mass (%.4g of %.4g) on %zu element(s) (view 'added mass')\n",
            100.0 * ms->total_added / ms->total_mass, ms->total_added, ms->total_mass, ms->scaled);
}

static void print_histogram(const dtm_analysis *a, FILE *f) {
  int lo = (int)floor(log10(a->dt_min)), hi = lo;
  for (size_t i = 0; i < a->nel; i++)
    if (isfinite(a->dt[i]) && (int)floor(log10(a->dt[i])) > hi) hi = (int)floor(log10(a->dt[i]));
  if (hi - lo > 15) hi = lo + 15;
  size_t count[16] = {0}, most = 1;
  for (size_t i = 0; i < a->nel; i++) {
    if (!isfinite(a->dt[i])) continue; /* no effect limits this element */
    int d = (int)floor(log10(a->dt[i])) - lo;
    count[d < 0 ? 0 : d > hi - lo ? hi - lo : d]++;
  }
  for (int d = 0; d <= hi - lo; d++) most = count[d] > most ? count[d] : most;
  fprintf(f, "\ndt by decade:\n");
  for (int d = 0; d <= hi - lo; d++) {
    int bar = (int)(40.0 * (double)count[d] / (double)most + 0.5);
    fprintf(f, "  [1e%+03d, 1e%+03d) %10zu %5.1f%% ", lo + d, lo + d + 1, count[d], 100.0 * count[d] / a->nel);
    for (int c = 0; c < bar; c++) fputc('#', f);
    fputc('\n', f);
  }
}

void dtm_summary_print(const dtm_analysis *a, void *stream) {
  FILE *f = stream;
  print_counts(a, f);
  print_min(a, f);
  print_accuracy(a, f);
  print_cost(a, f);
  print_smallest(a, f);
  print_histogram(a, f);
}
