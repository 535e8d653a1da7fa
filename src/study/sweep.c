/* `dtmap sweep`: the scene meshed and analysed at each requested size, one
 * row per size with the mesh, the steps, the run's cost in element-steps
 * with and without ideal subcycling and that speed-up, the smallest
 * accuracy indicators (elements per process zone, per wavelength) and
 * dtmap's own time; the table for the terminal and the CSV file (units in
 * its header, counts as whole numbers). The plot is in src/cli/plot.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "dtmap/util.h"
#include "dtmap/cost.h"
#include "dtmap/sweep.h"

/* Smallest finite value of the accuracy indicator an effect declares under
 * that name (dtm_indicator.name), NaN if none. */
static double smallest_indicator(const dtm_analysis *a, const char *indicator) {
  double best = NAN;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const char *name = dtm_analysis_effect(a, k)->indicator.name;
    const double *res = dtm_analysis_resolution(a, k);
    if (!res || !name || strcmp(name, indicator)) continue;
    for (size_t i = 0; i < dtm_analysis_nelements(a); i++) {
      double v = res[i];
      if (isfinite(v) && !(v >= best)) best = v;
    }
  }
  return best;
}

static int fill_row(const dtm_analysis *a, double h, dtm_sweep_row *row) {
  double duration = dtm_analysis_scene(a)->duration;
  dtm_cost *c = NULL;
  DTM_CHECK(dtm_cost_create(a, &c));
  row->h = h;
  row->elements = dtm_analysis_nelements(a);
  row->nodes = dtm_analysis_mesh(a)->nnodes;
  row->flagged = dtm_analysis_mesh(a)->nflagged;
  row->dt_min = dtm_analysis_dt_min(a, NULL);
  row->recommended = dtm_analysis_recommended(a);
  row->steps = duration > 0 ? ceil(duration / row->recommended) : NAN;
  row->cost = c->element_steps;
  row->speedup = c->subcycling.speedup;
  row->cost_subcycled = c->element_steps_subcycled;
  dtm_cost_destroy(&c);
  row->per_zone = smallest_indicator(a, "elements_per_zone");
  row->per_wavelength = smallest_indicator(a, "elements_per_wavelength");
  return DTM_OK;
}

/* Re-raise the pending error with the size it happened at. */
static int at_size(int r, double h) {
  char msg[2048];
  snprintf(msg, sizeof msg, "%s", dtm_error_message());
  dtm_error_clear();
  return DTM_ERR(r, "sweep at size %g m: %s", h, msg);
}

static int sweep_one(const dtm_scene *s, double h, dtm_sweep_row *row) {
  dtm_scene sc = *s; /* shallow: the members stay owned by s */
  sc.mesh_size = h;
  if (sc.mesh_min_size > 0) sc.mesh_min_size = fmin(sc.mesh_min_size, h);
  double t0 = dtm_wtime();
  dtm_analysis *a = NULL;
  int r = dtm_analysis_run(&sc, &a);
  if (r == DTM_OK) r = fill_row(a, h, row);
  dtm_analysis_destroy(&a);
  row->seconds = dtm_wtime() - t0;
  return r ? at_size(r, h) : DTM_OK;
}

int dtm_sweep_run(const dtm_scene *s, const double *sizes, int n, dtm_sweep_row *rows) {
  if (!s->geometry) return DTM_ERR(DTM_ERR_INPUT, "%s:%d: sweep needs a geometry, not a mesh", s->path, s->source_line);
  if (n < 1) return DTM_ERR(DTM_ERR_INPUT, "sweep needs at least one size");
  for (int i = 0; i < n; i++)
    if (!(sizes[i] > 0) || !isfinite(sizes[i]))
      return DTM_ERR(DTM_ERR_INPUT, "sweep: size %d is %g; sizes must be positive and finite (m)", i + 1, sizes[i]);
  for (int i = 0; i < n; i++) DTM_CHECK(sweep_one(s, sizes[i], &rows[i]));
  return DTM_OK;
}

/* v with printf format f into buf, or "-" when v is NaN. */
static const char *cell(char *buf, size_t len, const char *f, double v) {
  if (isnan(v))
    snprintf(buf, len, "-");
  else
    snprintf(buf, len, f, v);
  return buf;
}

static void print_row(FILE *f, const dtm_sweep_row *r) {
  char c[8][32];
  fprintf(f, "%10.4g %9zu %9zu %11.4e %11.4e %10s %12s %12s %8.3g %8s %9s %8.3f\n", r->h, r->elements, r->nodes,
          r->dt_min, r->recommended, cell(c[0], 32, "%.0f", r->steps), cell(c[1], 32, "%.4e", r->cost),
          cell(c[2], 32, "%.4e", r->cost_subcycled), r->speedup, cell(c[3], 32, "%.3g", r->per_zone),
          cell(c[4], 32, "%.3g", r->per_wavelength), r->seconds);
}

void dtm_sweep_print(const dtm_sweep_row *rows, int n, void *stream) {
  FILE *f = stream;
  fprintf(f, "%10s %9s %9s %11s %11s %10s %12s %12s %8s %8s %9s %8s\n", "h", "elements", "nodes", "elem.bound",
          "dt rec.", "steps", "elem-steps", "subcycled", "speed-up", "per zone", "per wave", "time");
  fprintf(f, "%10s %9s %9s %11s %11s %10s %12s %12s %8s %8s %9s %8s\n", "(m)", "", "", "(s)", "(s)", "", "", "", "",
          "(min)", "(min)", "(s)");
  for (int i = 0; i < n; i++) print_row(f, &rows[i]);
}

/* The CSV header: units after the last underscore (_m metres, _s
 * seconds); the other columns are counts or ratios. */
static const char csv_header[] = "h_m,elements,nodes,dt_min_s,dt_recommended_s,steps,element_steps,"
                                 "element_steps_subcycled,subcycling_speedup,elements_per_zone,"
                                 "elements_per_wavelength,time_s\n";

/* One CSV row in the header's order: %.9g, counts as whole numbers
 * (rounded up), empty for NaN. */
static void csv_row(FILE *f, const dtm_sweep_row *r) {
  const struct {
    double v;  /* the value */
    int whole; /* a count */
  } c[] = {{r->h, 0},        {(double)r->elements, 1}, {(double)r->nodes, 1},
           {r->dt_min, 0},   {r->recommended, 0},      {r->steps, 1},
           {r->cost, 1},     {r->cost_subcycled, 1},   {r->speedup, 0},
           {r->per_zone, 0}, {r->per_wavelength, 0},   {r->seconds, 0}};
  const size_t nc = sizeof c / sizeof c[0];
  for (size_t k = 0; k < nc; k++) {
    if (isnan(c[k].v))
      ;
    else if (c[k].whole)
      fprintf(f, "%.0f", ceil(c[k].v));
    else
      fprintf(f, "%.9g", c[k].v);
    fputs(k + 1 < nc ? "," : "\n", f);
  }
}

int dtm_sweep_write_csv(const char *path, const dtm_sweep_row *rows, int n) {
  dtm_atomic w;
  DTM_CHECK(dtm_atomic_open(&w, path, "", 1));
  fputs(csv_header, w.f);
  for (int i = 0; i < n; i++) csv_row(w.f, &rows[i]);
  return dtm_atomic_commit(&w);
}
