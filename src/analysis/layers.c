/* Thin layers: the shape-limited elements whose feature is a thin part (two
 * boundaries that do not touch, closer than the size the target needs; see
 * shape.c), gathered per layer: the physical group and the pair of model
 * boundaries the element's thickness spans. A lining, a coating, a thin
 * wall or a ligament between a hole and an edge caps every element across
 * it near its own thickness, so each such layer gets its own: a part with
 * 10 mm walls and a 2.5 mm ligament is two or more layers, never one layer
 * as thin as its thinnest place. No size suggestion lifts them, so the
 * advice names each layer, its local thickness, how many elements, the
 * best step any mesh of it can reach there, and the step LS-DYNA's shell
 * rule (L_s / c_p; in 2D the same for a beam along the layer) would give
 * the layer at its present in-plane size if it were modelled as its
 * mid-surface, at the layer's own thickness. Layers come smallest reach
 * first. The mass and the subcycling remedies are the cost module's.
 * Without a target the same is said of the elements at the smallest steps
 * (at_minimum): the layer they cross and the best step a fresh mesh of it
 * reaches there. */
#include <math.h>
#include <stdlib.h>

#include "analysis-impl.h"
#include "dtmap/gmsh.h"

/* The boundary pair of s, the smaller {dim, tag} first. */
static void pair_of(const dtm_shape_limited *s, int f[2][2]) {
  int a0 = s->entity_dim, a1 = s->entity_tag, b0 = s->other_dim, b1 = s->other_tag;
  int swap = b0 < a0 || (b0 == a0 && b1 < a1);
  f[0][0] = swap ? b0 : a0, f[0][1] = swap ? b1 : a1;
  f[1][0] = swap ? a0 : b0, f[1][1] = swap ? a1 : b1;
}

static int same_pair(const int f[2][2], const int g[2][2]) {
  return f[0][0] == g[0][0] && f[0][1] == g[0][1] && f[1][0] == g[1][0] && f[1][1] == g[1][1];
}

#define JOIN 1.1 /* pairs of one group within this factor of the thinnest of them are one layer */

static size_t layer_of(dtm_analysis *a, int g, const int f[2][2], int at_minimum) {
  for (size_t k = 0; k < a->nlayers; k++)
    if (a->layers[k].group == g && same_pair(a->layers[k].faces, f)) return k;
  dtm_layer *l = &a->layers[a->nlayers];
  *l = (dtm_layer){g, {{f[0][0], f[0][1]}, {f[1][0], f[1][1]}}, 0, INFINITY, INFINITY, 0, 0, NAN, at_minimum};
  return a->nlayers++;
}

static void add_element(dtm_analysis *a, dtm_layer *l, const dtm_shape_limited *s) {
  size_t i = s->element;
  if (!l->elements || a->local[i] < a->local[l->worst]) l->worst = i;
  l->elements++;
  l->thickness = fmin(l->thickness, s->size);
  l->reach = fmin(l->reach, s->reach);
  l->size += a->h[i];
}

#define GAP_FLOOR 0.4 /* a geometric gap below this x the mesh's is taken for a wrong pair */

static void centroid(const dtm_analysis *a, size_t i, double x[3]) {
  int b;
  size_t e;
  dtm_analysis_locate(a, i, &b, &e);
  const dtm_block *blk = &a->mesh->blocks[b];
  x[0] = x[1] = x[2] = 0;
  for (int q = 0; q < blk->nn; q++)
    for (int d = 0; d < 3; d++) x[d] += a->mesh->xyz[3 * blk->conn[e * blk->nn + q] + d] / blk->nn;
}

/* Layer l's thickness from the geometry (dtm_gmsh_gap) near its thinnest
 * element: kept when it is at most the mesh's (the mesh's nodes lie on the
 * two boundaries, so their distance bounds the gap from above), at least
 * GAP_FLOOR of it and its closest points lie within the mesh's gap plus
 * two element sizes of that element (the projections are onto untrimmed
 * surfaces: two planes that do not touch as faces may meet far away). The
 * reach scales with the thickness to the limiting effect's step exponent
 * (the well-shaped element across the layer, shape.c). */
static void geometric_thickness(dtm_analysis *a, dtm_layer *l, size_t thinnest) {
  double x[3], pa[3], pb[3], t = l->thickness;
  if (!a->geo) return;
  centroid(a, thinnest, x);
  double g = dtm_gmsh_gap(l->faces[0], l->faces[1], x, pa, pb), far = t + 2 * a->h[thinnest];
  if (!(g <= t * (1 + 1e-9)) || !(g >= GAP_FLOOR * t)) return;
  double da = 0, db = 0;
  for (int d = 0; d < 3; d++) da += (pa[d] - x[d]) * (pa[d] - x[d]), db += (pb[d] - x[d]) * (pb[d] - x[d]);
  if (sqrt(da) > far || sqrt(db) > far) return;
  int k = a->limiting[thinnest];
  double p = k >= 0 ? a->effects[k].cls->exponent : 1.0;
  l->reach *= pow(g / t, p);
  l->thickness = g;
}

#define SAME_GAP 1e-9 /* thicknesses this close (relative) are one: rounding, not geometry */

/* The order of two layers' pairs: the thinner first; at one thickness up
 * to rounding, the pair of higher dimension (a layer lies between
 * surfaces; nodes on their curves are on them too), then the smaller
 * {dim, tag}. The last bits of the coordinates (which the unit system
 * changes, tests/t381) never decide which pair names a layer. */
static int pair_order(const dtm_layer *x, const dtm_layer *y) {
  double tx = x->thickness, ty = y->thickness;
  if (fabs(tx - ty) > SAME_GAP * fmax(tx, ty)) return tx < ty ? -1 : 1;
  int dx = x->faces[0][0] + x->faces[1][0], dy = y->faces[0][0] + y->faces[1][0];
  if (dx != dy) return dx > dy ? -1 : 1;
  for (int k = 0; k < 4; k++)
    if (x->faces[k / 2][k % 2] != y->faces[k / 2][k % 2])
      return x->faces[k / 2][k % 2] < y->faces[k / 2][k % 2] ? -1 : 1;
  return 0;
}

/* Layer into layer: its elements, thinnest pair and worst element. */
static void absorb(const dtm_analysis *a, dtm_layer *into, const dtm_layer *from) {
  if (pair_order(from, into) < 0)
    for (int k = 0; k < 4; k++) into->faces[k / 2][k % 2] = from->faces[k / 2][k % 2];
  if (a->local[from->worst] < a->local[into->worst]) into->worst = from->worst;
  into->elements += from->elements;
  into->thickness = fmin(into->thickness, from->thickness);
  into->reach = fmin(into->reach, from->reach);
  into->size += from->size;
}

static size_t root(const size_t *up, size_t k) { return up[k]; /* one step: a layer's pairs point at its root */ }

typedef struct {
  const dtm_layer *l;
  size_t k;
} thick_key;

static int by_thickness(const void *p, const void *q) {
  const thick_key *x = p, *y = q;
  int c = pair_order(x->l, y->l);
  return c ? c : (x->k > y->k) - (x->k < y->k);
}

/* Pairs of one group whose thicknesses lie within JOIN of the thinnest of
 * them are one layer: a face Gmsh splits in patches, the two legs of an L
 * of one thickness, two ligaments of one width. From the thinnest up, a
 * pair joins a layer of its group it lies within JOIN of, or starts one;
 * up[k] gets each pair's layer (its thinnest pair). */
static int join_thickness(const dtm_analysis *a, size_t *up) {
  size_t L = a->nlayers;
  thick_key *o = malloc((L + 1) * sizeof *o);
  if (!o) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t k = 0; k < L; k++) o[k] = (thick_key){&a->layers[k], k};
  qsort(o, L, sizeof *o, by_thickness);
  for (size_t j = 0; j < L; j++) {
    const dtm_layer *lk = &a->layers[o[j].k];
    for (size_t q = 0; q < j && up[o[j].k] == o[j].k; q++) {
      const dtm_layer *lr = &a->layers[o[q].k];
      if (up[o[q].k] == o[q].k && lr->group == lk->group && lk->thickness <= JOIN * lr->thickness) up[o[j].k] = o[q].k;
    }
  }
  free(o);
  return DTM_OK;
}

/* Join the pairs into layers (JOIN), keep the roots in order, renumber. */
static int join_layers(dtm_analysis *a, dtm_shape_limited *sl, size_t n) {
  size_t *up = malloc((a->nlayers + 1) * 2 * sizeof *up), m = 0;
  if (!up) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t *to = up + a->nlayers + 1;
  for (size_t k = 0; k < a->nlayers; k++) up[k] = k;
  int r = join_thickness(a, up);
  for (size_t k = 0; k < a->nlayers && r == DTM_OK; k++)
    if (root(up, k) != k) absorb(a, &a->layers[root(up, k)], &a->layers[k]);
  for (size_t k = 0; k < a->nlayers && r == DTM_OK; k++)
    if (root(up, k) == k) to[k] = m, a->layers[m++] = a->layers[k];
  for (size_t j = 0; j < n && r == DTM_OK; j++)
    if (sl[j].layer >= 0) sl[j].layer = (int)to[root(up, (size_t)sl[j].layer)];
  if (r == DTM_OK) a->nlayers = m;
  free(up);
  return r;
}
/* LS-DYNA's rule for a shell (or beam) of the layer's material at the mean
 * size of its elements. */
static void shell_rule(dtm_analysis *a, dtm_layer *l) {
  int b;
  size_t e;
  dtm_analysis_locate(a, l->worst, &b, &e);
  const dtm_material *m = &a->scene->materials[a->mesh->blocks[b].mat[e]].m;
  double E = dtm_material_value(m, "E"), nu = dtm_material_value(m, "nu"), rho = dtm_material_value(m, "rho");
  l->size /= (double)l->elements;
  l->shell_step = l->size / sqrt(E / (rho * (1 - nu * nu)));
}

/* Smallest reach first; then more elements first, then the group. */
static int by_reach(const void *p, const void *q) {
  const dtm_layer *x = p, *y = q;
  if (x->reach != y->reach) return x->reach < y->reach ? -1 : 1;
  if (x->elements != y->elements) return x->elements > y->elements ? -1 : 1;
  return (x->group > y->group) - (x->group < y->group);
}

/* The layers in order (by_reach), the elements' indices renumbered. */
static int sort_layers(dtm_analysis *a, dtm_shape_limited *sl, size_t n) {
  size_t L = a->nlayers, *old = malloc((2 * L + 1) * sizeof *old), *to = old + L;
  if (!old) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t k = 0; k < L; k++) old[k] = a->layers[k].worst; /* distinct: each holds its own */
  qsort(a->layers, L, sizeof *a->layers, by_reach);
  for (size_t k = 0; k < L; k++)
    for (size_t m = 0; m < L; m++)
      if (a->layers[m].worst == old[k]) to[k] = m;
  for (size_t j = 0; j < n; j++)
    if (sl[j].layer >= 0) sl[j].layer = (int)to[sl[j].layer];
  free(old);
  return DTM_OK;
}

int dtm_layers_gather_from(dtm_analysis *a, dtm_shape_limited *sl, size_t n, int at_minimum) {
  free(a->layers);
  a->layers = NULL, a->nlayers = 0;
  if (!n) return DTM_OK;
  a->layers = malloc((n + 1) * sizeof *a->layers);
  if (!a->layers) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t *thinnest = malloc((n + 1) * sizeof *thinnest);
  if (!thinnest) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t j = 0; j < n; j++) {
    int f[2][2];
    sl[j].layer = -1;
    if (sl[j].feature != DTM_FEATURE_THIN) continue;
    pair_of(&sl[j], f);
    sl[j].layer = (int)layer_of(a, dtm_analysis_group(a, sl[j].element), f, at_minimum);
    dtm_layer *l = &a->layers[sl[j].layer];
    if (!l->elements || sl[j].size < l->thickness) thinnest[sl[j].layer] = sl[j].element;
    add_element(a, l, &sl[j]);
  }
  for (size_t k = 0; k < a->nlayers; k++) geometric_thickness(a, &a->layers[k], thinnest[k]);
  free(thinnest);
  DTM_CHECK(join_layers(a, sl, n));
  for (size_t k = 0; k < a->nlayers; k++) shell_rule(a, &a->layers[k]);
  return sort_layers(a, sl, n);
}

int dtm_layers_gather(dtm_analysis *a) { return dtm_layers_gather_from(a, a->shape, a->nshape, 0); }

const dtm_layer *dtm_analysis_layers(const dtm_analysis *a, size_t *n) {
  *n = a->nlayers;
  return a->layers;
}
