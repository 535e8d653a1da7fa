/* Validity of an element's shape, the basis of dtmap's invalid-element
 * policy: the scaled Jacobian det J / (product of the column lengths of J),
 * which is 1 where the element's edges meet at right angles, near 0 where
 * it is flat and negative where it is inverted, evaluated at every
 * integration point of the element's full rule and at every node. An
 * element whose Jacobian is safely positive (above 32 eps, see map.c) at
 * every integration point has well-defined element matrices, so it can be
 * analysed even when a corner is inverted (DTM_SHAPE_CORNER); one that is
 * not safely positive at some integration point cannot (DTM_SHAPE_FOLDED,
 * or DTM_SHAPE_FLAT when it has no positive point: zero measure). Linear
 * simplices have one constant Jacobian, computed from their edges. A tri6
 * or tet10 valid at all those samples is also checked between them by a
 * Bernstein bound of det J (bezier.c), and refused (DTM_SHAPE_INSIDE)
 * when that bound does not prove it positive. */
#include <float.h>
#include <math.h>

#include "dtmap/error.h"
#include "assemble-impl.h"
#include "kernel-impl.h"

#define SAFE (32 * DBL_EPSILON) /* safely positive scaled Jacobian (map.c) */

static double len3(const double *v) { return sqrt(dtm_v3_dot(v, v)); }

/* Scaled Jacobian of a linear simplex: its edges from node 0 are the
 * columns of J (in the element's own line or plane for line2 and tri3). */
static double simplex_scaled(int type, const double *x) {
  double e[3][3], c[3];
  int d;
  dtm_elem_info(type, &d, NULL);
  for (int k = 0; k < d; k++) dtm_v3_sub(x + 3 * (k + 1), x, e[k]);
  if (type == DTM_LINE2) return len3(e[0]) > 0 ? 1.0 : 0.0;
  if (type == DTM_TRI3) {
    dtm_v3_cross(e[0], e[1], c);
    return len3(c) / (len3(e[0]) * len3(e[1]));
  }
  dtm_v3_cross(e[1], e[2], c);
  return dtm_v3_dot(e[0], c) / (len3(e[0]) * len3(e[1]) * len3(e[2]));
}

/* At the point of table t's row k when there is a table, else at p. */
static double scaled_at(int type, int d, int nn, const double (*xl)[3], const dtm_ref_table *t, int k,
                        const double p[3]) {
  double had,
      dj = t ? dtm_map_det_dn(d, nn, xl, (const double(*)[3])t->dN[k], &had) : dtm_map_det(type, d, nn, xl, p, &had);
  return had > 0 ? dj / had : 0.0;
}

/* Status from whether some integration point is bad, and whether every
 * bad one is flat (|scaled| <= SAFE) rather than negative. */
static int status_of(int bad_point, int all_flat, double min_node) {
  if (bad_point) return all_flat ? DTM_SHAPE_FLAT : DTM_SHAPE_FOLDED;
  return min_node > SAFE ? DTM_SHAPE_VALID : DTM_SHAPE_CORNER;
}

static void shape_simplex(int type, const double *x, dtm_shape *s) {
  double v = simplex_scaled(type, x);
  s->min_jacobian = v;
  s->node = -1;
  s->point = v > SAFE ? -1 : 0;
  s->status = v > SAFE ? DTM_SHAPE_VALID : v < -SAFE ? DTM_SHAPE_FOLDED : DTM_SHAPE_FLAT;
}

/* Smallest scaled Jacobian over the nodes, and the node where it is. */
static double min_at_nodes(int type, int d, int nn, const double (*xl)[3], int *node) {
  double p[3], min = INFINITY;
  const dtm_ref_table *t = dtm_ref_node_table(type);
  for (int a = 0; a < nn; a++) {
    dtm_ref_node(type, a, p);
    double v = scaled_at(type, d, nn, xl, t, a, p);
    if (!(v >= min)) min = v, *node = a;
  }
  return min;
}

/* A valid tri6 or tet10 must also be positive between its sampling
 * points: the Bernstein bound decides (bezier.c). */
static void inside(int type, int d, int nn, const double (*xl)[3], dtm_shape *s) {
  double ratio, scaled;
  int r = dtm_elem_jacobian_bound(type, d, nn, xl, &ratio, &scaled);
  if (r != 0 && r != -1) return;
  s->status = DTM_SHAPE_INSIDE;
  s->min_jacobian = r < 0 ? scaled : fmin(ratio, 0);
  s->node = -1;
}

static void shape_generic(int type, const double *x, dtm_shape *s) {
  double xl[DTM_K_NODES][3], min_point = INFINITY;
  int d, nn, all_flat = 1, node = -1;
  dtm_elem_info(type, &d, &nn);
  *s = (dtm_shape){DTM_SHAPE_FLAT, 0.0, -1, 0};
  if (dtm_elem_local(type, x, xl)) return;
  double v;
  if (dtm_affine_scaled(type, d, nn, (const double(*)[3])xl, &v) && v > 1000 * SAFE) {
    /* straight-sided tri6 / tet10: one Jacobian, clearly valid at every
     * sample and in between (what the samples and the Bernstein bound
     * below find, to rounding) */
    *s = (dtm_shape){DTM_SHAPE_VALID, v, -1, -1};
    return;
  }
  const dtm_ref_table *t = dtm_ref_rule_table(type, 0); /* the shape functions evaluated once */
  dtm_qrule q;
  if (!t) dtm_ref_rule(type, &q);
  const dtm_qrule *r = t ? &t->q : &q;
  s->point = -1;
  for (int k = 0; k < r->n; k++) {
    double v = scaled_at(type, d, nn, (const double(*)[3])xl, t, k, r->p[k]);
    if (!(v > SAFE) && s->point < 0) s->point = k;
    if (!(v > SAFE)) all_flat &= fabs(v) <= SAFE;
    if (!(v >= min_point)) min_point = v;
  }
  double min_node = min_at_nodes(type, d, nn, (const double(*)[3])xl, &node);
  s->min_jacobian = min_node < min_point ? min_node : min_point;
  s->node = min_node < min_point ? node : -1;
  s->status = status_of(s->point >= 0, all_flat, min_node);
  if (s->status == DTM_SHAPE_VALID) inside(type, d, nn, (const double(*)[3])xl, s);
}

int dtm_kernel_shape(int type, const double *x, dtm_shape *s) {
  DTM_CHECK(dtm_elem_info(type, NULL, NULL));
  if (dtm_elem_is_simplex(type))
    shape_simplex(type, x, s);
  else
    shape_generic(type, x, s);
  return DTM_OK;
}

const char *dtm_shape_describe(int status) {
  switch (status) {
  case DTM_SHAPE_VALID: return "valid";
  case DTM_SHAPE_CORNER: return "inverted at a node, valid at every integration point";
  case DTM_SHAPE_FOLDED: return "inverted or folded (Jacobian not positive at an integration point)";
  case DTM_SHAPE_INSIDE:
    return "inverted inside (Jacobian determinant not positive between its nodes and integration points, by a Bezier "
           "bound)";
  default: return "flat (zero measure)";
  }
}
