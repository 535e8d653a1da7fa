/* `dtmap snapshot` draws a result with Gmsh's own renderer. The test runs
 * it with DISPLAY removed from the environment, so dtmap must start its own
 * virtual display (Xvfb), and checks both pictures: valid PNGs (libpng
 * decodes them) of exactly the requested size, and not blank: a dt map on a
 * log colour scale with text has far more than a few distinct colours.
 * Then what a user reads in them, pixel by pixel: the elements with the
 * smallest and the largest step are drawn (their centroids, projected as
 * the camera frames the model, are coloured, not background), every dt
 * picture has its colour bar, the 2D worst picture frames the worst
 * elements, nothing but dtmap's own messages on the standard error, and a
 * mesh without dtmap's views is refused. */
#include <gmshc.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* Decode path; *colours receives the number of distinct RGB colours (up to
 * 4096 counted). Returns 0 when libpng reads it. */
static int read_png(const char *path, unsigned *w, unsigned *h, int *colours) {
  png_image im;
  memset(&im, 0, sizeof im);
  im.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&im, path)) return -1;
  im.format = PNG_FORMAT_RGB;
  unsigned char *px = malloc(PNG_IMAGE_SIZE(im));
  if (!px || !png_image_finish_read(&im, NULL, px, 0, NULL)) return free(px), -1;
  *w = im.width, *h = im.height;
  unsigned *seen = malloc(4096 * sizeof *seen);
  int n = 0;
  for (size_t i = 0; i < (size_t)im.width * im.height && n < 4096; i++) {
    unsigned c = (unsigned)px[3 * i] << 16 | (unsigned)px[3 * i + 1] << 8 | px[3 * i + 2];
    int k = 0;
    while (k < n && seen[k] != c) k++;
    if (k == n) seen[n++] = c;
  }
  free(seen), free(px);
  *colours = n;
  return 0;
}

static void check_png(const char *path, unsigned w, unsigned h) {
  unsigned pw = 0, ph = 0;
  int colours = 0;
  assert_int_equal(read_png(path, &pw, &ph, &colours), 0);
  assert_int_equal(pw, w);
  assert_int_equal(ph, h);
  /* the dt map alone has 12 discrete colour bands besides the background
   * and the text; a blank or one-colour picture has 1 or 2 */
  assert_true(colours > 8);
}

/* In d: the bundled scene name copied there (NULL: d/prefix.xml is there
 * already), `dtmap run` on it into prefix.msh, then `dtmap snapshot
 * prefix.msh --png prefix args` with DISPLAY removed; both exit 0. */
static void run_and_snap(const char *d, const char *name, const char *prefix, const char *args) {
  char *out = NULL, copy[1400] = "";
  if (name)
    snprintf(copy, sizeof copy, "cp %s/geometries/%s.geo . && cp %s/geometries/%s.xml %s.xml && ", tu_src(), name,
             tu_src(), name, prefix);
  int r = tu_run(&out, "cd %s && %s%s run %s.xml -q -o %s.msh && env -u DISPLAY %s snapshot %s.msh --png %s %s -q", d,
                 copy, tu_cli(), prefix, prefix, tu_cli(), prefix, prefix, args);
  if (r) fprintf(stderr, "%s\n", out ? out : "");
  free(out);
  assert_int_equal(r, 0);
}

static void test_snapshot_without_display(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  run_and_snap(d, "brazilian_disc", "pic", "--width 400 --height 300");
  char path[600];
  snprintf(path, sizeof path, "%s/pic_dt.png", d);
  check_png(path, 400, 300);
  snprintf(path, sizeof path, "%s/pic_worst.png", d);
  check_png(path, 400, 300);
}

/* A picture's pixels, RGB. */
typedef struct {
  unsigned w, h;
  unsigned char *px; /* [h][w][3] */
} picture;

static void load(const char *path, picture *p) {
  png_image im;
  memset(&im, 0, sizeof im);
  im.version = PNG_IMAGE_VERSION;
  assert_true(png_image_begin_read_from_file(&im, path));
  im.format = PNG_FORMAT_RGB;
  p->px = malloc(PNG_IMAGE_SIZE(im));
  assert_non_null(p->px);
  assert_true(png_image_finish_read(&im, NULL, p->px, 0, NULL));
  p->w = im.width, p->h = im.height;
}

static const unsigned char *at(const picture *p, unsigned x, unsigned y) { return p->px + 3 * ((size_t)y * p->w + x); }

/* A colour of the viridis map (the model, a colour bar), not the white
 * background, grey shading or black text. */
static int coloured(const unsigned char *c) {
  int hi = c[0] > c[1] ? (c[0] > c[2] ? c[0] : c[2]) : (c[1] > c[2] ? c[1] : c[2]);
  int lo = c[0] < c[1] ? (c[0] < c[2] ? c[0] : c[2]) : (c[1] < c[2] ? c[1] : c[2]);
  return hi - lo > 40;
}

static int text_ink(const unsigned char *c) { return c[0] < 90 && c[1] < 90 && c[2] < 90 && !coloured(c); }

static int row_coloured(const picture *p, unsigned y) {
  for (unsigned x = 0; x < p->w; x++)
    if (coloured(at(p, x, y))) return 1;
  return 0;
}

/* The first line of dtmap's text (y 8-30) spans at least 7.5 pixels per
 * character of its text (the .opt's first T2 string): Gmsh's Helvetica
 * draws about 10; without it (no xfonts-75dpi) X falls back to a small
 * fixed font and drops the spaces, about 5. */
static void check_text(const picture *p, const char *opt) {
  char *text = NULL;
  assert_int_equal(tu_run(&text, "sed -n '0,/^Printf(\\\"\\(.*\\)\\\");/s//\\1/p' '%s'", opt), 0);
  size_t n = strcspn(text, "\n");
  free(text);
  unsigned x0 = p->w, x1 = 0;
  for (unsigned y = 8; y < 30; y++)
    for (unsigned x = 0; x < p->w; x++)
      if (text_ink(at(p, x, y))) x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
  assert_true(n > 20);
  if (!(x1 > x0 && x1 - x0 >= 7.5 * n)) fprintf(stderr, "text: %u pixels for %zu characters\n", x1 - x0, n);
  assert_true(x1 > x0 && x1 - x0 >= 7.5 * n);
}

/* The whole model in the picture, apart from its colour scales: no
 * coloured pixel on the picture's border, and between the scales at the
 * bottom and the model above them at least 5 rows without colour. */
static void check_framed(const picture *p) {
  for (unsigned x = 0; x < p->w; x++) assert_false(coloured(at(p, x, 0)) || coloured(at(p, x, p->h - 1)));
  for (unsigned y = 0; y < p->h; y++) assert_false(coloured(at(p, 0, y)) || coloured(at(p, p->w - 1, y)));
  unsigned y = p->h - 1, gap = 0;
  while (y > 0 && !row_coloured(p, y)) y--; /* below the scales */
  while (y > 0 && row_coloured(p, y)) y--;  /* the colour bars */
  while (y > 0 && !row_coloured(p, y)) y--, gap++;
  assert_true(gap >= 5);
  assert_true(y > 0); /* the model above */
}

/* The bundled reinforced block (3D, trusses and a membrane in concrete):
 * its dt map whole, above its colour bar, with readable text. */
static void test_block_framed(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  char path[600];
  run_and_snap(d, "reinforced_block", "rb", "");
  picture p;
  for (int k = 0; k < 2; k++) {
    snprintf(path, sizeof path, "%s/rb_%s.png", d, k ? "worst" : "dt");
    load(path, &p);
    assert_int_equal(p.w, 1024);
    check_framed(&p);
    snprintf(path, sizeof path, "%s/rb.msh.opt", d);
    check_text(&p, path);
    free(p.px);
  }
}

/* The six faces of a box as shells (Gmsh's OpenCASCADE box without its
 * volume, a surface model like Gmsh's tower; default shell section), the
 * face x = 0 meshed five times finer: its elements hold the smallest steps,
 * the darkest colours. Seen from the top, as dtmap showed a surface model,
 * that face is edge-on (4 % of the picture dark, the neighbours' graded
 * elements); seen from the side of the worst elements it is in front:
 * at least 10 % of the picture above the scales in the darkest three
 * bands (14 %). */
static const char shell_box[] =
    "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\nDelete{ Volume{1}; }\n"
    "f() = Surface In BoundingBox{-0.01, -0.01, -0.01, 0.01, 1.01, 1.01};\nMeshSize{PointsOf{Surface{f()};}} = 0.05;\n"
    "Physical Surface(\"skin\") = {1:6};\n";

static void test_shells_seen_obliquely(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  char path[600];
  snprintf(path, sizeof path, "%s/shellbox.geo", d);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(shell_box, f);
  fclose(f);
  snprintf(path, sizeof path, "%s/sb.xml", d);
  f = fopen(path, "w");
  assert_non_null(f);
  fputs("<dtmap-scene version=\"1\">\n  <geometry file=\"shellbox.geo\"/>\n  <meshing size=\"0.25\" dim=\"2\"/>\n"
        "  <material name=\"steel\" default=\"true\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
        "  <section default=\"true\" kind=\"shell\" thickness=\"0.01\"/>\n  <effects><elastic/></effects>\n"
        "</dtmap-scene>\n",
        f);
  fclose(f);
  run_and_snap(d, NULL, "sb", "");
  picture p;
  snprintf(path, sizeof path, "%s/sb_dt.png", d);
  load(path, &p);
  size_t dark = 0, all = 0;
  for (unsigned y = 0; y + 110 < p.h; y++)
    for (unsigned x = 0; x < p.w; x++, all++) {
      const unsigned char *c = at(&p, x, y); /* viridis's darkest three bands: (68, 1, 84) to (62, 73, 137) */
      dark += c[2] > c[0] && c[2] > c[1] && c[0] < 90 && c[1] < 110 && c[2] > 70;
    }
  free(p.px);
  if (dark < all / 10) fprintf(stderr, "%zu of %zu pixels in the darkest colours\n", dark, all);
  assert_true(dark >= all / 10);
}

/* ---- the plate with a hole (2D): what its pictures show, by pixel ---- */

/* The camera's contract (src/gmsh/frame.c): a box of the model's plane
 * (x0..x1, y0..y1) is fitted, centred, into the band between the text (80
 * pixels at the top) and the colour scales (110 at the bottom), 12 pixels
 * from the sides, the same scale along x and y; the 2D worst picture's box
 * is the worst elements' grown by 0.2 of its largest side on each side. */
typedef struct {
  double lo[2], hi[2]; /* the framed box, m */
} frame2d;

static void project(const frame2d *f, const picture *p, const double *x, double *px, double *py) {
  double dx = f->hi[0] - f->lo[0], dy = f->hi[1] - f->lo[1];
  double k = fmin((p->w - 2.0 * 12) / dx, (p->h - 80.0 - 110) / dy); /* pixels per metre */
  *px = 0.5 * p->w + k * (x[0] - 0.5 * (f->lo[0] + f->hi[0]));
  *py = 0.5 * (80.0 + p->h - 110) - k * (x[1] - 0.5 * (f->lo[1] + f->hi[1]));
}

/* Centroid (mean of the nodes) of element tag, and its nodes into box f. */
static void element_nodes(size_t tag, double c[3], frame2d *f) {
  int type = 0, ierr = 0;
  size_t *nodes = NULL, nn = 0;
  gmshModelMeshGetElement(tag, &type, &nodes, &nn, &ierr);
  assert_int_equal(ierr, 0);
  c[0] = c[1] = c[2] = 0;
  for (size_t k = 0; k < nn; k++) {
    double *x = NULL, *u = NULL;
    size_t nx = 0, nu = 0;
    gmshModelMeshGetNode(nodes[k], &x, &nx, &u, &nu, &ierr);
    assert_int_equal(ierr, 0);
    for (int d = 0; d < 3; d++) c[d] += x[d] / (double)nn;
    for (int d = 0; f && d < 2; d++) f->lo[d] = fmin(f->lo[d], x[d]), f->hi[d] = fmax(f->hi[d], x[d]);
    gmshFree(x), gmshFree(u);
  }
  gmshFree(nodes);
}

/* The box of the elements of view name, and (when not NULL) the centroids
 * of its elements with the smallest and the largest value. */
static void view_box(const char *name, frame2d *f, double cmin[3], double cmax[3], double *vmin, double *vmax) {
  tu_view v;
  double c[3];
  size_t lo = 0, hi = 0;
  assert_int_equal(tu_view_read(name, &v), 0);
  f->lo[0] = f->lo[1] = INFINITY, f->hi[0] = f->hi[1] = -INFINITY;
  for (size_t i = 0; i < v.n; i++) {
    element_nodes(v.tags[i], c, f);
    if (v.values[i] < v.values[lo]) lo = i;
    if (v.values[i] > v.values[hi]) hi = i;
  }
  if (cmin) element_nodes(v.tags[lo], cmin, NULL), element_nodes(v.tags[hi], cmax, NULL);
  if (vmin) *vmin = v.values[lo], *vmax = v.values[hi];
  tu_view_free(&v);
}

/* The pixel at a point of the model is coloured (a colour of the map, not
 * the white background). */
static void check_drawn(const picture *p, const frame2d *f, const double *x, const char *what) {
  double px, py;
  project(f, p, x, &px, &py);
  assert_true(px >= 0 && py >= 0 && px < p->w && py < p->h);
  const unsigned char *c = at(p, (unsigned)px, (unsigned)py);
  if (!coloured(c))
    fprintf(stderr, "%s at (%.4g, %.4g) m: pixel (%.1f, %.1f) is (%u, %u, %u)\n", what, x[0], x[1], px, py, c[0], c[1],
            c[2]);
  assert_true(coloured(c));
}

/* A colour bar: in the bottom 110 rows, a row with at least a quarter of
 * the picture's width coloured. */
static int has_colour_bar(const picture *p) {
  for (unsigned y = p->h - 110; y < p->h; y++) {
    unsigned n = 0;
    for (unsigned x = 0; x < p->w; x++) n += coloured(at(p, x, y));
    if (n >= p->w / 4) return 1;
  }
  return 0;
}

/* Gmsh's bounds of the first and the last of the 12 discrete intervals of
 * a log scale over [lo, hi] (PViewOptions::getScaleValue): a value below
 * the first or above the last is not drawn. */
static double first_bound(double lo) { return pow(10., log10(lo)); }
static double last_bound(double lo, double hi) { return pow(10., log10(lo) + 12 * (log10(hi) - log10(lo)) / 12); }

/* The bundled plate with a hole, its density 2602 kg/m^3 instead of 2700:
 * then Gmsh's rounding of the interval bounds (above) leaves out both the
 * element with the smallest step and the one with the largest, which a
 * default range drew white (checked below, so that the test keeps its
 * meaning if the mesh changes). Those elements are drawn in PREFIX_dt.png,
 * which
 * has its colour bar; PREFIX_worst.png differs from it, frames the worst
 * elements (the below-target view's), shows the smallest step's element,
 * and has its colour bar; no X error on the standard error. */
static void test_plate_extremes_drawn(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  char path[600], *out = NULL;
  int r = tu_run(&out,
                 "cd %s && cp %s/geometries/plate_with_hole.geo . && sed 's/rho=\"2700\"/rho=\"2602\"/' "
                 "%s/geometries/plate_with_hole.xml > ph.xml && %s run ph.xml -q -o ph.msh && env -u DISPLAY %s "
                 "snapshot ph.msh",
                 d, tu_src(), tu_src(), tu_cli(), tu_cli());
  if (r || strstr(out, "X_ChangeProperty")) fprintf(stderr, "%s\n", out);
  assert_int_equal(r, 0);
  assert_null(strstr(out, "X_"));
  assert_non_null(strstr(out, "wrote        ")); /* the only line: no stderr noise */
  assert_null(strchr(strchr(out, '\n') + 1, '\n'));
  free(out);
  tu_gmsh_begin();
  int ierr = 0;
  snprintf(path, sizeof path, "%s/ph.msh", d);
  gmshOpen(path, &ierr);
  assert_int_equal(ierr, 0);
  frame2d whole, worst;
  double cmin[3], cmax[3], vmin, vmax;
  view_box("dt", &whole, cmin, cmax, &vmin, &vmax);
  view_box("below target [s]", &worst, NULL, NULL, NULL, NULL);
  tu_gmsh_end();
  double side = fmax(worst.hi[0] - worst.lo[0], worst.hi[1] - worst.lo[1]);
  for (int k = 0; k < 2; k++) worst.lo[k] -= 0.2 * side, worst.hi[k] += 0.2 * side;
  assert_true(vmax > 2 * vmin); /* a graded mesh: a real range */
  if (!(first_bound(vmin) > vmin && last_bound(vmin, vmax) < vmax))
    fprintf(stderr, "the steps %.17g to %.17g are no longer left out by Gmsh's rounding: choose another density\n",
            vmin, vmax);
  assert_true(first_bound(vmin) > vmin && last_bound(vmin, vmax) < vmax);
  picture dt, wp;
  snprintf(path, sizeof path, "%s/ph_dt.png", d);
  load(path, &dt);
  snprintf(path, sizeof path, "%s/ph_worst.png", d);
  load(path, &wp);
  check_drawn(&dt, &whole, cmin, "smallest step's element (dt)");
  check_drawn(&dt, &whole, cmax, "largest step's element (dt)");
  check_drawn(&wp, &worst, cmin, "smallest step's element (worst)");
  assert_true(has_colour_bar(&dt));
  assert_true(has_colour_bar(&wp));
  assert_true(memcmp(dt.px, wp.px, (size_t)dt.w * dt.h * 3) != 0);
  free(dt.px), free(wp.px);
}

/* A 3D result without sections (the bundled box): its dt picture has its
 * colour bar (the .opt hides dt's, a faint skin in 3D). */
static void test_solid_dt_has_colour_bar(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  char path[600];
  run_and_snap(d, "box", "bx", "--width 600 --height 450");
  picture p;
  snprintf(path, sizeof path, "%s/bx_dt.png", d);
  load(path, &p);
  assert_true(has_colour_bar(&p));
  free(p.px);
}

/* A mesh without dtmap's views: exit 2, saying so, and no picture. */
static void test_snapshot_plain_mesh(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  char *out = NULL, path[600];
  int r = tu_run(&out,
                 "cd %s && cp %s/geometries/plate_with_hole.geo . && gmsh plate_with_hole.geo -2 -o plain.msh "
                 ">/dev/null && env -u DISPLAY %s snapshot plain.msh",
                 d, tu_src(), tu_cli());
  if (r != 2) fprintf(stderr, "%s\n", out);
  assert_int_equal(r, 2);
  assert_non_null(strstr(out, "plain.msh: no view named 'dt'"));
  free(out);
  snprintf(path, sizeof path, "%s/plain_dt.png", d);
  assert_false(tu_exists(path));
  snprintf(path, sizeof path, "%s/plain_worst.png", d);
  assert_false(tu_exists(path));
}

/* A file that is not a result is bad input: exit 2, no picture. */
static void test_snapshot_bad_input(void **state) {
  (void)state;
  const char *d = tu_tmpdir();
  assert_int_equal(tu_run(NULL, "cd %s && %s snapshot missing.msh --png bad -q", d, tu_cli()), 2);
  char path[600];
  snprintf(path, sizeof path, "%s/bad_dt.png", d);
  assert_false(tu_exists(path));
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_snapshot_without_display),
      cmocka_unit_test(test_snapshot_bad_input),
      cmocka_unit_test(test_block_framed),
      cmocka_unit_test(test_shells_seen_obliquely),
      cmocka_unit_test(test_plate_extremes_drawn),
      cmocka_unit_test(test_solid_dt_has_colour_bar),
      cmocka_unit_test(test_snapshot_plain_mesh),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
