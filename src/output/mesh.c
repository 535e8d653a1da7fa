/* The output .msh and its .opt: gather the contract views (dt,
 * characteristic length, limiting effect, size suggestion) plus one
 * "dt <effect>" view per limiting effect, "shape limited" (the feature
 * kind, 1 flat angle, 2 small angle, 3 short curve, 4 thin) where there
 * are such elements, one "dt <solver>" view per solver of run
 * --solver-rule, and for a 3D mesh with trusses or membranes
 * DTM_VIEW_DT_SKIN (dt over its solid elements, drawn last); write them (after the mesh, or alone in a views-only
 * file) to a temporary file, then rename into place. The encoding is the
 * caller's choice, else the scene's <output format>, else binary above
 * DTM_BINARY_ABOVE elements and ASCII below (small files stay readable).
 * The scene's input mesh is never overwritten. The same views, styled the
 * same way, can instead be added to the open Gmsh session of a script.
 *
 * A write that fails says so about the target the user named, not about
 * its temporary, and leaves both older files (.msh and .opt) as they were:
 * the .opt is written before the .msh is renamed into place. */
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "dtmap/progress.h"
#include "dtmap/util.h"
#include "dtmap/units.h"

static int check_target(const dtm_scene *s, const char *path) { return dtm_output_path_check(s, path, ".msh", NULL); }

/* Raise code with text, keeping the traceback of the pending error (lines
 * "file:line in func"). */
static int reraise(int code, const char *text) {
  char trace[4096], file[512], func[128];
  int line, raised = 0;
  snprintf(trace, sizeof trace, "%s", dtm_error_traceback());
  dtm_error_clear();
  char *save = NULL;
  for (char *l = strtok_r(trace, "\n", &save); l; l = strtok_r(NULL, "\n", &save)) {
    if (sscanf(l, "%511[^:]:%d in %127s", file, &line, func) != 3) continue;
    if (raised++)
      dtm_error_trace(code, file, line, func);
    else
      dtm_error_raise(code, file, line, func, "%s", text);
  }
  return raised ? code : DTM_ERR(code, "%s", text);
}

/* The pending error r of a write to w's temporary, naming w's target
 * instead: the user's path, which keeps its older file. */
static int name_target(int r, const dtm_atomic *w) {
  const char *msg = dtm_error_message(), *at = r ? strstr(msg, w->tmp) : NULL;
  if (!at) return r;
  char text[8192];
  snprintf(text, sizeof text, "%.*s%s%s", (int)(at - msg), msg, w->path, at + strlen(w->tmp));
  return reraise(r, text);
}

/* Node data over the nodes that carry a finite value. */
static size_t node_view(const dtm_mesh *m, const double *src, size_t *tags, double *vals) {
  size_t k = 0;
  for (size_t v = 0; v < m->nnodes; v++)
    if (isfinite(src[v])) tags[k] = m->node_tags[v], vals[k++] = src[v];
  return k;
}

/* Whether src[n] has a finite value. */
static int any_finite(const double *src, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (isfinite(src[i])) return 1;
  return 0;
}

/* The views and what they point to: element views share one tag array and
 * are written straight from the analysis' arrays (integers and the finite
 * subset of an effect's values included: the writer converts and filters),
 * so writing copies no per-element value. */
typedef struct {
  size_t *etags, *ntags;    /* element tags [nel], node tags [nnodes] */
  int etags_own;            /* etags is a copy (several blocks), else the one block's own tags */
  double *nvals;            /* node values [nnodes] */
  size_t *dtags;            /* node tags of the nodal-dt view [nnodes] */
  double *dvals;            /* its values [nnodes] */
  size_t *btags;            /* element tags of the "below target" view [nel] */
  double *bvals;            /* their steps [nel] */
  double below_at;          /* its threshold, s: the target, or the 1 % quantile */
  char (*names)[96];        /* "dt <effect>" names [neffects] */
  dtm_view *views;          /* [10 + 2 neffects] */
  size_t *stags;            /* tags of the shape-limited elements */
  double *svals;            /* their feature (dtm_feature_kind) */
  size_t *ttags;            /* tags of the thickness-limited elements */
  double *tvals;            /* the local thickness there, in the scene's length unit */
  size_t *itags;            /* tags of the flagged elements [nflagged] */
  double *ivals;            /* their smallest scaled Jacobians [nflagged] */
  size_t *mtags;            /* node tags of the point masses [nnodes] */
  double *mvals;            /* the masses, in the scene's mass unit [nnodes] */
  size_t *ktags;            /* tags of the solid elements of DTM_VIEW_DT_SKIN */
  double *kvals;            /* their steps */
  char (*solver_names)[32]; /* "dt <solver>" names [nsolvers] */
  const char *units;        /* the scene's system of units (dtm_scene.units): the views' lengths */
  const char *mass_unit;    /* the unit of the views' masses (dtm_scene_mass_unit) */
} view_set;

static void free_views(view_set *vs) {
  free(vs->btags);
  free(vs->bvals);
  free(vs->stags);
  free(vs->svals);
  free(vs->ttags);
  free(vs->tvals);
  free(vs->dtags);
  free(vs->dvals);
  if (vs->etags_own) free(vs->etags);
  free(vs->ntags);
  free(vs->nvals);
  free(vs->names);
  free(vs->itags);
  free(vs->ivals);
  free(vs->mtags);
  free(vs->mvals);
  free(vs->ktags);
  free(vs->kvals);
  free(vs->solver_names);
  free(vs->views);
}

static int alloc_views(const dtm_analysis *a, view_set *vs) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t nel = dtm_analysis_nelements(a), nn = m->nnodes, ne = (size_t)dtm_analysis_neffects(a);
  vs->units = dtm_analysis_scene(a)->units;
  vs->mass_unit = dtm_scene_mass_unit(dtm_analysis_scene(a), m->dim);
  vs->etags_own = m->nblocks != 1; /* one block: its tags are the views' (no copy of nel tags) */
  vs->etags = vs->etags_own ? malloc((nel + 1) * sizeof *vs->etags) : m->blocks[0].tags;
  vs->ntags = malloc((nn + 1) * sizeof *vs->ntags);
  vs->nvals = malloc((nn + 1) * sizeof *vs->nvals);
  vs->dtags = malloc((nn + 1) * sizeof *vs->dtags);
  vs->dvals = malloc((nn + 1) * sizeof *vs->dvals);
  vs->btags = malloc((nel + 1) * sizeof *vs->btags);
  vs->bvals = malloc((nel + 1) * sizeof *vs->bvals);
  vs->names = calloc(ne + 1, sizeof *vs->names);
  vs->views = calloc(2 * ne + 20, sizeof *vs->views);
  if (!vs->etags || !vs->ntags || !vs->nvals || !vs->names || !vs->views || !vs->dtags || !vs->dvals || !vs->btags ||
      !vs->bvals)
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  return DTM_OK;
}

/* "invalid elements": the smallest scaled Jacobian of each element dtmap
 * analysed although it is inverted at a node (dtm_mesh_check); no view
 * when there is none. */
static int invalid_view(const dtm_mesh *m, view_set *vs, int *k) {
  if (!m->nflagged) return DTM_OK;
  vs->itags = malloc(m->nflagged * sizeof *vs->itags);
  vs->ivals = malloc(m->nflagged * sizeof *vs->ivals);
  if (!vs->itags || !vs->ivals) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < m->nflagged; i++) {
    const dtm_flagged *f = &m->flagged[i];
    vs->itags[i] = m->blocks[f->block].tags[f->index];
    vs->ivals[i] = f->min_jacobian;
  }
  vs->views[(*k)++] = (dtm_view){"invalid elements", 0, vs->itags, vs->ivals, m->nflagged, NULL, 0};
  return DTM_OK;
}

/* The contract views, then nodal dt, subcycling and added mass. */
static int mesh_views(const dtm_results *r, view_set *vs) {
  const dtm_analysis *a = r->analysis;
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t nel = dtm_analysis_nelements(a), first = 0;
  for (int b = 0; vs->etags_own && b < m->nblocks; first += m->blocks[b].n, b++)
    memcpy(vs->etags + first, m->blocks[b].tags, m->blocks[b].n * sizeof(size_t));
  size_t nnv = node_view(m, dtm_analysis_size_suggestion(a), vs->ntags, vs->nvals);
  size_t ndv = node_view(m, dtm_analysis_nodal(a), vs->dtags, vs->dvals);
  int k = 0;
  vs->views[k++] = (dtm_view){"dt", 0, vs->etags, dtm_analysis_dt(a), nel, NULL, 0};
  vs->views[k++] = (dtm_view){"characteristic length", 0, vs->etags, dtm_analysis_length(a), nel, NULL, 0};
  vs->views[k++] = (dtm_view){"limiting effect", 0, vs->etags, NULL, nel, dtm_analysis_limiting(a), 0};
  vs->views[k++] = (dtm_view){"size suggestion", 1, vs->ntags, vs->nvals, nnv, NULL, 0};
  if (ndv) vs->views[k++] = (dtm_view){"nodal dt", 1, vs->dtags, vs->dvals, ndv, NULL, 0};
  if (r->cost) vs->views[k++] = (dtm_view){"subcycling level", 0, vs->etags, NULL, nel, r->cost->subcycling.level, 0};
  if (r->cost && r->cost->mass)
    vs->views[k++] = (dtm_view){"added mass", 0, vs->etags, r->cost->mass->added, nel, NULL, 0};
  return k;
}

/* DTM_VIEW_NODE_MASS: the point masses the mesh carries (refine's added
 * mass, or the input's), kg, at the nodes that carry one, so that the mesh
 * read back carries them again (src/gmsh/node_mass.c). */
static int point_mass_view(const dtm_analysis *a, view_set *vs, int *k) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  const double *pm = dtm_analysis_point_masses(a);
  size_t n = 0;
  if (!pm) return DTM_OK;
  vs->mtags = malloc((m->nnodes + 1) * sizeof *vs->mtags), vs->mvals = malloc((m->nnodes + 1) * sizeof *vs->mvals);
  if (!vs->mtags || !vs->mvals) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < m->nnodes; v++)
    if (pm[v] > 0) vs->mtags[n] = m->node_tags[v], vs->mvals[n++] = pm[v];
  if (n) vs->views[(*k)++] = (dtm_view){DTM_VIEW_NODE_MASS, 1, vs->mtags, vs->mvals, n, NULL, 0};
  return DTM_OK;
}

/* "dt <effect>" of each limiting effect and each accuracy view, over the
 * elements where they are finite; appended from views[k]. */
static int effect_views(const dtm_analysis *a, view_set *vs, int *k) {
  size_t nel = dtm_analysis_nelements(a), ne = (size_t)dtm_analysis_neffects(a);
  for (size_t j = 0; j < 2 * ne; j++) {
    const dtm_effect_class *c = dtm_analysis_effect(a, (int)(j % ne));
    const double *src = j < ne ? dtm_analysis_effect_dt(a, (int)j) : dtm_analysis_resolution(a, (int)(j - ne));
    if (!src || !any_finite(src, nel)) continue;
    if (j < ne) snprintf(vs->names[j], sizeof vs->names[j], "dt %s", c->name);
    vs->views[(*k)++] = (dtm_view){j < ne ? vs->names[j] : c->indicator.view, 0, vs->etags, src, nel, NULL, 1};
  }
  return DTM_OK;
}

/* "below target [s]": with a target, the elements below it on the one
 * basis of the recommendation (safety x their own safe step, the count
 * the summary and report give as below_target), with that step; without
 * one, the 1 % smallest element steps. It goes first among the views:
 * Gmsh draws views in order, and the faint (translucent) dt view drawn over
 * it in 3D must not hide it in the depth buffer. */
static void below_view(const dtm_analysis *a, const dtm_output_part *part, view_set *vs, int *k) {
  size_t nel = dtm_analysis_nelements(a), n = 0;
  const double *dt = dtm_analysis_dt(a), *own = dtm_analysis_local_step(a);
  double target = dtm_analysis_advice_target(a), safety = dtm_analysis_scene(a)->safety;
  vs->below_at = target > 0 ? target : part ? part->below_at : dtm_analysis_dt_quantile(a);
  for (size_t i = 0; i < nel; i++) {
    double step = target > 0 ? safety * own[i] : dt[i];
    if (step < vs->below_at || (target <= 0 && step == vs->below_at))
      vs->btags[n] = vs->etags[i], vs->bvals[n++] = step;
  }
  if (!n) return;
  memmove(vs->views + 1, vs->views, (size_t)*k * sizeof *vs->views);
  vs->views[0] =
      (dtm_view){target > 0 ? DTM_VIEW_BELOW_TARGET : DTM_VIEW_SMALLEST, 0, vs->btags, vs->bvals, n, NULL, 0};
  (*k)++;
}

/* "shape limited": the feature kind on the shape-limited elements. */
static int shape_view(const dtm_analysis *a, view_set *vs, int *k) {
  size_t n;
  const dtm_shape_limited *sl = dtm_analysis_shape_limited(a, &n);
  if (!n) return DTM_OK;
  vs->stags = malloc(n * sizeof *vs->stags), vs->svals = malloc(n * sizeof *vs->svals);
  if (!vs->stags || !vs->svals) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t j = 0; j < n; j++) vs->stags[j] = dtm_analysis_tag(a, sl[j].element), vs->svals[j] = sl[j].feature;
  vs->views[(*k)++] = (dtm_view){"shape limited", 0, vs->stags, vs->svals, n, NULL, 0};
  return DTM_OK;
}

/* "thickness limited": the local thickness (m) on the elements that the
 * thickness of their layer caps (the thin feature). */
static int thickness_view(const dtm_analysis *a, view_set *vs, int *k) {
  size_t n, m = 0;
  const dtm_shape_limited *sl = dtm_analysis_shape_limited(a, &n);
  for (size_t j = 0; j < n; j++) m += sl[j].feature == DTM_FEATURE_THIN;
  if (!m) return DTM_OK;
  vs->ttags = malloc(m * sizeof *vs->ttags), vs->tvals = malloc(m * sizeof *vs->tvals);
  if (!vs->ttags || !vs->tvals) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  m = 0;
  for (size_t j = 0; j < n; j++)
    if (sl[j].feature == DTM_FEATURE_THIN)
      vs->ttags[m] = dtm_analysis_tag(a, sl[j].element), vs->tvals[m++] = sl[j].size;
  vs->views[(*k)++] = (dtm_view){"thickness limited", 0, vs->ttags, vs->tvals, m, NULL, 0};
  return DTM_OK;
}

/* "dt <solver>" of each solver's own rule (run --solver-rule), over the
 * elements the rule covers. */
static int solver_views(const dtm_analysis *a, const dtm_deck_steps *st, int n, view_set *vs, int *k) {
  if (n <= 0) return DTM_OK;
  vs->solver_names = calloc((size_t)n, sizeof *vs->solver_names);
  if (!vs->solver_names) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < n && i < 3; i++) {
    snprintf(vs->solver_names[i], sizeof vs->solver_names[i], "dt %s", st[i].solver);
    vs->views[(*k)++] = (dtm_view){vs->solver_names[i], 0, vs->etags, st[i].dt, dtm_analysis_nelements(a), NULL, 1};
  }
  return DTM_OK;
}

/* Whether a 3D mesh m has trusses or membranes, drawn inside its solid
 * elements' faint skin (DTM_VIEW_DT_SKIN). */
static int has_skin(const dtm_mesh *m);

/* DTM_VIEW_DT_SKIN, last: dt over the solid elements alone, for a 3D mesh
 * with trusses or membranes. Gmsh draws the views in their order and a
 * translucent face hides what is drawn after it, so the faint skin of the
 * solid elements comes last, and dt itself draws the sections alone,
 * opaque, with the colour bar: they show inside the solid. A model-based
 * view of its own (a script reads it as any other), not a copy the .opt
 * makes. */
static int skin_view(const dtm_analysis *a, view_set *vs, int *k) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  const double *dt = dtm_analysis_dt(a);
  size_t n = 0, i = 0;
  if (!has_skin(m)) return DTM_OK;
  vs->ktags = malloc((dtm_analysis_nelements(a) + 1) * sizeof *vs->ktags);
  vs->kvals = malloc((dtm_analysis_nelements(a) + 1) * sizeof *vs->kvals);
  if (!vs->ktags || !vs->kvals) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int b = 0; b < m->nblocks; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++, i++)
      if (m->blocks[b].dim == 3) vs->ktags[n] = vs->etags[i], vs->kvals[n++] = dt[i];
  if (n) vs->views[(*k)++] = (dtm_view){DTM_VIEW_DT_SKIN, 0, vs->ktags, vs->kvals, n, NULL, 1};
  return DTM_OK;
}

static int build_views(const dtm_results *r, const dtm_output_part *part, const dtm_deck_steps *solvers, int nsolvers,
                       view_set *vs, int *nviews) {
  DTM_CHECK(alloc_views(r->analysis, vs));
  *nviews = mesh_views(r, vs);
  DTM_CHECK(point_mass_view(r->analysis, vs, nviews));
  DTM_CHECK(shape_view(r->analysis, vs, nviews));
  DTM_CHECK(thickness_view(r->analysis, vs, nviews));
  DTM_CHECK(effect_views(r->analysis, vs, nviews));
  below_view(r->analysis, part, vs, nviews);
  DTM_CHECK(invalid_view(dtm_analysis_mesh(r->analysis), vs, nviews));
  const double *curv = dtm_analysis_curvature_ratio(r->analysis);
  /* "curvature": min det J / max det J of each second-order element (1:
   * straight-sided), only when the mesh has some (src/analysis/curvature.c) */
  if (curv)
    vs->views[(*nviews)++] = (dtm_view){"curvature", 0, vs->etags, curv, dtm_analysis_nelements(r->analysis), NULL, 1};
  DTM_CHECK(solver_views(r->analysis, solvers, nsolvers, vs, nviews));
  return skin_view(r->analysis, vs, nviews);
}

/* The unit of a view's values, from its name: s, the scene's length unit
 * (units: the scene's system) or mass_unit, or "" (a count, a kind). */
static const char *unit_of(const char *name, const char *units, const char *mass_unit) {
  if (!strcmp(name, "dt") || !strncmp(name, "dt ", 3) || !strcmp(name, "nodal dt") || strstr(name, "[s]")) return "s";
  if (!strcmp(name, "characteristic length") || !strcmp(name, "size suggestion") || !strcmp(name, "thickness limited"))
    return dtm_units_name(units, DTM_UNIT_LENGTH);
  if (!strncmp(name, "added mass", 10)) return mass_unit;
  return "";
}

static int is_below(const char *name) {
  return !strcmp(name, DTM_VIEW_BELOW_TARGET) || !strcmp(name, DTM_VIEW_SMALLEST);
}

/* One display option of a view, with its comment in the .opt. */
typedef struct {
  dtm_view_option o; /* View[i].<name> = value */
  const char *why;   /* comment in the .opt, or NULL */
  char text[24];     /* o.text when it is made here (the Format with its unit) */
} styled;
#define MAX_STYLE 24

static void add_style(styled *s, int *k, const char *name, double number, const char *text, const char *why) {
  s[(*k)++] = (styled){{name, number, text}, why, ""};
}

/* Bit d set when mesh m has elements of dimension d below its own: the
 * trusses (bit 1) and membranes (bit 2) of sections. */
static unsigned lower_dims(const dtm_mesh *m) {
  unsigned bits = 0;
  for (int b = 0; b < m->nblocks; b++)
    if (m->blocks[b].dim < m->dim && m->blocks[b].n) bits |= 1u << m->blocks[b].dim;
  return bits;
}

static int has_skin(const dtm_mesh *m) { return m->dim == 3 && lower_dims(m); }

/* The smallest and largest finite values of view v into lo, hi; 1 when
 * they are positive (a log scale can show them). */
static int positive_range(const dtm_view *v, double *lo, double *hi) {
  *lo = INFINITY, *hi = -INFINITY;
  for (size_t i = 0; v->values && !v->ivalues && i < v->n; i++) {
    double x = v->values[i];
    if (!isfinite(x)) continue;
    if (x < *lo) *lo = x; /* comparisons, not fmin and fmax: a call each per value */
    if (x > *hi) *hi = x;
  }
  return *lo > 0 && *hi >= *lo && isfinite(*hi);
}

/* A step view's colour range, widened by RANGE_MARGIN (relative) beyond its
 * smallest and largest values: Gmsh puts the bounds of a log scale's
 * discrete intervals at 10^(log10 min + k (log10 max - log10 min) / n),
 * whose rounding may put the first bound above the smallest value and the
 * last below the largest, and an element outside every interval is not
 * drawn (the smallest and the largest steps were left white). The margin
 * is far above that rounding (about 1e-15) and far below what the colour
 * bar's three digits show. */
#define RANGE_MARGIN 1e-6
static void range_style(const dtm_view *of, styled *s, int *k) {
  double lo, hi;
  if (!positive_range(of, &lo, &hi)) return;
  add_style(s, k, "RangeType", 2, NULL, "custom: every step inside the colour range");
  add_style(s, k, "CustomMin", lo * (1 - RANGE_MARGIN), NULL, NULL);
  add_style(s, k, "CustomMax", hi * (1 + RANGE_MARGIN), NULL, NULL);
}

/* The 3D dt view and its skin: dt faint (only its skin drawn) and without
 * its colour bar, the below-target view showing the worst elements inside;
 * with trusses or membranes, dt draws them alone, opaque, with the colour
 * bar, and DTM_VIEW_DT_SKIN the faint skin of the solid elements. */
static void solid_style(int primary, const dtm_mesh *m, styled *s, int *k) {
  static const char *const solid[] = {"DrawTetrahedra", "DrawHexahedra", "DrawPrisms", "DrawPyramids"};
  if (primary && has_skin(m)) {
    add_style(s, k, "ColormapAlpha", 1, NULL, "dt: the trusses and membranes alone, opaque");
    add_style(s, k, "ShowScale", 1, NULL, NULL);
    for (int j = 0; j < 4; j++) add_style(s, k, solid[j], 0, NULL, NULL);
    return;
  }
  add_style(s, k, "ColormapAlpha", 0.2, NULL, "a faint skin over the worst elements");
  add_style(s, k, "DrawSkinOnly", 1, NULL, NULL);
  add_style(s, k, "ShowScale", 0, NULL, NULL);
}

/* The options of view i of vs over mesh m: unlit; steps on a log scale,
 * viridis (dark is small), over a range that holds every value (ranged: a
 * whole mesh's output; a distributed run's part knows only its own
 * values); colour bars in s or m; dt visible (a faint skin in 3D), the
 * below-target view too in 3D, the others hidden until ticked; where the
 * mesh has line elements (trusses) below its dimension, lines drawn as
 * thick tubes. Returns the count written to s[MAX_STYLE]. */
static int view_style(const view_set *vs, int nviews, int i, const dtm_mesh *m, int ranged, styled *s) {
  const char *name = vs->views[i].name, *u = unit_of(name, vs->units, vs->mass_unit);
  int primary = !strcmp(name, "dt"), skin = !strcmp(name, DTM_VIEW_DT_SKIN), below = is_below(name), k = 0;
  add_style(s, &k, "Light", 0, NULL, name);
  int step = !strcmp(u, "s");
  if (step) add_style(s, &k, "ScaleType", 2, NULL, "logarithmic");
  if (step) add_style(s, &k, "ColormapNumber", 23, NULL, "viridis: dark = small");
  add_style(s, &k, "Format", 0, NULL, NULL);
  snprintf(s[k - 1].text, sizeof s[k - 1].text, "%%.3g%s%s", u[0] ? " " : "", u);
  s[k - 1].o.text = s[k - 1].text;
  if (primary || below || skin)
    add_style(s, &k, "IntervalsType", 3, NULL, NULL), add_style(s, &k, "NbIso", 12, NULL, NULL);
  const dtm_view *of = &vs->views[i]; /* the skin takes dt's range, so its colours are dt's bar's */
  for (int j = 0; skin && j < nviews; j++)
    if (!strcmp(vs->views[j].name, "dt")) of = &vs->views[j];
  if (step && ranged) range_style(of, s, &k);
  add_style(s, &k, "Visible", primary || skin || (below && m->dim == 3), NULL, NULL);
  if ((primary || skin) && m->dim == 3) solid_style(primary, m, s, &k);
  if (lower_dims(m) & 2u) {
    add_style(s, &k, "LineType", 1, NULL, "trusses as tubes, seen inside the solid");
    add_style(s, &k, "LineWidth", 4, NULL, NULL);
  }
  return k;
}

/* The options of view i, each as "View[dtmap_v0 + i].option = value;"
 * (numbers with the fewest digits that read back the same). */
static void write_style(FILE *f, const view_set *vs, int nviews, int i, const dtm_mesh *m, int ranged) {
  styled s[MAX_STYLE];
  int n = view_style(vs, nviews, i, m, ranged, s);
  for (int k = 0; k < n; k++) {
    fprintf(f, "View[dtmap_v0 + %d].%s = ", i, s[k].o.name);
    if (s[k].o.text)
      fprintf(f, "\"%s\";", s[k].o.text);
    else {
      char num[40];
      for (int p = 6; p <= 17; p++)
        if (snprintf(num, sizeof num, "%.*g", p, s[k].o.number), strtod(num, NULL) == s[k].o.number) break;
      fprintf(f, "%s;", num);
    }
    if (s[k].why)
      fprintf(f, " // %s\n", s[k].why);
    else
      fputc('\n', f);
  }
}

/* dtmap's text view: the recommended step, the target and the worst element. */
/* The smallest step's element and group, and the elements below the target
 * (or in the 1 % view) out of all: this mesh's, or a distributed run's
 * whole mesh's. */
typedef struct {
  size_t element, below, elements; /* Gmsh tag, counts */
  char group[160];                 /* physical group, quotes replaced */
} annotated;

static void annotated_of(const dtm_analysis *a, const dtm_output_part *part, size_t nbelow, annotated *n) {
  size_t e = 0;
  char buf[32];
  dtm_analysis_dt_min(a, &e);
  n->element = part ? part->min_element : dtm_analysis_tag(a, e);
  n->below = part ? part->below : nbelow;
  n->elements = part ? part->elements : dtm_analysis_nelements(a);
  snprintf(n->group, sizeof n->group, "%s",
           part ? part->min_group
                : dtm_mesh_group_label(dtm_analysis_mesh(a), dtm_analysis_group(a, e), buf, sizeof buf));
  for (char *c = n->group; *c; c++)
    if (*c == '"') *c = '\'';
}

/* One line of dtmap's figures as Printf("..."); in the .opt: Gmsh prints
 * it in its message console and status bar on opening; dtmap's snapshots
 * draw the same lines at the top of the picture (src/gmsh/snapshot.c reads
 * them back). Printf formats its string: '%' is written "%%". */
static void figure_line(FILE *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void figure_line(FILE *f, const char *fmt, ...) {
  char text[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(text, sizeof text, fmt, ap);
  va_end(ap);
  fputs("Printf(\"", f);
  for (const char *c = text; *c; c++) fputs(*c == '%' ? "%%" : *c == '"' ? "'" : (char[2]){*c, 0}, f);
  fputs("\");\n", f);
}

/* The recommended step, the smallest element step and where it is, and
 * the target (or the 1 % view). Not a text view: a list-based view makes
 * gmsh.view.getModelData abort a script that reads every view (Gmsh 4.8). */
static void annotation(FILE *f, const dtm_results *r, const view_set *vs, const annotated *n) {
  const dtm_analysis *a = r->analysis;
  const dtm_scene *s = dtm_analysis_scene(a);
  fprintf(f, "// dtmap's figures, in Gmsh's message console and status bar:\n");
  figure_line(f, "recommended step %.3g s (safety %g x %s)", dtm_analysis_recommended(a), s->safety,
              dtm_analysis_basis(a));
  figure_line(f, "smallest element step %.3g s: element %zu, group %s", dtm_analysis_dt_min(a, NULL), n->element,
              n->group);
  if (s->target > 0)
    figure_line(f, "target %.3g s: %zu of %zu elements below (view '%s')", s->target, n->below, n->elements,
                DTM_VIEW_BELOW_TARGET);
  else
    figure_line(f, "no target: the 1 %% smallest steps, below %.3g s (view '%s')", vs->below_at, DTM_VIEW_SMALLEST);
}

/* Options Gmsh merges when it opens or merges X.msh. Views are addressed
 * relative to PostProcessing.NbViews, so the right views are styled however
 * many were loaded before: scalar views unlit, steps on a log scale (viridis:
 * dark is small) over a range that holds every step, colour bars in s or m,
 * dt visible (faint in 3D, where the below-target view shows the worst
 * elements inside), the others hidden until ticked, the mesh wireframe off;
 * then dtmap's figures, printed. Written to the temporary w, opened here and
 * flushed; the caller commits it once X.msh is in place (a failure here
 * removes it and leaves both). */
static int write_opt(const char *path, const dtm_results *r, const dtm_output_part *part, const view_set *vs,
                     int nviews, dtm_atomic *w) {
  char opt[DTM_PATH_MAX + 8];
  const dtm_mesh *mesh = dtm_analysis_mesh(r->analysis);
  size_t nbelow = 0;
  for (int i = 0; i < nviews; i++)
    if (is_below(vs->views[i].name)) nbelow = vs->views[i].n;
  snprintf(opt, sizeof opt, "%s.opt", path);
  DTM_CHECK(dtm_atomic_open(w, opt, "", 1));
  FILE *f = w->f;
  const char *base = strrchr(path, '/');
  fprintf(f, "// Written by dtmap: styles the %d views of %s, counted back from the last view loaded.\n", nviews,
          base ? base + 1 : path);
  fprintf(
      f,
      "dtmap_v0 = PostProcessing.NbViews - %d;\nMesh.SurfaceEdges = 0;\nMesh.VolumeEdges = 0;\nGeometry.Points = 0;\n",
      nviews);
  for (int i = 0; i < nviews; i++) write_style(f, vs, nviews, i, mesh, !part);
  annotated n;
  annotated_of(r->analysis, part, nbelow, &n);
  annotation(f, r, vs, &n);
  if (fflush(f) || ferror(f)) return dtm_atomic_commit(w); /* fails: removes it, names it and the reason */
  return DTM_OK;
}

/* The encoding of the output: the caller's, else the scene's, else by size. */
static dtm_msh_format format_of(const dtm_scene *s, size_t nel, const dtm_output_opts *o) {
  int f = o && o->format ? o->format : s->out_format;
  if (f == DTM_MSH_AUTO) f = nel > DTM_BINARY_ABOVE ? DTM_MSH_BINARY : DTM_MSH_ASCII;
  return (dtm_msh_format){f == DTM_MSH_BINARY, o ? o->views_only : 0, o && o->part ? o->part->part : 0};
}

static int check_views_only(const dtm_scene *s, const dtm_output_opts *o) {
  if (!o || !o->views_only || s->mesh) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: a views-only output needs a <mesh file=\"...\"> input to merge onto; this scene meshes "
                 "%s, whose mesh exists only in a full output",
                 s->path, s->geometry);
}

/* An output mesh being written: the mesh first (possibly long before the
 * views exist, possibly on a thread of its own while the analysis
 * computes), the views when the results are there. */
struct dtm_output_file {
  dtm_atomic w;                  /* the temporary beside the target */
  dtm_msh_format fmt;            /* its encoding; views_only: no mesh */
  const dtm_output_part *part;   /* a distributed run's part, or NULL */
  pthread_t writer;              /* the thread writing the mesh (background) */
  int writing;                   /* 1 until the writer is joined */
  int written;                   /* the writer's result */
  char msg[4096];                /* its error message (error records are per thread) */
  const dtm_deck_steps *solvers; /* run --solver-rule: the solvers' own steps (not owned) */
  int nsolvers;                  /* their count */
};

void dtm_output_solver_steps(dtm_output_file *f, const dtm_deck_steps *steps, int n) {
  f->solvers = steps, f->nsolvers = n;
}

static int write_mesh(dtm_output_file *f) {
  dtm_progress_begin("writing the mesh");
  int r = name_target(dtm_gmsh_write_mesh(f->w.tmp, f->fmt.binary), &f->w);
  dtm_progress_end();
  return r;
}

/* The background writer: the mesh, then the model released (no progress:
 * the library's stages belong to the caller's thread). */
static void *writer(void *arg) {
  dtm_output_file *f = arg;
  dtm_gmsh_lock(); /* the analysis's own calls into Gmsh wait (dtm_gmsh_gap) */
  /* the part of a distributed run is its own mesh; else a .msh read as it
   * is: its own mesh sections, copied (the model released first) */
  if (f->part)
    f->written = name_target(dtm_gmsh_write_mesh(f->w.tmp, f->fmt.binary), &f->w), dtm_gmsh_release();
  else
    f->written = name_target(dtm_gmsh_write_mesh_as_read(f->w.tmp, f->fmt.binary, 1), &f->w);
  snprintf(f->msg, sizeof f->msg, "%s", f->written ? dtm_error_message() : "");
  dtm_error_clear();
  dtm_gmsh_unlock();
  return NULL;
}

/* Wait for the background writer; its error, raised on this thread. */
static int join_writer(dtm_output_file *f) {
  if (f->writing) {
    dtm_progress_begin("writing the mesh");
    pthread_join(f->writer, NULL);
    dtm_progress_end();
  }
  dtm_gmsh_model_given(0); /* released (or never given): the next model is the caller's */
  if (!f->writing) return DTM_OK;
  f->writing = 0;
  return f->written ? DTM_ERR(f->written, "%s", f->msg) : DTM_OK;
}

static int start_writer(dtm_output_file *f) {
  dtm_gmsh_model_given(1);
  f->writing = pthread_create(&f->writer, NULL, writer, f) == 0;
  if (f->writing) return DTM_OK;
  int r = write_mesh(f); /* no thread: now */
  dtm_gmsh_release();
  return r;
}

int dtm_output_begin(const dtm_scene *s, const char *path, const dtm_output_opts *o, size_t nelements,
                     dtm_output_file **out) {
  *out = NULL;
  DTM_CHECK(check_target(s, path));
  DTM_CHECK(check_views_only(s, o));
  dtm_output_file *f = calloc(1, sizeof *f);
  if (!f) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  f->fmt = format_of(s, nelements, o);
  f->part = o ? o->part : NULL;
  int r = dtm_atomic_open(&f->w, path, ".msh", 0);
  int background = o && o->background;
  if (r == DTM_OK && !f->fmt.views_only) r = background ? start_writer(f) : write_mesh(f);
  if (r == DTM_OK && f->fmt.views_only && background) /* nothing to write */
    dtm_gmsh_model_given(1), dtm_gmsh_release();
  if (r) dtm_atomic_abort(&f->w);
  if (r) return free(f), dtm_error_trace(r, __FILE__, __LINE__, __func__);
  *out = f;
  return DTM_OK;
}

void dtm_output_abort(dtm_output_file **pf) {
  if (!*pf) return;
  if (join_writer(*pf)) dtm_error_clear(); /* the caller's own error is the one to report */
  dtm_atomic_abort(&(*pf)->w);
  free(*pf);
  *pf = NULL;
}

int dtm_output_finish(dtm_output_file **pf, const dtm_results *res) {
  dtm_output_file *f = *pf;
  view_set vs = {0};
  dtm_atomic opt = {.fd = -1};
  int nviews = 0, r = join_writer(f), with_opt = !f->part || f->part->part == 1;
  if (r == DTM_OK) r = build_views(res, f->part, f->solvers, f->nsolvers, &vs, &nviews);
  if (r == DTM_OK) {
    dtm_progress_begin("writing the views");
    r = name_target(dtm_gmsh_write_views(f->w.tmp, vs.views, nviews, &f->fmt), &f->w);
    dtm_progress_end();
  }
  if (r == DTM_OK && with_opt) r = write_opt(f->w.path, res, f->part, &vs, nviews, &opt);
  r = r ? (dtm_atomic_abort(&f->w), r) : dtm_atomic_commit(&f->w);
  if (with_opt) r = r ? (dtm_atomic_abort(&opt), r) : dtm_atomic_commit(&opt);
  free_views(&vs);
  free(f);
  *pf = NULL;
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_output_write(const dtm_results *res, const char *path) { return dtm_output_write_ex(res, path, NULL); }

int dtm_output_write_ex(const dtm_results *res, const char *path, const dtm_output_opts *o) {
  dtm_output_file *f = NULL;
  const dtm_analysis *a = res->analysis;
  DTM_CHECK(dtm_output_begin(dtm_analysis_scene(a), path, o, dtm_analysis_nelements(a), &f));
  return dtm_output_finish(&f, res);
}

/* The views in the session, styled as the .opt styles them (the .opt's
 * global options and its text view stay out of a script's session). */
static int show_views(const dtm_results *r, const view_set *vs, const int *tags, int nviews) {
  const dtm_mesh *mesh = dtm_analysis_mesh(r->analysis);
  for (int i = 0; i < nviews; i++) {
    styled s[MAX_STYLE];
    int n = view_style(vs, nviews, i, mesh, 1, s);
    for (int k = 0; k < n; k++) DTM_CHECK(dtm_gmsh_view_option(tags[i], &s[k].o));
  }
  return DTM_OK;
}

int dtm_output_add_views(const dtm_results *res, int *tags, int cap, int *n) {
  view_set vs = {0};
  int nviews = 0, r = build_views(res, NULL, NULL, 0, &vs, &nviews);
  int *own = r ? NULL : malloc(((size_t)nviews + 1) * sizeof *own);
  if (r == DTM_OK && !own) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = dtm_gmsh_add_views(vs.views, nviews, own);
  if (r == DTM_OK) r = show_views(res, &vs, own, nviews);
  for (int i = 0; r == DTM_OK && tags && i < nviews && i < cap; i++) tags[i] = own[i];
  if (n) *n = r ? 0 : nviews;
  free(own);
  free_views(&vs);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}
