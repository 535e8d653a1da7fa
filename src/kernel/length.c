/* Geometric characteristic lengths (dtm_kernel_length). One definition per
 * kind for every type, chosen so that it is the textbook quantity on
 * simplices:
 *   SAFE         2 / sqrt(sum_a integral|grad N_a|^2 / m_a), m_a the lumped
 *                mass per unit density (integral N_a for linear types). On a
 *                simplex this is 2/sqrt((d+1) sum_a h_a^-2), DESIGN.md's
 *                L_safe. On any type it is provably safe for nu >= 0: the
 *                elastic element bound is at most c^2 times that sum
 *                (split Ke over quadrature points; at each, the simplex
 *                argument bounds the normal block by modulus tr S), so
 *                L_safe / c <= 2/sqrt(lambda_e). It is not safe for
 *                auxetic materials (nu < 0), where 2 mu s_max can exceed
 *                modulus tr S. NaN for a degenerate or inverted element.
 *   MIN_EDGE     shortest edge.
 *   MIN_ALTITUDE the element's smallest width across a facet: min over
 *                facets of the largest distance of a node from the
 *                facet's plane (3D; Newell plane through the facet's
 *                centroid), line (2D) or point (1D). On a simplex it is the
 *                smallest altitude; on a box the shortest side.
 *   INRADIUS     2 d V / (total facet measure), twice the inradius on a
 *                simplex; the same formula otherwise (a box of sides a <= b
 *                <= c gives 3abc/(ab+bc+ca), a cube its side).
 *   VOLUME_AREA  V / largest facet measure (3D: face area, 2D: edge
 *                length, 1D: the length itself, a point counting as 1).
 *   EIGEN        not geometric: NaN.
 * Second-order elements: SAFE is computed on the element itself, with its
 * own shape functions and HRZ lumped masses m_a in place of integral N_a
 * (which is negative at tet10 corners): 2/sqrt(sum_a integral|grad N_a|^2
 * / m_a). The proof above holds for any positive diagonal mass and a rule
 * with positive weights, so it stays safe (for nu >= 0) with respect to
 * the second-order element bound. Every other kind is geometric and is
 * taken on the linear parent, i.e. on the corner nodes only (the first
 * nodes in Gmsh's order): edges are the chords between corners, facets
 * the flat corner polygons and V the parent's measure; mid-side nodes,
 * and so curvature, are ignored.
 * Facet areas of warped quadrangles are those of their Newell projection.
 * V is the signed measure, so inverted 3D elements give negative
 * INRADIUS and VOLUME_AREA. An unknown type gives NaN. */
#include <math.h>

#include "dtmap/error.h"
#include "assemble-impl.h"
#include "kernel-impl.h"

/* A facet reduced to what lengths need: measure, and a point and unit
 * direction that define its plane (normal), line (tangent) or point. */
typedef struct {
  int d;          /* element dimension: facet is a plane, line, point */
  double measure; /* area, length, or 1 for a point */
  double c[3];    /* a point of the facet (centroid for planes) */
  double n[3];    /* unit normal (3D) or unit tangent (2D) */
} facet;

static void plane_facet(const dtm_topology *t, int f, const double *x, facet *F) {
  int k = t->facet_nn[f];
  const double *x0 = x + 3 * t->facet[f][0];
  double r[3], s[3], c[3];
  for (int i = 0; i < 3; i++) F->n[i] = 0, F->c[i] = 0;
  for (int a = 0; a < k; a++) {
    for (int i = 0; i < 3; i++) F->c[i] += x[3 * t->facet[f][a] + i] / k;
    if (a == 0 || a + 1 == k) continue;
    dtm_v3_sub(x + 3 * t->facet[f][a], x0, r);
    dtm_v3_sub(x + 3 * t->facet[f][a + 1], x0, s);
    dtm_v3_cross(r, s, c);
    for (int i = 0; i < 3; i++) F->n[i] += c[i];
  }
  double nn = sqrt(dtm_v3_dot(F->n, F->n));
  F->measure = nn / 2;
  for (int i = 0; i < 3; i++) F->n[i] = nn > 0 ? F->n[i] / nn : 0;
}

static void get_facet(int d, const dtm_topology *t, int f, const double *x, facet *F) {
  F->d = d;
  if (d == 3) {
    plane_facet(t, f, x, F);
    return;
  }
  const double *a = x + 3 * t->facet[f][0];
  for (int i = 0; i < 3; i++) F->c[i] = a[i], F->n[i] = 0;
  F->measure = 1;
  if (d == 1) return;
  dtm_v3_sub(x + 3 * t->facet[f][1], a, F->n);
  F->measure = sqrt(dtm_v3_dot(F->n, F->n));
  for (int i = 0; i < 3; i++) F->n[i] = F->measure > 0 ? F->n[i] / F->measure : 0;
}

/* Distance of point p from the facet's plane, line or point. */
static double distance(const facet *F, const double *p) {
  double r[3], c[3];
  dtm_v3_sub(p, F->c, r);
  if (F->d == 3) return fabs(dtm_v3_dot(r, F->n));
  if (F->d == 1) return sqrt(dtm_v3_dot(r, r));
  dtm_v3_cross(r, F->n, c);
  return sqrt(dtm_v3_dot(c, c));
}

static double min_edge(const dtm_topology *t, const double *x) {
  double m = INFINITY, r[3];
  for (int e = 0; e < t->nedge; e++) {
    dtm_v3_sub(x + 3 * t->edge[e][1], x + 3 * t->edge[e][0], r);
    m = fmin(m, sqrt(dtm_v3_dot(r, r)));
  }
  return m;
}

static double min_width(int d, int nn, const dtm_topology *t, const double *x) {
  double m = INFINITY;
  for (int f = 0; f < t->nfacet; f++) {
    facet F;
    double w = 0;
    get_facet(d, t, f, x, &F);
    for (int a = 0; a < nn; a++) w = fmax(w, distance(&F, x + 3 * a));
    m = fmin(m, w);
  }
  return m;
}

/* Sum (or, with take_max, largest) of the facet measures. */
static double facets(int d, const dtm_topology *t, const double *x, int take_max) {
  double s = 0;
  for (int f = 0; f < t->nfacet; f++) {
    facet F;
    get_facet(d, t, f, x, &F);
    s = take_max ? fmax(s, F.measure) : s + F.measure;
  }
  return s;
}

static double safe_length(int type, const double *x) {
  if (dtm_elem_is_simplex(type)) { /* closed form: (d+1) tr S, S = sum_a g_a g_a^T */
    int d;
    double S[6], scale, vol;
    if (dtm_simplex_metric(type, x, &d, S, &scale, &vol)) return dtm_error_clear(), NAN;
    return 2 / sqrt((d + 1) * scale * (S[0] + S[1] + S[2]));
  }
  dtm_elem_geom eg;
  double K[DTM_K_NODES * DTM_K_NODES], m[DTM_K_NODES], sum = 0;
  if (dtm_elem_setup(type, x, DTM_INTEGRATION_CONVERGED, &eg)) return NAN;
  dtm_elem_laplace(&eg, K);
  dtm_elem_mass(&eg, m);
  for (int a = 0; a < eg.nn; a++) sum += K[a * eg.nn + a] / m[a];
  return 2 / sqrt(sum);
}

double dtm_kernel_length(int type, dtm_length_kind kind, const double *x) {
  const dtm_topology *t = dtm_elem_topology(type);
  int d, nn, parent = dtm_elem_parent(type); /* geometry: corners only */
  if (!t) return NAN;
  dtm_elem_info(parent, &d, &nn);
  switch (kind) {
  case DTM_LEN_SAFE: return safe_length(type, x);
  case DTM_LEN_MIN_EDGE: return min_edge(t, x);
  case DTM_LEN_MIN_ALTITUDE: return min_width(d, nn, t, x);
  case DTM_LEN_INRADIUS: return 2 * d * dtm_elem_measure(parent, x) / facets(d, t, x, 0);
  case DTM_LEN_VOLUME_AREA: return dtm_elem_measure(parent, x) / facets(d, t, x, 1);
  default: return NAN;
  }
}
