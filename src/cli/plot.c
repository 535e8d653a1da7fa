/* The sweep's picture: cost against accuracy on log-log axes, drawn with
 * PLplot's pngcairo device into a PNG written atomically (a temporary name
 * ending in .png, renamed into place once PLplot has closed it). x is the
 * accuracy indicator (smallest elements per wavelength, else per process
 * zone, else 1/h), y the element-steps of the scene's duration with one
 * global step and with ideal subcycling. PLplot exits the process on a
 * fatal error, so every condition it would die on (no pngcairo device, an
 * unwritable file) is checked before it is called. */
#include <errno.h>
#include <math.h>
#include <plplot.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/util.h"
#include "dtmap/error.h"
#include "cli-impl.h"

/* The points to draw, as log10 values. */
typedef struct {
  int n;              /* points kept (positive and finite) */
  double *x;          /* [n] log10 accuracy indicator */
  double *y;          /* [n] log10 element-steps, one global step */
  double *ys;         /* [n] log10 element-steps, ideal subcycling */
  const char *xlabel; /* x axis label, with units */
  const char *ylabel; /* y axis label, with units */
} plot_data;

static int all_positive(const dtm_sweep_row *rows, int n, size_t offset) {
  for (int i = 0; i < n; i++) {
    double v = *(const double *)((const char *)&rows[i] + offset);
    if (!(v > 0) || !isfinite(v)) return 0;
  }
  return 1;
}

/* Which accuracy indicator the x axis shows: 0 per wavelength, 1 per zone,
 * 2 for 1/h. */
static int choose_x(const dtm_sweep_row *rows, int n, plot_data *d) {
  if (all_positive(rows, n, offsetof(dtm_sweep_row, per_wavelength)))
    return d->xlabel = "smallest elements per wavelength", 0;
  if (all_positive(rows, n, offsetof(dtm_sweep_row, per_zone)))
    return d->xlabel = "smallest elements per cohesive process zone", 1;
  return d->xlabel = "1/h (1/m), h the mesh size", 2;
}

static double x_value(const dtm_sweep_row *r, int kind) {
  return kind == 0 ? r->per_wavelength : kind == 1 ? r->per_zone : 1.0 / r->h;
}

/* y of one row: the cost of the duration, or per simulated second when the
 * scene has no duration. */
static void y_values(const dtm_sweep_row *r, int per_second, double *y, double *ys) {
  *y = per_second ? (double)r->elements / r->recommended : r->cost;
  *ys = per_second ? *y / r->speedup : r->cost_subcycled;
}

static int collect(const dtm_sweep_row *rows, int n, plot_data *d) {
  int kind = choose_x(rows, n, d), per_second = !all_positive(rows, n, offsetof(dtm_sweep_row, cost));
  d->ylabel = per_second ? "element-steps per simulated second (1/s)" : "element-steps over the duration";
  d->x = malloc(3 * (size_t)n * sizeof *d->x);
  if (!d->x) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  d->y = d->x + n, d->ys = d->y + n, d->n = 0;
  for (int i = 0; i < n; i++) {
    double x = x_value(&rows[i], kind), y, ys;
    y_values(&rows[i], per_second, &y, &ys);
    if (!(x > 0 && y > 0 && ys > 0) || !isfinite(x) || !isfinite(y) || !isfinite(ys)) continue;
    d->x[d->n] = log10(x), d->y[d->n] = log10(y), d->ys[d->n] = log10(ys), d->n++;
  }
  if (d->n > 0) return DTM_OK;
  free(d->x);
  return DTM_ERR(DTM_ERR_INPUT, "sweep plot: no size has a positive, finite cost and accuracy value");
}

/* [lo, hi] of v[0..n) and w[0..n), padded by 8% (0.25 decade when flat),
 * widened to whole decades when fewer than two decades would be labelled. */
static void range(const double *v, const double *w, int n, double *lo, double *hi) {
  *lo = INFINITY, *hi = -INFINITY;
  for (int i = 0; i < n; i++) {
    *lo = fmin(*lo, fmin(v[i], w ? w[i] : v[i]));
    *hi = fmax(*hi, fmax(v[i], w ? w[i] : v[i]));
  }
  double pad = *hi - *lo > 0.1 ? 0.08 * (*hi - *lo) : 0.25;
  *lo -= pad, *hi += pad;
  if (floor(*hi) - ceil(*lo) < 1) *lo = floor(*lo), *hi = ceil(*hi);
}

/* PLplot would prompt on stdin for a device it does not have. */
static int have_pngcairo(void) {
  const char *menu[128], *names[128], **pm = menu, **pn = names;
  int ndev = 128;
  plgDevs(&pm, &pn, &ndev);
  for (int i = 0; i < ndev; i++)
    if (!strcmp(names[i], "pngcairo")) return 1;
  return 0;
}

static void draw_series(const plot_data *d, const double *y, int color, const char *symbol) {
  plcol0(color);
  plwidth(2.0);
  if (d->n > 1) plline(d->n, d->x, y);
  plstring(d->n, d->x, y, symbol);
}

/* Above the box, outside it, in two columns, so it never hides a point. */
static void draw_legend(void) {
  PLINT opt[2] = {PL_LEGEND_LINE | PL_LEGEND_SYMBOL, PL_LEGEND_LINE | PL_LEGEND_SYMBOL};
  PLINT tcol[2] = {1, 1}, lcol[2] = {2, 3}, lsty[2] = {1, 1}, scol[2] = {2, 3}, snum[2] = {1, 1};
  PLFLT lwid[2] = {2.0, 2.0}, sscale[2] = {1.0, 1.0}, w, h;
  const char *text[2] = {"one global step (recommended dt)", "ideal subcycling (levels dt_min 2^k)"};
  const char *sym[2] = {"#(840)", "#(841)"};
  pllegend(&w, &h, 0, PL_POSITION_TOP | PL_POSITION_OUTSIDE, 0.0, 0.06, 0.07, 0, 0, 1, 1, 2, 2, opt, 0.8, 0.85, 1.5,
           0.0, tcol, text, NULL, NULL, NULL, NULL, lcol, lsty, lwid, scol, sscale, snum, sym);
}

static void set_colors(void) {
  plscolbg(255, 255, 255);
  plscol0(1, 0, 0, 0);       /* axes and text */
  plscol0(2, 31, 119, 180);  /* one global step */
  plscol0(3, 214, 39, 40);   /* subcycled */
  plscol0(4, 210, 210, 210); /* grid */
}

/* Box, log-decade labels, grid, axis labels and title. */
static void draw_axes(const plot_data *d, const char *title) {
  double x0, x1, y0, y1;
  char t[512];
  range(d->x, NULL, d->n, &x0, &x1);
  range(d->y, d->ys, d->n, &y0, &y1);
  snprintf(t, sizeof t, "dtmap sweep: %s", title ? title : "cost against accuracy");
  pladv(0);
  plvpor(0.11, 0.95, 0.12, 0.78);
  plwind(x0, x1, y0, y1);
  plcol0(4);
  plbox("ghl", 0, 0, "ghl", 0, 0);
  plcol0(1);
  plbox("bclnst", 0, 0, "bclnstv", 0, 0);
  plmtex("b", 3.2, 0.5, 0.5, d->xlabel);
  plmtex("l", 5.0, 0.5, 0.5, d->ylabel);
  plmtex("t", 6.5, 0.5, 0.5, t);
}

static void draw(const char *file, const char *title, const plot_data *d) {
  plsdev("pngcairo");
  plsfnam(file);
  plspage(0, 0, 1000, 700, 0, 0);
  set_colors();
  plinit();
  draw_axes(d, title);
  draw_series(d, d->y, 2, "#(840)");
  draw_series(d, d->ys, 3, "#(841)");
  plwidth(1.0);
  draw_legend();
  plend();
}

/* The file PLplot wrote starts with the PNG signature. */
static int png_ok(const char *file) {
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  unsigned char b[8] = {0};
  FILE *f = fopen(file, "rb");
  if (!f) return 0;
  size_t got = fread(b, 1, 8, f);
  fclose(f);
  return got == 8 && !memcmp(b, sig, 8);
}

/* PLplot exits the process when it cannot open its output, so the
 * temporary is created (and its directory proven writable) first. */
static int plot_file(const char *path, const char *title, const plot_data *d) {
  dtm_atomic w;
  DTM_CHECK(dtm_atomic_open(&w, path, ".png", 1));
  if (fclose(w.f)) return w.f = NULL, dtm_atomic_abort(&w), DTM_ERR(DTM_ERR_INPUT, "%s: cannot write", path);
  w.f = NULL;
  draw(w.tmp, title, d);
  if (!png_ok(w.tmp)) return dtm_atomic_abort(&w), DTM_ERR(DTM_ERR_INTERNAL, "%s: PLplot did not write a PNG", path);
  return dtm_atomic_commit(&w);
}

int dtm_cli_sweep_plot_titled(const char *path, const char *title, const dtm_sweep_row *rows, int n) {
  if (n < 1) return DTM_ERR(DTM_ERR_INPUT, "sweep plot: no rows to draw");
  if (!have_pngcairo()) return DTM_ERR(DTM_ERR_INTERNAL, "PLplot has no pngcairo device: install plplot-driver-cairo");
  plot_data d;
  DTM_CHECK(collect(rows, n, &d));
  int r = plot_file(path, title, &d);
  free(d.x);
  return r;
}

int dtm_cli_sweep_plot(const char *path, const dtm_sweep_row *rows, int n) {
  return dtm_cli_sweep_plot_titled(path, NULL, rows, n);
}

int dtm_cli_can_plot(void) { return 1; }
