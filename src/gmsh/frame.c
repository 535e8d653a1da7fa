/* The camera of a snapshot (snapshot.c): which way the model is seen and
 * how it is framed, set through Gmsh's General.Rotation, Scale and
 * Translation options before its window exists.
 * - A model whose nodes span 3D (a solid, or shells such as Gmsh's tower)
 *   is seen obliquely, 30 degrees above the horizontal (z up) from one of
 *   the four diagonal directions: the one facing the worst elements (the
 *   centroid of the view "below target [s]" or "smallest 1% [s]", seen from
 *   the model's centre), so that they are in front, and no face parallel to
 *   a coordinate plane is seen edge-on. A flat model is seen from its
 *   normal, as Gmsh shows it.
 * - The model as drawn (the nodes of the dt view's elements: curves and
 *   surfaces no view holds are not drawn) is scaled and moved so that its
 *   projection fills the window
 *   between the text at the top (dtmap's annotation, three lines) and the
 *   colour scales at the bottom (Gmsh draws them horizontally, centred, in
 *   a band of about 90 pixels), with a margin: nothing is cut off and no
 *   scale lies over the model.
 * Gmsh maps a point p to s (R (p - cg) + t) in a world window fitted to the
 * unrotated bounding box (drawContext::initProjection, with a border of
 * General.DisplayBorderFactor on each side) and centred on its centre cg;
 * the rotation with RotationY = 0 is Rx(rx) Rz(rz). The framing computes
 * the projection of every node with the same R and picks s and t. */
#include <gmshc.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

#define PI 3.14159265358979323846
#define TEXT_BAND 80   /* pixels at the top for the annotation's three lines */
#define SCALE_BAND 110 /* pixels at the bottom for the colour scales */
#define MARGIN 12      /* pixels on the left and right */
#define ELEVATION 30.0 /* degrees above the horizontal */

static double option(const char *name) {
  double v = 0;
  int ierr = 0;
  gmshOptionGetNumber(name, &v, &ierr);
  return v;
}

static void set_option(const char *name, double v) {
  int ierr = 0;
  gmshOptionSetNumber(name, v, &ierr);
}

/* The rows of R = Rx(rx) Rz(rz) (degrees), as Gmsh builds it. */
static void rotation(double rx, double rz, double m[3][3]) {
  double A = cos(rx * PI / 180), B = sin(rx * PI / 180), E = cos(rz * PI / 180), F = sin(rz * PI / 180);
  double r[3][3] = {{E, -F, 0}, {A * F, A * E, -B}, {B * F, B * E, A}};
  memcpy(m, r, sizeof r);
}

/* Index of the view called name, -1 when none. */
static int view_index(const char *name) {
  int n = (int)option("PostProcessing.NbViews");
  for (int i = 0; i < n; i++)
    if (dtm_gmsh_view_is(i, name)) return i;
  return -1;
}

/* Centroid of element tag into c (added with weight 1); 1 when found. */
static int add_centroid(size_t tag, double c[3]) {
  int type = 0, ierr = 0, ok = 0;
  size_t *nodes = NULL, nn = 0;
  gmshModelMeshGetElement(tag, &type, &nodes, &nn, &ierr);
  for (size_t k = 0; !ierr && k < nn; k++) {
    double *x = NULL, *u = NULL;
    size_t nx = 0, nu = 0;
    int e2 = 0;
    gmshModelMeshGetNode(nodes[k], &x, &nx, &u, &nu, &e2);
    for (int d = 0; !e2 && nx == 3 && d < 3; d++) c[d] += x[d] / (double)nn;
    ok = !e2;
    gmshFree(x), gmshFree(u);
  }
  gmshFree(nodes);
  return ok;
}

/* Centroid of the elements of the worst-elements view, into c; 0 when
 * there is none. */
static int worst_centroid(double c[3]) {
  int i = view_index("below target [s]");
  if (i < 0) i = view_index("smallest 1% [s]");
  int *tags = NULL, ierr = 0, found = 0;
  size_t nt = 0;
  gmshViewGetTags(&tags, &nt, &ierr);
  if (i < 0 || ierr || (size_t)i >= nt) return gmshFree(tags), 0;
  char *type = NULL;
  size_t *et = NULL, ne = 0, *dn = NULL, dnn = 0;
  double **data = NULL, time = 0;
  int ncomp = 0;
  gmshViewGetModelData(tags[i], 0, &type, &et, &ne, &data, &dn, &dnn, &time, &ncomp, &ierr);
  c[0] = c[1] = c[2] = 0;
  for (size_t e = 0; !ierr && e < ne; e++) found += add_centroid(et[e], c);
  for (int d = 0; found && d < 3; d++) c[d] /= found;
  for (size_t k = 0; k < dnn; k++) gmshFree(data[k]);
  gmshFree(data), gmshFree(dn), gmshFree(et), gmshFree(type), gmshFree(tags);
  return found > 0;
}

static int by_tag(const void *a, const void *b) {
  size_t x = *(const size_t *)a, y = *(const size_t *)b;
  return (x > y) - (x < y);
}

static int has_tag(const size_t *v, size_t n, size_t t) { return bsearch(&t, v, n, sizeof *v, by_tag) != NULL; }

/* use[index] = 1 for the nodes of the elements whose tags are in vt[nv]. */
static void mark_drawn(const size_t *vt, size_t nv, const size_t *at, size_t maxtag, unsigned char *use) {
  int *types = NULL, ierr = 0;
  size_t nty = 0, **et = NULL, *etn = NULL, etnn = 0, **nt = NULL, *ntn = NULL, ntnn = 0;
  gmshModelMeshGetElements(&types, &nty, &et, &etn, &etnn, &nt, &ntn, &ntnn, -1, -1, &ierr);
  for (size_t t = 0; !ierr && t < nty; t++) {
    size_t per = etn[t] ? ntn[t] / etn[t] : 0;
    for (size_t e = 0; e < etn[t]; e++)
      for (size_t k = 0; has_tag(vt, nv, et[t][e]) && k < per; k++)
        if (nt[t][e * per + k] <= maxtag && at[nt[t][e * per + k]]) use[at[nt[t][e * per + k]] - 1] = 1;
  }
  for (size_t t = 0; t < etnn; t++) gmshFree(et[t]);
  for (size_t t = 0; t < ntnn; t++) gmshFree(nt[t]);
  gmshFree(et), gmshFree(etn), gmshFree(nt), gmshFree(ntn), gmshFree(types);
}

/* The element tags of view i, sorted (free), and their count. */
static size_t view_elements(int i, size_t **out) {
  int *tags = NULL, ierr = 0, ncomp = 0;
  size_t nt = 0, *et = NULL, ne = 0, *dn = NULL, dnn = 0;
  char *type = NULL;
  double **data = NULL, time = 0;
  gmshViewGetTags(&tags, &nt, &ierr);
  if (!ierr && i >= 0 && (size_t)i < nt)
    gmshViewGetModelData(tags[i], 0, &type, &et, &ne, &data, &dn, &dnn, &time, &ncomp, &ierr);
  for (size_t k = 0; k < dnn; k++) gmshFree(data[k]);
  gmshFree(data), gmshFree(dn), gmshFree(type), gmshFree(tags);
  *out = ierr || !ne ? NULL : malloc(ne * sizeof **out);
  if (*out) memcpy(*out, et, ne * sizeof **out), qsort(*out, ne, sizeof **out, by_tag);
  gmshFree(et);
  return *out ? ne : 0;
}

/* The coordinates of the nodes of the elements view i draws (every node
 * of the model when it has none), xyz[3 n] (free). */
static double *drawn_nodes(int i, size_t *n) {
  size_t *vt = NULL, nv = view_elements(i, &vt), *ntag = NULL, nn = 0, nc = 0, np = 0;
  double *xyz = NULL, *p = NULL, *out = NULL;
  int ierr = 0;
  gmshModelMeshGetNodes(&ntag, &nn, &xyz, &nc, &p, &np, -1, -1, 0, 0, &ierr);
  size_t maxtag = 0, k = 0;
  for (size_t i = 0; !ierr && i < nn; i++) maxtag = ntag[i] > maxtag ? ntag[i] : maxtag;
  size_t *at = ierr ? NULL : calloc(maxtag + 1, sizeof *at); /* node tag -> its index + 1 */
  unsigned char *use = at ? calloc(nn + 1, 1) : NULL;
  for (size_t i = 0; use && i < nn; i++) at[ntag[i]] = i + 1;
  if (use) mark_drawn(vt, nv, at, maxtag, use);
  out = use ? malloc((nn + 1) * 3 * sizeof *out) : NULL;
  for (size_t i = 0; out && i < nn; i++)
    if (use[i] || !nv) memcpy(out + 3 * k++, xyz + 3 * i, 3 * sizeof *out);
  *n = out ? k : 0;
  free(vt), free(at), free(use), gmshFree(ntag), gmshFree(xyz), gmshFree(p);
  return out;
}

typedef struct {
  double lo[3], hi[3]; /* the nodes' bounding box, m */
  double cg[3];        /* Gmsh's centre: that of its bounding box */
} model_box;

static void box_of(const double *xyz, size_t n, model_box *b) {
  for (int d = 0; d < 3; d++) b->lo[d] = INFINITY, b->hi[d] = -INFINITY;
  for (size_t i = 0; i < n; i++)
    for (int d = 0; d < 3; d++) b->lo[d] = fmin(b->lo[d], xyz[3 * i + d]), b->hi[d] = fmax(b->hi[d], xyz[3 * i + d]);
  static const char *const mins[3] = {"General.MinX", "General.MinY", "General.MinZ"};
  static const char *const maxs[3] = {"General.MaxX", "General.MaxY", "General.MaxZ"};
  for (int d = 0; d < 3; d++) b->cg[d] = 0.5 * (option(mins[d]) + option(maxs[d]));
}

/* Whether the nodes span 3D: no side of their box below 1e-6 of the largest. */
static int spans_3d(const model_box *b) {
  double s[3] = {b->hi[0] - b->lo[0], b->hi[1] - b->lo[1], b->hi[2] - b->lo[2]};
  double big = fmax(s[0], fmax(s[1], s[2]));
  return s[0] > 1e-6 * big && s[1] > 1e-6 * big && s[2] > 1e-6 * big;
}

/* rx, rz of the diagonal view facing the worst elements (the first
 * diagonal when they sit at the centre or are unknown). */
static void oblique(const model_box *b, double *rx, double *rz) {
  double c[3], best = -INFINITY;
  int have = worst_centroid(c);
  *rx = ELEVATION - 90, *rz = -45;
  for (int k = 0; k < 4; k++) {
    double az = (45 + 90 * k) * PI / 180, h[2] = {cos(az), sin(az)};
    double score = have ? h[0] * (c[0] - b->cg[0]) + h[1] * (c[1] - b->cg[1]) : -k;
    if (score > best + 1e-12 * (b->hi[0] - b->lo[0] + b->hi[1] - b->lo[1]))
      best = score, *rz = atan2(-h[0], -h[1]) * 180 / PI;
  }
}

/* World units per pixel of Gmsh's initial window of width x height. */
static double world_per_pixel(int width, int height) {
  double x0 = option("General.MinX"), x1 = option("General.MaxX"), y0 = option("General.MinY"),
         y1 = option("General.MaxY"), f = option("General.DisplayBorderFactor");
  double va = (double)height / width, wa = (y1 - y0) / (x1 - x0);
  double wide = va > wa ? x1 - x0 : (y1 - y0) / va;
  return wide * (1 + 2 * f) / width;
}

/* Scale and translation that fit the projection of the nodes into the
 * window between the text and the scales. */
static void fit(const double *xyz, size_t n, const model_box *b, double m[3][3], int width, int height) {
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (size_t i = 0; i < n; i++)
    for (int r = 0; r < 2; r++) {
      double q = 0;
      for (int d = 0; d < 3; d++) q += m[r][d] * (xyz[3 * i + d] - b->cg[d]);
      lo[r] = fmin(lo[r], q), hi[r] = fmax(hi[r], q);
    }
  double pe = world_per_pixel(width, height), w = width - 2.0 * MARGIN, h = height - TEXT_BAND - SCALE_BAND;
  double s = fmin(w * pe / fmax(hi[0] - lo[0], 1e-300), h * pe / fmax(hi[1] - lo[1], 1e-300));
  if (!(s > 0) || !isfinite(s) || h < 16) return;
  double yc = 0.5 * (SCALE_BAND - TEXT_BAND) * pe; /* the free band's centre above the window's */
  set_option("General.ScaleX", s), set_option("General.ScaleY", s), set_option("General.ScaleZ", s);
  set_option("General.TranslationX", -0.5 * (lo[0] + hi[0]));
  set_option("General.TranslationY", yc / s - 0.5 * (lo[1] + hi[1]));
}

void dtm_gmsh_snapshot_camera(int width, int height) {
  double rx = 0, rz = 0, m[3][3];
  size_t n = 0;
  model_box b;
  double *xyz = drawn_nodes(view_index("dt"), &n);
  if (n) box_of(xyz, n, &b);
  if (!n) {
    free(xyz);
    return;
  }
  if (spans_3d(&b)) {
    oblique(&b, &rx, &rz);
    set_option("General.Trackball", 0);
    set_option("General.RotationX", rx), set_option("General.RotationY", 0), set_option("General.RotationZ", rz);
  }
  rotation(rx, rz, m);
  fit(xyz, n, &b, m, width, height);
  free(xyz);
}

/* The worst elements framed: their box (the nodes of the view "below
 * target [s]", else "smallest 1% [s]") grown by WORST_PAD of its largest
 * side on every side, fitted as the whole model is. */
#define WORST_PAD 0.2
int dtm_gmsh_snapshot_camera_worst(int width, int height) {
  double m[3][3], c[12];
  size_t n = 0, all = 0;
  model_box b, w;
  int i = view_index("below target [s]");
  if (i < 0) i = view_index("smallest 1% [s]");
  double *xyz = drawn_nodes(view_index("dt"), &all), *worst = i < 0 ? NULL : drawn_nodes(i, &n);
  if (all) box_of(xyz, all, &b);
  int flat = all && n && !spans_3d(&b);
  if (flat) {
    box_of(worst, n, &w);
    double side = fmax(w.hi[0] - w.lo[0], fmax(w.hi[1] - w.lo[1], w.hi[2] - w.lo[2]));
    double pad = WORST_PAD * side;
    for (int k = 0; k < 4; k++) { /* the grown box's corners in the model's plane */
      c[3 * k] = k & 1 ? w.hi[0] + pad : w.lo[0] - pad;
      c[3 * k + 1] = k & 2 ? w.hi[1] + pad : w.lo[1] - pad;
      c[3 * k + 2] = 0.5 * (w.lo[2] + w.hi[2]);
    }
    rotation(0, 0, m);
    fit(c, 4, &b, m, width, height);
  }
  free(xyz), free(worst);
  return flat;
}

/* The worst element marked in the picture of the worst elements: a ring
 * RING_PX pixels across in the plane of the screen around its centroid and
 * a tag beside it with its tag and step, "element 264: 1.3608e-05 s", in a
 * list-based view of this session only ("worst element", red). The worst
 * is the element of the smallest value of the dt view. */
#define RING_PX 16.0 /* the ring's radius, pixels */
#define RING_SEGMENTS 36

static const char *const box_lo[3] = {"General.MinX", "General.MinY", "General.MinZ"};
static const char *const box_hi[3] = {"General.MaxX", "General.MaxY", "General.MaxZ"};

/* The ring and the tag of element worst (centroid c, step v) in a view of
 * their own; 1 when drawn. Both are moved towards the eye to the front of
 * the model's box: drawn over the model, at the same place on the screen
 * (the projection is orthographic). The tag stands on the side of the
 * window's centre, so that it is not cut off. */
static int mark(const double c[3], size_t worst, double v, int width, int height) {
  double m[3][3], scale = option("General.ScaleX"), depth = 0, diag = 0, across = option("General.TranslationX");
  rotation(option("General.RotationX"), option("General.RotationZ"), m);
  for (int d = 0; d < 3; d++) {
    double mid = 0.5 * (option(box_lo[d]) + option(box_hi[d]));
    depth += m[2][d] * (c[d] - mid), across += m[0][d] * (c[d] - mid);
    diag += pow(option(box_hi[d]) - option(box_lo[d]), 2);
  }
  double front[3], r = RING_PX * world_per_pixel(width, height) / (scale > 0 ? scale : 1.0), ring[8 * RING_SEGMENTS];
  for (int d = 0; d < 3; d++) front[d] = c[d] + (0.5 * sqrt(diag) - depth) * m[2][d];
  for (int k = 0; k < RING_SEGMENTS; k++) /* SL: x1 x2 y1 y2 z1 z2 v1 v2, in the screen's plane */
    for (int end = 0; end < 2; end++) {
      double t = 2 * PI * (k + end) / RING_SEGMENTS;
      for (int d = 0; d < 3; d++) ring[8 * k + 2 * d + end] = front[d] + r * (cos(t) * m[0][d] + sin(t) * m[1][d]);
      ring[8 * k + 6 + end] = 1.0; /* 0.8 of the range: red in Gmsh's default colour map */
    }
  char text[96], *strings[1] = {text}, align[] = "Align", right[] = "Right", *style[2] = {align, right};
  int left = across > 0, ierr = 0;
  double at[3];
  snprintf(text, sizeof text, "element %zu: %.4e s", worst, v);
  for (int d = 0; d < 3; d++) at[d] = front[d] + (left ? -1.4 : 1.4) * r * m[0][d] + 0.3 * r * m[1][d];
  int view = gmshViewAdd("worst element", -1, &ierr);
  if (!ierr) gmshViewAddListData(view, "SL", RING_SEGMENTS, ring, 8 * RING_SEGMENTS, &ierr);
  if (!ierr) gmshViewAddListDataString(view, at, 3, strings, 1, left ? style : NULL, left ? 2 : 0, &ierr);
  int k = view_index("worst element");
  if (ierr || k < 0) return 0;
  char key[64];
  static const struct {
    const char *opt;
    double value;
  } look[] = {{"LineWidth", 4}, {"Light", 0},     {"ShowScale", 0},
              {"RangeType", 2}, {"CustomMin", 0}, {"CustomMax", 1.25}};
  for (size_t j = 0; j < sizeof look / sizeof *look; j++)
    snprintf(key, sizeof key, "View[%d].%s", k, look[j].opt), set_option(key, look[j].value);
  snprintf(key, sizeof key, "View[%d].Color.Text3D", k);
  gmshOptionSetColor(key, 220, 0, 0, 255, &ierr);
  return 1;
}

int dtm_gmsh_snapshot_mark_worst(int width, int height) {
  int i = view_index("dt"), *tags = NULL, ierr = 0, ncomp = 0;
  size_t nt = 0, *et = NULL, ne = 0, *dn = NULL, dnn = 0, worst = 0;
  double **data = NULL, time = 0, vmin = INFINITY, c[3] = {0, 0, 0};
  char *type = NULL;
  gmshViewGetTags(&tags, &nt, &ierr);
  if (i >= 0 && !ierr && (size_t)i < nt)
    gmshViewGetModelData(tags[i], 0, &type, &et, &ne, &data, &dn, &dnn, &time, &ncomp, &ierr);
  for (size_t e = 0; !ierr && e < ne && e < dnn; e++)
    for (size_t k = 0; k < dn[e]; k++)
      if (data[e][k] < vmin) vmin = data[e][k], worst = et[e];
  for (size_t k = 0; k < dnn; k++) gmshFree(data[k]);
  gmshFree(data), gmshFree(dn), gmshFree(et), gmshFree(type), gmshFree(tags);
  if (!isfinite(vmin) || !add_centroid(worst, c)) return 0;
  return mark(c, worst, vmin, width, height);
}
