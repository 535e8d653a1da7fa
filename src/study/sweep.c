/* `dtmap sweep`: the scene meshed and analysed at each requested size, one
 * row per size with the mesh, the steps, the run's cost in element-steps
 * and in hours with one global step, with ideal subcycling and with mass
 * scaling to the scene's target, the accuracy each buys (the phase-speed
 * error at one frequency for all sizes, the smallest elements per process
 * zone, per wavelength and across the diffusion length) and dtmap's own
 * time; the cheapest size inside every band; the table for the terminal
 * and the CSV file (units in its header, counts as whole numbers). The plot
 * is in src/cli/plot.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "dtmap/util.h"
#include "dtmap/cost.h"
#include "dtmap/sweep.h"
#include "dtmap/units.h"

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

/* The phase errors with subcycling and with mass scaling to the target. */
static int phase_variants(const dtm_analysis *a, const dtm_cost *c, dtm_sweep_row *row) {
  dtm_measure_step sub = {c->subcycling.level, 0, NULL}, mass = {NULL, 0, NULL};
  dtm_measures *m = NULL;
  row->phase_subcycled = row->phase_mass = NAN;
  DTM_CHECK(dtm_measures_compute(a, row->frequency, &sub, &m));
  for (int k = 0; k < m->n; k++)
    if (m->m[k].kind == DTM_MEASURE_PHASE) row->phase_subcycled = m->m[k].worst;
  dtm_measures_destroy(&m);
  if (!c->mass || !(dtm_analysis_scene(a)->target > row->recommended)) return DTM_OK; /* nothing to lift */
  mass.target = dtm_analysis_scene(a)->target, mass.added = c->mass->added;
  DTM_CHECK(dtm_measures_compute(a, row->frequency, &mass, &m));
  for (int k = 0; k < m->n; k++)
    if (m->m[k].kind == DTM_MEASURE_PHASE) row->phase_mass = m->m[k].worst;
  dtm_measures_destroy(&m);
  return DTM_OK;
}

/* The measures of the recommended step into the row; in_band when every
 * one is inside its band. */
static int fill_measures(const dtm_analysis *a, const dtm_cost *c, dtm_sweep_row *row) {
  dtm_measures *m = NULL;
  row->phase_error = row->phase_median = row->per_diffusion = NAN;
  row->phase_wave = -1;
  row->in_band = 1;
  DTM_CHECK(dtm_measures_compute(a, row->frequency, NULL, &m));
  int phase = 0;
  for (int k = 0; k < m->n; k++) {
    const dtm_measure *x = &m->m[k];
    row->in_band &= x->in_band;
    if (x->kind == DTM_MEASURE_PHASE)
      phase = 1, row->phase_error = x->worst, row->phase_wave = x->wave, row->phase_median = x->median,
      row->unresolved = x->unresolved, row->frequency = x->f, row->frequency_default = x->f_default,
      row->per_wave_default = x->per_wavelength;
    if (x->kind == DTM_MEASURE_DIFFUSION && !(x->worst >= row->per_diffusion)) row->per_diffusion = x->worst;
  }
  dtm_measures_destroy(&m);
  if (!phase) row->frequency = NAN;
  return phase ? phase_variants(a, c, row) : DTM_OK;
}

static void fill_hours(const dtm_analysis *a, const dtm_cost *c, dtm_sweep_row *row) {
  const dtm_scene *s = dtm_analysis_scene(a);
  row->per_element_step = c->per_element_step;
  row->hours = c->hours, row->hours_subcycled = c->hours_subcycled;
  row->hours_mass = s->target > row->recommended && s->duration > 0
                        ? (double)row->elements * ceil(s->duration / s->target) * c->per_element_step / 3600
                        : NAN;
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
  fill_hours(a, c, row);
  int r = fill_measures(a, c, row);
  dtm_cost_destroy(&c);
  row->per_zone = smallest_indicator(a, "elements_per_zone");
  row->per_wavelength = smallest_indicator(a, "elements_per_wavelength");
  if (isnan(row->per_wavelength)) row->per_wavelength = row->per_wave_default; /* no f-max: at the default */
  return r;
}

/* A row for size h with no figures and the pending error as its reason
 * (cleared). */
static void failed_row(double h, double seconds, dtm_sweep_row *row) {
  static const dtm_sweep_row none = {0};
  *row = none;
  row->h = h, row->seconds = seconds;
  row->dt_min = row->recommended = row->steps = row->cost = row->cost_subcycled = NAN;
  row->per_zone = row->per_wavelength = row->speedup = row->per_element_step = NAN;
  row->hours = row->hours_subcycled = row->hours_mass = row->frequency = NAN;
  row->phase_error = row->phase_median = row->phase_subcycled = row->phase_mass = NAN;
  row->per_diffusion = row->per_wave_default = NAN;
  row->phase_wave = -1;
  snprintf(row->failed, sizeof row->failed, "%s", dtm_error_message());
  if (!row->failed[0]) snprintf(row->failed, sizeof row->failed, "failed (no reason given)");
  dtm_error_clear();
}

/* row->frequency on entry: the phase error's frequency (0: the scene's
 * f-max, else this mesh's default). */
static int sweep_one(const dtm_scene *s, double h, dtm_sweep_row *row) {
  dtm_scene sc = *s; /* shallow: the members stay owned by s */
  row->failed[0] = '\0';
  sc.mesh_size = h;
  if (sc.mesh_min_size > 0) sc.mesh_min_size = fmin(sc.mesh_min_size, h);
  double t0 = dtm_wtime();
  dtm_analysis *a = NULL;
  int r = dtm_analysis_run(&sc, &a);
  if (r == DTM_OK) r = fill_row(a, h, row);
  dtm_analysis_destroy(&a);
  row->seconds = dtm_wtime() - t0;
  if (r) failed_row(h, row->seconds, row);
  row->length_unit = dtm_units_name(s->units, DTM_UNIT_LENGTH);
  return r;
}

int dtm_sweep_run(const dtm_scene *s, const double *sizes, int n, dtm_sweep_row *rows) {
  if (!s->geometry) return DTM_ERR(DTM_ERR_INPUT, "%s:%d: sweep needs a geometry, not a mesh", s->path, s->source_line);
  if (n < 1) return DTM_ERR(DTM_ERR_INPUT, "sweep needs at least one size");
  for (int i = 0; i < n; i++)
    if (!(sizes[i] > 0) || !isfinite(sizes[i]))
      return DTM_ERR(DTM_ERR_INPUT, "sweep: size %d is %g; sizes must be positive and finite (%s)", i + 1, sizes[i],
                     dtm_units_name(s->units, DTM_UNIT_LENGTH));
  /* one frequency for every size: the scene's, else the default of the
   * first mesh that gave figures */
  int first = -1, code = DTM_OK;
  for (int i = 0; i < n; i++) {
    rows[i].frequency = first >= 0 && rows[first].frequency_default ? rows[first].frequency : 0;
    int r = sweep_one(s, sizes[i], &rows[i]); /* a size that fails, Gmsh's crash included, is a failed row */
    if (r && code == DTM_OK) code = r;
    if (r) continue;
    if (first >= 0 && rows[first].frequency_default) rows[i].frequency_default = 1;
    if (first < 0) first = i;
  }
  if (first >= 0) return DTM_OK;
  return DTM_ERR(code, "sweep: no size gave figures; at size %g %s: %s", sizes[0], rows[0].length_unit, rows[0].failed);
}

int dtm_sweep_cheapest(const dtm_sweep_row *rows, int n) {
  int best = -1;
  for (int i = 0; i < n; i++) {
    if (!rows[i].in_band || rows[i].failed[0]) continue;
    double c = isfinite(rows[i].hours) ? rows[i].hours : (double)rows[i].elements / rows[i].recommended;
    double b = best < 0                     ? INFINITY
               : isfinite(rows[best].hours) ? rows[best].hours
                                            : (double)rows[best].elements / rows[best].recommended;
    if (c < b) best = i;
  }
  return best;
}

/* v with printf format f into buf, or "-" when v is NaN. */
static const char *cell(char *buf, size_t len, const char *f, double v) {
  if (isnan(v))
    snprintf(buf, len, "-");
  else
    snprintf(buf, len, f, v);
  return buf;
}

/* A phase error in percent, "unres." when some element is unresolved;
 * wave >= 0: followed by the wave it is of (P or S). */
static const char *phase_cell(char *buf, size_t len, double v, size_t unresolved, int wave) {
  if (unresolved) return snprintf(buf, len, "unres."), buf;
  if (isnan(v) || wave < 0) return cell(buf, len, "%+.3g", 100 * v);
  return snprintf(buf, len, "%+.3g %c", 100 * v, wave ? 'S' : 'P'), buf;
}

static void print_row(FILE *f, const dtm_sweep_row *r) {
  char c[14][32];
  if (r->failed[0]) {
    fprintf(f, "%10.4g  FAILED: %s\n", r->h, r->failed);
    return;
  }
  fprintf(f,
          "%10.4g %9zu %9zu %11.4e %11.4e %10s %12s %12s %8.3g %8s %9s %9s %8s %7zu %9s %9s %9s %9s %9s %8s %4s "
          "%8.3f\n",
          r->h, r->elements, r->nodes, r->dt_min, r->recommended, cell(c[0], 32, "%.0f", r->steps),
          cell(c[1], 32, "%.4e", r->cost), cell(c[2], 32, "%.4e", r->cost_subcycled), r->speedup,
          cell(c[3], 32, "%.3g", r->per_zone), cell(c[4], 32, "%.3g", r->per_wavelength),
          phase_cell(c[5], 32, r->phase_error, r->unresolved, r->phase_wave),
          cell(c[12], 32, "%+.3g", 100 * r->phase_median), r->unresolved,
          phase_cell(c[6], 32, r->phase_subcycled, r->unresolved, -1), cell(c[7], 32, "%+.3g", 100 * r->phase_mass),
          cell(c[8], 32, "%.4g", r->hours), cell(c[9], 32, "%.4g", r->hours_subcycled),
          cell(c[10], 32, "%.4g", r->hours_mass), cell(c[11], 32, "%.3g", r->per_diffusion), r->in_band ? "yes" : "no",
          r->seconds);
}

/* The unit of a row's size (m when not set). */
static const char *unit_of(const dtm_sweep_row *r) { return r->length_unit ? r->length_unit : "m"; }

void dtm_sweep_print(const dtm_sweep_row *rows, int n, void *stream) {
  FILE *f = stream;
  static const char fmt[] = "%10s %9s %9s %11s %11s %10s %12s %12s %8s %8s %9s %9s %8s %7s %9s %9s %9s %9s %9s %8s %4s "
                            "%8s\n";
  fprintf(f, fmt, "h", "elements", "nodes", "elem.bound", "dt rec.", "steps", "elem-steps", "subcycled", "speed-up",
          "per zone", "per wave", "phase", "ph.med.", "unres.", "ph.subc.", "ph.mass", "run", "run subc.", "run mass",
          "per diff", "band", "time");
  char hu[16];
  snprintf(hu, sizeof hu, "(%s)", n ? unit_of(&rows[0]) : "m");
  fprintf(f, fmt, hu, "", "", "(s)", "(s)", "", "", "", "", "(min)", "(min)", "(%)", "(%)", "", "(%)", "(%)", "(h)",
          "(h)", "(h)", "(min)", "1stp", "(s)");
  for (int i = 0; i < n; i++) print_row(f, &rows[i]);
  int fr = 0;
  while (fr < n - 1 && rows[fr].failed[0]) fr++;
  if (n && isfinite(rows[fr].frequency))
    fprintf(f,
            "\nphase-speed error at %.4g Hz%s, worst over the mesh and its wave (P or S), lumped mass, central "
            "differences\n",
            rows[fr].frequency,
            rows[fr].frequency_default ? " (no <time f-max>: the default of the first size's mesh, "
                                         "at least 10 cells per shear wavelength in every element; 'per wave' is "
                                         "at that frequency)"
                                       : " (<time f-max>)");
  int ok = -1, failed = 0;
  for (int i = 0; i < n; i++) failed += rows[i].failed[0] != '\0', ok = ok < 0 && !rows[i].failed[0] ? i : ok;
  if (ok >= 0)
    fprintf(f,
            "band (1stp): every measure's worst inside its band with one global step (phase, per zone, per diff); "
            "the subcycled and mass-scaled errors (ph.subc., ph.mass) are shown, not judged\n"
            "run time at %.3g ns per element-step\n",
            1e9 * rows[ok].per_element_step);
  if (failed)
    fprintf(f, "%d of %d size%s FAILED: no figures (the reason is on its row)\n", failed, n, n > 1 ? "s" : "");
  int b = dtm_sweep_cheapest(rows, n);
  char hb[32];
  if (b >= 0)
    fprintf(f, "cheapest size inside every band: h = %g %s, %s h with one global step\n", rows[b].h, unit_of(&rows[b]),
            cell(hb, sizeof hb, "%.4g", rows[b].hours));
  else if (n)
    fprintf(f,
            "no size is inside every band (phase |error| <= %g %%, >= 5 elements per zone, >= %g across "
            "the diffusion length)\n",
            100 * DTM_BAND_PHASE, DTM_BAND_DIFFUSION);
}

/* The CSV header: units after the last underscore (h_m metres, or h_mm
 * under mm-t-s, written first; _s seconds); the other columns are counts
 * or ratios. */
static const char csv_header[] = "elements,nodes,dt_min_s,dt_recommended_s,steps,element_steps,"
                                 "element_steps_subcycled,subcycling_speedup,elements_per_zone,"
                                 "elements_per_wavelength,time_s,frequency_hz,phase_error,phase_error_median,"
                                 "unresolved,phase_error_subcycled,phase_error_mass_scaled,"
                                 "elements_per_diffusion_length,cost_per_element_step_s,run_h,run_subcycled_h,"
                                 "run_mass_scaled_h,in_band,failed\n";

/* text as a CSV cell: nothing when empty, else quoted with its quotes
 * doubled (and its line breaks as spaces). */
static void csv_text(FILE *f, const char *text) {
  if (!text[0]) return;
  fputc('"', f);
  for (const char *p = text; *p; p++)
    if (*p == '"')
      fputs("\"\"", f);
    else
      fputc(*p == '\n' || *p == '\r' ? ' ' : *p, f);
  fputc('"', f);
}

/* One CSV row in the header's order: %.9g, counts as whole numbers
 * (rounded up), empty for NaN. */
static void csv_row(FILE *f, const dtm_sweep_row *r) {
  const struct {
    double v;  /* the value */
    int whole; /* a count */
  } c[] = {{r->h, 0},
           {r->failed[0] ? NAN : (double)r->elements, 1},
           {r->failed[0] ? NAN : (double)r->nodes, 1},
           {r->dt_min, 0},
           {r->recommended, 0},
           {r->steps, 1},
           {r->cost, 1},
           {r->cost_subcycled, 1},
           {r->speedup, 0},
           {r->per_zone, 0},
           {r->per_wavelength, 0},
           {r->seconds, 0},
           {r->frequency, 0},
           {r->unresolved ? NAN : r->phase_error, 0},
           {r->phase_median, 0},
           {r->failed[0] ? NAN : (double)r->unresolved, 1},
           {r->unresolved ? NAN : r->phase_subcycled, 0},
           {r->phase_mass, 0},
           {r->per_diffusion, 0},
           {r->per_element_step, 0},
           {r->hours, 0},
           {r->hours_subcycled, 0},
           {r->hours_mass, 0},
           {r->failed[0] ? NAN : (double)r->in_band, 1}};
  const size_t nc = sizeof c / sizeof c[0];
  for (size_t k = 0; k < nc; k++) {
    if (isnan(c[k].v))
      ;
    else if (c[k].whole)
      fprintf(f, "%.0f", ceil(c[k].v));
    else
      fprintf(f, "%.9g", c[k].v);
    fputc(',', f);
  }
  csv_text(f, r->failed);
  fputc('\n', f);
}

int dtm_sweep_write_csv(const char *path, const dtm_sweep_row *rows, int n) {
  dtm_atomic w;
  DTM_CHECK(dtm_atomic_open(&w, path, "", 1));
  fprintf(w.f, "h_%s,", n ? unit_of(&rows[0]) : "m");
  fputs(csv_header, w.f);
  for (int i = 0; i < n; i++) csv_row(w.f, &rows[i]);
  return dtm_atomic_commit(&w);
}
