/* Where the sweep plot's labels go (plot.c draws them): each label beside
 * its point, clear of every point's marker, of the labels placed before it
 * and of the legend, inside the plot's box. Pure geometry in millimetres
 * on the page, so that it can be tested without drawing. Each label tries
 * eight places around its point (right, left, above, below, then the
 * corners) at growing distances, each also slid into the box when it
 * sticks out: the nearest place that overlaps nothing wins (one across a
 * curve counts 1.5 rings further, a slid one half a ring), else the one
 * that overlaps least. The caller places the most important label first. */
#include <math.h>

#include "cli-impl.h"

#define RINGS 6 /* distances tried, each one label height further */

static double overlap(const dtm_plot_box *a, const dtm_plot_box *b) {
  double w = fmin(a->x1, b->x1) - fmax(a->x0, b->x0), h = fmin(a->y1, b->y1) - fmax(a->y0, b->y0);
  return w > 0 && h > 0 ? w * h : 0;
}

static int inside(const dtm_plot_box *in, const dtm_plot_box *frame) {
  return in->x0 >= frame->x0 && in->x1 <= frame->x1 && in->y0 >= frame->y0 && in->y1 <= frame->y1;
}

/* Whether segment (x0, y0)-(x1, y1) meets box b (Liang-Barsky clipping). */
static int crosses(const double *s, const dtm_plot_box *b) {
  double t0 = 0, t1 = 1, dx = s[2] - s[0], dy = s[3] - s[1];
  double p[4] = {-dx, dx, -dy, dy}, q[4] = {s[0] - b->x0, b->x1 - s[0], s[1] - b->y0, b->y1 - s[1]};
  for (int i = 0; i < 4; i++) {
    if (p[i] == 0) {
      if (q[i] < 0) return 0;
      continue;
    }
    double r = q[i] / p[i];
    if (p[i] < 0)
      t0 = fmax(t0, r);
    else
      t1 = fmin(t1, r);
    if (t0 > t1) return 0;
  }
  return 1;
}

/* The box of label l at place k (0-7) of ring r around its point. */
static dtm_plot_box candidate(const dtm_plot_label *l, double gap, int k, int r) {
  static const double dir[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
  double d = gap + r * l->h, cx = l->px + dir[k][0] * (l->radius + d + l->w / 2),
         cy = l->py + dir[k][1] * (l->radius + d + l->h / 2);
  return (dtm_plot_box){cx - l->w / 2, cy - l->h / 2, cx + l->w / 2, cy + l->h / 2};
}

/* Overlap of box b with the hard obstacles and the labels placed so far
 * (mm^2), and whether it crosses a curve. */
static double cost(const dtm_plot_box *b, const dtm_plot_scene *s, const dtm_plot_box *placed, int np, int *cross) {
  double o = 0;
  for (int i = 0; i < s->nhard; i++) o += overlap(b, &s->hard[i]);
  for (int i = 0; i < np; i++) o += overlap(b, &placed[i]);
  *cross = 0;
  for (int i = 0; i < s->nseg && !*cross; i++) *cross = crosses(s->seg[i], b);
  return o;
}

/* Lower is better: a clear place by its ring (across a curve, 1.5 rings
 * further), an overlapping one after every clear one. */
static double score(const dtm_plot_box *b, const dtm_plot_scene *s, const dtm_plot_box *placed, int np, int r, int k) {
  int cross;
  double o = cost(b, s, placed, np, &cross);
  return o > 0 ? 1000 + o : r + (cross ? 1.5 : 0) + 0.01 * k;
}

/* b moved the least into the frame (when it fits in it). */
static dtm_plot_box into(dtm_plot_box b, const dtm_plot_box *frame) {
  double dx = b.x0 < frame->x0 ? frame->x0 - b.x0 : b.x1 > frame->x1 ? frame->x1 - b.x1 : 0;
  double dy = b.y0 < frame->y0 ? frame->y0 - b.y0 : b.y1 > frame->y1 ? frame->y1 - b.y1 : 0;
  return (dtm_plot_box){b.x0 + dx, b.y0 + dy, b.x1 + dx, b.y1 + dy};
}

void dtm_cli_place_labels(const dtm_plot_scene *s, const dtm_plot_label *labels, int n, dtm_plot_box *out) {
  for (int i = 0; i < n; i++) {
    double best = INFINITY;
    out[i] = candidate(&labels[i], s->gap, 0, 0); /* when nothing fits the frame */
    for (int r = 0; r < RINGS && best >= 1; r++)
      for (int k = 0; k < 16; k++) {
        /* the eight places, then the same slid into the frame (a long label
         * beside a point near the frame's edge: issue 37) */
        dtm_plot_box b = candidate(&labels[i], s->gap, k % 8, r);
        if (k >= 8) b = into(b, &s->frame);
        double v = inside(&b, &s->frame) ? score(&b, s, out, i, r, k) + (k >= 8 ? 0.5 : 0) : INFINITY;
        if (v < best) best = v, out[i] = b;
      }
  }
}
