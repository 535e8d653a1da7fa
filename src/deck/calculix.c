/* The CalculiX 2.20 deck (ccx, Abaqus-style input; its manual's chapters
 * 6 and 7 and its sources). Elements: C3D4, C3D10 (with the scene's elastic
 * effect set to integration="calculix", so that the step is the one of
 * CalculiX's 4-point C3D10 and its lumping, docs/curved.md), C3D8 (full
 * integration, as dtmap's hex8), CPE3/CPE4/CPE6/CPE8 and CPS*, M3D3/M3D4,
 * S3/S4, B31, and trusses as SPRINGA springs of stiffness E A / L with
 * their mass rho A L / 2 in MASS elements at their nodes: exactly dtmap's
 * truss (CalculiX's T3D2 becomes a hinged brick whose rigid-body MPCs
 * explicit dynamics refuses beside the linear ones that tie it to other
 * elements). CalculiX has no genuine 2D element, nor beam: it extrudes each
 * into a layer of solids (gen3delem.f) of the section's thickness (plane,
 * membrane, shell) or sides (the beam's rectangle), so
 * - plane strain is exact (the layer's nodes are tied to the midplane);
 * - plane stress leaves the layer's thickness strain free, and at the top
 *   frequencies the layer cannot follow it: the elements stiffen towards
 *   plane strain, so the deck's step is dtmap's plane-stress step times
 *   sqrt(M_ps / M_pe) = sqrt(1 - 2 nu) / (1 - nu) (M the P-wave moduli);
 * - a membrane, shell, beam or plane stress layer has thickness modes of
 *   its own, about t / c_d across the thickness t: the deck's step is
 *   capped at a share of the element bound of those solids measured per
 *   CalculiX element (caps[] below); a plane stress element thicker than
 *   its longest side is left to the factor above (measured on the plate
 *   with a hole, 1 m thick), the caps' runs reaching t / h = 0.6;
 * - the header's estimate builds shells and membranes along the normals
 *   CalculiX gives their corners (shell_normals below);
 * - beams on shell nodes get nodes of their own (beam_twins below).
 * The step is the increment of *DYNAMIC, EXPLICIT (ALPHA=0: central
 * differences, as dtmap's step assumes) and its maximum. What CalculiX 2.20
 * does with it (nonlingeo.c): it takes the smaller of its own estimate and
 * the maximum increment, so a packaged ccx runs at its own estimate; a
 * minimum increment above its estimate would switch on selective mass
 * scaling instead (the deck leaves it at 1e-30). A ccx built with
 * bench/ccx_fixed_inc.sh runs at CCX_FIXED_INC. With --selective-mass the
 * minimum increment is the target, and ccx scales selectively (sms.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deck-impl.h"
#include "dtmap/scene.h"

static const double PI = 3.14159265358979323846;
static const int c3d10[] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8}; /* Gmsh's last two mid-edge nodes swap */

static const deck_elem_row rows[] = {
    {DTM_SECTION_SOLID, DTM_TET4, "C3D4", 0, NULL},         {DTM_SECTION_SOLID, DTM_TET10, "C3D10", 0, c3d10},
    {DTM_SECTION_SOLID, DTM_HEX8, "C3D8", 0, NULL},         {DTM_SECTION_PLANE_STRAIN, DTM_TRI3, "CPE3", 0, NULL},
    {DTM_SECTION_PLANE_STRAIN, DTM_QUAD4, "CPE4", 0, NULL}, {DTM_SECTION_PLANE_STRAIN, DTM_TRI6, "CPE6", 0, NULL},
    {DTM_SECTION_PLANE_STRAIN, DTM_QUAD8, "CPE8", 0, NULL}, {DTM_SECTION_PLANE_STRESS, DTM_TRI3, "CPS3", 0, NULL},
    {DTM_SECTION_PLANE_STRESS, DTM_QUAD4, "CPS4", 0, NULL}, {DTM_SECTION_PLANE_STRESS, DTM_TRI6, "CPS6", 0, NULL},
    {DTM_SECTION_PLANE_STRESS, DTM_QUAD8, "CPS8", 0, NULL}, {DTM_SECTION_MEMBRANE, DTM_TRI3, "M3D3", 0, NULL},
    {DTM_SECTION_MEMBRANE, DTM_QUAD4, "M3D4", 0, NULL},     {DTM_SECTION_SHELL, DTM_TRI3, "S3", 0, NULL},
    {DTM_SECTION_SHELL, DTM_QUAD4, "S4", 0, NULL},          {DTM_SECTION_TRUSS, DTM_LINE2, "SPRINGA", 0, NULL},
    {DTM_SECTION_BEAM, DTM_LINE2, "B31", 0, NULL}};

/* A beam section's rectangle: sides a (along the section's y) and b (z)
 * with its second moments (exact for a rectangle), or the square of its
 * area for a circle (CalculiX's B31 takes no circle). */
static int is_circle(const dtm_section *s) {
  return fabs(s->iy - s->iz) <= 1e-12 * s->iy && fabs(s->iy - s->area * s->area / (4 * PI)) <= 1e-9 * s->iy;
}

static void beam_sides(const dtm_section *s, double *a, double *b) {
  if (is_circle(s)) {
    *a = *b = sqrt(s->area);
    return;
  }
  *a = sqrt(12 * s->iz / s->area), *b = sqrt(12 * s->iy / s->area);
}

/* The sides of the solid a beam becomes, or the thickness of a 2D part. */
static void layer(const deck_ctx *c, const deck_part *p, double *t, double *a, double *b) {
  *t = p->thickness, *a = *b = 0.0;
  if (p->kind == DTM_SECTION_BEAM) beam_sides(&c->s->sections[p->section], a, b);
}

/* Parts CalculiX extrudes into a layer with a thickness mode of its own
 * (plane stress too: its layer's thickness strain is free). */
static int layered(const deck_part *p) {
  return p->kind == DTM_SECTION_MEMBRANE || p->kind == DTM_SECTION_SHELL || p->kind == DTM_SECTION_BEAM ||
         p->kind == DTM_SECTION_PLANE_STRESS;
}

/* The share of the element bound of a layer's solids (below) the deck's
 * step takes before the safety factor, per CalculiX element, and the
 * fixed-increment runs it rests on (bench/ccx_shell_caps.py, docs/deck.md:
 * meshes of that element alone, flat and curved, triangles, quadrangles
 * and both, h = 20 mm, t = 0.2 (shells, membranes), 1, 4 and 12 mm; beams
 * straight and curved, two sections; 400 increments): CalculiX's limit as
 * a share of that bound, its lowest bracket and the range. The ties of the layer to its midsurface are not a
 * subspace of the solids' motion, so the element bound is no bound there;
 * S4 and B31 become incompatible-mode bricks (C3D8I, whose internal modes
 * CalculiX gives a mass of their own), far below it. */
static const struct {
  const char *elem;
  double share;     /* 0.95 x the lowest limit measured, rounded down */
  const char *seen; /* the limits measured, as a share of the element bound */
} caps[] = {
    {"S3", 0.76, "0.809 - 0.817 (t = 0.2 mm) to 1.19 (12 mm)"},
    {"S4", 0.30, "0.317 - 0.325 (t = 0.2 and 1 mm) to 0.51 (12 mm)"},
    {"M3D3", 0.76, "0.809 - 0.817 (t = 0.2 mm) to 1.19 (12 mm)"},
    {"M3D4", 0.76, "0.809 - 0.817 (t = 0.2 mm) to 1.27 (12 mm)"},
    {"B31", 0.31, "0.333 - 0.341 (10 x 30 mm) to 0.356 (20 x 20 mm)"},
    {"CPS3", 0.94, "0.997 - 1.005 (t = 1 mm) to 1.39 (12 mm)"},
    {"CPS4", 0.94, "0.997 - 1.005 (t = 1 mm) to 1.41 (12 mm)"},
};

/* The row of caps[] of part p's element (-1: not capped). */
static int cap_row(const deck_part *p) {
  for (int i = 0; layered(p) && i < (int)(sizeof caps / sizeof *caps); i++)
    if (!strcmp(caps[i].elem, p->elem)) return i;
  return -1;
}

/* The share the deck takes for part p (INFINITY: not capped). */
static double measured(const deck_part *p) {
  int i = cap_row(p);
  return i < 0 ? INFINITY : caps[i].share;
}

static int element(deck_ctx *c, deck_part *p) {
  DTM_CHECK(deck_element_from(c, p, rows, sizeof rows / sizeof *rows));
  char lbl[160];
  double t, a, b;
  int line = p->kind == DTM_SECTION_BEAM;
  layer(c, p, &t, &a, &b);
  if (p->kind == DTM_SECTION_BEAM && is_circle(&c->s->sections[p->section]))
    deck_warn(c,
              "%s: CalculiX's B31 takes no circular section; the deck gives them the square of the same area "
              "(bending stiffness x pi/3 = 1.047)",
              deck_part_label(c, p, lbl, sizeof lbl));
  int i = cap_row(p);
  if (i >= 0)
    deck_warn(c,
              "%s: CalculiX expands %s into a layer of solids %.4g m across, whose thickness modes cap the "
              "step at %.2f x their element bound; the limit of a fixed-increment CalculiX on meshes of %s alone "
              "was measured at %s of that bound (bench/ccx_shell_caps.py, docs/deck.md)",
              deck_part_label(c, p, lbl, sizeof lbl), p->elem, line ? fmin(a, b) : t, caps[i].share, p->elem,
              caps[i].seen);
  return DTM_OK;
}

/* c_d of part p's material, m/s. */
static double speed(const deck_ctx *c, const deck_part *p) {
  double E, nu, rho;
  deck_elastic(c, p->mat, &E, &nu, &rho);
  return deck_speed_3d(E, nu, rho);
}

/* The unit normal of the 2D element x (nc corners) at corner a: the cross
 * product of its two sides there (norshell3.f, norshell4.f), into n[3]. */
static void corner_normal(const double *x, int nc, int a, double *n) {
  const double *p = x + 3 * a, *q = x + 3 * ((a + 1) % nc), *r = x + 3 * ((a + nc - 1) % nc);
  double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
  n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
  double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int k = 0; k < 3; k++) n[k] /= l;
}

#define SHELL_COS 0.939693 /* gen3dnor.f: shell normals within 20 degrees share a node's expansion */
#define NODE_DATA 8        /* per node: reference normal, sum of normals, reference tag, thickness */

/* Visit the corners of every shell element (part k, element e of block b,
 * its coordinates x, its corner a at node v, normal n) in one of two
 * passes: 0 keeps at each node the normal of its shell element of the
 * lowest tag (gen3dnor.f's reference), 1 adds the normals within 20
 * degrees of it and of the same thickness. */
static void shell_corner(deck_ctx *c, int pass, const deck_part *p, size_t tag, size_t v, const double *n) {
  double *d = c->node_data + NODE_DATA * v;
  if (pass == 0 && (d[6] == 0 || (double)tag < d[6])) {
    memcpy(d, n, 3 * sizeof *n);
    d[6] = (double)tag, d[7] = p->thickness;
  }
  if (pass == 1 && n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > SHELL_COS && fabs(p->thickness - d[7]) < 1e-10)
    for (int k = 0; k < 3; k++) d[3 + k] += n[k];
}

/* The normals along which CalculiX 2.20 expands each shell node
 * (gen3dnor.f): the sum of the unit normals of the shell elements there
 * within 20 degrees of the reference (the element of the lowest number),
 * made unit. Membranes keep each element's own normal. Shells whose
 * normals differ more get expansions of their own in CalculiX; the deck
 * takes their own normal there. */
static int shell_normals(deck_ctx *c) {
  double x[3 * DTM_MAX_NODES], n[3];
  int shells = 0;
  for (int k = 0; k < c->nparts; k++) shells |= c->parts[k].kind == DTM_SECTION_SHELL;
  if (!shells) return DTM_OK;
  if (!(c->node_data = calloc(NODE_DATA * (c->m->nnodes + 1), sizeof *c->node_data)))
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int pass = 0; pass < 2; pass++)
    for (int k = 0; k < c->nparts; k++) {
      const deck_part *p = &c->parts[k];
      size_t off;
      const dtm_block *b = deck_part_block(c, p, &off);
      if (p->kind != DTM_SECTION_SHELL) continue;
      for (size_t j = c->first[k]; j < c->first[k + 1]; j++) {
        size_t e = c->order[j] - off;
        dtm_mesh_gather_one(c->m, b, e, x);
        for (int a = 0; a < b->nn; a++) {
          corner_normal(x, b->nn, a, n);
          shell_corner(c, pass, p, b->tags[e], b->conn[e * b->nn + a], n);
        }
      }
    }
  for (size_t v = 0; v < c->m->nnodes; v++) {
    double *d = c->node_data + NODE_DATA * v, l = sqrt(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
    for (int k = 3; l > 0 && k < 6; k++) d[k] /= l;
  }
  return DTM_OK;
}

/* The corner normals n[nn][3] of the layer CalculiX builds from element e
 * of block b (coordinates x) in part p. */
static void layer_normals(const deck_ctx *c, const dtm_block *b, size_t e, const deck_part *p, const double *x,
                          double *n) {
  for (int a = 0; a < b->nn; a++) {
    const double *d = c->node_data ? c->node_data + NODE_DATA * b->conn[e * b->nn + a] : NULL;
    corner_normal(x, b->nn, a, n + 3 * a);
    if (p->kind == DTM_SECTION_SHELL && d && d[6] > 0 &&
        n[3 * a] * d[0] + n[3 * a + 1] * d[1] + n[3 * a + 2] * d[2] > SHELL_COS && fabs(p->thickness - d[7]) < 1e-10)
      memcpy(n + 3 * a, d + 3, 3 * sizeof *n);
  }
}

/* CalculiX's rule (rules.c); it passes over springs. Shells and membranes
 * on the layer CalculiX builds along its corner normals. */
static double own(const deck_ctx *c, const dtm_block *b, size_t e, size_t i, const deck_part *p) {
  double x[3 * DTM_MAX_NODES], n[3 * DTM_MAX_NODES], t, sa, sb, h;
  if (p->kind == DTM_SECTION_TRUSS) return INFINITY;
  dtm_mesh_gather_one(c->m, b, e, x);
  layer(c, p, &t, &sa, &sb);
  (void)i;
  if (p->kind == DTM_SECTION_SHELL || p->kind == DTM_SECTION_MEMBRANE) {
    layer_normals(c, b, e, p, x, n);
    h = deck_ccx_layer_length(b->type, x, n, t);
  } else {
    h = deck_ccx_length(b->type, x, t, sa, sb);
  }
  return 0.8 * 0.98 * h * deck_ccx_elemfac(p->elem) / speed(c, p);
}

/* Called for every part once the plan is made, before the step and the
 * own estimate: the shell normals are computed on the first call. */
static double factor(deck_ctx *c, const deck_part *p) {
  if (!c->node_data && shell_normals(c)) return dtm_error_clear(), 1.0; /* own() then takes each element's normal */
  if (p->kind != DTM_SECTION_PLANE_STRESS) return 1.0;
  double E, nu, rho, f;
  deck_elastic(c, p->mat, &E, &nu, &rho);
  f = sqrt(1 - 2 * nu) / (1 - nu);
  char lbl[160];
  deck_warn(c,
            "%s: CalculiX's plane stress layer stiffens towards plane strain at the top frequencies; the step is "
            "dtmap's plane-stress step x sqrt(1 - 2 nu) / (1 - nu) = %.4f",
            deck_part_label(c, p, lbl, sizeof lbl), f);
  return f;
}

/* Unit vector of a (returns its length). */
static double unit(double *a) {
  double n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  for (int k = 0; k < 3; k++) a[k] /= n;
  return n;
}

/* The 2D element of nc corners x extruded by t along its normal into
 * y[2 nc][3] (prism6 or hex8, Gmsh's order: the -t/2 face first). */
static int extrude(const double *x, int nc, double t, double *y) {
  double u[3], v[3], n[3];
  for (int k = 0; k < 3; k++) u[k] = x[6 + k] - x[k], v[k] = x[3 * (nc - 1) + k] - x[3 + k];
  n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
  unit(n);
  for (int a = 0; a < nc; a++)
    for (int k = 0; k < 3; k++)
      y[3 * a + k] = x[3 * a + k] - n[k] * t / 2, y[3 * (a + nc) + k] = x[3 * a + k] + n[k] * t / 2;
  return nc == 3 ? DTM_PRISM6 : DTM_HEX8;
}

/* The beam x[2][3] as a brick of sides a (along its section's y, the
 * orientation vector o made normal to the axis) and b, into y[8][3]. */
static int brick(const double *x, const double *o, double a, double b, double *y) {
  static const int s[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  double e1[3], e2[3], e3[3];
  for (int k = 0; k < 3; k++) e1[k] = x[3 + k] - x[k];
  unit(e1);
  double d = o[0] * e1[0] + o[1] * e1[1] + o[2] * e1[2];
  for (int k = 0; k < 3; k++) e2[k] = o[k] - d * e1[k];
  unit(e2);
  e3[0] = e1[1] * e2[2] - e1[2] * e2[1], e3[1] = e1[2] * e2[0] - e1[0] * e2[2], e3[2] = e1[0] * e2[1] - e1[1] * e2[0];
  for (int end = 0; end < 2; end++)
    for (int q = 0; q < 4; q++)
      for (int k = 0; k < 3; k++)
        y[3 * (4 * end + q) + k] = x[3 * end + k] + s[q][0] * a / 2 * e2[k] + s[q][1] * b / 2 * e3[k];
  return DTM_HEX8;
}

/* The longest side of the polygon x of nc corners, m. */
static double longest(const double *x, int nc) {
  double mx = 0;
  for (int a = 0; a < nc; a++) {
    const double *p = x + 3 * a, *q = x + 3 * ((a + 1) % nc);
    mx = fmax(mx, sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2])));
  }
  return mx;
}

/* The element bound of the solid CalculiX builds from element e of a
 * layered part, by dtmap's prism6 and hex8 kernels (full integration, row
 * sums), s (INFINITY for the other parts). */
static double bound(const deck_ctx *c, const dtm_block *b, size_t e, const deck_part *p) {
  double x[3 * DTM_MAX_NODES], y[24], t, sa, sb, E, nu, rho, lambda, v[3];
  dtm_elastic_moduli mod;
  if (cap_row(p) < 0) return INFINITY;
  dtm_mesh_gather_one(c->m, b, e, x);
  layer(c, p, &t, &sa, &sb);
  if (p->kind == DTM_SECTION_PLANE_STRESS && t > longest(x, b->type == DTM_TRI3 ? 3 : 4)) return INFINITY;
  deck_elastic(c, p->mat, &E, &nu, &rho);
  if (p->kind == DTM_SECTION_BEAM) deck_beam_axis(&c->s->sections[p->section], x, v);
  int type = p->kind == DTM_SECTION_BEAM ? brick(x, v, sa, sb, y) : extrude(x, b->type == DTM_TRI3 ? 3 : 4, t, y);
  if (dtm_elastic_moduli_init(DTM_FORM_3D, E, nu, rho, &mod) || dtm_kernel_elastic_lambda(type, &mod, y, &lambda))
    return dtm_error_clear(), INFINITY;
  return 2 / sqrt(lambda);
}

/* The step that solid allows: the measured share of its element bound. */
static double cap(const deck_ctx *c, const dtm_block *b, size_t e, const deck_part *p) {
  return measured(p) * bound(c, b, e, p);
}

/* The smallest element bound of part k's solids, s. */
static double part_bound(const deck_ctx *c, int k) {
  size_t off;
  const deck_part *p = &c->parts[k];
  const dtm_block *b = deck_part_block(c, p, &off);
  double mn = INFINITY;
  for (size_t j = c->first[k]; j < c->first[k + 1]; j++) mn = fmin(mn, bound(c, b, c->order[j] - off, p));
  return mn;
}

/* One line per layered part: the smallest element bound of its solids and
 * the cap it gives (bench/ccx_shell_caps.py reads the bound). */
static void layer_lines(deck_ctx *c) {
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    if (cap_row(p) < 0) continue;
    double bd = part_bound(c, k);
    if (!isfinite(bd)) continue; /* plane stress thicker than its elements: the factor alone */
    fprintf(c->f, "** layer %s (%s): element bound of its solids %.10g s; cap %.2f x it = %.10g s\n", p->set, p->elem,
            bd, measured(p), measured(p) * bd);
  }
}

/* integration="calculix" on the elastic effect: CalculiX's C3D10. */
static int adapt(dtm_scene *s, char *note, size_t len) {
  for (int k = 0; k < s->neffects; k++) {
    dtm_scene_effect *ef = &s->effects[k];
    if (strcmp(ef->name, "elastic")) continue;
    const char *was = dtm_scene_effect_attr(ef, "integration");
    if (was && !strcmp(was, "calculix")) return DTM_OK;
    DTM_CHECK(dtm_scene_effect_set(ef, "integration", "calculix"));
    snprintf(note, len,
             "the elastic effect is analysed with integration=\"calculix\" (was \"%s\"): CalculiX's "
             "C3D10 integration and lumping",
             was ? was : "converged");
  }
  return DTM_OK;
}

static void section_beam(deck_ctx *c, const deck_part *p) {
  double a, b, v[3];
  char name[DECK_NAME_MAX];
  beam_sides(&c->s->sections[p->section], &a, &b);
  deck_beam_orientation(c, p, v);
  deck_safe_name(c->s->materials[p->mat].m.name, p->mat + 1, name);
  fprintf(c->f, "*BEAM SECTION, ELSET=%s, MATERIAL=%s, SECTION=RECT\n", p->set, name);
  deck_inp_reals(c, 2, (double[]){a, b});
  deck_inp_reals(c, 3, v);
}

/* Length of element e of block b (a line), m. */
static double length(const deck_ctx *c, const dtm_block *b, size_t e) {
  const double *p = c->m->xyz + 3 * b->conn[2 * e], *q = c->m->xyz + 3 * b->conn[2 * e + 1];
  return sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]));
}

/* k with a decimal point ("1e+09" -> "1.e+09", "12" -> "12."). */
static void with_point(char *k) {
  if (strchr(k, '.')) return;
  size_t at = strcspn(k, "eE");
  memmove(k + at + 1, k + at, strlen(k + at) + 1);
  k[at] = '.';
}

/* A truss part as springs: each element its own set and *SPRING, E A / L
 * written with a decimal point (CalculiX tells stiffness from degrees of
 * freedom by it). */
static void springs(deck_ctx *c, const deck_part *p) {
  size_t off;
  const dtm_block *b = deck_part_block(c, p, &off);
  double E, nu, rho;
  char k[48];
  deck_elastic(c, p->mat, &E, &nu, &rho);
  for (size_t j = c->first[p - c->parts]; j < c->first[p - c->parts + 1]; j++) {
    size_t e = c->order[j] - off;
    deck_number(E * p->thickness / length(c, b, e), 20, k);
    with_point(k);
    fprintf(c->f, "*ELSET, ELSET=DTMAP_SPRING%zu\n%zu\n*SPRING, ELSET=DTMAP_SPRING%zu\n\n%s\n", b->tags[e], b->tags[e],
            b->tags[e], k);
  }
}

static int own_card(deck_ctx *c, const deck_part *p, int *done) {
  *done = p->kind == DTM_SECTION_BEAM || p->kind == DTM_SECTION_TRUSS;
  if (p->kind == DTM_SECTION_BEAM) section_beam(c, p);
  if (p->kind == DTM_SECTION_TRUSS) springs(c, p);
  return DTM_OK;
}

/* The trusses' lumped masses rho A L / 2 at their nodes, [nnodes] kg
 * (NULL when there are none, or out of memory: *r). */
static double *truss_masses(deck_ctx *c, int *r) {
  double *m = NULL;
  *r = DTM_OK;
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    if (p->kind != DTM_SECTION_TRUSS) continue;
    if (!m && !(m = calloc(c->m->nnodes + 1, sizeof *m))) return *r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory"), NULL;
    size_t off;
    const dtm_block *b = deck_part_block(c, p, &off);
    double E, nu, rho;
    deck_elastic(c, p->mat, &E, &nu, &rho);
    for (size_t j = c->first[k]; j < c->first[k + 1]; j++) {
      size_t e = c->order[j] - off;
      double half = rho * p->thickness * length(c, b, e) / 2;
      m[b->conn[2 * e]] += half, m[b->conn[2 * e + 1]] += half;
    }
  }
  return m;
}

/* Rayleigh damping: CalculiX takes one global *DAMPING, and in explicit
 * dynamics (without massless contact) only its mass part. */
static void damping(deck_ctx *c) {
  double alpha = -1, a, b, xi;
  int uniform = 1;
  for (int k = 0; k < c->nparts; k++) {
    deck_damping(c, c->parts[k].mat, &a, &b, &xi);
    if (b > 0 || (alpha >= 0 && a != alpha)) uniform = 0;
    alpha = a;
  }
  if (uniform && alpha > 0) fprintf(c->f, "*DAMPING, ALPHA=%.14g, BETA=0\n", alpha);
  if (!uniform)
    deck_warn(c, "the scene's Rayleigh damping (a stiffness part beta, or values differing by material) has no "
                 "CalculiX explicit equivalent: it takes one mass-proportional *DAMPING for the model; not written");
}

/* Beams on the nodes of shells or membranes get nodes of their own.
 * CalculiX 2.20 joins the two expansions at a shared node by a KNOT (a
 * rigid body with a rotation node, gen3dnor.f), and in explicit dynamics
 * that model diverged: panel_quad_shell_beam (a curved quad/tri shell with
 * a ring beam on its edge) goes to NaN in Debian's ccx at its own estimate
 * and at 1e-8 s (1/13 of it, 400 increments), whatever the beam's
 * orientation, the divergence starting at the model's highest-numbered
 * nodes (it follows them when the nodes are renumbered), not at the beam;
 * the same deck with the beams on nodes of their own tied by *EQUATION
 * runs (docs/deck.md). Each beam through a shell node gets a node of its
 * own there: two beams meeting at an angle on one node (a stiffener cross,
 * an L-frame) would make CalculiX join them by a KNOT, a nonlinear MPC,
 * on a node the linear *EQUATION ties to the shell, which ccx refuses at
 * once ("nonlinear MPCs depend on each other"). A beam is the elements of
 * one part at the node whose axes are parallel (a straight beam through
 * the node keeps one node there). twin[2 i + a]: the tag of beam element
 * i's node a (above every tag), 0 for its own; twin_node[t]: the mesh node
 * twin tag top + 1 + t is tied to. */
typedef struct {
  size_t v;    /* the shell node */
  size_t i;    /* the beam element (global index) */
  int a, part; /* its local node there, its part */
  double t[3]; /* its unit axis */
} beam_end;

static int by_node(const void *pa, const void *pb) {
  const beam_end *x = pa, *y = pb;
  if (x->v != y->v) return x->v < y->v ? -1 : 1;
  if (x->i != y->i) return x->i < y->i ? -1 : 1;
  return (x->a > y->a) - (x->a < y->a);
}

#define BEAM_PARALLEL 0.9998 /* |cos| of the angle between two elements of one beam (1.1 degrees) */

/* The ends of beam elements on the nodes flat[] marks, into *out (*n of them). */
static int beam_ends(deck_ctx *c, const char *flat, beam_end **out, size_t *n) {
  size_t cap = 0;
  *n = 0, *out = NULL;
  for (int k = 0; k < c->nparts; k++)
    if (c->parts[k].kind == DTM_SECTION_BEAM) cap += 2 * (c->first[k + 1] - c->first[k]);
  if (!cap || !(*out = malloc(cap * sizeof **out))) return cap ? DTM_ERR(DTM_ERR_INTERNAL, "out of memory") : DTM_OK;
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    size_t off;
    const dtm_block *b = deck_part_block(c, p, &off);
    if (p->kind != DTM_SECTION_BEAM) continue;
    for (size_t j = c->first[k]; j < c->first[k + 1]; j++) {
      const size_t *conn = b->conn + (c->order[j] - off) * b->nn;
      for (int a = 0; a < 2; a++) {
        if (!flat[conn[a]]) continue;
        beam_end *e = &(*out)[(*n)++];
        const double *x = c->m->xyz + 3 * conn[a], *y = c->m->xyz + 3 * conn[1 - a];
        double len =
            sqrt((y[0] - x[0]) * (y[0] - x[0]) + (y[1] - x[1]) * (y[1] - x[1]) + (y[2] - x[2]) * (y[2] - x[2]));
        *e = (beam_end){conn[a], c->order[j], a, k, {0, 0, 0}};
        for (int d = 0; d < 3 && len > 0; d++) e->t[d] = (y[d] - x[d]) / len;
      }
    }
  }
  qsort(*out, *n, sizeof **out, by_node);
  return DTM_OK;
}

/* The twin of end e among those of its node before it, ends[lo, e): one of
 * the same part along the same axis, else 0. */
static size_t same_beam(const deck_ctx *c, const beam_end *ends, size_t lo, size_t e) {
  for (size_t f = lo; f < e; f++) {
    const double *s = ends[f].t, *t = ends[e].t;
    if (ends[f].part == ends[e].part && fabs(s[0] * t[0] + s[1] * t[1] + s[2] * t[2]) >= BEAM_PARALLEL)
      return c->twin[2 * ends[f].i + (size_t)ends[f].a];
  }
  return 0;
}

/* The nodes the 2D parts use, into flat[nnodes]; the largest node tag. */
static size_t flat_nodes(deck_ctx *c, char *flat) {
  size_t top = 0;
  for (size_t v = 0; v < c->m->nnodes; v++) top = c->m->node_tags[v] > top ? c->m->node_tags[v] : top;
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    size_t off;
    const dtm_block *b = deck_part_block(c, p, &off);
    if (p->kind != DTM_SECTION_SHELL && p->kind != DTM_SECTION_MEMBRANE) continue;
    for (size_t j = c->first[k]; j < c->first[k + 1]; j++)
      for (int a = 0; a < b->nn; a++) flat[b->conn[(c->order[j] - off) * b->nn + a]] = 1;
  }
  return top;
}

static int beam_twins(deck_ctx *c, size_t *count) {
  char *flat = calloc(c->m->nnodes + 1, 1);
  beam_end *ends = NULL;
  size_t n = 0;
  *count = 0;
  if (!flat) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t top = flat_nodes(c, flat);
  int r = beam_ends(c, flat, &ends, &n);
  free(flat);
  if (r || !n) return free(ends), r;
  c->twin = calloc(2 * dtm_analysis_nelements(c->a) + 1, sizeof *c->twin);
  c->twin_node = malloc(n * sizeof *c->twin_node);
  if (!c->twin || !c->twin_node) return free(ends), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t lo = 0, e = 0; e < n; e++) {
    if (ends[e].v != ends[lo].v) lo = e;
    size_t tag = same_beam(c, ends, lo, e);
    if (!tag) c->twin_node[*count] = ends[e].v, tag = top + ++*count;
    c->twin[2 * ends[e].i + (size_t)ends[e].a] = tag;
  }
  c->top_tag = top, c->ntwins = *count;
  free(ends);
  return DTM_OK;
}

/* The beams' own nodes (continuing the *NODE block). */
static void twin_nodes(deck_ctx *c) {
  for (size_t t = 0; t < c->ntwins; t++) {
    fprintf(c->f, "%zu, ", c->top_tag + 1 + t);
    deck_inp_reals(c, 3, c->m->xyz + 3 * c->twin_node[t]);
  }
}

/* Each beam node tied to its shell node: the three translations equal. */
static void twin_equations(deck_ctx *c) {
  for (size_t t = 0; t < c->ntwins; t++)
    for (int d = 1; d <= 3; d++)
      fprintf(c->f, "*EQUATION\n2\n%zu, %d, 1., %zu, %d, -1.\n", c->top_tag + 1 + t, d,
              c->m->node_tags[c->twin_node[t]], d);
}

static int write(deck_ctx *c) {
  FILE *f = c->f;
  size_t twins;
  DTM_CHECK(beam_twins(c, &twins));
  if (twins)
    deck_warn(c,
              "%zu beam nodes are shell or membrane nodes: the beams get nodes of their own (numbered above the "
              "mesh's; two beams crossing or cornering on one node, one each), each tied to its shell node by "
              "*EQUATION on the three translations, so their rotations are "
              "free of the shell's (hinged); CalculiX 2.20's KNOT at a shared node diverged in explicit dynamics "
              "(docs/deck.md). Loads go on the shell nodes (the node sets name them)",
              twins);
  deck_header(c, "**");
  if (!c->info->selective)
    fprintf(f,
            "** CalculiX 2.20 takes the smaller of its own estimate and the maximum increment (this step); a\n"
            "** ccx built with bench/ccx_fixed_inc.sh runs at CCX_FIXED_INC=%.10g. A minimum increment above\n"
            "** its estimate would switch on its selective mass scaling instead.\n",
            c->info->step);
  layer_lines(c);
  fprintf(f, "*HEADING\ndtmap deck of %s\n", c->s->path);
  DTM_CHECK(deck_inp_nodes(c));
  twin_nodes(c);
  DTM_CHECK(deck_inp_elements(c));
  DTM_CHECK(deck_inp_sets(c));
  if (c->info->selective) deck_sms_elset(c);
  DTM_CHECK(deck_inp_materials(c, 0));
  DTM_CHECK(deck_inp_sections(c, own_card));
  int r;
  double *tm = truss_masses(c, &r);
  if (r == DTM_OK) r = deck_inp_masses(c, tm);
  free(tm);
  DTM_CHECK(r);
  damping(c);
  twin_equations(c);
  deck_inp_slot(c, "model", "boundary and initial conditions, contact (model data)");
  fputs("*STEP, INC=1000000000\n*DYNAMIC, EXPLICIT, ALPHA=0\n", f);
  /* with --selective-mass the minimum increment is the target: ccx scales to reach it */
  double least = c->info->selective ? c->info->step : 1e-30;
  deck_inp_reals(c, 4, (double[]){c->info->step, c->info->duration, least, c->info->step});
  deck_inp_slot(c, "step", "loads and output requests (step data)");
  fputs("*END STEP\n", f);
  return DTM_OK;
}

const deck_writer dtm_deck_calculix = {
    "calculix", "CalculiX 2.20",
    ".inp",     "0.8 x 0.98 x min over faces (volume weight / face area) x elemfac / c_d",
    element,    own,
    factor,     cap,
    adapt,      write};
