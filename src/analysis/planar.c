/* Plane problems must be plane. A plane-strain or plane-stress model (the
 * elastic formulation of a 2D mesh, or a plane section) describes slices,
 * each in its own plane. Surfaces that all share one normal (a stack of
 * slices at several heights) are such a problem even when they do not lie
 * in one plane: every element acts in its own plane, which is the same
 * plane up to a shift along the normal, and two elements sharing a node
 * with the same normal lie in the same plane. The global operator treats
 * them as elements of lower dimension in 3D space (the in-plane
 * projector is the same for all, so the displacements along the normal
 * carry no stiffness and couple nothing), the element and nodal bounds
 * work in each element's own frame: the figures are those of the same
 * slices moved into one plane. Surfaces that are tilted or curved (a
 * tower's walls, a curved panel) are shells or membranes, and analysing
 * them as a plane problem gives numbers that mean nothing. Before any step
 * is computed, the nodes of every surface element that a central-difference
 * effect with an operator (elasticity) treats as a plane problem are
 * measured against the plane through the element's first node normal to
 * the largest such element; beyond 1e-9 of the model's size the run is
 * refused, naming the distance, the element where it is largest and its
 * group, and the remedies that keep the formulation. Otherwise the number
 * of distinct parallel planes is kept for the summary. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "dtmap/units.h"

/* Whether element e of b is a plane-problem element: a surface of a 2D
 * model without a membrane or shell section. */
static int plane_element(const dtm_analysis *a, const dtm_block *b, size_t e) {
  if (b->dim != 2 || a->mesh->dim != 2) return 0;
  const dtm_section *s = dtm_analysis_section(a, b, e);
  return !s || (s->kind != DTM_SECTION_MEMBRANE && s->kind != DTM_SECTION_SHELL);
}

/* The elastic effect with an operator, -1 when none. */
static int elastic_effect(const dtm_analysis *a) {
  for (int k = 0; k < a->neffects; k++)
    if (dtm_effect_is_wave(a->effects[k].cls) && a->effects[k].cls->coefficients) return k;
  return -1;
}

/* Area vector (twice the area times the unit normal) of the polygon of
 * the first corners of element e of b (3 for triangles, 4 for quads). */
static void area_vector(const dtm_mesh *m, const dtm_block *b, size_t e, double n[3]) {
  int nc = b->type == DTM_TRI3 || b->type == DTM_TRI6 ? 3 : 4;
  n[0] = n[1] = n[2] = 0;
  for (int i = 0; i < nc; i++) {
    const double *p = m->xyz + 3 * b->conn[e * (size_t)b->nn + (size_t)i];
    const double *q = m->xyz + 3 * b->conn[e * (size_t)b->nn + (size_t)((i + 1) % nc)];
    n[0] += (p[1] - q[1]) * (p[2] + q[2]), n[1] += (p[2] - q[2]) * (p[0] + q[0]), n[2] += (p[0] - q[0]) * (p[1] + q[1]);
  }
}

typedef struct {
  double n[3];  /* unit normal of the largest plane-problem element */
  double ref;   /* n . x of its first node, m */
  double lo[3]; /* bounding box of the plane-problem elements' nodes, m */
  double hi[3];
  double spread; /* largest distance of a node from that element's plane, m */
  double off;    /* largest distance of a node from its own element's plane normal to n, m */
  int block;     /* where it is largest */
  size_t elem;
  double *level; /* [nplane] each element's plane, n . x of its first node, m */
  size_t nplane; /* plane-problem elements */
} plane_fit;

static double along(const plane_fit *f, const double *x) { return x[0] * f->n[0] + x[1] * f->n[1] + x[2] * f->n[2]; }

static void find_normal(const dtm_analysis *a, plane_fit *f) {
  double best = 0;
  for (int b = 0; b < a->mesh->nblocks; b++)
    for (size_t e = 0; e < a->mesh->blocks[b].n; e++) {
      const dtm_block *blk = &a->mesh->blocks[b];
      double n[3];
      if (!plane_element(a, blk, e)) continue;
      area_vector(a->mesh, blk, e, n);
      double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(len > best)) continue;
      best = len;
      for (int i = 0; i < 3; i++) f->n[i] = n[i] / len;
      f->ref = along(f, a->mesh->xyz + 3 * blk->conn[e * (size_t)blk->nn]);
    }
}

/* Element e of blk: its plane's level, its nodes' largest distance from it. */
static void measure_one(const dtm_analysis *a, const dtm_block *blk, int b, size_t e, plane_fit *f) {
  const double *x0 = a->mesh->xyz + 3 * blk->conn[e * (size_t)blk->nn];
  f->level[f->nplane++] = along(f, x0);
  for (int k = 0; k < blk->nn; k++) {
    const double *x = a->mesh->xyz + 3 * blk->conn[e * (size_t)blk->nn + (size_t)k];
    double d = fabs(along(f, x) - along(f, x0));
    f->spread = fmax(f->spread, fabs(along(f, x) - f->ref));
    for (int i = 0; i < 3; i++) f->lo[i] = fmin(f->lo[i], x[i]), f->hi[i] = fmax(f->hi[i], x[i]);
    if (d > f->off) f->off = d, f->block = b, f->elem = e;
  }
}

static void measure(const dtm_analysis *a, plane_fit *f) {
  for (int i = 0; i < 3; i++) f->lo[i] = INFINITY, f->hi[i] = -INFINITY;
  f->off = f->spread = 0, f->block = -1, f->nplane = 0;
  for (int b = 0; b < a->mesh->nblocks; b++)
    for (size_t e = 0; e < a->mesh->blocks[b].n; e++)
      if (plane_element(a, &a->mesh->blocks[b], e)) measure_one(a, &a->mesh->blocks[b], b, e, f);
}

static int by_value(const void *x, const void *y) {
  double u = *(const double *)x, v = *(const double *)y;
  return (u > v) - (u < v);
}

/* The distinct planes among the elements' levels (within tol). */
static int count_planes(plane_fit *f, double tol) {
  qsort(f->level, f->nplane, sizeof *f->level, by_value);
  int n = f->nplane > 0;
  for (size_t i = 1; i < f->nplane; i++) n += f->level[i] - f->level[i - 1] > tol;
  return n;
}

/* The formulation the refused element is analysed in: its plane section's,
 * else effect k's formulation attribute (a 2D model's default: plane strain). */
static const char *formulation(const dtm_analysis *a, const plane_fit *f, int k) {
  const dtm_section *s = dtm_analysis_section(a, &a->mesh->blocks[f->block], f->elem);
  if (s) return dtm_section_kind_name(s->kind);
  const char *v = dtm_scene_effect_attr(&a->scene->effects[k], "formulation");
  return v ? v : "plane-strain";
}

static int refuse(const dtm_analysis *a, const plane_fit *f, double size, int k) {
  char place[256];
  dtm_mesh_element_place(a->mesh, f->block, f->elem, place, sizeof place);
  const char *form = formulation(a, f, k);
  int strain = !strcmp(form, "plane-strain");
  const char *L = dtm_units_name(a->scene->units, DTM_UNIT_LENGTH);
  return DTM_ERR(
      DTM_ERR_INPUT,
      "%s: the surfaces are not plane and parallel: nodes lie up to %.4g %s out of one plane (over a model "
      "of %.4g %s), and %s is tilted from it (its nodes lie up to %.4g %s off the plane through it normal to "
      "(%.3g, %.3g, %.3g), the largest element's normal), so this is no %s problem (plane surfaces that "
      "share one normal are analysed each in its own plane). %s",
      a->scene->path, f->spread, L, size, L, place, f->off, L, f->n[0], f->n[1], f->n[2], form,
      strain ? "Plane strain describes a thick body: mesh it as a volume (dim=\"3\"), or make the surfaces "
               "plane and parallel; a membrane section (kind=\"membrane\") would make it plane stress in "
               "each element's own plane, a shell (kind=\"shell\") adds bending and transverse shear"
             : "Keep plane stress in each element's own plane with <section groups=\"...\" "
               "kind=\"membrane\" thickness=\"...\"/>, or analyse them as shells (kind=\"shell\": membrane, "
               "bending and transverse shear)");
}

int dtm_analysis_check_planar(dtm_analysis *a) {
  int k = elastic_effect(a);
  a->planes = 0;
  if (a->mesh->dim != 2 || k < 0) return DTM_OK;
  plane_fit f = {{0, 0, 1}, 0, {0}, {0}, 0, 0, -1, 0, NULL, 0};
  f.level = malloc((dtm_mesh_nelements(a->mesh) + 1) * sizeof *f.level);
  if (!f.level) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  find_normal(a, &f);
  measure(a, &f);
  double size = fmax(f.hi[0] - f.lo[0], fmax(f.hi[1] - f.lo[1], f.hi[2] - f.lo[2]));
  int r = f.block >= 0 && f.off > 1e-9 * size ? refuse(a, &f, size, k) : DTM_OK;
  if (r == DTM_OK) a->planes = count_planes(&f, 1e-9 * size);
  free(f.level);
  return r;
}
