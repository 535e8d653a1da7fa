/* What a mesh and its recommended step buy: one accuracy measure per
 * effect the scene names, computed for every element of the real mesh.
 * - elastic waves: the phase-speed error at the frequency of interest
 *   (<time f-max>, else a default from the mesh, said so in the note),
 *   lumped mass, central differences at the recommended step (or at the
 *   element's subcycling level's step, or at the target step with the
 *   element's mass scaling), from the model of each element type and
 *   material (dtm_acc_table, once each): the mesh's own shapes, a
 *   structured mesh's own lattice, the measured table of Gmsh's
 *   unstructured tetrahedra, or the regular lattice. The error is the
 *   worse of P and S over the model's directions; the measured table takes
 *   each element at the root mean square of the mean edges around it (how
 *   the table was measured, and what a wave crossing them sees).
 *   Fewer than 2 cells per wavelength (or a step above the element's own
 *   safe step: unstable) is "unresolved", counted, never a small number.
 *   The worst names its wave, direction and model; --calibrate's ratios
 *   (dtm_scene.phase_ratio) multiply each branch's error;
 * - cohesive zones: elements per process zone (the effect's own view),
 *   per group, against the 5-10 band;
 * - diffusion (thermal, hydraulic): elements across sqrt(D t) at the
 *   scene's duration, at least DTM_BAND_DIFFUSION.
 * Each measure keeps the worst and the median over its elements. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accuracy-impl.h"
#include "dispersion-impl.h"
#include "dtmap/cost.h"
#include "dtmap/kernel.h"
#include "dtmap/topology.h"
#include "dtmap/util.h"

#define PI 3.14159265358979323846
#define MAX_TABLES 64 /* element type x material pairs kept at once */
#define SHAPE_WORK                                                                                                     \
  8192 /* node pairs of the elements an own-shape table is built from (tri3: 512 elements, hex8: 128) */

#define CURVE_N 512     /* points of a curve over k h in [0, pi] */
#define SMOOTH_PASSES 3 /* rings of elements the measured model's spacing is averaged over */
#define MAX_CURVES 64   /* curves kept (table x subcycling level) */

/* The worst error of one table at one x = pi f dt against k h, both
 * branches, sampled once so that an element costs an interpolation instead
 * of a sweep over the table's directions (the measure would otherwise cost
 * as much as the analysis). */
typedef struct {
  const dtm_dispersion *t;  /* the table */
  double x;                 /* pi f dt */
  double w[2][CURVE_N + 1]; /* [P, S][k h = pi j / CURVE_N] (NaN: unresolved or unstable) */
} curve;

/* The lattice tables and curves met so far. */
typedef struct {
  int n;                         /* tables in use */
  dtm_dispersion *t[MAX_TABLES]; /* owned (NULL: no model for that type and material) */
  int mat[MAX_TABLES];           /* the material of each */
  int type[MAX_TABLES];          /* the element type of each */
  int nc;                        /* curves in use */
  curve *c[MAX_CURVES];          /* owned */
} table_cache;

static void cache_free(table_cache *c) {
  for (int i = 0; i < c->n; i++) free(c->t[i]); /* NULL for a pair without a model */
  for (int i = 0; i < c->nc; i++) free(c->c[i]);
}

/* The curve of table t at x, built on first use; NULL when the cache is
 * full or out of memory (then the caller evaluates directly). */
static const curve *curve_get(table_cache *c, const dtm_dispersion *t, double x) {
  for (int i = 0; i < c->nc; i++)
    if (c->c[i]->t == t && c->c[i]->x == x) return c->c[i];
  curve *k = c->nc < MAX_CURVES ? malloc(sizeof *k) : NULL;
  if (!k) return NULL;
  k->t = t, k->x = x;
  for (int m = 0; m < 2; m++) {
    k->w[m][0] = dtm_dispersion_time(0, x) > -1 ? dtm_dispersion_time(0, x) : NAN;
    for (int j = 1; j <= CURVE_N; j++) k->w[m][j] = dtm_dispersion_worst(t, m, PI * j / CURVE_N, x);
  }
  return c->c[c->nc++] = k;
}

/* The curve of table t at x if built, else NULL (read only: safe in the
 * element loop's threads). */
static const curve *curve_find(const table_cache *c, const dtm_dispersion *t, double x) {
  for (int i = 0; i < c->nc; i++)
    if (c->c[i]->t == t && c->c[i]->x == x) return c->c[i];
  return NULL;
}

/* Linear in k h between the curve's points; NaN beyond pi. */
static double curve_at(const curve *k, int mode, double kh) {
  double u = kh / PI * CURVE_N;
  if (!(u <= CURVE_N)) return NAN;
  int j = (int)u;
  if (j == CURVE_N) return k->w[mode][j];
  double f = u - j;
  return f == 0 ? k->w[mode][j] : (1 - f) * k->w[mode][j] + f * k->w[mode][j + 1];
}

/* Up to SHAPE_WORK / nn^2 elements (at most 512) of type and material mat
 * (no section), every stride-th of them in mesh order, as coordinates
 * x[n][nn][3]. */
static int shape_sample(const dtm_mesh *mesh, int type, int mat, double **x, size_t *n) {
  size_t count = 0, k = 0, i = 0;
  int d, nn;
  dtm_elem_info(type, &d, &nn);
  for (int b = 0; b < mesh->nblocks; b++)
    for (size_t e = 0; mesh->blocks[b].type == type && e < mesh->blocks[b].n; e++)
      count += mesh->blocks[b].mat[e] == mat && !(mesh->blocks[b].section && mesh->blocks[b].section[e] >= 0);
  size_t most = (size_t)(SHAPE_WORK / (nn * nn) < 512 ? SHAPE_WORK / (nn * nn) : 512);
  size_t stride = count > most ? count / most : 1;
  *x = malloc(((count + stride - 1) / stride + 1) * (size_t)nn * 3 * sizeof **x);
  if (!*x) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int b = 0; b < mesh->nblocks; b++)
    for (size_t e = 0; mesh->blocks[b].type == type && e < mesh->blocks[b].n; e++) {
      const dtm_block *bl = &mesh->blocks[b];
      if (bl->mat[e] != mat || (bl->section && bl->section[e] >= 0)) continue;
      if (i++ % stride == 0) dtm_mesh_gather_one(mesh, bl, e, *x + k++ * (size_t)nn * 3);
    }
  *n = k;
  return DTM_OK;
}

int dtm_acc_table(const dtm_mesh *mesh, int type, int mat, double r, dtm_dispersion *t, int *have) {
  *have = 1;
  if (dtm_dispersion_has_shapes(type) && r > 0) {
    double *x = NULL;
    size_t n = 0;
    int rc = shape_sample(mesh, type, mat, &x, &n);
    if (!rc) rc = dtm_dispersion_table_shapes(type, r, x, n, t);
    free(x);
    return rc;
  }
  *have = 0;
  if (type != DTM_LINE2) DTM_CHECK(dtm_dispersion_table_mesh(mesh, type, mat, r, t, have));
  if (*have) return DTM_OK;
  *have = dtm_dispersion_has_model(type);
  if (dtm_dispersion_has_measured(type) && r > 0) return dtm_dispersion_table_measured(type, r, t);
  return *have ? dtm_dispersion_table(type, DTM_LATTICE_REGULAR, r, t) : DTM_OK;
}

/* The table of element type and material mat (r its mu / M), built on
 * first use; *out = NULL when no model applies to them. */
static int cache_get(table_cache *c, const dtm_mesh *mesh, int type, int mat, double r, const dtm_dispersion **out) {
  for (int i = 0; i < c->n; i++)
    if (c->type[i] == type && c->mat[i] == mat) return *out = c->t[i], DTM_OK;
  if (c->n == MAX_TABLES) return DTM_ERR(DTM_ERR_INPUT, "more than %d element type and material pairs", MAX_TABLES);
  dtm_dispersion *t = malloc(sizeof *t);
  int have = 0, rc = t ? dtm_acc_table(mesh, type, mat, r, t, &have) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (rc || !have) free(t), t = NULL;
  if (rc) return rc;
  c->mat[c->n] = mat, c->type[c->n] = type;
  *out = c->t[c->n++] = t;
  return DTM_OK;
}

/* The lattice spacing of an element of type and measure meas: the cell
 * edge of the lattice of its type whose elements have its measure (the
 * default frequency's). */
static double lattice_h(int type, int d, double meas) {
  double per = dtm_dispersion_cell_elements(type);
  return d == 1 ? meas : d == 2 ? sqrt(per * meas) : cbrt(per * meas);
}

double dtm_acc_spacing(const dtm_dispersion *t, int d, double meas, double edge) {
  if (!(t->per_cell > 0)) return edge;
  return d == 1 ? meas : d == 2 ? sqrt(t->per_cell * meas) : cbrt(t->per_cell * meas);
}

/* The measure of element e of block bl (m^d) and its mean edge (m). */
static double element_measure(const dtm_mesh *mesh, const dtm_block *bl, size_t e, double *edge) {
  double x[3 * DTM_MAX_NODES];
  for (int j = 0; j < bl->nn; j++) memcpy(x + 3 * j, mesh->xyz + 3 * bl->conn[e * bl->nn + j], 3 * sizeof *x);
  if (edge) *edge = dtm_elem_mean_edge(bl->type, x);
  return fabs(dtm_elem_measure(bl->type, x));
}

/* Median of v[n] (reordered), NaN when n = 0. */
static double median(double *v, size_t n) {
  if (!n) return NAN;
  double hi = dtm_select_kth(v, n, n / 2);
  if (n % 2) return hi;
  double lo = v[0];
  for (size_t i = 1; i < n / 2; i++) lo = fmax(lo, v[i]);
  return 0.5 * (lo + hi);
}

static int push(dtm_measures *ms, const dtm_measure *m) {
  dtm_measure *p = realloc(ms->m, (size_t)(ms->n + 1) * sizeof *p);
  if (!p) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  ms->m = p;
  ms->m[ms->n++] = *m;
  return DTM_OK;
}

dtm_formulation dtm_acc_formulation(const dtm_analysis *a, int k) {
  const char *names[] = DTM_FORMULATION_NAMES;
  const char *f = dtm_scene_effect_attr(&dtm_analysis_scene(a)->effects[k], "formulation");
  for (int i = 0; f && names[i]; i++)
    if (!strcmp(f, names[i])) return (dtm_formulation)i;
  return dtm_formulation_default(dtm_analysis_mesh(a)->dim);
}

int dtm_acc_moduli(const dtm_analysis *a, int mat, dtm_formulation f, dtm_elastic_moduli *m) {
  const dtm_material *mt = &dtm_analysis_scene(a)->materials[mat].m;
  double nu = f == DTM_FORM_BAR ? 0 : dtm_material_value(mt, "nu");
  return dtm_elastic_moduli_init(f, dtm_material_value(mt, "E"), nu, dtm_material_value(mt, "rho"), m) ? -1 : 0;
}

/* The steps the elements take (dtm_measure_step) and the recommended one. */
typedef struct {
  const dtm_measure_step *st; /* the steps (NULL: the recommended step everywhere) */
  double dt;                  /* the recommended step, s */
  const double *own;          /* [nel] each element's own safe step (dtm_analysis_local_step) */
} step_rule;

static void element_step(const step_rule *sr, size_t i, double mass, double *dt, double *speed) {
  *dt = sr->dt, *speed = 1;
  if (!sr->st) return;
  if (sr->st->level) *dt = sr->dt * ldexp(1.0, sr->st->level[i]);
  if (sr->st->level && sr->own && *dt > sr->own[i] * (1 + 1e-12)) *dt = NAN; /* unstable */
  if (sr->st->target > 0) *dt = sr->st->target;
  if (sr->st->added && mass > 0) *speed = 1 / sqrt(1 + sr->st->added[i] / mass);
}

/* The worst error of branch mode at kh: from the curve when there is one
 * (unscaled elements), else over the table's directions. */
static double worst(const dtm_dispersion *t, const curve *k, int mode, double kh, double x) {
  return k ? curve_at(k, mode, kh) : dtm_dispersion_worst(t, mode, kh, x);
}

/* The ratio --calibrate applies to branch mode (dtm_scene.phase_ratio; 1: none). */
static double branch_scale(const dtm_analysis *a, int mode) {
  const dtm_scene *s = dtm_analysis_scene(a);
  double r = s->phase_ratio[mode];
  return s->phase_calibrate && r != 0 && isfinite(r) ? r : 1;
}

/* The phase error of one element at frequency f: the worse of P and S,
 * each times its ratio sc[branch]. */
static double element_phase(const table_cache *c, const dtm_dispersion *t, const dtm_elastic_moduli *m, double h,
                            double f, double dt, double speed, const double sc[2]) {
  double cp = m->cd * speed, cs = sqrt(m->mu / m->rho) * speed, x = PI * f * dt;
  const curve *k = speed == 1 ? curve_find(c, t, x) : NULL;
  /* the lattice's own error at the scaled speed, then the speed's own factor */
  double ep = sc[0] * worst(t, k, 0, 2 * PI * f * h / cp, x);
  double es = m->form == DTM_FORM_BAR ? 0 : sc[1] * worst(t, k, 1, 2 * PI * f * h / cs, x);
  if (isnan(ep) || isnan(es)) return NAN;
  double e = fabs(es) > fabs(ep) ? es : ep;
  return (1 + e) * speed - 1;
}

/* Each element's measure (m^d) and mean edge (m): the analysis's own,
 * else gathered once into buf[2 nel] (the element loop's threads). */
static void element_sizes(const dtm_analysis *a, double *buf, const double **meas, const double **edge) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  size_t i0 = 0, nel = dtm_analysis_nelements(a);
  *meas = dtm_analysis_measure(a), *edge = dtm_analysis_size(a);
  if (*meas && *edge) return;
  for (int b = 0; b < mesh->nblocks; i0 += mesh->blocks[b++].n) {
    const dtm_block *bl = &mesh->blocks[b];
    const long long n = (long long)bl->n;
#pragma omp parallel for schedule(static)
    for (long long e = 0; e < n; e++) {
      size_t i = i0 + (size_t)e;
      buf[i] = element_measure(mesh, bl, (size_t)e, &buf[nel + i]);
    }
  }
  *meas = buf, *edge = buf + nel;
}

/* The shear (bar: axial) speed of each material in formulation f, NaN
 * where it lacks E, nu or rho, into cs[nmat]. */
static void shear_speeds(const dtm_analysis *a, dtm_formulation f, double *cs) {
  for (int k = 0; k < dtm_analysis_scene(a)->nmaterials; k++) {
    dtm_elastic_moduli m;
    cs[k] = dtm_acc_moduli(a, k, f, &m) ? NAN : f == DTM_FORM_BAR ? m.cd : sqrt(m.mu / m.rho);
  }
}

/* The default frequency of a mesh: the smallest over its elements of
 * c_S / (N h), N the scene's elements per wavelength: the highest
 * frequency at which every element has at least N cells per shear
 * wavelength (on a graded mesh the coarse part sets it). */
static int default_frequency(const dtm_analysis *a, dtm_formulation f, const double *meas, double *fd) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  double N = dtm_analysis_scene(a)->elements_per_wavelength, lo = INFINITY;
  double *cs = malloc(((size_t)dtm_analysis_scene(a)->nmaterials + 1) * sizeof *cs);
  if (!(N > 0)) N = DTM_SCENE_PER_WAVELENGTH;
  if (!cs) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  shear_speeds(a, f, cs);
  size_t i0 = 0;
  for (int b = 0; b < mesh->nblocks; i0 += mesh->blocks[b++].n) {
    const dtm_block *bl = &mesh->blocks[b];
    const long long n = (long long)bl->n;
#pragma omp parallel for schedule(static) reduction(min : lo)
    for (long long e = 0; e < n; e++)
      if (bl->mat[e] >= 0 && !(bl->section && bl->section[e] >= 0) && !isnan(cs[bl->mat[e]]))
        lo = fmin(lo, cs[bl->mat[e]] / (N * lattice_h(bl->type, bl->dim, meas[i0 + (size_t)e])));
  }
  free(cs);
  *fd = isfinite(lo) ? lo : NAN;
  return DTM_OK;
}

/* One block's material slots: the moduli and table of each material the
 * block uses (NULL table: the material lacks E, nu or rho, or no model
 * applies to the block's type). */
typedef struct {
  dtm_elastic_moduli m;    /* moduli in the formulation */
  const dtm_dispersion *t; /* its table, or NULL */
} slot;

/* The tables of every material of block bl into s[nmat], and the curves
 * of every step its elements take (levels) when no mass is added, so that
 * the element loop only reads the cache. */
static int prepare_block(const dtm_analysis *a, dtm_formulation f, double freq, const step_rule *sr,
                         const dtm_block *bl, size_t i0, table_cache *cache, slot *s) {
  int nmat = dtm_analysis_scene(a)->nmaterials;
  for (int k = 0; k < nmat; k++) s[k].t = NULL;
  char *seen = calloc((size_t)nmat + 1, 1);
  if (!seen) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int rc = DTM_OK, levels = 1;
  for (size_t e = 0; e < bl->n && !rc; e++) {
    int mt = bl->mat[e];
    if (sr->st && sr->st->level && sr->st->level[i0 + e] + 1 > levels) levels = sr->st->level[i0 + e] + 1;
    if (mt < 0 || seen[mt] || (bl->section && bl->section[e] >= 0)) continue;
    seen[mt] = 1;
    if (!dtm_acc_moduli(a, mt, f, &s[mt].m))
      rc = cache_get(cache, dtm_analysis_mesh(a), bl->type, mt, f == DTM_FORM_BAR ? 0 : s[mt].m.mu / s[mt].m.modulus,
                     &s[mt].t);
  }
  for (int k = 0; k < nmat && !rc; k++)
    for (int l = 0; s[k].t && l < levels && !(sr->st && sr->st->added); l++) {
      double dt = sr->st && sr->st->target > 0 ? sr->st->target : sr->dt * ldexp(1.0, sr->st && sr->st->level ? l : 0);
      curve_get(cache, s[k].t, PI * freq * dt);
    }
  free(seen);
  return rc;
}

/* Whether element e of block bl takes the measured table (slots s). */
static int is_measured(const dtm_block *bl, size_t e, const slot *s) {
  int mt = bl->mat[e];
  return mt >= 0 && !(bl->section && bl->section[e] >= 0) && s[mt].t && s[mt].t->shape == DTM_LATTICE_MEASURED;
}

/* Where smooth_pass sums: block b (bl, its first element i0, nv corners)
 * of the mesh, the nodes split into parts (the analysis's), the element
 * values v (smoothed in place) and measures meas, the node sums sum and w. */
typedef struct {
  const dtm_mesh *mesh;
  const dtm_node_parts *parts;
  const dtm_block *bl;
  int b, nv, first;
  size_t i0;
  const slot *s;
  const double *meas;
  double *v, *sum, *w;
} smooth_sums;

/* Element e's value into its corners in [lo, hi). */
static void smooth_element(const smooth_sums *ss, size_t e, size_t lo, size_t hi) {
  if (!is_measured(ss->bl, e, ss->s)) return;
  double x = ss->v[ss->i0 + e], m = ss->meas[ss->i0 + e];
  const size_t *c = ss->bl->conn + e * (size_t)ss->bl->nn;
  for (int j = 0; j < ss->nv; j++) {
    if (c[j] < lo || c[j] >= hi) continue;
    ss->sum[c[j]] += m * x;
    if (ss->first) ss->w[c[j]] += m;
  }
}

/* The sums of part p's nodes (its listed elements, then its core), then
 * each node's mean, sum / w, in place of its sum: the quotient each
 * element around the node read before, divided once per node. */
static void smooth_part(const smooth_sums *ss, int p) {
  const size_t *list;
  size_t lo, hi, nlist, e0, e1;
  dtm_mesh_node_part(ss->parts, p, &lo, &hi);
  dtm_mesh_node_part_elements(ss->parts, p, ss->b, &list, &nlist, &e0, &e1);
  for (size_t j = 0; j < nlist; j++) smooth_element(ss, list[j], lo, hi);
  for (size_t e = e0; e < e1; e++) smooth_element(ss, e, lo, hi);
  for (size_t v = lo; v < hi && v < ss->mesh->nnodes; v++) ss->sum[v] /= ss->w[v];
}

/* One pass of smooth_sizes: at each corner node the volume-weighted mean
 * of its elements' values v (each part of the nodes summed on a thread of
 * its own, each node's sum in the elements' order: the serial loop's
 * bits), then at each element the mean over its nv corners (sum holds the
 * nodes' means then: nodes of no measured element get 0/0, never read). sum and w:
 * [nnodes] work arrays; w, the volumes around each node, is the same at
 * every pass: summed at the first (first set) and kept. */
static void smooth_pass(const smooth_sums *ss) {
  const dtm_block *bl = ss->bl;
  const size_t nn = (size_t)bl->nn, i0 = ss->i0;
  const int nv = ss->nv;
  const slot *s = ss->s;
  double *v = ss->v, *sum = ss->sum, *w = ss->w;
  memset(sum, 0, ss->mesh->nnodes * sizeof *sum);
  if (ss->first) memset(w, 0, ss->mesh->nnodes * sizeof *w);
#pragma omp parallel for schedule(dynamic, 1)
  for (int p = 0; p < ss->parts->n; p++) smooth_part(ss, p);
  const long long n = (long long)bl->n;
#pragma omp parallel for schedule(static)
  for (long long e = 0; e < n; e++) {
    if (!is_measured(bl, (size_t)e, s)) continue;
    double x = 0;
    for (int j = 0; j < nv; j++) x += sum[bl->conn[(size_t)e * nn + (size_t)j]];
    v[i0 + (size_t)e] = x / nv;
  }
}

/* The spacing at which each element of block bl under the measured table
 * enters it, into hs: the root mean square of the mean edges of the
 * elements around it, SMOOTH_PASSES rings deep, volume-weighted. The table
 * gives a mesh's error at the root mean square of its mean edges; a wave
 * crossing the mesh sees the elements within a fraction of its wavelength
 * so, not one element alone. sum and w: [nnodes] work arrays. */
static void smooth_sizes(const dtm_analysis *a, int b, size_t i0, const slot *s, const double *meas, const double *edge,
                         double *hs, double *sum, double *w) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  const dtm_block *bl = &mesh->blocks[b];
  int d, nv;
  dtm_elem_info(dtm_elem_parent(bl->type), &d, &nv);
  smooth_sums ss = {mesh, dtm_analysis_node_parts(a), bl, b, nv, 1, i0, s, meas, hs, sum, w};
  const long long n = (long long)bl->n;
#pragma omp parallel for schedule(static)
  for (long long e = 0; e < n; e++) hs[i0 + (size_t)e] = edge[i0 + (size_t)e] * edge[i0 + (size_t)e];
  for (int p = 0; p < SMOOTH_PASSES; p++, ss.first = 0) smooth_pass(&ss);
#pragma omp parallel for schedule(static)
  for (long long e = 0; e < n; e++) hs[i0 + (size_t)e] = sqrt(hs[i0 + (size_t)e]);
}

/* Whether any slot of the block's materials takes the measured table. */
static int any_measured(const slot *s, int nmat) {
  for (int k = 0; k < nmat; k++)
    if (s[k].t && s[k].t->shape == DTM_LATTICE_MEASURED) return 1;
  return 0;
}

/* What phase_errors needs besides the analysis. */
typedef struct {
  dtm_formulation f;   /* the elastic formulation */
  double freq;         /* Hz */
  const step_rule *sr; /* the steps */
  const double *meas;  /* [nel] element measures, m^d */
  const double *edge;  /* [nel] mean edges, m */
  double *hs;          /* [nel] the measured table's spacings (smooth_sizes), m */
  double *alone_err;   /* [nel] or NULL: each element's error at its own mean edge as well (the
                          measured table's elements; the others' is err's) */
  int measured_any;    /* set when an element takes the measured table */
  double sc[2];        /* --calibrate's ratios of P and S (1: none) */
  table_cache cache;   /* the tables and curves met */
} phase_run;

/* The errors of block bl into err (INFINITY where it does not apply,
 * counted in *skip; NaN unresolved); the smallest shear wavelength over
 * mean edge into *pwmin. The element loop runs on the OpenMP threads,
 * reading the tables and curves prepared for it. */
static void block_errors(const dtm_block *bl, size_t i0, const slot *s, phase_run *p, double *err, size_t *skip,
                         double *pwmin) {
  const long long n = (long long)bl->n;
  size_t sk = 0;
  double pw = INFINITY;
#pragma omp parallel for schedule(static) reduction(+ : sk) reduction(min : pw)
  for (long long e = 0; e < n; e++) {
    size_t i = i0 + (size_t)e;
    int mt = bl->mat[e];
    err[i] = INFINITY; /* not applicable */
    if (mt < 0 || (bl->section && bl->section[e] >= 0) || !s[mt].t) {
      sk++;
      if (p->alone_err) p->alone_err[i] = INFINITY;
      continue;
    }
    const dtm_elastic_moduli *m = &s[mt].m;
    int measured = s[mt].t->shape == DTM_LATTICE_MEASURED;
    double dt, speed, h = measured ? p->hs[i] : dtm_acc_spacing(s[mt].t, bl->dim, p->meas[i], p->edge[i]);
    pw = fmin(pw, (p->f == DTM_FORM_BAR ? m->cd : sqrt(m->mu / m->rho)) / (p->freq * p->edge[i]));
    element_step(p->sr, i, m->rho * p->meas[i], &dt, &speed);
    err[i] = isnan(dt) ? NAN : element_phase(&p->cache, s[mt].t, m, h, p->freq, dt, speed, p->sc);
    if (p->alone_err) /* the same element alone: only the measured table's spacing differs */
      p->alone_err[i] =
          measured && !isnan(dt) ? element_phase(&p->cache, s[mt].t, m, p->edge[i], p->freq, dt, speed, p->sc) : err[i];
  }
  *skip += sk, *pwmin = fmin(*pwmin, pw);
}

/* Per element phase errors into err[nel] (NaN: unresolved; the elements
 * it does not apply to are skipped and counted in *skipped); the smallest
 * shear wavelength over mean edge into *per_wave; work: [2 nnodes]. */
static int phase_errors(const dtm_analysis *a, phase_run *p, double *err, double *work, size_t *skipped,
                        double *per_wave) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  int nmat = dtm_analysis_scene(a)->nmaterials;
  slot *s = malloc(((size_t)nmat + 1) * sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t i0 = 0, skip = 0;
  double pwmin = INFINITY;
  int rc = DTM_OK;
  for (int b = 0; b < mesh->nblocks && !rc; i0 += mesh->blocks[b++].n) {
    const dtm_block *bl = &mesh->blocks[b];
    rc = prepare_block(a, p->f, p->freq, p->sr, bl, i0, &p->cache, s);
    if (rc) break;
    if (any_measured(s, nmat)) smooth_sizes(a, b, i0, s, p->meas, p->edge, p->hs, work, work + mesh->nnodes);
    p->measured_any |= any_measured(s, nmat);
    block_errors(bl, i0, s, p, err, &skip, &pwmin);
  }
  *skipped = skip;
  *per_wave = isfinite(pwmin) ? pwmin : NAN;
  free(s);
  return rc;
}

/* The wave (branch), direction and model of the worst element's error. */
static int describe_worst(const dtm_analysis *a, phase_run *p, dtm_measure *m) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  size_t i0 = 0, i = m->worst_element;
  int b = 0;
  while (i >= i0 + mesh->blocks[b].n) i0 += mesh->blocks[b++].n;
  const dtm_block *bl = &mesh->blocks[b];
  int mt = bl->mat[i - i0];
  dtm_elastic_moduli mod;
  const dtm_dispersion *t;
  if (dtm_acc_moduli(a, mt, p->f, &mod)) return DTM_OK;
  DTM_CHECK(cache_get(&p->cache, mesh, bl->type, mt, p->f == DTM_FORM_BAR ? 0 : mod.mu / mod.modulus, &t));
  double dt, speed, e[2] = {0, 0};
  double h = t->shape == DTM_LATTICE_MEASURED ? p->hs[i] : dtm_acc_spacing(t, bl->dim, p->meas[i], p->edge[i]);
  int dir[2] = {0, 0};
  element_step(p->sr, i, mod.rho * p->meas[i], &dt, &speed);
  for (int w = 0; w < (p->f == DTM_FORM_BAR ? 1 : 2); w++) {
    double c = (w ? sqrt(mod.mu / mod.rho) : mod.cd) * speed;
    e[w] = p->sc[w] * dtm_dispersion_worst_dir(t, w, 2 * PI * p->freq * h / c, PI * p->freq * dt, &dir[w]);
  }
  m->wave = fabs(e[1]) > fabs(e[0]);
  memcpy(m->direction, t->dir[dir[m->wave]], sizeof m->direction);
  m->model = t->shape;
  return DTM_OK;
}

/* Worst (largest magnitude, signed), median of the signed errors (so a
 * mesh whose waves all lag shows a negative median, as its worst) and
 * counts. scratch may be err itself (the values are moved down, never
 * ahead of where they are read): err is then reordered. */
static void phase_summary(const double *err, size_t n, double *scratch, dtm_measure *m) {
  size_t k = 0;
  m->worst = 0;
  for (size_t i = 0; i < n; i++) {
    if (isinf(err[i])) continue;
    m->elements++;
    if (isnan(err[i])) {
      m->unresolved++;
      continue;
    }
    scratch[k++] = err[i];
    if (fabs(err[i]) >= fabs(m->worst)) m->worst = err[i], m->worst_element = i;
  }
  m->median = median(scratch, k);
  if (m->unresolved) m->worst = NAN;
  if (!k && !m->unresolved) m->worst = NAN;
  m->in_band = m->elements > 0 && !m->unresolved && fabs(m->worst) <= m->band_hi;
}

/* The worst of the errors err[n] each element at its own spacing into
 * m->worst_alone (NaN when one is unresolved) and its element. */
static void alone_summary(const double *err, size_t n, dtm_measure *m) {
  m->worst_alone = 0, m->worst_alone_element = m->worst_element;
  for (size_t i = 0; i < n; i++) {
    if (isinf(err[i])) continue;
    if (isnan(err[i])) {
      m->worst_alone = NAN;
      return;
    }
    if (fabs(err[i]) > fabs(m->worst_alone)) m->worst_alone = err[i], m->worst_alone_element = i;
  }
}

/* The worst element alone (m->worst_alone): the elements of the measured
 * table each at its own mean edge instead of the average over its rings
 * (phase_errors' alone_err, from the same pass); the other models'
 * elements already are at their own spacing. */
static void alone_worst(const phase_run *p, size_t n, dtm_measure *m) {
  m->worst_alone = m->worst, m->worst_alone_element = m->worst_element;
  m->rings = p->measured_any ? SMOOTH_PASSES : 0;
  if (p->measured_any && m->elements) alone_summary(p->alone_err, n, m);
}

/* Why there is no default frequency (it is taken from the elements with a
 * dispersion model, and no element has one): how many elements are in
 * sections, of types without a model, or without E, nu and rho. */
static void no_model_note(const dtm_analysis *a, char *note, size_t len) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  size_t sec = 0, type = 0, n = dtm_analysis_nelements(a);
  for (int b = 0; b < mesh->nblocks; b++) {
    const dtm_block *bl = &mesh->blocks[b];
    if (!dtm_dispersion_has_model(bl->type)) type += bl->n;
    for (size_t e = 0; dtm_dispersion_has_model(bl->type) && bl->section && e < bl->n; e++) sec += bl->section[e] >= 0;
  }
  snprintf(note, len,
           "no <time f-max>, and no default frequency: the default comes from the elements with a dispersion model, "
           "and none of the %zu has one (%zu in sections: shells, membranes, trusses and beams have none; %zu of "
           "types without one; %zu without E, nu or rho)",
           n, sec, type, n - sec - type);
}

/* What verify --accuracy's reports said of the prediction (--verified), into the note at len. */
static void verified_note(const dtm_scene *s, dtm_measure *m, size_t len) {
  static const char *const names[2] = {"P", "S"};
  for (int b = 0; b < 2; b++) {
    double r = s->phase_ratio[b];
    if (r == 0 || !isfinite(r)) continue;
    len += (size_t)snprintf(m->note + len, sizeof m->note - len,
                            "%sverify --accuracy measured %.3g x the predicted %s error (%s)%s", len ? "; " : "", r,
                            names[b], fabs(r - 1) <= 0.2 ? "agrees" : "DISAGREES",
                            s->phase_calibrate ? ", applied (--calibrate)" : ", not applied (--calibrate applies it)");
    if (len >= sizeof m->note) return;
  }
}

/* The note of a phase measure: the default frequency, what was not measured, verify's word. */
static void phase_note(const dtm_analysis *a, size_t skipped, dtm_measure *m) {
  size_t len;
  if (m->f_default)
    snprintf(m->note, sizeof m->note,
             "no <time f-max>: at the mesh's default %.4g Hz (at least %g cells per shear wavelength in "
             "every element)",
             m->f, dtm_analysis_scene(a)->elements_per_wavelength);
  len = strlen(m->note);
  if (skipped)
    snprintf(m->note + len, sizeof m->note - len,
             "%s%zu elements not measured (a section, no E/nu/rho, or a type without a dispersion model)",
             len ? "; " : "", skipped);
  verified_note(dtm_analysis_scene(a), m, strlen(m->note));
}

static int wave_measure(const dtm_analysis *a, int k, double freq, const dtm_measure_step *st, dtm_measures *ms) {
  dtm_measure m = {.kind = DTM_MEASURE_PHASE,
                   .effect = k,
                   .group = -1,
                   .band_lo = -DTM_BAND_PHASE,
                   .band_hi = DTM_BAND_PHASE,
                   .f = freq,
                   .wave = -1,
                   .model = -1};
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  size_t n = dtm_analysis_nelements(a), skipped, nw = 2 * mesh->nnodes;
  int kept = dtm_analysis_measure(a) && dtm_analysis_size(a); /* else gathered after err */
  double *err = malloc(((kept ? 3 : 5) * n + nw + 1) * sizeof *err);
  if (!err) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  step_rule sr = {st, dtm_analysis_recommended(a), dtm_analysis_local_step(a)};
  phase_run p = {.f = dtm_acc_formulation(a, k), .sr = &sr, .sc = {branch_scale(a, 0), branch_scale(a, 1)}};
  p.hs = err + n + nw;
  p.alone_err = err + (kept ? 2 : 4) * n + nw;
  element_sizes(a, err + 2 * n + nw, &p.meas, &p.edge);
  int rc = DTM_OK;
  if (!(m.f > 0)) m.f = dtm_analysis_scene(a)->f_max;
  if (!(m.f > 0)) rc = default_frequency(a, p.f, p.meas, &m.f), m.f_default = 1;
  p.freq = m.f;
  m.per_wavelength = NAN;
  if (!rc) rc = phase_errors(a, &p, err, err + n, &skipped, &m.per_wavelength);
  if (!rc) phase_summary(err, n, err, &m); /* in place: err is not read again */
  if (!rc && isfinite(m.worst) && m.elements) rc = describe_worst(a, &p, &m);
  if (!rc) alone_worst(&p, n, &m);
  cache_free(&p.cache);
  free(err);
  if (rc) return rc;
  if (m.f_default && !isfinite(m.f)) return no_model_note(a, m.note, sizeof m.note), push(ms, &m);
  phase_note(a, skipped, &m);
  return push(ms, &m);
}

/* Cohesive: elements per zone from the effect's own view, one measure per
 * group that has any (the group of the element; -1 for none). */
static int zone_measures(const dtm_analysis *a, int k, dtm_measures *ms) {
  const double *res = dtm_analysis_resolution(a, k);
  size_t n = dtm_analysis_nelements(a);
  if (!res) return DTM_OK;
  int ng = dtm_analysis_mesh(a)->ngroups;
  double *v = malloc((n + 1) * sizeof *v);
  if (!v) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int rc = DTM_OK;
  for (int g = -1; g < ng && !rc; g++) {
    dtm_measure m = {.kind = DTM_MEASURE_ZONE, .effect = k, .group = g, .worst = INFINITY, .band_lo = 5, .band_hi = 10};
    for (size_t i = 0; i < n; i++) {
      if (!isfinite(res[i]) || dtm_analysis_group(a, i) != g) continue;
      if (res[i] < m.worst) m.worst = res[i], m.worst_element = i;
      v[m.elements++] = res[i];
    }
    if (!m.elements) continue;
    m.median = median(v, m.elements);
    m.in_band = m.worst >= m.band_lo;
    rc = push(ms, &m);
  }
  free(v);
  return rc;
}

/* Diffusivity of material mat for the built-in diffusion effect name, NaN
 * when unknown. */
static double diffusivity(const dtm_material *m, const char *effect) {
  if (!strcmp(effect, "thermal"))
    return dtm_material_value(m, "conductivity") /
           (dtm_material_value(m, "rho") * dtm_material_value(m, "heat-capacity"));
  if (!strcmp(effect, "hydraulic"))
    return dtm_material_value(m, "permeability") /
           (dtm_material_value(m, "viscosity") * dtm_material_value(m, "storage"));
  return NAN;
}

static int diffusion_measure(const dtm_analysis *a, int k, dtm_measures *ms) {
  const dtm_scene *s = dtm_analysis_scene(a);
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  dtm_measure m = {.kind = DTM_MEASURE_DIFFUSION,
                   .effect = k,
                   .group = -1,
                   .worst = NAN,
                   .median = NAN,
                   .band_lo = DTM_BAND_DIFFUSION,
                   .band_hi = INFINITY};
  const char *name = dtm_analysis_effect(a, k)->name;
  if (!(s->duration > 0)) {
    snprintf(m.note, sizeof m.note, "no <time duration>: the diffusion length sqrt(D t) needs one");
    return push(ms, &m);
  }
  size_t n = dtm_analysis_nelements(a), i = 0;
  double *v = malloc((n + 1) * sizeof *v), x[3 * DTM_MAX_NODES];
  if (!v) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  m.worst = INFINITY;
  for (int b = 0; b < mesh->nblocks; b++)
    for (size_t e = 0; e < mesh->blocks[b].n; e++, i++) {
      const dtm_block *bl = &mesh->blocks[b];
      double D = bl->mat[e] < 0 ? NAN : diffusivity(&s->materials[bl->mat[e]].m, name);
      if (!(D > 0)) continue;
      for (int j = 0; j < bl->nn; j++) memcpy(x + 3 * j, mesh->xyz + 3 * bl->conn[e * bl->nn + j], 3 * sizeof *x);
      double across = sqrt(D * s->duration) / dtm_elem_mean_edge(bl->type, x);
      if (across < m.worst) m.worst = across, m.worst_element = i;
      v[m.elements++] = across;
    }
  m.median = median(v, m.elements);
  free(v);
  if (!m.elements) m.worst = NAN;
  m.in_band = m.worst >= m.band_lo;
  return push(ms, &m);
}

int dtm_measures_compute(const dtm_analysis *a, double f, const dtm_measure_step *st, dtm_measures **out) {
  dtm_measures *ms = calloc(1, sizeof *ms);
  if (!ms) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int rc = DTM_OK;
  for (int k = 0; k < dtm_analysis_neffects(a) && !rc; k++) {
    const dtm_effect_class *c = dtm_analysis_effect(a, k);
    if (!strcmp(c->name, "elastic"))
      rc = wave_measure(a, k, f, st, ms);
    else if (!strcmp(c->name, "cohesive"))
      rc = zone_measures(a, k, ms);
    else if (c->scheme == DTM_SCHEME_FORWARD_EULER)
      rc = diffusion_measure(a, k, ms);
  }
  if (rc) {
    dtm_measures_destroy(&ms);
    return dtm_error_trace(rc, __FILE__, __LINE__, __func__);
  }
  *out = ms;
  return DTM_OK;
}

void dtm_measures_destroy(dtm_measures **p) {
  if (!*p) return;
  free((*p)->m);
  free(*p);
  *p = NULL;
}

const char *dtm_measure_name(int kind) {
  return kind == DTM_MEASURE_PHASE  ? "phase-speed error"
         : kind == DTM_MEASURE_ZONE ? "elements per cohesive zone"
                                    : "elements across sqrt(D t)";
}
