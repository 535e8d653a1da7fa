/* The terminal summary of a distributed run, printed by rank 0 from the
 * global figures: the whole mesh and how it was split, the smallest step
 * and where, the nodal bound and the global estimate, the recommendation,
 * subcycling, the cost and mass scaling, the elements below the target,
 * the slowest part's time per stage and the warnings. */
#include <math.h>
#include <stdio.h>

#include "parallel-impl.h"
#include "report.h"

static void print_parts(const dtm_par *p, const dtm_par_figures *f) {
  printf("mesh         %.0f elements, %.0f nodes, analysed in %dD, in %d parts (%s):", f->elements, f->nodes, p->dim,
         p->size, p->scene->partitions ? "the scene's part files" : "split by Gmsh with METIS");
  for (int r = 0; r < p->size; r++) printf("%s %.0f", r ? "," : "", f->rows[r * ROW_COUNT + ROW_ELEMENTS]);
  printf(" elements\n");
}

static void print_steps(const dtm_par *p, const dtm_par_figures *f) {
  const dtm_analysis *a = p->analysis;
  const dtm_scene *s = p->scene;
  const dtm_par_where *w = &f->dt;
  double rec = dtm_analysis_recommended(a);
  printf("dt min       %.4e s at element %llu (%s) in '%s' at (%.4g, %.4g, %.4g), limited by %s\n",
         dtm_analysis_dt_min(a, NULL), w->tag, w->type, w->group, w->centroid[0], w->centroid[1], w->centroid[2],
         dtm_analysis_effect(a, w->effect)->name);
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const dtm_effect_min *pe = dtm_analysis_effect_min(a, k);
    const dtm_global_info *g = dtm_analysis_global(a, k);
    if (isfinite(pe->nodal))
      printf("nodal bound  %-10s %.4e s (%.2fx its element bound)\n", dtm_analysis_effect(a, k)->name, pe->nodal,
             pe->nodal / pe->min);
    if (g)
      printf("global       %-10s dt in [%.4e, %.4e] s after %d products (SLEPc, %.2f s), %s\n",
             dtm_analysis_effect(a, k)->name, g->dt_low, g->dt_high, g->iterations, g->seconds,
             g->converged ? "converged" : "NOT converged: the nodal bound stays the basis");
  }
  printf("recommended  %.4e s = safety %.2f x %.4e s (%s)\n", rec, s->safety, rec / s->safety, dtm_analysis_basis(a));
}

static void print_cost(const dtm_par *p, const dtm_par_figures *f) {
  const dtm_scene *s = p->scene;
  double rec = dtm_analysis_recommended(p->analysis), steps = ceil(s->duration / rec);
  printf("subcycling   %d level(s), ideal speed-up %.2fx\n", f->sub.nlevels, f->sub.speedup);
  if (s->duration > 0)
    printf("cost         %g s needs %.0f steps of %.4e s: %.4g element-steps (%.4g with subcycling)\n", s->duration,
           steps, rec, steps * f->elements, steps * f->elements / f->sub.speedup);
  if (f->mass)
    printf("mass scaling to %.4e s at the %s: %.4g %s added to %zu element(s), %.3g%% of %.4g %s\n", f->mass->target,
           f->mass->nodal ? "nodes" : "elements", f->mass->total_added, dtm_scene_mass_unit(s, p->dim), f->mass->scaled,
           100.0 * f->mass->total_added / f->mass->total_mass, f->mass->total_mass, dtm_scene_mass_unit(s, p->dim));
  if (s->target > 0 && !p->advice) printf("below target %.0f element(s)\n", f->below);
}

/* The shape-limited elements and the layers, as a serial run prints them. */
static void print_advice(const dtm_par *p, const dtm_par_figures *f) {
  dtm_cost c = *p->cost;
  dtm_par_whole_cost(p, f, &c);
  c.subcycling = f->sub, c.shape_mass = c.layer_mass = NULL; /* the parts' masses are indexed by part */
  dtm_results res = {p->advice, &c, NULL, 0.0, 0.0, 0, 0, {NULL}, {NULL}, NULL, NULL};
  if (p->advice) dtm_summary_advice(&res, stdout);
}

static void print_warnings(const dtm_par *p, const dtm_par_figures *f) {
  cJSON *w = dtm_par_warnings(p, f), *it;
  if (cJSON_GetArraySize(w) > 0) printf("\n");
  cJSON_ArrayForEach(it, w) printf("WARNING: %s\n", it->valuestring);
  cJSON_Delete(w);
}

static void print_times(const dtm_par *p, const dtm_par_figures *f) {
  static const char *const names[PAR_T_COUNT] = {"read", "extract", "layout", "effects", "nodal", "global", "output"};
  printf("time (s)    ");
  for (int t = 0; t < PAR_T_COUNT; t++) {
    double mx = 0;
    for (int r = 0; r < p->size; r++) mx = fmax(mx, f->rows[r * ROW_COUNT + ROW_T + t]);
    printf(" %s %.3f", names[t], mx);
  }
  printf(" (slowest part)\n");
}

void dtm_par_summary(const dtm_par *p, const dtm_parallel_opts *o, const dtm_par_figures *f) {
  if (p->rank != 0 || !o->verbosity) return;
  printf("dtmap %s: %s, distributed over %d ranks\n", DTM_VERSION, p->scene->path, p->size);
  print_parts(p, f);
  print_steps(p, f);
  print_cost(p, f);
  print_advice(p, f);
  print_times(p, f);
  print_warnings(p, f);
  char out[4096];
  if (dtm_scene_part_path(o->out, 1, out, sizeof out) == DTM_OK)
    printf("\nwrote        %s ... (%d parts, + .opt)%s%s\n", out, p->size, o->report ? ", " : "",
           o->report ? o->report : "");
}
