/* The node counts a model fixes, and the ones refine sets itself. Two kinds
 * of curve keep their node count whatever the size field: the transfinite
 * ones (Transfinite Curve, with a progression, a bump or a beta law), whose
 * count Gmsh's API can set, and the layers of an extrusion (Extrude with
 * Layers{}), which it cannot. Gmsh 4.8's API can list neither, so:
 *  - the curves are meshed in a child process at two uniform sizes, and a
 *    curve whose node count does not follow is fixed (the probe);
 *  - the transfinite attributes are read from the model written as
 *    .geo_unrolled (Gmsh writes every entity's "Transfinite Line/Surface"
 *    there, with the count, the law and its coefficient, and the corners of
 *    a surface): a fixed curve that is not transfinite is a layer curve.
 * A transfinite surface ties its curves together: opposite sides must have
 * the same number of segments (3 corners: the two sides at the first
 * corner), a side being the curves between two corners. For a size field
 * a curve keeps as many nodes as its law allows while its smallest segment
 * grows by the largest growth the field asks at its nodes (size over
 * current size): with a uniform law the segments divided by that growth,
 * with a progression (whose smallest segment L (r - 1) / (r^(n-1) - 1)
 * grows fast as nodes go) or a bump (Gmsh's spacing, a parabola along the
 * curve whose shape does not depend on the count, integrated here) fewer
 * nodes removed; then every tie whose
 * two sides differ brings the longer one down to the shorter's total,
 * shared over its curves in proportion to their counts, until all ties
 * hold (the counts only fall, so this ends). The law and coefficient of
 * each curve stay. A surface with a curve that is not transfinite, or ties
 * that cannot hold (a side of more curves than the other has segments),
 * keep the model's counts.
 * A layer curve of segment length s caps every element of the entities it
 * bounds near s: when a node there needs a size above s, no remesh meets
 * the target, and the layers the target needs are named instead. */
#define _DEFAULT_SOURCE /* mkstemps() */
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

#define PROBE_NODES 2e5 /* at most this many nodes on the curves at the probe's finer size */
#define MIN_JUDGED 3.0  /* a curve is judged when the finer size puts at least this many segments on it */
#define GROWS 1.001     /* a node whose field exceeds its size by this needs a larger element */

/* One curve of the model that has a length. */
typedef struct {
  int tag;       /* Gmsh tag */
  double length; /* its mesh length, m */
  int fixed;     /* node count that does not follow the size (the probe), 0: it follows */
  int tf;        /* 1: transfinite (from .geo_unrolled) */
  int nodes;     /* transfinite: the model's count */
  int law;       /* transfinite: 1 progression, 2 bump, 3 beta; negative: reversed */
  double coef;   /* transfinite: the law's coefficient */
  int kept;      /* 1: on a transfinite surface refine cannot tie: never changed */
  int plan;      /* the node count planned for the next remesh */
  int set;       /* the count last set on the model (its own until refine sets one) */
  double need;   /* layer curves: the largest size a node of its entities needs, m */
  int nent;      /* entities whose mesh its count sets */
  long *ent;     /* [nent] their keys, dim * KEY + tag: the curve, its points, the surfaces on it
                    and their volumes (transfinite curves: only transfinite ones) (owned) */
} curve;

#define KEY 100000000L /* entity key = dim * KEY + tag */

/* Two sides of a transfinite surface that must have as many segments. */
#define SIDE_MAX 16
typedef struct {
  int n[2];           /* curves on each side */
  int c[2][SIDE_MAX]; /* their indices */
} tie;

/* The largest growth, and size needed, over the nodes of one entity. */
typedef struct {
  long key;    /* dim * KEY + tag */
  double grow; /* size over current size (1: none asked) */
  double need; /* the largest size asked where a node must grow, m (0: none) */
} ent_stat;

struct dtm_structure {
  int n;          /* curves */
  curve *c;       /* [n] */
  int nties;      /* ties */
  tie *ties;      /* [nties] */
  int ntf[2];     /* transfinite surfaces and volumes */
  int *tf[2];     /* [ntf] their tags */
  int nstat;      /* entities the curves' counts set */
  ent_stat *stat; /* [nstat] sorted by key */
  double h[2];    /* the probe's two uniform sizes, m */
  int caps[2];    /* 1: a layer curve ([0]) or a transfinite one ([1]) keeps a node below its need */
};

static int find_curve(const dtm_structure *s, int tag) {
  for (int i = 0; i < s->n; i++)
    if (s->c[i].tag == tag) return i;
  return -1;
}

/* ---- the probe: which curves keep their count ------------------------- */

static int curves_make(const dtm_geo *g, dtm_structure *s) {
  double lmin = INFINITY, total = 0;
  s->c = calloc((size_t)g->nent + 1, sizeof *s->c);
  if (!s->c) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < g->nent; i++)
    if (g->ent[i].dim == 1 && g->ent[i].size > 0) {
      curve *c = &s->c[s->n];
      c->tag = g->ent[i].tag, c->length = g->ent[i].size, s->n++;
      lmin = fmin(lmin, c->length), total += c->length;
    }
  s->h[1] = fmax(lmin / (2 * MIN_JUDGED), total / PROBE_NODES);
  s->h[0] = 2.2 * s->h[1];
  return DTM_OK;
}

static size_t curve_nodes(int tag) {
  size_t *tags = NULL, n = 0, nc = 0, np = 0;
  double *xyz = NULL, *par = NULL;
  int ierr = 0;
  gmshModelMeshGetNodes(&tags, &n, &xyz, &nc, &par, &np, 1, tag, 1, 0, &ierr);
  gmshFree(tags), gmshFree(xyz), gmshFree(par);
  return ierr ? 0 : n;
}

/* The spacing law of curve tag's mesh, from its segments in the order of
 * the curve's parameter: uniform (law 1, coef 1), a progression (law 1,
 * coef the ratio of a segment to the one before), or a bump (law 2, coef
 * the end segment over the middle one, Gmsh's meaning). */
#define PROBE_MAX_NODES 4096
static void fit_law(int tag, double *law, double *coef) {
  size_t *tags = NULL, n = 0, nc = 0, np = 0;
  double *xyz = NULL, *par = NULL, seg[PROBE_MAX_NODES];
  int ierr = 0, order[PROBE_MAX_NODES];
  *law = 1, *coef = 1;
  gmshModelMeshGetNodes(&tags, &n, &xyz, &nc, &par, &np, 1, tag, 1, 1, &ierr);
  int ok = !ierr && n >= 4 && n <= PROBE_MAX_NODES && np == n;
  for (int i = 0; ok && i < (int)n; i++) { /* insertion sort by parameter */
    int j = i;
    while (j > 0 && par[order[j - 1]] > par[i]) order[j] = order[j - 1], j--;
    order[j] = i;
  }
  for (size_t k = 0; ok && k + 1 < n; k++) {
    const double *a = xyz + 3 * order[k], *b = xyz + 3 * order[k + 1];
    seg[k] = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
  }
  int m = (int)n - 1;
  if (ok) {
    double r = pow(seg[m - 1] / seg[0], 1.0 / (m - 1)), worst = 0, mid = seg[m / 2], sym = 0;
    for (int k = 0; k < m; k++) worst = fmax(worst, fabs(seg[k] / (seg[0] * pow(r, k)) - 1));
    for (int k = 0; k < m; k++) sym = fmax(sym, fabs(seg[k] / seg[m - 1 - k] - 1));
    if (worst < 1e-3)
      *coef = fabs(r - 1) < 1e-6 ? 1 : r;
    else if (sym < 1e-3)
      *law = 2, *coef = seg[0] / mid;
  }
  gmshFree(tags), gmshFree(xyz), gmshFree(par);
}

/* In the child: the curves' node counts at the two sizes, each the only
 * size source (a constant background field in place of the model's own,
 * whose sizes would otherwise hold a curve's count as a fixed one does);
 * out[4 i] = the count when curve i kept it (and is long enough to judge),
 * else 0; then, for a kept count, whether setting it by the API moves it
 * (out[4 i + 1]: a transfinite curve, 0 for an extrusion's), and the law
 * and coefficient of its spacing (out[4 i + 2], out[4 i + 3]): Gmsh does
 * not write every transfinite curve into .geo_unrolled. */
static int probe_curves(void *arg, double *out, size_t nout) {
  const dtm_structure *s = arg;
  static const char *const off[] = {"Mesh.MeshSizeFromPoints", "Mesh.MeshSizeFromCurvature", "Mesh.MeshSizeMin"};
  int ierr = 0, field = gmshModelMeshFieldAdd("MathEval", -1, &ierr), n = (int)(nout / 4);
  for (int k = 0; k < 3; k++) gmshOptionSetNumber(off[k], 0, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeFactor", 1, &ierr);
  gmshModelMeshFieldSetAsBackgroundMesh(field, &ierr);
  for (int pass = 0; pass < 3; pass++) {
    char h[64];
    snprintf(h, sizeof h, "%.17g", s->h[pass > 0]);
    gmshModelMeshFieldSetString(field, "F", h, &ierr);
    dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
    gmshModelMeshClear(NULL, 0, &ierr);
    gmshOptionSetNumber("Mesh.MeshSizeMax", s->h[pass > 0], &ierr);
    gmshModelMeshGenerate(1, &ierr);
    DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "meshing the curves for the probe");
    for (int i = 0; i < n; i++) {
      double count = (double)curve_nodes(s->c[i].tag), *o = out + 4 * i;
      if (pass == 0) o[0] = count;
      if (pass == 1) o[0] = o[0] == count && s->c[i].length / s->h[1] >= MIN_JUDGED ? count : 0;
      if (pass == 1 && o[0] > 0) fit_law(s->c[i].tag, &o[2], &o[3]);
      if (pass == 1 && o[0] > 0) gmshModelMeshSetTransfiniteCurve(s->c[i].tag, (int)o[0] + 2, "Progression", 1, &ierr);
      if (pass == 2) o[1] = o[0] > 0 && count == o[0] + 2;
    }
  }
  return DTM_OK;
}

/* ---- the transfinite attributes from .geo_unrolled ---------------------- */

static int law_of(const char *word) {
  return !strcmp(word, "Progression") ? 1 : !strcmp(word, "Bump") ? 2 : !strcmp(word, "Beta") ? 3 : 1;
}

/* "Transfinite Line {T} = N [Using Law C];" */
static void parse_line(dtm_structure *s, const char *p) {
  int tag, nodes, i;
  char law[32] = "Progression";
  double coef = 1.0;
  if (sscanf(p, "Transfinite Line {%d} = %d Using %31s %lf", &tag, &nodes, law, &coef) < 2) return;
  if ((i = find_curve(s, abs(tag))) < 0) return;
  curve *c = &s->c[i];
  c->tf = 1, c->nodes = c->set = nodes, c->coef = coef;
  c->law = law_of(law) * (tag < 0 ? -1 : 1);
}

/* A surface's boundary curves in loop order, signed by orientation. */
static int surface_loop(int tag, int **curves, size_t *n) {
  int dt[2] = {2, tag}, ierr = 0, *out = NULL;
  size_t nout = 0;
  gmshModelGetBoundary(dt, 2, &out, &nout, 0, 1, 0, &ierr);
  if (ierr) return gmshFree(out), -1;
  *n = nout / 2;
  *curves = malloc((*n + 1) * sizeof **curves);
  for (size_t i = 0; *curves && i < *n; i++) (*curves)[i] = out[2 * i + 1];
  gmshFree(out);
  return *curves ? 0 : -1;
}

/* The point a signed curve starts from. */
static int start_point(int signed_tag) {
  int dt[2] = {1, abs(signed_tag)}, ierr = 0, *out = NULL, p = -1;
  size_t n = 0;
  gmshModelGetBoundary(dt, 2, &out, &n, 0, 0, 0, &ierr);
  if (!ierr && n >= 2) p = signed_tag > 0 || n < 4 ? out[1] : out[3];
  gmshFree(out);
  return p;
}

/* Side k of the loop (sides start at the curves whose start point is a
 * corner) into t->c[slot]. */
static int side_of(const int *idx, const int *starts, int nsides, int ncurves, int k, tie *t, int slot) {
  int next = k + 1 < nsides ? starts[k + 1] : starts[0] + ncurves, n = 0;
  for (int i = starts[k]; i < next && n < SIDE_MAX; i++) t->c[slot][n++] = idx[i % ncurves];
  t->n[slot] = n;
  return n == next - starts[k];
}

static int add_tie(dtm_structure *s, const int *idx, const int *starts, int ns, int n, int a, int b) {
  tie t;
  if (!side_of(idx, starts, ns, n, a, &t, 0) || !side_of(idx, starts, ns, n, b, &t, 1)) return 0;
  tie *grown = realloc(s->ties, ((size_t)s->nties + 1) * sizeof *grown);
  if (!grown) return 0;
  s->ties = grown, s->ties[s->nties++] = t;
  return 1;
}

/* Tie the opposite sides of a transfinite surface whose loop is curves[n]
 * and whose corners are given (ncorners > 0) or its curves' start points;
 * a surface with a curve that is not transfinite keeps its curves. */
static void tie_sides(dtm_structure *s, const int *curves, int n, const int *corners, int ncorners) {
  int starts[8], ns = 0, idx[64], ok = n <= 64;
  for (int i = 0; i < n && ok; i++) {
    idx[i] = find_curve(s, abs(curves[i]));
    ok = idx[i] >= 0 && s->c[idx[i]].tf;
    int p = start_point(curves[i]), corner = ncorners == 0;
    for (int k = 0; k < ncorners; k++) corner |= corners[k] == p;
    if (corner && ns < 8) starts[ns++] = i;
  }
  ok = ok && (ns == 3 || ns == 4) && add_tie(s, idx, starts, ns, n, 0, 2);
  if (ok && ns == 4) ok = add_tie(s, idx, starts, ns, n, 1, 3);
  for (int i = 0; i < n && !ok && n <= 64; i++) /* keep them all as the model has them */
    if (idx[i] >= 0) s->c[idx[i]].kept = 1;
}

/* Record a transfinite surface (k = 0) or volume (1). */
static void keep_tag(dtm_structure *s, int k, int tag) {
  int *grown = realloc(s->tf[k], ((size_t)s->ntf[k] + 1) * sizeof *grown);
  if (grown) s->tf[k] = grown, s->tf[k][s->ntf[k]++] = tag;
}

/* "Transfinite Surface {S} [= {c1,c2,c3[,c4]}];" */
static void parse_surface(dtm_structure *s, const char *p) {
  int tag, corners[4], nc = 0, *curves = NULL;
  size_t n = 0;
  if (sscanf(p, "Transfinite Surface {%d}", &tag) != 1) return;
  keep_tag(s, 0, tag);
  const char *eq = strstr(p, "= {");
  if (eq) nc = sscanf(eq, "= {%d,%d,%d,%d}", &corners[0], &corners[1], &corners[2], &corners[3]);
  if (nc < 0) nc = 0;
  if (surface_loop(tag, &curves, &n)) return;
  tie_sides(s, curves, (int)n, corners, nc);
  free(curves);
}

/* Gmsh writes the model as .geo_unrolled; its transfinite lines are read
 * first, then the surfaces that tie them. */
static int read_transfinite(dtm_structure *s) {
  const char *tmp = getenv("TMPDIR");
  char path[512], line[1024];
  int tag;
  snprintf(path, sizeof path, "%s/dtmap-model-XXXXXX.geo_unrolled", tmp && tmp[0] ? tmp : "/tmp");
  int fd = mkstemps(path, 13), ierr = 0;
  if (fd < 0) return DTM_ERR(DTM_ERR_INTERNAL, "cannot make a temporary file in %s", tmp && tmp[0] ? tmp : "/tmp");
  close(fd);
  dtm_gmsh_log_reset();
  gmshWrite(path, &ierr); /* a surface GEO cannot express is logged and skipped: its curves are still written */
  dtm_gmsh_log_reset();
  FILE *f = ierr ? NULL : fopen(path, "r");
  for (int pass = 0; f && pass < 2; pass++, rewind(f))
    while (fgets(line, sizeof line, f))
      if (!pass && !strncmp(line, "Transfinite Line", 16))
        parse_line(s, line);
      else if (pass && !strncmp(line, "Transfinite Surface", 19))
        parse_surface(s, line);
      else if (!pass && sscanf(line, "Transfinite Volume {%d}", &tag) == 1)
        keep_tag(s, 1, tag);
  if (f) fclose(f);
  unlink(path);
  return DTM_OK;
}

/* Gmsh's bump on [0, 1]: the spacing -a (x - 1/2)^2 + b for coefficient
 * coef (src Mesh/meshGEdge.cpp, with the count and the length scaled
 * out: they scale a and b alike), times its density's integral's inverse
 * at k / segs: the smallest of the segments of a curve of unit length. */
#define BUMP_SAMPLES 2048
static double bump_smallest(double coef, int segs) {
  double s = sqrt(fabs(coef - 1)), a, b, cum[BUMP_SAMPLES + 1] = {0}, prev = 0, small = 1;
  a = coef > 1 ? -4 * s * atan2(1.0, s) : 2 * s * log(fabs((1 + 1 / s) / (1 - 1 / s)));
  b = -a / (4 * (coef - 1));
  for (int i = 1; i <= BUMP_SAMPLES; i++) { /* midpoint rule on the density 1 / spacing */
    double x = (i - 0.5) / BUMP_SAMPLES;
    cum[i] = cum[i - 1] + 1.0 / (-a * (x - 0.5) * (x - 0.5) + b) / BUMP_SAMPLES;
  }
  for (int k = 1, i = 1; k <= segs; k++) {
    double want = cum[BUMP_SAMPLES] * k / segs;
    while (i < BUMP_SAMPLES && cum[i] < want) i++;
    double x = (i - 1 + (want - cum[i - 1]) / (cum[i] - cum[i - 1])) / BUMP_SAMPLES;
    small = fmin(small, x - prev), prev = x;
  }
  return small;
}

/* The smallest segment of a curve of length L with n nodes under its law. */
static double smallest_segment(const curve *c, int n) {
  int segs = n - 1, law = abs(c->law);
  double r = c->coef;
  if (segs < 1) return c->length;
  if (law == 1 && r > 0 && fabs(r - 1) > 1e-12) {
    double a = c->length * (r - 1) / (pow(r, segs) - 1);
    return fmin(a, a * pow(r, segs - 1));
  }
  if (law == 2 && r > 0 && fabs(r - 1) > 1e-12) return c->length * bump_smallest(r, segs);
  return c->length / segs;
}

/* ---- layer curves: the extrusions' fixed counts ------------------------ */

/* Growth the field asks at node v (size over current size; 1 when none). */
static double growth(const double *size, const double *cur, size_t v) {
  return isfinite(size[v]) && isfinite(cur[v]) && cur[v] > 0 ? size[v] / cur[v] : 1.0;
}

static int has_tag(const int *tags, int n, int tag) {
  for (int i = 0; i < n; i++)
    if (tags[i] == tag) return 1;
  return 0;
}

/* Whether entity (dim, tag) belongs to curve c's keys: any entity for a
 * layer curve, transfinite ones for a transfinite curve. */
static int keeps(const dtm_structure *s, const curve *c, int dim, int tag) {
  return !c->tf || dim < 2 || has_tag(s->tf[dim - 2], s->ntf[dim - 2], tag);
}

static int add_key(curve *c, int max, int dim, int tag) {
  if (c->nent < max) c->ent[c->nent++] = dim * KEY + tag;
  return c->nent < max;
}

/* A volume's key and its boundary surfaces' (a structured volume's count
 * along a curve sets the elements at all its faces). */
static void add_volume(curve *c, int max, int tag) {
  int dt[2] = {3, tag}, *out = NULL, ierr = 0;
  size_t n = 0;
  add_key(c, max, 3, tag);
  gmshModelGetBoundary(dt, 2, &out, &n, 0, 0, 0, &ierr);
  for (size_t i = 0; !ierr && i + 1 < n; i += 2) add_key(c, max, 2, abs(out[i + 1]));
  gmshFree(out);
}

/* The keys of the entities whose mesh curve c's count sets. */
static int curve_keys(const dtm_structure *s, const dtm_geo *g, curve *c) {
  int *up = NULL, *down = NULL, ierr = 0, max = 128;
  size_t nu = 0, nd = 0;
  const dtm_geo_entity *e = dtm_geo_find(g, 1, c->tag);
  if (!(c->ent = malloc((size_t)max * sizeof *c->ent))) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  add_key(c, max, 1, c->tag);
  for (int k = 0; e && k < e->npoints; k++) add_key(c, max, 0, e->points[k]);
  gmshModelGetAdjacencies(1, c->tag, &up, &nu, &down, &nd, &ierr);
  for (size_t i = 0; !ierr && i < nu; i++) {
    int *vu = NULL, *vd = NULL;
    size_t nvu = 0, nvd = 0;
    if (!keeps(s, c, 2, up[i])) continue;
    add_key(c, max, 2, up[i]);
    gmshModelGetAdjacencies(2, up[i], &vu, &nvu, &vd, &nvd, &ierr);
    for (size_t j = 0; !ierr && j < nvu; j++)
      if (keeps(s, c, 3, vu[j])) add_volume(c, max, vu[j]);
    gmshFree(vu), gmshFree(vd);
  }
  gmshFree(up), gmshFree(down);
  return DTM_OK;
}

static int cmp_long(const void *x, const void *y) {
  long u = *(const long *)x, v = *(const long *)y;
  return u < v ? -1 : u > v;
}

static ent_stat *stat_find(const dtm_structure *s, long key) {
  size_t lo = 0, hi = (size_t)s->nstat;
  while (lo < hi) {
    size_t mid = (lo + hi) / 2;
    if (s->stat[mid].key < key)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < (size_t)s->nstat && s->stat[lo].key == key ? &s->stat[lo] : NULL;
}

/* The entities of every fixed or transfinite curve, once each, sorted. */
static int stats_make(dtm_structure *s, const dtm_geo *g) {
  int total = 0;
  for (int i = 0; i < s->n; i++) {
    if (!s->c[i].fixed && !s->c[i].tf) continue;
    DTM_CHECK(curve_keys(s, g, &s->c[i]));
    total += s->c[i].nent;
  }
  long *keys = malloc(((size_t)total + 1) * sizeof *keys);
  s->stat = malloc(((size_t)total + 1) * sizeof *s->stat);
  if (!keys || !s->stat) return free(keys), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  total = 0;
  for (int i = 0; i < s->n; i++)
    for (int k = 0; k < s->c[i].nent; k++) keys[total++] = s->c[i].ent[k];
  qsort(keys, (size_t)total, sizeof *keys, cmp_long);
  for (int k = 0; k < total; k++)
    if (!s->nstat || keys[k] != s->stat[s->nstat - 1].key) s->stat[s->nstat++] = (ent_stat){keys[k], 1.0, 0.0};
  free(keys);
  return DTM_OK;
}

/* The growth and need of each entity over its nodes, for a size field. */
static void stats_fill(dtm_structure *s, const dtm_geo *g, const double *size, const double *cur) {
  for (int k = 0; k < s->nstat; k++) s->stat[k].grow = 1.0, s->stat[k].need = 0.0;
  for (size_t v = 0; v < g->nnodes; v++) {
    ent_stat *e = g->node_tag[v] >= 0 ? stat_find(s, g->node_dim[v] * KEY + g->node_tag[v]) : NULL;
    double gr = growth(size, cur, v);
    if (!e) continue;
    e->grow = fmax(e->grow, gr);
    if (gr >= GROWS) e->need = fmax(e->need, size[v]);
  }
}

/* The largest growth (need: 0) or needed size (need: 1) over curve c's entities. */
static double curve_max(const dtm_structure *s, const curve *c, int need) {
  double m = need ? 0.0 : 1.0;
  for (int k = 0; k < c->nent; k++) {
    const ent_stat *e = stat_find(s, c->ent[k]);
    if (e) m = fmax(m, need ? e->need : e->grow);
  }
  return m;
}

/* For each layer curve (fixed, not transfinite): the size its entities'
 * nodes need, and whether it is above the curve's segment, which caps it. */
static void layer_needs(dtm_structure *s, const dtm_geo *g, const double *size, const double *cur) {
  stats_fill(s, g, size, cur);
  for (int i = 0; i < s->n; i++) {
    curve *c = &s->c[i];
    if (!c->fixed && !c->tf) continue;
    c->need = curve_max(s, c, 1);
    double seg = c->tf ? smallest_segment(c, c->nodes) : c->fixed > 1 ? c->length / (c->fixed - 1) : INFINITY;
    if (c->need > seg) s->caps[c->tf] = 1;
  }
}

/* ---- the structure ------------------------------------------------------ */

/* A curve from the probe's numbers o[4]: fixed, and transfinite (its count
 * set by the API moved it) with the law its mesh shows, until
 * .geo_unrolled gives the model's own. */
static void settable(curve *c, const double *o) {
  c->fixed = (int)o[0];
  if (!(o[1] > 0)) return;
  c->tf = 1, c->nodes = c->set = c->fixed, c->law = (int)o[2], c->coef = o[3];
}

int dtm_gmsh_structure(const dtm_geo *g, const double *size, const double *cur, dtm_structure **out) {
  *out = NULL;
  if (!g) return DTM_OK;
  dtm_structure *s = calloc(1, sizeof *s);
  double *fixed = NULL;
  int r = s ? curves_make(g, s) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t nout = 4 * (size_t)s->n;
  if (r == DTM_OK && !(fixed = calloc(nout + 1, sizeof *fixed))) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK && s->n && dtm_gmsh_contained_probe("probing the curves' node counts", probe_curves, s, fixed, nout))
    dtm_error_clear(), memset(fixed, 0, (nout + 1) * sizeof *fixed); /* no probe: no curve is fixed */
  for (int i = 0; r == DTM_OK && i < s->n; i++) settable(&s->c[i], fixed + 4 * i);
  free(fixed);
  if (r == DTM_OK && s->n) r = read_transfinite(s);
  if (r == DTM_OK) r = stats_make(s, g);
  if (r == DTM_OK) layer_needs(s, g, size, cur);
  if (r) return dtm_gmsh_structure_destroy(&s), r;
  *out = s;
  return DTM_OK;
}

void dtm_gmsh_structure_destroy(dtm_structure **ps) {
  if (!*ps) return;
  for (int i = 0; i < (*ps)->n; i++) free((*ps)->c[i].ent);
  free((*ps)->c);
  free((*ps)->ties);
  free((*ps)->tf[0]), free((*ps)->tf[1]), free((*ps)->stat);
  free(*ps);
  *ps = NULL;
}

int dtm_gmsh_counts_cap(const dtm_structure *s, int keep_counts) {
  return s && (s->caps[0] || (keep_counts && s->caps[1]));
}

int dtm_gmsh_fixed_curves(const dtm_structure *s, int transfinite, dtm_fixed_curve *out, int max) {
  int n = 0;
  for (int i = 0; s && i < s->n; i++) {
    const curve *c = &s->c[i];
    if (!(c->fixed || c->tf) || (c->tf != 0) != (transfinite != 0)) continue;
    if (n < max) out[n] = (dtm_fixed_curve){c->tag, c->length, c->tf ? c->nodes : c->fixed, c->need};
    n++;
  }
  return n;
}

/* ---- counts for a size field -------------------------------------------- */

/* The most nodes, at most the model's, whose smallest segment is grow
 * times the model's own. */
static int count_for(const curve *c, double grow) {
  double want = grow * smallest_segment(c, c->nodes) * (1 - 1e-9);
  int n = c->nodes;
  while (n > 2 && smallest_segment(c, n) < want) n--;
  return n;
}

static int side_sum(const dtm_structure *s, const tie *t, int k) {
  int sum = 0;
  for (int i = 0; i < t->n[k]; i++) sum += s->c[t->c[k][i]].plan - 1;
  return sum;
}

/* Bring side k of t down to total segments, shared over its curves in
 * proportion to their segments (largest remainders); 0 when it has more
 * curves than segments to share. */
static int shrink_side(dtm_structure *s, const tie *t, int k, int total) {
  int have = side_sum(s, t, k), given = 0, n = t->n[k];
  if (total < n) return 0;
  for (int i = 0; i < n; i++)
    if (s->c[t->c[k][i]].kept) return 0;
  double rem[SIDE_MAX];
  for (int i = 0; i < n; i++) {
    curve *c = &s->c[t->c[k][i]];
    double share = (double)total * (c->plan - 1) / have;
    int segs = share < 1 ? 1 : (int)share;
    rem[i] = share - segs, c->plan = segs + 1, given += segs;
  }
  while (given < total) { /* the largest remainder gets one more */
    int best = 0;
    for (int i = 1; i < n; i++)
      if (rem[i] > rem[best]) best = i;
    s->c[t->c[k][best]].plan++, rem[best] = -1, given++;
  }
  return given == total;
}

/* Make every tie hold by bringing its longer side down to the shorter's
 * total; 0 when some tie cannot hold. */
static int hold_ties(dtm_structure *s) {
  for (int changed = 1, sweeps = 0; changed && sweeps < 1000; sweeps++) {
    changed = 0;
    for (int j = 0; j < s->nties; j++) {
      const tie *t = &s->ties[j];
      int a = side_sum(s, t, 0), b = side_sum(s, t, 1);
      if (a == b) continue;
      if (!shrink_side(s, t, a > b ? 0 : 1, a > b ? b : a)) return 0;
      changed = 1;
    }
  }
  for (int j = 0; j < s->nties; j++)
    if (side_sum(s, &s->ties[j], 0) != side_sum(s, &s->ties[j], 1)) return 0;
  return 1;
}

int dtm_gmsh_counts_plan(dtm_structure *s, const dtm_geo *g, const double *size, const double *cur) {
  stats_fill(s, g, size, cur);
  for (int i = 0; i < s->n; i++) {
    curve *c = &s->c[i];
    if (!c->tf) continue;
    c->plan = c->kept ? c->nodes : count_for(c, curve_max(s, c, 0));
  }
  if (!hold_ties(s))
    for (int i = 0; i < s->n; i++) s->c[i].plan = s->c[i].nodes; /* the model's own counts hold */
  return DTM_OK;
}

static const char *law_name(int law) {
  int a = abs(law);
  return a == 2 ? "Bump" : a == 3 ? "Beta" : "Progression";
}

int dtm_gmsh_counts_apply(dtm_structure *s, int *changed) {
  int ierr = 0;
  *changed = 0;
  for (int i = 0; i < s->n; i++) {
    curve *c = &s->c[i];
    if (!c->tf || c->plan < 2 || c->plan == c->set) continue;
    gmshModelMeshSetTransfiniteCurve(c->tag, c->plan, law_name(c->law), c->law < 0 ? -c->coef : c->coef, &ierr);
    DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "setting a transfinite curve's node count");
    c->set = c->plan;
  }
  for (int i = 0; i < s->n; i++) *changed += s->c[i].tf && s->c[i].set != s->c[i].nodes;
  return DTM_OK;
}

int dtm_gmsh_counts_list(const dtm_structure *s, dtm_count_change **out, int *n) {
  *n = 0;
  *out = malloc(((size_t)s->n + 1) * sizeof **out);
  if (!*out) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < s->n; i++)
    if (s->c[i].tf && s->c[i].set != s->c[i].nodes)
      (*out)[(*n)++] = (dtm_count_change){s->c[i].tag, s->c[i].nodes, s->c[i].set};
  return DTM_OK;
}
