/* The sweep's picture, drawn with PLplot's pngcairo device into a PNG
 * written atomically (a temporary name ending in .png, renamed into place
 * once PLplot has closed it). When the sweep has accuracy measures: error
 * against run time in hours on log-log axes, one panel per kind of measure
 * (the worst phase-speed error in %; the smallest elements per cohesive
 * zone or across the diffusion length), one curve per way of running (one
 * global step, ideal subcycling, mass scaling to the target), the band as
 * dashed lines and the cheapest size inside every band ringed and named;
 * every point of the first curve named by its size, each label placed
 * clear of the markers, the other labels and the legend, which stands
 * outside the box on its right (labels.c; the layout of the last plot is
 * kept for the tests). Without measures: element-steps against 1/h as before. Without a
 * duration the time axis is hours per simulated second. PLplot exits the
 * process on a fatal error, so every condition it would die on (no
 * pngcairo device, an unwritable file) is checked before it is called. */
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
  char xtext[64];     /* xlabel when it is made here (1/h in the scene's length unit) */
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
  snprintf(d->xtext, sizeof d->xtext, "1/h (1/%s), h the mesh size",
           n && rows[0].length_unit ? rows[0].length_unit : "m");
  return d->xlabel = d->xtext, 2;
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

static dtm_plot_layout last; /* what the last plot drew (dtm_cli_sweep_plot_layout) */

const dtm_plot_layout *dtm_cli_sweep_plot_layout(void) { return &last; }

static void draw(const char *file, const char *title, const plot_data *d) {
  last.npanels = 0;
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

/* One curve of the error plot: log10 run time against log10 measure. */
typedef struct {
  int n;               /* points kept */
  double x[64], y[64]; /* log10 hours (or hours per simulated second), log10 value */
  int row[64];         /* the row of each point */
  const char *label;   /* legend */
  int color;           /* cmap0 index */
  const char *symbol;  /* PLplot symbol */
} curve;

/* The time of a row for one way of running: hours, or hours per simulated
 * second without a duration (way: 0 global, 1 subcycled, 2 mass scaled). */
static double row_time(const dtm_sweep_row *r, int way) {
  double h = way == 0 ? r->hours : way == 1 ? r->hours_subcycled : r->hours_mass;
  if (isfinite(h) || way == 2) return h;
  double per_s = (double)r->elements / r->recommended * r->per_element_step / 3600;
  return way == 0 ? per_s : per_s / r->speedup;
}

/* The measure of a row for panel p (0 phase error in %, 1 smallest count). */
static double row_value(const dtm_sweep_row *r, int p, int way) {
  if (p == 1) return isfinite(r->per_zone) ? r->per_zone : r->per_diffusion;
  double e = way == 0 ? r->phase_error : way == 1 ? r->phase_subcycled : r->phase_mass;
  return r->unresolved ? NAN : 100 * fabs(e);
}

static void fill_curve(const dtm_sweep_row *rows, int n, int p, int way, curve *c) {
  /* the band judges the one global step only (issue 37): its legend says so */
  static const char *labels[3] = {"one global step, judged", "ideal subcycling", "mass scaling to the target"};
  static const char *symbols[3] = {"#(840)", "#(841)", "#(842)"};
  static const int colors[3] = {2, 3, 7};
  c->n = 0, c->label = labels[way], c->color = colors[way], c->symbol = symbols[way];
  for (int i = 0; i < n && c->n < 64; i++) {
    double x = row_time(&rows[i], way), y = row_value(&rows[i], p, p == 1 ? 0 : way);
    if (!(x > 0 && y > 0) || !isfinite(x) || !isfinite(y)) continue;
    c->x[c->n] = log10(x), c->y[c->n] = log10(y), c->row[c->n++] = i;
  }
}

/* One panel's axes: ranges over its curves and the band. */
static void panel_axes(const curve *c, int nc, double band_lo, double band_hi, const char *xl, const char *yl,
                       const char *title) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = log10(band_lo), y1 = log10(band_hi);
  for (int k = 0; k < nc; k++)
    for (int i = 0; i < c[k].n; i++)
      x0 = fmin(x0, c[k].x[i]), x1 = fmax(x1, c[k].x[i]), y0 = fmin(y0, c[k].y[i]), y1 = fmax(y1, c[k].y[i]);
  double px = x1 - x0 > 0.1 ? 0.08 * (x1 - x0) : 0.25, py = y1 - y0 > 0.1 ? 0.08 * (y1 - y0) : 0.25;
  x0 -= px, x1 += px, y0 -= py, y1 += py;
  if (floor(x1) - ceil(x0) < 1) x0 = floor(x0), x1 = ceil(x1);
  if (floor(y1) - ceil(y0) < 1) y0 = floor(y0), y1 = ceil(y1);
  plwind(x0, x1, y0, y1);
  plcol0(4);
  plbox("ghl", 0, 0, "ghl", 0, 0);
  plcol0(1);
  plbox("bclnst", 0, 0, "bclnstv", 0, 0);
  plmtex("b", 3.2, 0.5, 0.5, xl);
  plmtex("l", 4.2, 0.5, 0.5, yl);
  plschr(0, 0.85);
  plmtex("t", 1.0, 0.5, 0.5, title);
  plschr(0, 1.0);
  plwind(x0, x1, y0, y1); /* keep the world window for the labels */
  plcol0(5);
  pllsty(2);
  for (int k = 0; k < 2; k++) {
    double v = log10(k ? band_hi : band_lo), xs[2] = {x0, x1}, ys[2] = {v, v};
    if (isfinite(v) && (k == 0 || band_hi != band_lo)) plline(2, xs, ys);
  }
  pllsty(1);
}

/* World coordinates of the current window to mm on the page, and back. */
typedef struct {
  double wx0, wx1, wy0, wy1; /* world window */
  double mx0, mx1, my0, my1; /* the viewport in mm */
} page_map;

static page_map page_of_viewport(void) {
  page_map m;
  double sx0, sx1, sy0, sy1, vx0, vx1, vy0, vy1;
  plgspa(&sx0, &sx1, &sy0, &sy1);
  plgvpd(&vx0, &vx1, &vy0, &vy1);
  plgvpw(&m.wx0, &m.wx1, &m.wy0, &m.wy1);
  m.mx0 = sx0 + vx0 * (sx1 - sx0), m.mx1 = sx0 + vx1 * (sx1 - sx0);
  m.my0 = sy0 + vy0 * (sy1 - sy0), m.my1 = sy0 + vy1 * (sy1 - sy0);
  return m;
}

static double to_mm_x(const page_map *m, double x) {
  return m->mx0 + (x - m->wx0) / (m->wx1 - m->wx0) * (m->mx1 - m->mx0);
}
static double to_mm_y(const page_map *m, double y) {
  return m->my0 + (y - m->wy0) / (m->wy1 - m->wy0) * (m->my1 - m->my0);
}
static double to_world_x(const page_map *m, double x) {
  return m->wx0 + (x - m->mx0) / (m->mx1 - m->mx0) * (m->wx1 - m->wx0);
}
static double to_world_y(const page_map *m, double y) {
  return m->wy0 + (y - m->my0) / (m->my1 - m->my0) * (m->wy1 - m->wy0);
}

#define MARKER 1.1 /* a marker's size in character heights */
#define TEXT_W                                                                                                         \
  0.72 /* a character's width in character heights, at least (DejaVu Sans through cairo, digits and lower case) */

static double char_height(double scale) {
  double def, ht;
  plschr(0, scale);
  plgchr(&def, &ht);
  plschr(0, 1.0);
  return ht;
}

/* The curves, with every point's marker box into the panel's layout. */
static void panel_curves(const curve *c, int nc, const page_map *m, dtm_plot_panel *pl) {
  double r = MARKER * char_height(1.0) / 2;
  for (int k = 0; k < nc; k++) {
    if (!c[k].n) continue;
    plcol0(c[k].color);
    plwidth(2.0);
    if (c[k].n > 1) plline(c[k].n, c[k].x, c[k].y);
    plstring(c[k].n, c[k].x, c[k].y, c[k].symbol);
    plwidth(1.0);
    for (int i = 0; i < c[k].n; i++) {
      double x = to_mm_x(m, c[k].x[i]), y = to_mm_y(m, c[k].y[i]);
      pl->point[pl->npoints++] = (dtm_plot_box){x - r, y - r, x + r, y + r};
    }
  }
}

/* To the right of the box, outside it, so it hides no point; its box
 * (pllegend gives its size as a fraction of the viewport) into pl. */
static void panel_legend(const curve *c, int nc, const page_map *m, dtm_plot_panel *pl) {
  PLINT opt[3], tcol[3], lcol[3], lsty[3], scol[3], snum[3];
  PLFLT lwid[3], sscale[3], w = 0, h = 0;
  const char *text[3], *sym[3];
  int n = 0;
  for (int k = 0; k < nc; k++) {
    if (!c[k].n) continue;
    opt[n] = PL_LEGEND_LINE | PL_LEGEND_SYMBOL, tcol[n] = 1, lcol[n] = scol[n] = c[k].color, lsty[n] = 1;
    snum[n] = 1, lwid[n] = 2.0, sscale[n] = 1.0, text[n] = c[k].label, sym[n] = c[k].symbol, n++;
  }
  if (!n) return;
  pllegend(&w, &h, 0, PL_POSITION_RIGHT | PL_POSITION_OUTSIDE, 0.02, 0.0, 0.05, 0, 0, 1, 0, 0, n, opt, 0.8, 0.7, 1.5,
           0.0, tcol, text, NULL, NULL, NULL, NULL, lcol, lsty, lwid, scol, sscale, snum, sym);
  double x0 = m->mx1 + 0.02 * (m->mx1 - m->mx0), yc = 0.5 * (m->my0 + m->my1), hh = 0.5 * h * (m->my1 - m->my0);
  pl->legend = (dtm_plot_box){x0, yc - hh, x0 + w * (m->mx1 - m->mx0), yc + hh};
}

/* One label at its box (text centred in it), the cheapest size's point
 * ringed; a thin leader line from the point when the box stands off it. */
static void draw_label(const dtm_plot_label *l, const dtm_plot_box *b, const char *text, double scale, int top,
                       const page_map *m) {
  double px = to_world_x(m, l->px), py = to_world_y(m, l->py);
  double nx = fmin(fmax(l->px, b->x0), b->x1), ny = fmin(fmax(l->py, b->y0), b->y1); /* nearest point of the box */
  plcol0(top ? 6 : 1);
  if (top) plstring(1, &px, &py, "#(850)");
  if (hypot(nx - l->px, ny - l->py) > l->radius + l->h) {
    double xs[2] = {px, to_world_x(m, nx)}, ys[2] = {py, to_world_y(m, ny)};
    plwidth(0.5);
    plline(2, xs, ys);
    plwidth(1.0);
  }
  plschr(0, scale);
  plptex(to_world_x(m, 0.5 * (b->x0 + b->x1)), to_world_y(m, 0.5 * (b->y0 + b->y1)), 1, 0, 0.5, text);
  plschr(0, 1.0);
}

/* The labels of the first curve's points ("h = ..."; the cheapest size in
 * the band ringed and named first), placed clear of the markers, of each
 * other and of the legend (labels.c), with a leader line when a label
 * stands off its point. */
static void panel_labels(const curve *c, int nc, const dtm_sweep_row *rows, int best, const page_map *m,
                         dtm_plot_panel *pl) {
  dtm_plot_label lab[DTM_PLOT_MAX];
  double seg[3 * DTM_PLOT_MAX][4], scale[DTM_PLOT_MAX];
  int order[DTM_PLOT_MAX], n = 0, ns = 0;
  for (int i = 0; i < c[0].n; i++)
    if (c[0].row[i] == best) order[n++] = i; /* the cheapest first */
  for (int i = 0; i < c[0].n; i++)
    if (c[0].row[i] != best) order[n++] = i;
  for (int k = 0; k < nc; k++)
    for (int i = 1; i < c[k].n; i++)
      seg[ns][0] = to_mm_x(m, c[k].x[i - 1]), seg[ns][1] = to_mm_y(m, c[k].y[i - 1]),
      seg[ns][2] = to_mm_x(m, c[k].x[i]), seg[ns++][3] = to_mm_y(m, c[k].y[i]);
  for (int j = 0; j < n; j++) {
    int i = order[j], top = c[0].row[i] == best;
    const dtm_sweep_row *r = &rows[c[0].row[i]];
    snprintf(pl->text[j], sizeof pl->text[j], "%s%g %s", top ? "cheapest in band: h = " : "h = ", r->h,
             r->length_unit ? r->length_unit : "m");
    scale[j] = top ? 0.8 : 0.65;
    double ht = char_height(scale[j]);
    lab[j] = (dtm_plot_label){to_mm_x(m, c[0].x[i]), to_mm_y(m, c[0].y[i]), MARKER * char_height(1.0) / 2,
                              TEXT_W * ht * (double)strlen(pl->text[j]), 1.4 * ht};
  }
  dtm_plot_box hard[3 * DTM_PLOT_MAX + 1];
  int nh = pl->npoints;
  memcpy(hard, pl->point, (size_t)nh * sizeof *hard);
  hard[nh++] = pl->legend;
  double gap = 0.3 * char_height(1.0);
  dtm_plot_box inner = {pl->frame.x0 + gap, pl->frame.y0 + gap, pl->frame.x1 - gap, pl->frame.y1 - gap};
  dtm_plot_scene sc = {inner, hard, nh, (const double(*)[4])seg, ns, gap};
  dtm_cli_place_labels(&sc, lab, n, pl->label);
  pl->nlabels = n;
  for (int j = 0; j < n; j++) draw_label(&lab[j], &pl->label[j], pl->text[j], scale[j], c[0].row[order[j]] == best, m);
}
/* The error panels that have points: 0 phase error, 1 counts. */
static int measure_panels(const dtm_sweep_row *rows, int n, curve c[2][3], int have[2]) {
  int np = 0;
  for (int p = 0; p < 2; p++) {
    have[p] = 0;
    for (int w = 0; w < 3; w++) fill_curve(rows, n, p, w, &c[p][w]), have[p] |= c[p][w].n > 0;
    np += have[p];
  }
  return np;
}

/* The panel title of measure p. */
static void panel_title(const dtm_sweep_row *rows, int p, char *pt, size_t len) {
  if (p == 0)
    snprintf(pt, len, "worst phase-speed error at %.4g Hz%s; band %g %%", rows[0].frequency,
             rows[0].frequency_default ? " (mesh default)" : " (f-max)", 100 * DTM_BAND_PHASE);
  else
    snprintf(pt, len, "smallest elements per %s; band %s",
             isfinite(rows[0].per_zone) ? "cohesive zone" : "diffusion length",
             isfinite(rows[0].per_zone) ? "5-10" : ">= 5");
}

/* Panel p of the error plot in the current viewport, into pl. */
static void draw_panel(const dtm_sweep_row *rows, int p, const curve *c, int best, const char *xl, dtm_plot_panel *pl) {
  char pt[1024];
  int nc = p ? 1 : 3;
  panel_title(rows, p, pt, sizeof pt);
  panel_axes(c, nc, p ? 5 : 100 * DTM_BAND_PHASE, p ? (isfinite(rows[0].per_zone) ? 10 : 5) : 100 * DTM_BAND_PHASE, xl,
             p ? "elements" : "|phase-speed error| (%)", pt);
  page_map m = page_of_viewport();
  *pl = (dtm_plot_panel){.frame = {m.mx0, m.my0, m.mx1, m.my1}};
  panel_curves(c, nc, &m, pl);
  panel_legend(c, nc, &m, pl);
  panel_labels(c, nc, rows, best, &m, pl);
}

static void draw_measures(const char *file, const char *title, const dtm_sweep_row *rows, int n, curve c[2][3],
                          const int have[2]) {
  int best = dtm_sweep_cheapest(rows, n), np = have[0] + have[1], j = 0;
  const char *xl = !isfinite(rows[0].hours) ? "run time per simulated second (h/s)" : "run time (h)";
  char t[512];
  plsdev("pngcairo");
  plsfnam(file);
  plspage(0, 0, 1250, np > 1 ? 1100 : 700, 0, 0);
  set_colors();
  plscol0(5, 44, 160, 44);  /* band */
  plscol0(6, 148, 0, 211);  /* cheapest in band */
  plscol0(7, 255, 127, 14); /* mass scaling */
  plinit();
  pladv(0);
  snprintf(t, sizeof t, "dtmap sweep: %s", title ? title : "what accuracy costs");
  last.npanels = 0;
  for (int p = 0; p < 2; p++) {
    if (!have[p]) continue;
    double top = 0.90 - j * (0.86 / np), bottom = top - 0.86 / np + 0.11;
    plvpor(0.09, 0.70, bottom, top);
    if (j == 0) plmtex("t", 2.6, 0.5, 0.5, t);
    draw_panel(rows, p, c[p], best, xl, &last.panel[last.npanels++]);
    j++;
  }
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
static int plot_file(const char *path, const char *title, const plot_data *d, const dtm_sweep_row *rows, int n) {
  dtm_atomic w;
  curve c[2][3];
  int have[2];
  DTM_CHECK(dtm_atomic_open(&w, path, ".png", 1));
  if (fclose(w.f)) return w.f = NULL, dtm_atomic_abort(&w), DTM_ERR(DTM_ERR_INPUT, "%s: cannot write", path);
  w.f = NULL;
  if (measure_panels(rows, n, c, have))
    draw_measures(w.tmp, title, rows, n, c, have);
  else
    draw(w.tmp, title, d);
  if (!png_ok(w.tmp)) return dtm_atomic_abort(&w), DTM_ERR(DTM_ERR_INTERNAL, "%s: PLplot did not write a PNG", path);
  return dtm_atomic_commit(&w);
}

int dtm_cli_sweep_plot_titled(const char *path, const char *title, const dtm_sweep_row *rows, int n) {
  if (n < 1) return DTM_ERR(DTM_ERR_INPUT, "sweep plot: no rows to draw");
  if (!have_pngcairo()) return DTM_ERR(DTM_ERR_INTERNAL, "PLplot has no pngcairo device: install plplot-driver-cairo");
  plot_data d;
  DTM_CHECK(collect(rows, n, &d));
  int r = plot_file(path, title, &d, rows, n);
  free(d.x);
  return r;
}

int dtm_cli_sweep_plot(const char *path, const dtm_sweep_row *rows, int n) {
  return dtm_cli_sweep_plot_titled(path, NULL, rows, n);
}

int dtm_cli_can_plot(void) { return 1; }
