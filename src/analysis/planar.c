/* Plane problems must be plane. A plane-strain or plane-stress model (the
 * elastic formulation of a 2D mesh, or a plane section) describes a slice
 * in its own plane; surfaces that are not plane (a tower's walls, a curved
 * panel) are shells or membranes, and analysing them as a plane problem
 * gives numbers that mean nothing. Before any step is computed, the nodes
 * of every surface element that a central-difference effect with an
 * operator (elasticity) treats as a plane problem are measured against the
 * plane of the largest of those elements; beyond 1e-9 of the model's size
 * the run is refused, naming the out-of-plane extent, the element where it
 * is largest and its group, and the membrane section as the way out. */
#include <math.h>
#include <stdio.h>

#include "analysis-impl.h"

/* Whether element e of b is a plane-problem element: a surface of a 2D
 * model without a membrane or shell section. */
static int plane_element(const dtm_analysis *a, const dtm_block *b, size_t e) {
  if (b->dim != 2 || a->mesh->dim != 2) return 0;
  const dtm_section *s = dtm_analysis_section(a, b, e);
  return !s || (s->kind != DTM_SECTION_MEMBRANE && s->kind != DTM_SECTION_SHELL);
}

static int has_elastic(const dtm_analysis *a) {
  for (int k = 0; k < a->neffects; k++)
    if (dtm_effect_is_wave(a->effects[k].cls) && a->effects[k].cls->coefficients) return 1;
  return 0;
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
  double n[3], p[3]; /* unit normal and a point of the reference plane */
  double lo[3], hi[3];
  double off; /* largest distance from the plane, m */
  int block;  /* where it is largest */
  size_t elem;
} plane_fit;

static void find_plane(const dtm_analysis *a, plane_fit *f) {
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
      for (int i = 0; i < 3; i++) f->n[i] = n[i] / len, f->p[i] = a->mesh->xyz[3 * blk->conn[e * (size_t)blk->nn] + i];
    }
}

static void measure(const dtm_analysis *a, plane_fit *f) {
  for (int i = 0; i < 3; i++) f->lo[i] = INFINITY, f->hi[i] = -INFINITY;
  f->off = 0, f->block = -1;
  for (int b = 0; b < a->mesh->nblocks; b++)
    for (size_t e = 0; e < a->mesh->blocks[b].n; e++) {
      const dtm_block *blk = &a->mesh->blocks[b];
      if (!plane_element(a, blk, e)) continue;
      for (int k = 0; k < blk->nn; k++) {
        const double *x = a->mesh->xyz + 3 * blk->conn[e * (size_t)blk->nn + (size_t)k];
        double d = fabs((x[0] - f->p[0]) * f->n[0] + (x[1] - f->p[1]) * f->n[1] + (x[2] - f->p[2]) * f->n[2]);
        for (int i = 0; i < 3; i++) f->lo[i] = fmin(f->lo[i], x[i]), f->hi[i] = fmax(f->hi[i], x[i]);
        if (d > f->off) f->off = d, f->block = b, f->elem = e;
      }
    }
}

int dtm_analysis_check_planar(const dtm_analysis *a) {
  if (a->mesh->dim != 2 || !has_elastic(a)) return DTM_OK;
  plane_fit f = {{0, 0, 1}, {0, 0, 0}, {0}, {0}, 0, -1, 0};
  find_plane(a, &f);
  measure(a, &f);
  double size = fmax(f.hi[0] - f.lo[0], fmax(f.hi[1] - f.lo[1], f.hi[2] - f.lo[2]));
  if (f.block < 0 || !(f.off > 1e-9 * size)) return DTM_OK;
  char place[256];
  dtm_mesh_element_place(a->mesh, f.block, f.elem, place, sizeof place);
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: the surfaces are not plane: nodes lie up to %.4g m out of one plane (over a model of %.4g m; "
                 "largest at %s), so this is no plane-strain or plane-stress problem. Analyse the surfaces as "
                 "shells or membranes in 3D with <section groups=\"...\" kind=\"shell\" thickness=\"...\"/> (membrane, "
                 "bending and transverse shear) or kind=\"membrane\" (plane stress in each element's own plane)",
                 a->scene->path, f.off, size, place);
}
