/* Below the target: size-limited or shape-limited. With a target, every
 * element whose own safe step (safety included) is below it is counted; for
 * each, the question is whether a larger element there would lift its
 * step. The element's step is compared with that of the well-shaped
 * (regular) element of its size, its quality q, and with the typical
 * quality of the mesh, q_typ (the median over a sample of its elements: a
 * fresh mesh is made of such elements, not of regular ones). The model
 * feature it sits on is read from the Gmsh classification of its nodes:
 *  - a near-flat angle (>= 150 deg) between model curves (2D, at a model
 *    point) or surfaces (3D, along a model curve) that this one element
 *    holds: a remesh at any size puts the angle in one element again;
 *  - a small angle (< 30 deg) there: every element at it is a needle;
 *  - a model curve through two of its corners that is shorter than the size
 *    a typical element needs for the target, or two boundaries that do not
 *    touch, closer than that (a thin feature): the size cannot grow.
 * At an angle the shape stays (when it is what limits: q < 0.6 q_typ) and
 * only the size can grow, up to the shortest model curve at the feature; at
 * a short or thin feature the shape can improve (to q_typ) but the size
 * cannot exceed the curve or the gap. Either size is taken times the
 * spread of a fresh Gmsh mesh (its worst elements are about 0.78 (3D), 0.8
 * (2D) of its nominal size, dtm_analysis_mesh_spread). When the step that
 * allows stays below the target the element is shape-limited, with its
 * cheapest remedy: splitting a near-flat 2D angle by local refinement, an
 * optimiser pass for a flat 3D dihedral or a small angle split finer than
 * the geometry forces, else the mass its nodes need (the cost module
 * computes it). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "dtmap/topology.h"
#include "reference.h"

#define FLAT_DEG 150.0   /* an element angle at least this is near-flat */
#define SMALL_DEG 30.0   /* a model angle below this is small */
#define POOR_QUALITY 0.6 /* below this x q_typ the shape, not the size, sets the step */
#define SAMPLE 401       /* elements sampled for the typical quality */
#define RAD2DEG 57.295779513082323

int dtm_analysis_step_at(const dtm_analysis *a, size_t i, int type, const double *x, double *dt) {
  int b;
  size_t l;
  dtm_analysis_locate(a, i, &b, &l);
  const dtm_block *blk = &a->mesh->blocks[b];
  const dtm_material *mat = &a->scene->materials[blk->mat[l]].m;
  const dtm_section *sec = dtm_analysis_section(a, blk, l);
  dtm_batch bt = {type, blk->dim, blk->nn, 1, x, blk->tags + l, blk->group + l, blk->gmask ? blk->gmask + l : NULL,
                  &mat, &sec,     NULL};
  *dt = INFINITY;
  for (int k = 0; k < a->neffects; k++) {
    const dtm_effect *ef = &a->effects[k];
    double dk, len, f = 1.0;
    if (!a->dt_effect[k]) continue;
    DTM_CHECK(ef->cls->element_dt(ef->state, &bt, &dk, &len));
    if (dtm_analysis_is_wave(a, k) && isfinite(dk)) DTM_CHECK(dtm_analysis_wave_factor(a, blk->mat[l], 2.0 / dk, &f));
    *dt = fmin(*dt, dk * f);
  }
  return DTM_OK;
}

/* A line element's well-shaped version of length h: its own direction
 * (a beam's bending axes hang on it), from its first node. */
static void own_segment(const dtm_analysis *a, const dtm_block *blk, size_t l, double h, double *x) {
  dtm_mesh_gather_one(a->mesh, blk, l, x);
  double d[3], n = 0;
  for (int k = 0; k < 3; k++) d[k] = x[3 + k] - x[k], n += d[k] * d[k];
  n = sqrt(n);
  for (int k = 0; k < 3; k++) x[3 + k] = x[k] + (n > 0 ? h * d[k] / n : (k == 0) * h);
}

/* Element i's steps over that of the well-shaped element of its size: its
 * element step (*q) and its own safe step (*r, the ratio decisions use). */
static int quality(const dtm_analysis *a, size_t i, double *q, double *r) {
  int b;
  size_t l;
  double x[DTM_MAX_NODES * 3], well;
  dtm_analysis_locate(a, i, &b, &l);
  if (a->mesh->blocks[b].type == DTM_LINE2)
    own_segment(a, &a->mesh->blocks[b], l, a->h[i], x);
  else
    DTM_CHECK(dtm_elem_regular(a->mesh->blocks[b].type, a->h[i], x));
  DTM_CHECK(dtm_analysis_step_at(a, i, a->mesh->blocks[b].type, x, &well));
  int ok = well > 0 && isfinite(well);
  *q = ok ? a->dt[i] / well : 1.0;
  *r = ok ? a->local[i] / well : 1.0;
  return DTM_OK;
}

double dtm_analysis_mesh_spread(int dim) { return dim == 3 ? 0.78 : dim == 2 ? 0.8 : 1.0; }

static int cmp_double(const void *x, const void *y) {
  double u = *(const double *)x, v = *(const double *)y;
  return u < v ? -1 : u > v;
}

/* Median of the own-step ratio r over a strided sample of the elements
 * (those some effect limits). */
static int typical_quality(const dtm_analysis *a, double *r_typ) {
  size_t n = a->nel < SAMPLE ? a->nel : SAMPLE, stride = a->nel / n, k = 0;
  double r[SAMPLE], q;
  for (size_t j = 0; j < n; j++)
    if (isfinite(a->local[j * stride])) DTM_CHECK(quality(a, j * stride, &q, &r[k++]));
  qsort(r, k, sizeof r[0], cmp_double);
  *r_typ = k ? r[k / 2] : 1.0;
  return DTM_OK;
}

/* Elements around each node (CSR over all nodes). */
typedef struct {
  size_t *start; /* [nnodes + 1] */
  size_t *list;  /* [start[nnodes]] global element indices */
} incidence;

/* Pass 0 counts the elements of each node into start[v + 2]; pass 1,
 * after the prefix sums, files them (start[v + 1] runs over v's range).
 * Only the nodes marked in only (NULL: all) get their elements. */
static void scatter(const dtm_analysis *a, incidence *inc, int fill, const unsigned char *only) {
  const dtm_mesh *m = a->mesh;
  for (int b = 0; b < m->nblocks; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++)
      for (int c = 0; c < m->blocks[b].nn; c++) {
        size_t v = m->blocks[b].conn[e * m->blocks[b].nn + c];
        if (only && !only[v]) continue;
        if (fill)
          inc->list[inc->start[v + 1]++] = a->offset[b] + e;
        else
          inc->start[v + 2]++;
      }
}

static int build_incidence_of(const dtm_analysis *a, incidence *inc, const unsigned char *only) {
  const dtm_mesh *m = a->mesh;
  inc->start = calloc(m->nnodes + 2, sizeof *inc->start);
  if (!inc->start) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  scatter(a, inc, 0, only);
  for (size_t v = 0; v < m->nnodes; v++) inc->start[v + 2] += inc->start[v + 1];
  inc->list = malloc((inc->start[m->nnodes + 1] + 1) * sizeof *inc->list);
  if (!inc->list) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  scatter(a, inc, 1, only);
  return DTM_OK;
}

static int build_incidence(const dtm_analysis *a, incidence *inc) { return build_incidence_of(a, inc, NULL); }

/* The corners of element i: type of the linear parent's count, node
 * indices and coordinates. */
typedef struct {
  int type, nc;       /* element type, corner count */
  size_t v[8];        /* corner node indices */
  const double *x[8]; /* their coordinates */
} corners;

/* Corners of a type from its dimension and edge count: a polygon has as
 * many as edges; tet 6 edges -> 4, pyramid 8 -> 5, prism 9 -> 6, hex 12 -> 8. */
static int corner_count(int dim, int nedges) {
  if (dim < 2) return 2;
  if (dim == 2) return nedges;
  return nedges == 6 ? 4 : nedges == 8 ? 5 : nedges == 9 ? 6 : 8;
}

static void get_corners(const dtm_analysis *a, size_t i, corners *c) {
  int b;
  size_t l;
  dtm_analysis_locate(a, i, &b, &l);
  const dtm_block *blk = &a->mesh->blocks[b];
  const int(*edges)[2];
  c->type = blk->type;
  c->nc = corner_count(blk->dim, dtm_elem_edges(blk->type, &edges));
  for (int k = 0; k < c->nc && k < 8; k++) c->v[k] = blk->conn[l * blk->nn + k], c->x[k] = a->mesh->xyz + 3 * c->v[k];
}

static double angle_between(const double *o, const double *p, const double *q) {
  double u[3], w[3], uu = 0, ww = 0, uw = 0;
  for (int d = 0; d < 3; d++) u[d] = p[d] - o[d], w[d] = q[d] - o[d], uu += u[d] * u[d], ww += w[d] * w[d];
  for (int d = 0; d < 3; d++) uw += u[d] * w[d];
  double cs = uw / sqrt(uu * ww);
  return acos(cs > 1 ? 1 : cs < -1 ? -1 : cs) * RAD2DEG;
}

/* 2D: the angle of corner k (its neighbours in the cyclic corner order). */
static double corner_angle(const corners *c, int k) {
  return angle_between(c->x[k], c->x[(k + 1) % c->nc], c->x[(k + c->nc - 1) % c->nc]);
}

/* 3D tetrahedron: the dihedral angle along edge (j, k): between the
 * directions to the two other corners, projected normal to the edge. */
static double dihedral(const corners *c, int j, int k) {
  int o[2], n = 0;
  double e[3], ee = 0, u[2][3];
  for (int m = 0; m < 4; m++)
    if (m != j && m != k) o[n++] = m;
  for (int d = 0; d < 3; d++) e[d] = c->x[k][d] - c->x[j][d], ee += e[d] * e[d];
  for (int s = 0; s < 2; s++) {
    double t = 0;
    for (int d = 0; d < 3; d++) u[s][d] = c->x[o[s]][d] - c->x[j][d], t += u[s][d] * e[d];
    for (int d = 0; d < 3; d++) u[s][d] -= t / ee * e[d];
  }
  const double zero[3] = {0, 0, 0};
  return angle_between(zero, u[0], u[1]);
}

static int corner_of(const corners *c, size_t v) {
  for (int k = 0; k < c->nc; k++)
    if (c->v[k] == v) return k;
  return -1;
}

/* What one element sits on. */
typedef struct {
  int kind;       /* dtm_feature_kind, 0: none */
  double angle;   /* model angle, degrees */
  double own;     /* the element's own angle there, degrees */
  int dim, tag;   /* entity of the feature */
  double size;    /* the largest size the feature allows, m */
  int odim, otag; /* thin: the other of the two boundaries (-1 otherwise) */
} feature;

/* Shortest model curve through model point p (2D), +inf if none. */
static double shortest_curve_at(const dtm_geo *g, int p) {
  double best = INFINITY;
  for (int e = 0; e < g->nent; e++) {
    const dtm_geo_entity *en = &g->ent[e];
    if (en->dim != 1 || !(en->size > 0)) continue;
    for (int k = 0; k < en->npoints; k++)
      if (en->points[k] == p) best = fmin(best, en->size);
  }
  return best;
}

#define NO_NODE ((size_t)-1)

/* The model's angle, summed over the elements of i's entity around node v:
 * 2D (w = NO_NODE) the corner angles at v; 3D the dihedral angles of the
 * tetrahedra along the edge (v, w). */
static double model_angle(const dtm_analysis *a, const incidence *inc, size_t i, size_t v, size_t w) {
  double sum = 0;
  for (size_t j = inc->start[v]; j < inc->start[v + 1]; j++) {
    size_t o = inc->list[j];
    corners c;
    if (a->geo->elem_entity[o] != a->geo->elem_entity[i]) continue;
    get_corners(a, o, &c);
    if (c.nc < 3) continue; /* a truss on the entity's edge (entity tags of other dimensions may coincide) */
    int p = corner_of(&c, v), q = w == NO_NODE ? -1 : corner_of(&c, w);
    if (p >= 0 && w == NO_NODE) sum += corner_angle(&c, p);
    if (p >= 0 && q >= 0 && c.nc == 4) sum += dihedral(&c, p, q);
  }
  return sum;
}

static void set_angle(feature *f, double model, double own, int dim, int tag, double size) {
  int kind = own >= FLAT_DEG ? DTM_FEATURE_FLAT_ANGLE : model < SMALL_DEG ? DTM_FEATURE_SMALL_ANGLE : 0;
  if (!kind || f->kind == DTM_FEATURE_FLAT_ANGLE) return;
  *f = (feature){kind, model, own, dim, tag, size, -1, -1};
}

/* Angles at the model points among the corners of a 2D element. */
static void angles_2d(const dtm_analysis *a, const incidence *inc, size_t i, const corners *c, feature *f) {
  for (int k = 0; k < c->nc; k++) {
    size_t v = c->v[k];
    if (a->geo->node_dim[v] != 0) continue;
    int p = a->geo->node_tag[v];
    set_angle(f, model_angle(a, inc, i, v, NO_NODE), corner_angle(c, k), 0, p, shortest_curve_at(a->geo, p));
  }
}

/* The model curve through corners v and w (3D edge on a curve), or NULL. */
static const dtm_geo_entity *curve_of_edge(const dtm_geo *g, size_t v, size_t w) {
  size_t on = g->node_dim[v] == 1 ? v : g->node_dim[w] == 1 ? w : (size_t)-1;
  if (on == (size_t)-1) return NULL;
  const dtm_geo_entity *cv = dtm_geo_find(g, 1, g->node_tag[on]);
  return cv && dtm_geo_node_on(g, v, cv) && dtm_geo_node_on(g, w, cv) ? cv : NULL;
}

/* Dihedral angles along the edges of a tetrahedron that lie on model curves. */
static void angles_3d(const dtm_analysis *a, const incidence *inc, size_t i, const corners *c, feature *f) {
  for (int j = 0; j < 4 && c->nc == 4; j++)
    for (int k = j + 1; k < 4; k++) {
      const dtm_geo_entity *cv = curve_of_edge(a->geo, c->v[j], c->v[k]);
      if (cv) set_angle(f, model_angle(a, inc, i, c->v[j], c->v[k]), dihedral(c, j, k), 1, cv->tag, cv->size);
    }
}

/* The shortest model curve touching the element (a corner on it or on one
 * of its points) whose length, times the spread of a fresh mesh, is below
 * need: the size the element needs with its shape. */
static void short_curves(const dtm_geo *g, const corners *c, double need, double spread, feature *f) {
  for (int e = 0; e < g->nent; e++) {
    const dtm_geo_entity *en = &g->ent[e];
    int on = 0;
    if (en->dim != 1 || !(en->size > 0) || !(spread * en->size < need) || en->size >= f->size) continue;
    for (int k = 0; k < c->nc; k++) on += dtm_geo_node_on(g, c->v[k], en);
    if (on) *f = (feature){DTM_FEATURE_SHORT_CURVE, NAN, NAN, 1, en->tag, en->size, -1, -1};
  }
}

#define THIN_TIE 1e-9 /* two gaps this close (relative) are one: rounding, not geometry */

/* Whether the gap t between boundaries (dv, tv) and (dw, tw) replaces f's:
 * a smaller one, or, at the same gap up to rounding, the pair of higher
 * dimension (a layer is the pair of surfaces it lies between; a node on
 * their curves is on them too), then the smaller tags. So the pair chosen
 * does not hang on the last bit of the coordinates, which the unit system
 * changes (tests/t381). */
static int thin_better(double t, int dv, int tv, int dw, int tw, const feature *f) {
  if (f->kind != DTM_FEATURE_THIN || t < f->size * (1 - THIN_TIE)) return t < f->size;
  if (t > f->size * (1 + THIN_TIE)) return 0;
  if (dv + dw != f->dim + f->odim) return dv + dw > f->dim + f->odim;
  int lo = tv < tw ? tv : tw, flo = f->tag < f->otag ? f->tag : f->otag;
  return lo != flo ? lo < flo : (tv > tw ? tv : tw) < (f->tag > f->otag ? f->tag : f->otag);
}

/* Two corners on boundaries that do not touch, closer than need. */
static void thin_parts(const dtm_analysis *a, const corners *c, double need, feature *f) {
  const dtm_geo *g = a->geo;
  for (int j = 0; j < c->nc; j++)
    for (int k = j + 1; k < c->nc; k++) {
      size_t v = c->v[j], w = c->v[k];
      if (g->node_dim[v] >= a->mesh->dim || g->node_dim[w] >= a->mesh->dim || dtm_geo_touch(g, v, w)) continue;
      double t = 0;
      for (int d = 0; d < 3; d++) t += (c->x[j][d] - c->x[k][d]) * (c->x[j][d] - c->x[k][d]);
      t = sqrt(t);
      if (t < need && thin_better(t, g->node_dim[v], g->node_tag[v], g->node_dim[w], g->node_tag[w], f))
        *f = (feature){DTM_FEATURE_THIN, NAN, NAN, g->node_dim[v], g->node_tag[v], t, g->node_dim[w], g->node_tag[w]};
    }
}

/* Step exponent of the effect that limits element i. */
static double exponent_of(const dtm_analysis *a, size_t i) {
  int k = a->limiting[i];
  return k >= 0 ? a->effects[k].cls->exponent : 1.0;
}

static double pow_p(double r, double p) { return p == 1.0 ? r : pow(r, p); }

/* What the classification of one mesh shares. */
typedef struct {
  incidence inc;       /* elements around each node */
  double q_typ;        /* typical own-step ratio of the mesh (median of r) */
  double spread;       /* worst / nominal size of a fresh mesh */
  unsigned char *near; /* [nnodes] 1 on the corners of elements with a boundary corner (NULL: not built) */
} judge_ctx;

/* The remedy of a shape-limited element with feature f, quality ratio
 * qr = q / q_typ, need factor F (target over its step). */
static void remedy(const dtm_analysis *a, size_t i, const feature *f, double qr, double F, dtm_shape_limited *s) {
  double p = exponent_of(a, i);
  s->remedy = DTM_REMEDY_MASS, s->split = NAN;
  if (f->kind == DTM_FEATURE_FLAT_ANGLE && a->mesh->dim == 3) s->remedy = DTM_REMEDY_OPTIMISE;
  if (f->kind == DTM_FEATURE_SMALL_ANGLE && f->own < 0.5 * f->angle) s->remedy = DTM_REMEDY_OPTIMISE;
  if (f->kind != DTM_FEATURE_FLAT_ANGLE || a->mesh->dim != 2) return;
  double split = a->h[i] * pow(F * qr, 1.0 / p); /* a typical element meeting the target */
  if (split <= f->size) s->remedy = DTM_REMEDY_SPLIT, s->split = split;
}

#define PATCH_MAX 256   /* boundary nodes of the patch around an element considered */
#define PATCH_ELEMS 128 /* elements of the patch kept for the inside test */

/* The patch around element i: the elements of its group that share a node
 * with it (a layer is a group: the neighbours across an interface are not
 * in it), into p->el, and their corners on a model entity below the mesh's
 * dimension (boundary nodes), into p->v. */
typedef struct {
  size_t v[PATCH_MAX], el[PATCH_ELEMS];
  int nv, nel;
} patch;

static void add_corners(const dtm_analysis *a, size_t o, patch *p) {
  corners d;
  get_corners(a, o, &d);
  if (p->nel < PATCH_ELEMS) p->el[p->nel++] = o;
  for (int j = 0; j < d.nc && p->nv < PATCH_MAX; j++) {
    int seen = a->geo->node_dim[d.v[j]] >= a->mesh->dim;
    for (int q = 0; q < p->nv && !seen; q++) seen = p->v[q] == d.v[j];
    if (!seen) p->v[p->nv++] = d.v[j];
  }
}

/* The elements already met around one element: an open-addressing set of
 * element index + 1 (0: empty), used while it is at most half full. */
#define SEEN_SLOTS 1024
typedef struct {
  size_t key[SEEN_SLOTS];
  int n;
} seen_set;

/* 1 when o was in s already (else it is added); -1 when s is full. */
static int seen_add(seen_set *s, size_t o) {
  if (2 * s->n >= SEEN_SLOTS) return -1;
  size_t h = (o * 0x9E3779B97F4A7C15u) >> 54; /* 10 bits */
  while (s->key[h] && s->key[h] != o + 1) h = (h + 1) & (SEEN_SLOTS - 1);
  if (s->key[h]) return 1;
  s->key[h] = o + 1, s->n++;
  return 0;
}

static void patch_of(const dtm_analysis *a, const judge_ctx *jc, size_t i, patch *p) {
  corners c;
  seen_set seen;
  int g = dtm_analysis_group(a, i);
  p->nv = p->nel = 0;
  memset(seen.key, 0, sizeof seen.key), seen.n = 0;
  get_corners(a, i, &c);
  for (int k = 0; k < c.nc; k++)
    for (size_t q = jc->inc.start[c.v[k]]; q < jc->inc.start[c.v[k] + 1]; q++) {
      size_t o = jc->inc.list[q];
      int dup = seen_add(&seen, o);
      for (int j = 0; j < p->nel && dup < 0; j++) dup = p->el[j] == o ? 1 : -1; /* full: as before */
      if (dup != 1 && dtm_analysis_group(a, o) == g) add_corners(a, o, p);
    }
}

static void sub3(const double *a, const double *b, double *c) {
  for (int d = 0; d < 3; d++) c[d] = a[d] - b[d];
}
static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double triple3(const double *a, const double *b, const double *c) {
  double t[3];
  cross3(b, c, t);
  return dot3(a, t);
}

/* Whether point x lies in the element with corners c (1e-9 of slack):
 * barycentric on triangles and tetrahedra, the corners' box otherwise. */
static int holds(const corners *c, const double x[3]) {
  double e[3][3], r[3], tol = 1e-9;
  for (int k = 0; k < 3 && k + 1 < c->nc; k++) sub3(c->x[k + 1], c->x[0], e[k]);
  sub3(x, c->x[0], r);
  if (c->nc == 3) { /* in the triangle's plane: the two sub-areas against the whole */
    double n[3], s[3], t[3], nn;
    cross3(e[0], e[1], n), nn = dot3(n, n);
    cross3(r, e[1], s), cross3(e[0], r, t);
    double u = dot3(s, n) / nn, v = dot3(t, n) / nn;
    return u >= -tol && v >= -tol && u + v <= 1 + tol;
  }
  if (c->nc == 4 && c->type != DTM_QUAD4 && c->type != DTM_QUAD8 && c->type != DTM_QUAD9) {
    double det = triple3(e[0], e[1], e[2]), u = triple3(r, e[1], e[2]) / det;
    double v = triple3(e[0], r, e[2]) / det, w = triple3(e[0], e[1], r) / det;
    return u >= -tol && v >= -tol && w >= -tol && u + v + w <= 1 + tol;
  }
  for (int d = 0; d < 3; d++) {
    double lo = INFINITY, hi = -INFINITY, span;
    for (int k = 0; k < c->nc; k++) lo = fmin(lo, c->x[k][d]), hi = fmax(hi, c->x[k][d]);
    span = tol * (hi - lo + 1e-300);
    if (x[d] < lo - span || x[d] > hi + span) return 0;
  }
  return 1;
}

/* Whether the segment between nodes v and w runs through the material of
 * the patch there (its midpoint lies in one of its elements): across a
 * layer, not across a gap between two faces (a notch, a slot). */
static int through_material(const dtm_analysis *a, const patch *p, size_t v, size_t w) {
  double m[3];
  for (int d = 0; d < 3; d++) m[d] = 0.5 * (a->mesh->xyz[3 * v + d] + a->mesh->xyz[3 * w + d]);
  for (int j = 0; j < p->nel; j++) {
    corners c;
    get_corners(a, p->el[j], &c);
    if (holds(&c, m)) return 1;
  }
  return 0;
}

/* The corners of every element that has a corner on a model entity below
 * the mesh's dimension (a boundary node, as the patch counts them): an
 * element none of whose corners is marked has no boundary node in its
 * patch, so nothing to measure across. NULL when out of memory (then every
 * patch is searched). */
static unsigned char *boundary_near(const dtm_analysis *a) {
  unsigned char *near = calloc(a->mesh->nnodes + 1, 1);
  for (size_t i = 0; near && i < a->nel; i++) {
    corners c;
    int any = 0;
    get_corners(a, i, &c);
    for (int k = 0; k < c.nc; k++) any |= a->geo->node_dim[c.v[k]] < a->mesh->dim;
    for (int k = 0; k < c.nc && any; k++) near[c.v[k]] = 1;
  }
  return near;
}

static int near_boundary(const dtm_analysis *a, const judge_ctx *jc, size_t i) {
  corners c;
  get_corners(a, i, &c);
  for (int k = 0; k < c.nc; k++)
    if (jc->near[c.v[k]]) return 1;
  return 0;
}

/* How thin the part is at element i: the smallest distance between two
 * boundary nodes of its patch on boundaries that do not touch, through its
 * material (a layer one or two elements across shows both of its faces
 * there), +inf when none; *dim, *tag get one of the two boundaries. */
static double across(const dtm_analysis *a, const judge_ctx *jc, size_t i, int *dim, int *tag, int *odim, int *otag) {
  const dtm_geo *g = a->geo;
  patch p;
  if (jc->near && !near_boundary(a, jc, i)) return INFINITY; /* its patch has no boundary node */
  patch_of(a, jc, i, &p);
  double best = INFINITY;
  for (int j = 0; j < p.nv; j++)
    for (int k = j + 1; k < p.nv; k++) {
      if (dtm_geo_touch(g, p.v[j], p.v[k])) continue;
      const double *x = a->mesh->xyz + 3 * p.v[j], *y = a->mesh->xyz + 3 * p.v[k];
      double t = sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) + (x[2] - y[2]) * (x[2] - y[2]));
      if (t < best && through_material(a, &p, p.v[j], p.v[k]))
        best = t, *dim = g->node_dim[p.v[j]], *tag = g->node_tag[p.v[j]], *odim = g->node_dim[p.v[k]],
        *otag = g->node_tag[p.v[k]];
    }
  return best;
}

/* The own safe step (safety included) a fresh mesh reaches across a layer
 * t thick at element i: the well-shaped element of i's type whose smallest
 * width is t, at the mesh's typical quality, times the spread of a fresh
 * mesh (its worst elements are that much below its nominal size). */
static int layer_reach(const dtm_analysis *a, const judge_ctx *jc, size_t i, double t, double *reach) {
  int b;
  size_t l;
  double x[DTM_MAX_NODES * 3], well;
  dtm_analysis_locate(a, i, &b, &l);
  int type = a->mesh->blocks[b].type;
  DTM_CHECK(dtm_elem_regular(type, 1.0, x));
  double width = dtm_kernel_length(type, DTM_LEN_MIN_ALTITUDE, x); /* of the unit element */
  DTM_CHECK(dtm_elem_regular(type, t / width, x));
  DTM_CHECK(dtm_analysis_step_at(a, i, type, x, &well));
  *reach = a->scene->safety * well * jc->q_typ * pow_p(jc->spread, exponent_of(a, i));
  return DTM_OK;
}

/* Element i spans a thin layer across which no fresh mesh reaches target:
 * *f gets the thin feature (its size the thickness) and *reach the best
 * step there. */
static int layer_limited(const dtm_analysis *a, const judge_ctx *jc, size_t i, double target, feature *f, double *reach,
                         int *limited) {
  int dim = -1, tag = -1, odim = -1, otag = -1;
  *limited = 0;
  double t = across(a, jc, i, &dim, &tag, &odim, &otag);
  if (!isfinite(t)) return DTM_OK;
  DTM_CHECK(layer_reach(a, jc, i, t, reach));
  if (!(*reach < target)) return DTM_OK;
  *f = (feature){DTM_FEATURE_THIN, NAN, NAN, dim, tag, t, odim, otag};
  *limited = 1;
  return DTM_OK;
}

/* The feature element i sits on, if any; need_own and need_typ are the
 * sizes it needs with its own shape and with the typical one. */
static void find_feature(const dtm_analysis *a, const judge_ctx *jc, size_t i, double qr, double need_own,
                         double need_typ, feature *f) {
  corners c;
  get_corners(a, i, &c);
  if (qr < POOR_QUALITY) (a->mesh->dim == 2 ? angles_2d : angles_3d)(a, &jc->inc, i, &c, f);
  if (!f->kind) short_curves(a->geo, &c, need_own, jc->spread, f);
  if (!f->kind) thin_parts(a, &c, need_typ, f);
}

/* Decide element i (below the target by the factor F). A layer's
 * thickness is judged first, by the best element that fits across it;
 * then the features of the element's own shape and size. */
static int judge(const dtm_analysis *a, const judge_ctx *jc, size_t i, double F, int *limited, dtm_shape_limited *s) {
  feature f = {0, NAN, NAN, -1, -1, INFINITY, -1, -1};
  double q = 1.0, rq = 1.0, p = exponent_of(a, i), reach = NAN;
  int b;
  size_t l;
  dtm_analysis_locate(a, i, &b, &l);
  *limited = 0;
  if (a->mesh->blocks[b].dim < a->mesh->dim) return DTM_OK; /* a truss or membrane: its own length or size sets it */
  DTM_CHECK(quality(a, i, &q, &rq));
  DTM_CHECK(layer_limited(a, jc, i, F * a->scene->safety * a->local[i], &f, &reach, limited));
  if (*limited) {
    *s = (dtm_shape_limited){i, f.kind, NAN, f.dim, f.tag, f.size, q, reach, 0, NAN, f.odim, f.otag, -1};
    remedy(a, i, &f, rq / jc->q_typ, F, s);
    return DTM_OK;
  }
  double qr = rq / jc->q_typ, need = a->h[i] * pow(F * qr, 1.0 / p);
  find_feature(a, jc, i, qr, a->h[i] * pow(F, 1.0 / p), need, &f);
  *limited = 0;
  if (!f.kind) return DTM_OK;
  int angle = f.kind <= DTM_FEATURE_SMALL_ANGLE;
  double grow = pow_p(fmax(jc->spread * f.size, a->h[i]) / a->h[i], p);
  if (f.kind == DTM_FEATURE_THIN) grow *= fmax(1.0, 1.0 / qr); /* across a gap the shape can improve */
  if (!(grow < F)) return DTM_OK;
  *limited = 1;
  *s = (dtm_shape_limited){i,
                           f.kind,
                           angle ? f.angle : NAN,
                           f.dim,
                           f.tag,
                           f.size,
                           q,
                           a->scene->safety * a->local[i] * grow,
                           0,
                           NAN,
                           f.odim,
                           f.otag,
                           -1};
  remedy(a, i, &f, qr, F, s);
  return DTM_OK;
}

/* Judge every element below the target, on the OpenMP threads: each into
 * its own slot of a->shape, then kept in element order. A worker's error
 * record is its thread's own, so the first failing element is judged again
 * on the calling thread for the message. */
static int judge_below(dtm_analysis *a, const judge_ctx *jc, double target, const size_t *idx, unsigned char *lim) {
  const long long n = (long long)a->below;
  long long failed = n;
#pragma omp parallel for schedule(dynamic, 256) reduction(min : failed)
  for (long long j = 0; j < n; j++) {
    int limited = 0;
    size_t i = idx[j];
    if (judge(a, jc, i, target / (a->scene->safety * a->local[i]), &limited, &a->shape[j])) failed = j;
    lim[j] = (unsigned char)limited;
  }
  if (failed < n) {
    int limited;
    size_t i = idx[failed];
    DTM_CHECK(judge(a, jc, i, target / (a->scene->safety * a->local[i]), &limited, &a->shape[failed]));
  }
  for (long long j = 0; j < n; j++)
    if (lim[j]) a->shape[a->nshape++] = a->shape[j];
  return DTM_OK;
}

static int classify_all(dtm_analysis *a, double target) {
  judge_ctx jc = {{NULL, NULL}, 1.0, dtm_analysis_mesh_spread(a->mesh->dim), boundary_near(a)};
  int r = build_incidence(a, &jc.inc);
  if (r == DTM_OK) r = typical_quality(a, &jc.q_typ);
  a->shape = r ? NULL : malloc((a->below + 1) * sizeof *a->shape);
  size_t *idx = malloc((a->below + 1) * sizeof *idx), k = 0;
  unsigned char *lim = malloc(a->below + 1);
  if (r == DTM_OK && (!a->shape || !idx || !lim)) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < a->nel && r == DTM_OK; i++)
    if (a->scene->safety * a->local[i] < target) idx[k++] = i;
  if (r == DTM_OK) r = judge_below(a, &jc, target, idx, lim);
  free(idx), free(lim), free(jc.near), free(jc.inc.start), free(jc.inc.list);
  return r;
}

#define AT_MIN_FACTOR 1.1 /* elements within this factor of the smallest own step */
#define AT_MIN_MAX 64     /* of which at most this many (the smallest) are examined */

/* The elements of the mesh's dimension whose own step is within
 * AT_MIN_FACTOR of the smallest, at most AT_MIN_MAX, smallest first; into
 * c, returns how many. */
static int near_minimum(const dtm_analysis *a, size_t *c) {
  double lo = INFINITY;
  int n = 0;
  for (size_t i = 0; i < a->nel; i++) lo = fmin(lo, a->local[i]);
  for (size_t i = 0; i < a->nel && isfinite(lo); i++) {
    int j;
    if (!(a->local[i] <= AT_MIN_FACTOR * lo)) continue;
    if (n < AT_MIN_MAX)
      j = n++;
    else if (a->local[i] < a->local[c[AT_MIN_MAX - 1]])
      j = AT_MIN_MAX - 1; /* the largest kept drops out */
    else
      continue;
    while (j > 0 && a->local[c[j - 1]] > a->local[i]) c[j] = c[j - 1], j--;
    c[j] = i;
  }
  return n;
}

/* Without a target: whether the smallest steps lie across a thin layer,
 * and what a fresh mesh of it reaches there (the layers, at_minimum). */
static int classify_minimum(dtm_analysis *a) {
  size_t c[AT_MIN_MAX];
  int n = near_minimum(a, c), k = 0;
  judge_ctx jc = {{NULL, NULL}, 1.0, dtm_analysis_mesh_spread(a->mesh->dim), NULL};
  unsigned char *only = calloc(a->mesh->nnodes + 1, 1);
  dtm_shape_limited found[AT_MIN_MAX];
  int r = only ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int j = 0; j < n && r == DTM_OK; j++) {
    corners cc;
    get_corners(a, c[j], &cc);
    for (int q = 0; q < cc.nc; q++) only[cc.v[q]] = 1;
  }
  if (r == DTM_OK && n) r = build_incidence_of(a, &jc.inc, only);
  if (r == DTM_OK && n) r = typical_quality(a, &jc.q_typ);
  for (int j = 0; j < n && r == DTM_OK; j++) {
    int dim = -1, tag = -1, odim = -1, otag = -1, b;
    size_t l;
    dtm_analysis_locate(a, c[j], &b, &l);
    double t = a->mesh->blocks[b].dim < a->mesh->dim ? INFINITY : across(a, &jc, c[j], &dim, &tag, &odim, &otag),
           reach = NAN;
    if (isfinite(t)) r = layer_reach(a, &jc, c[j], t, &reach);
    if (isfinite(t) && r == DTM_OK)
      found[k++] = (dtm_shape_limited){c[j], DTM_FEATURE_THIN, NAN, dim, tag, t, NAN, reach, 0, NAN, odim, otag, -1};
  }
  free(only), free(jc.inc.start), free(jc.inc.list);
  return r == DTM_OK ? dtm_layers_gather_from(a, found, (size_t)k, 1) : r;
}

int dtm_shape_classify(dtm_analysis *a) {
  double target = a->advice_target;
  free(a->shape), free(a->layers);
  a->shape = NULL, a->layers = NULL, a->nshape = a->nlayers = a->below = 0;
  if (!(target > 0)) return a->geo ? classify_minimum(a) : DTM_OK;
  for (size_t i = 0; i < a->nel; i++) a->below += a->scene->safety * a->local[i] < target;
  if (!a->below || !a->geo) return DTM_OK;
  DTM_CHECK(classify_all(a, target));
  return dtm_layers_gather(a);
}
