/* `dtmap sweep`: the scene meshed and analysed at each requested size, one
 * row per size with the mesh, the steps, the run's cost in element-steps
 * with and without ideal subcycling, the smallest accuracy indicators
 * (elements per process zone, per wavelength) and dtmap's own time; the
 * table for the terminal and the CSV file. The plot is in sweep_plot.c. */
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
  row->dt_min = dtm_analysis_dt_min(a, NULL);
  row->recommended = dtm_analysis_recommended(a);
  row->steps = duration > 0 ? duration / row->recommended : NAN;
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
          r->dt_min, r->recommended, cell(c[0], 32, "%.4g", r->steps), cell(c[1], 32, "%.4e", r->cost),
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

/* One CSV number: %.9g, empty for NaN. */
static void csv_number(FILE *f, double v, const char *sep) {
  if (!isnan(v)) fprintf(f, "%.9g", v);
  fputs(sep, f);
}

static void csv_row(FILE *f, const dtm_sweep_row *r) {
  const double v[] = {r->h,    (double)r->elements, (double)r->nodes, r->dt_min,         r->recommended, r->steps,
                      r->cost, r->cost_subcycled,   r->per_zone,      r->per_wavelength, r->seconds};
  const int nv = (int)(sizeof v / sizeof v[0]);
  for (int k = 0; k < nv; k++) csv_number(f, v[k], k + 1 < nv ? "," : "\n");
}

int dtm_sweep_write_csv(const char *path, const dtm_sweep_row *rows, int n) {
  dtm_atomic w;
  DTM_CHECK(dtm_atomic_open(&w, path, "", 1));
  FILE *f = w.f;
  fputs("h,elements,nodes,dt_min,dt_recommended,steps,element_steps,element_steps_subcycled,"
        "elements_per_zone,elements_per_wavelength,seconds\n",
        f);
  for (int i = 0; i < n; i++) csv_row(f, &rows[i]);
  return dtm_atomic_commit(&w);
}
