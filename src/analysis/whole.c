/* The advice on elements below the target (shape.c, layers.c) in a
 * distributed run. It reads the model's features, which only part 0
 * holds: the rank that meshed or read the scene's one mesh and split it
 * extracts the whole mesh as a serial run does (same element order) and
 * reads where it sits on the model, before the split. After the parts are
 * analysed, every part sends its elements' figures by Gmsh tag (element
 * step, own safe step, size, limiting effect, each limiting effect's
 * step); part 0 sets them on the whole mesh and classifies exactly as a
 * serial run does: the same elements, the same typical quality (the same
 * sample), the same patches, across what were part boundaries. The own
 * safe steps are already the whole mesh's (the nodal bound was combined
 * over the parts), so the classification equals the serial run's. The
 * below-target elements are few, but the figures of every element are
 * sent: the typical quality samples the whole mesh and a patch may reach
 * any part. Part 0 keeps the result as an analysis of the whole mesh that
 * holds those figures and nothing else, and shares the shape-limited
 * elements with the parts, which mark those they hold in their views. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"

#define NOT_YET (-2) /* limiting effect of an element no part has sent yet (-1: none) */
#define FIXED 5      /* per element: tag, dt, local, h, limiting; then one step per effect */

static size_t width(const dtm_analysis *a) { return FIXED + (size_t)a->neffects; }

/* This part's figures, width(a) per element, into *out (malloc'd). */
static int pack(const dtm_analysis *a, double **out) {
  size_t w = width(a);
  double *v = malloc((a->nel * w + 1) * sizeof *v);
  if (!v) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < a->nel; i++) {
    double *r = v + i * w;
    r[0] = (double)dtm_analysis_tag(a, i), r[1] = a->dt[i], r[2] = a->local[i], r[3] = a->h[i];
    r[4] = a->limiting[i];
    for (int k = 0; k < a->neffects; k++) r[FIXED + k] = a->dt_effect[k] ? a->dt_effect[k][i] : NAN;
  }
  *out = v;
  return DTM_OK;
}

/* The arrays of the whole mesh's analysis w the classification reads. */
static int alloc_whole(const dtm_analysis *part, dtm_analysis *w) {
  const dtm_mesh *m = w->mesh;
  w->offset = malloc(((size_t)m->nblocks + 1) * sizeof *w->offset);
  if (!w->offset) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  w->offset[0] = 0;
  for (int b = 0; b < m->nblocks; b++) w->offset[b + 1] = w->offset[b] + m->blocks[b].n;
  size_t n = w->nel = w->offset[m->nblocks];
  w->dt = malloc((n + 1) * sizeof *w->dt), w->local = malloc((n + 1) * sizeof *w->local);
  w->h = malloc((n + 1) * sizeof *w->h), w->limiting = malloc((n + 1) * sizeof *w->limiting);
  w->dt_effect = calloc((size_t)w->neffects + 1, sizeof *w->dt_effect);
  if (!w->dt || !w->local || !w->h || !w->limiting || !w->dt_effect) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int k = 0; k < w->neffects; k++)
    if (part->dt_effect[k] && !(w->dt_effect[k] = malloc((n + 1) * sizeof **w->dt_effect)))
      return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < n; i++) w->limiting[i] = NOT_YET;
  return DTM_OK;
}

/* The elements of an analysis by Gmsh tag (tags may be sparse): pairs
 * sorted by tag, looked up by bisection. */
typedef struct {
  size_t tag, i; /* Gmsh element tag, index in the analysis */
} tagged;

typedef struct {
  tagged *t; /* [n] by tag */
  size_t n;
} tag_index;

static int cmp_tagged(const void *x, const void *y) {
  size_t u = ((const tagged *)x)->tag, v = ((const tagged *)y)->tag;
  return u < v ? -1 : u > v;
}

static int index_build(const dtm_analysis *a, tag_index *ti) {
  ti->n = a->nel;
  ti->t = malloc((ti->n + 1) * sizeof *ti->t);
  if (!ti->t) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t k = 0;
  for (int b = 0; b < a->mesh->nblocks; b++)
    for (size_t e = 0; e < a->mesh->blocks[b].n; e++, k++) ti->t[k] = (tagged){a->mesh->blocks[b].tags[e], k};
  qsort(ti->t, ti->n, sizeof *ti->t, cmp_tagged);
  return DTM_OK;
}

/* Index of the element with this tag, (size_t)-1 if none. */
static size_t index_find(const tag_index *ti, double tag) {
  tagged key = {(size_t)tag, 0}, *hit = bsearch(&key, ti->t, ti->n, sizeof key, cmp_tagged);
  return hit ? hit->i : (size_t)-1;
}

/* Set the parts' figures (n rows) on w by tag; every element of the whole
 * mesh must get exactly one row. */
static int unpack(dtm_analysis *w, const double *all, size_t n) {
  size_t wd = width(w), got = 0;
  tag_index ti;
  DTM_CHECK(index_build(w, &ti));
  for (size_t j = 0; j < n; j++) {
    const double *r = all + j * wd;
    size_t i = index_find(&ti, r[0]);
    if (i == (size_t)-1 || w->limiting[i] != NOT_YET) continue; /* not in the whole mesh, or twice */
    w->dt[i] = r[1], w->local[i] = r[2], w->h[i] = r[3], w->limiting[i] = (int)r[4], got++;
    for (int k = 0; k < w->neffects; k++)
      if (w->dt_effect[k]) w->dt_effect[k][i] = r[FIXED + k];
  }
  free(ti.t);
  if (got != w->nel || n != w->nel)
    return DTM_ERR(DTM_ERR_INTERNAL,
                   "the parts hold %zu elements, %zu of the %zu of the whole mesh they were split from", n, got,
                   w->nel);
  return DTM_OK;
}

/* Part 0: the whole mesh's analysis from the parts' rows, classified. */
static int classify(const dtm_analysis *part, dtm_mesh **whole, dtm_geo **geo, const double *all, size_t n,
                    dtm_analysis **out) {
  dtm_analysis *w = calloc(1, sizeof *w);
  if (!w) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  w->scene = part->scene, w->mesh = *whole, w->geo = *geo, w->threads = part->threads, w->mesher = part->mesher;
  *whole = NULL, *geo = NULL;
  w->mesh->space_dim = part->mesh->space_dim; /* agreed over the parts */
  w->dt_min = part->dt_min, w->recommended = part->recommended, w->best = part->best, w->basis = part->basis;
  w->advice_target = part->advice_target;
  int r = dtm_effects_create(w->scene, w->mesh, &w->effects, &w->neffects);
  if (r == DTM_OK && w->neffects != part->neffects) r = DTM_ERR(DTM_ERR_INTERNAL, "the effects differ from the part's");
  if (r == DTM_OK) r = alloc_whole(part, w);
  if (r == DTM_OK) r = unpack(w, all, n / width(w));
  if (r == DTM_OK) r = dtm_shape_classify(w);
  if (r) {
    dtm_analysis_destroy(&w);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = w;
  return DTM_OK;
}

int dtm_analysis_classify_whole(const dtm_analysis *part, dtm_mesh **whole, dtm_geo **geo, dtm_analysis **out) {
  *out = NULL;
  if (!part->x) return DTM_OK;
  /* Does part 0 hold the model, and is anything to classify (with a
   * target, elements below it; without, the smallest steps)? */
  double v[2] = {*whole && *geo ? 1.0 : 0.0, (double)part->below}, *mine = NULL, *all = NULL;
  size_t nall = 0;
  int r = part->x->reduce(part->x->ctx, DTM_OK, v, 2, DTM_X_MAX);
  if (r || !v[0] || (part->advice_target > 0 && !v[1])) return r;
  r = pack(part, &mine);
  r = part->x->gather(part->x->ctx, r, mine, mine ? part->nel * width(part) : 0, &all, &nall);
  free(mine);
  if (r == DTM_OK && all) r = classify(part, whole, geo, all, nall, out);
  free(all);
  return part->x->reduce(part->x->ctx, r, NULL, 0, DTM_X_MAX);
}

#define SHARED 13 /* per shape-limited element: tag, then its fields after the element */

static void pack_one(const dtm_analysis *w, const dtm_shape_limited *e, double *r) {
  r[0] = (double)dtm_analysis_tag(w, e->element), r[1] = e->feature, r[2] = e->angle, r[3] = e->entity_dim;
  r[4] = e->entity_tag, r[5] = e->size, r[6] = e->quality, r[7] = e->reach, r[8] = e->remedy, r[9] = e->split;
  r[10] = e->other_dim, r[11] = e->other_tag, r[12] = e->layer;
}

static dtm_shape_limited unpack_one(size_t i, const double *r) {
  return (dtm_shape_limited){i,    (int)r[1], r[2], (int)r[3],  (int)r[4],  r[5],      r[6],
                             r[7], (int)r[8], r[9], (int)r[10], (int)r[11], (int)r[12]};
}

/* Part 0: the whole mesh's shape-limited elements, SHARED values each. */
static int pack_advice(const dtm_analysis *w, double **v, size_t *n) {
  *n = w ? w->nshape * SHARED : 0;
  *v = malloc((*n + 1) * sizeof **v);
  if (!*v) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t j = 0; w && j < w->nshape; j++) pack_one(w, &w->shape[j], *v + j * SHARED);
  return DTM_OK;
}

/* The entries of v[n] whose element this part holds, as its shape list. */
static int keep_own(dtm_analysis *a, const double *v, size_t n) {
  tag_index ti;
  free(a->shape), a->shape = NULL, a->nshape = 0;
  if (!n) return DTM_OK;
  DTM_CHECK(index_build(a, &ti));
  a->shape = malloc((n / SHARED + 1) * sizeof *a->shape);
  if (!a->shape) return free(ti.t), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t j = 0; j < n / SHARED; j++) {
    size_t i = index_find(&ti, v[j * SHARED]);
    if (i != (size_t)-1) a->shape[a->nshape++] = unpack_one(i, v + j * SHARED);
  }
  free(ti.t);
  return DTM_OK;
}

int dtm_analysis_share_advice(dtm_analysis *part, const dtm_analysis *advice) {
  if (!part->x) return DTM_OK;
  double *v = NULL;
  size_t n = 0;
  int r = advice ? pack_advice(advice, &v, &n) : DTM_OK;
  r = part->x->bcast(part->x->ctx, r, &v, &n);
  if (r == DTM_OK) r = keep_own(part, v, n);
  free(v);
  return part->x->reduce(part->x->ctx, r, NULL, 0, DTM_X_MAX);
}
