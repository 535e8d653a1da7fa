/* The analysis pipeline: evaluate every effect on every element in
 * cache-sized chunks (OpenMP over chunks), apply the wave modifiers
 * (damping), reduce to the per-element minimum and the summary, then the
 * nodal bound, the recommendation and the size suggestion. Loading through
 * Gmsh is run.c; what a run costs is the cost module's, above this one. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "reference.h"
#include "dtmap/topology.h"

#define CHUNK 512 /* elements per batch: x[CHUNK][8][3] stays in L2 */

int dtm_analysis_is_wave(const dtm_analysis *a, int k) { return dtm_effect_is_wave(a->effects[k].cls); }

static int has_modifiers(const dtm_analysis *a) {
  for (int j = 0; j < a->neffects; j++)
    if (a->effects[j].cls->role & DTM_ROLE_MODIFIES_WAVES) return 1;
  return 0;
}

/* The effect whose steps are every element's step when it is the only
 * one that limits (reduce_chunk then takes its value as it is), else -1. */
static int only_limiting(const dtm_analysis *a) {
  int k1 = -1;
  for (int k = 0; k < a->neffects; k++)
    if (a->dt_effect[k]) k1 = k1 < 0 ? k : a->neffects;
  return k1 < a->neffects ? k1 : -1;
}

/* The per-element results; with one limiting effect dt shares its row (a
 * copy would be nel fresh doubles, 80 MB at 1e7 elements). */
static int alloc_results(dtm_analysis *a) {
  size_t n = a->nel, ne = (size_t)a->neffects;
  a->len = malloc(n * sizeof *a->len);
  a->limiting = malloc(n * sizeof *a->limiting);
  a->h = malloc(n * sizeof *a->h);
  a->meas = malloc(n * sizeof *a->meas);
  a->hmax = malloc(n * sizeof *a->hmax);
  a->hmax_by = malloc(n * sizeof *a->hmax_by);
  a->resolution = calloc(ne + 1, sizeof *a->resolution);
  a->dt_effect = calloc(ne + 1, sizeof *a->dt_effect);
  a->per_effect = calloc(ne + 1, sizeof *a->per_effect);
  if (!a->len || !a->limiting || !a->h || !a->meas || !a->hmax || !a->hmax_by || !a->resolution || !a->dt_effect ||
      !a->per_effect)
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for %zu elements", n);
  for (size_t k = 0; k < ne; k++) {
    if (!(a->effects[k].cls->role & DTM_ROLE_LIMITS)) continue;
    a->dt_effect[k] = malloc(n * sizeof **a->dt_effect);
    if (!a->dt_effect[k]) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  int k1 = only_limiting(a);
  a->dt_shared = k1 >= 0;
  a->dt = a->dt_shared ? a->dt_effect[k1] : malloc(n * sizeof *a->dt);
  if (!a->dt) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for %zu elements", n);
  a->dt_bare = calloc(ne + 1, sizeof *a->dt_bare);
  if (!a->dt_bare) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t k = 0; k < ne && has_modifiers(a); k++) {
    if (!a->dt_effect[k] || !dtm_analysis_is_wave(a, (int)k)) continue;
    a->dt_bare[k] = malloc(n * sizeof **a->dt_bare);
    if (!a->dt_bare[k]) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  a->hmax_effect = calloc(ne + 1, sizeof *a->hmax_effect);
  if (!a->hmax_effect) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t k = 0; k < ne; k++) {
    if (!a->effects[k].cls->accuracy) continue;
    a->resolution[k] = malloc(n * sizeof **a->resolution);
    a->hmax_effect[k] = malloc(n * sizeof **a->hmax_effect);
    if (!a->resolution[k] || !a->hmax_effect[k]) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  return DTM_OK;
}

int dtm_scatter_parts = 4;

static int setup(dtm_analysis *a) {
  dtm_mesh *m = a->mesh;
  a->offset = malloc(((size_t)m->nblocks + 1) * sizeof *a->offset);
  if (!a->offset) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  a->offset[0] = 0;
  for (int b = 0; b < m->nblocks; b++) a->offset[b + 1] = a->offset[b] + m->blocks[b].n;
  a->nel = a->offset[m->nblocks];
  DTM_CHECK(dtm_mesh_node_parts(m, dtm_scatter_parts > 0 ? dtm_scatter_parts * omp_get_max_threads() : 1, &a->parts));
  return alloc_results(a);
}

/* Scale the wave-type steps of one chunk by every modifier's factor, taken
 * at the element's own undamped top frequency omega_e = 2/dt_e. */
static int apply_modifiers(const dtm_analysis *a, const dtm_batch *bt, size_t g0, double *lens) {
  for (int k = 0; k < a->neffects; k++) {
    const dtm_effect_class *c = a->effects[k].cls;
    if (!(c->role & DTM_ROLE_LIMITS) || !dtm_analysis_is_wave(a, k)) continue;
    for (int j = 0; j < a->neffects; j++) {
      const dtm_effect *mj = &a->effects[j];
      if (!(mj->cls->role & DTM_ROLE_MODIFIES_WAVES)) continue;
      for (size_t e = 0; e < bt->n; e++) {
        double *dt = &a->dt_effect[k][g0 + e], f = 1.0;
        DTM_CHECK(mj->cls->wave_factor(mj->state, bt->mat[e], 2.0 / *dt, &f));
        *dt *= f;
        lens[k * CHUNK + e] *= f;
      }
    }
  }
  return DTM_OK;
}

int dtm_analysis_wave_factor(const dtm_analysis *a, int mat, double omega, double *factor) {
  *factor = 1.0;
  for (int j = 0; j < a->neffects; j++) {
    const dtm_effect *mj = &a->effects[j];
    double f = 1.0;
    if (!(mj->cls->role & DTM_ROLE_MODIFIES_WAVES)) continue;
    DTM_CHECK(mj->cls->wave_factor(mj->state, &a->scene->materials[mat].m, omega, &f));
    *factor *= f;
  }
  return DTM_OK;
}

/* lev: the chunk's kept rule levels (dtm_analysis_levels), or NULL. */
static void reduce_chunk(const dtm_analysis *a, const dtm_batch *bt, size_t g0, const double *lens,
                         const unsigned char *lev) {
  for (size_t e = 0; e < bt->n; e++) {
    double best = INFINITY, len = NAN;
    int lim = -1;
    for (int k = 0; k < a->neffects; k++) {
      if (!a->dt_effect[k]) continue;
      double v = a->dt_effect[k][g0 + e];
      if (v < best || lim < 0) best = v, lim = k, len = lens[k * CHUNK + e];
    }
    a->dt[g0 + e] = best;
    a->limiting[g0 + e] = lim;
    a->len[g0 + e] = len;
    a->h[g0 + e] = dtm_elem_mean_edge(bt->type, bt->x + 3 * (size_t)bt->nn * e);
    a->meas[g0 + e] = fabs(dtm_elem_measure_at(bt->type, bt->x + 3 * (size_t)bt->nn * e, lev ? lev[e] : -1));
  }
}

/* Per-thread scratch for one chunk. */
typedef struct {
  double *x;                /* [CHUNK][nn][3] */
  const dtm_material **mat; /* [CHUNK] */
  const dtm_section **sec;  /* [CHUNK] */
  double *lens;             /* [neffects][CHUNK] */
} scratch;

/* Accuracy bounds of the chunk: each effect's own row, hmax = the min
 * over them, plus each effect's resolution values. */
static int accuracy_chunk(const dtm_analysis *a, const dtm_batch *bt, size_t g0) {
  for (size_t e = 0; e < bt->n; e++) a->hmax[g0 + e] = INFINITY, a->hmax_by[g0 + e] = -1;
  for (int k = 0; k < a->neffects; k++) {
    const dtm_effect *ef = &a->effects[k];
    if (!ef->cls->accuracy) continue;
    double *hm = a->hmax_effect[k] + g0;
    DTM_CHECK(ef->cls->accuracy(ef->state, bt, hm, a->resolution[k] + g0));
    for (size_t e = 0; e < bt->n; e++)
      if (hm[e] < a->hmax[g0 + e]) a->hmax[g0 + e] = hm[e], a->hmax_by[g0 + e] = k;
  }
  return DTM_OK;
}

/* An effect's element_dt failed on a batch (block b from element e0):
 * run it again an element at a time to find which, and name that element
 * by tag, type, physical group and centroid with the effect's own message
 * (an effect sees coordinates and tags, not groups' names or positions). */
static int name_failure(const dtm_analysis *a, const dtm_effect *ef, const dtm_batch *bt, int b, size_t e0, int r) {
  char first[512], place[256];
  snprintf(first, sizeof first, "%s", dtm_error_message());
  for (size_t e = 0; e < bt->n; e++) {
    dtm_batch one = *bt;
    double dt, len;
    one.n = 1, one.x = bt->x + 3 * (size_t)bt->nn * e, one.tags = bt->tags + e, one.group = bt->group + e;
    one.gmask = bt->gmask ? bt->gmask + e : NULL, one.mat = bt->mat + e;
    one.section = bt->section ? bt->section + e : NULL;
    one.level = bt->level ? bt->level + e : NULL;
    dtm_error_clear();
    int r1 = ef->cls->element_dt(ef->state, &one, &dt, &len);
    if (!r1) continue;
    snprintf(first, sizeof first, "%s", dtm_error_message());
    dtm_error_clear();
    return DTM_ERR(r1, "%s: effect '%s' on %s: %s", a->scene->path, ef->cls->name,
                   dtm_mesh_element_place(a->mesh, b, e0 + e, place, sizeof place), first);
  }
  dtm_error_clear(); /* not reproduced an element at a time: the batch's message */
  return DTM_ERR(r, "%s: effect '%s': %s", a->scene->path, ef->cls->name, first);
}

static int compute_chunk(const dtm_analysis *a, int b, size_t e0, scratch *w) {
  const dtm_block *blk = &a->mesh->blocks[b];
  size_t n = blk->n - e0 < CHUNK ? blk->n - e0 : CHUNK, g0 = a->offset[b] + e0;
  dtm_block sub = *blk;
  sub.n = n;
  sub.conn = blk->conn + e0 * (size_t)blk->nn;
  dtm_mesh_gather(a->mesh, &sub, w->x);
  dtm_analysis_levels_chunk(a, b, e0, n, w->x); /* just before the map: the kernel's memo holds what it integrated */
  for (size_t e = 0; e < n; e++) w->mat[e] = &a->scene->materials[blk->mat[e0 + e]].m;
  for (size_t e = 0; blk->section && e < n; e++) w->sec[e] = dtm_analysis_section(a, blk, e0 + e);
  dtm_batch bt = {blk->type,
                  blk->dim,
                  blk->nn,
                  n,
                  w->x,
                  blk->tags + e0,
                  blk->group + e0,
                  blk->gmask ? blk->gmask + e0 : NULL,
                  w->mat,
                  blk->section ? w->sec : NULL,
                  a->level && a->level[b] ? a->level[b] + e0 : NULL}; /* kept levels: no search in the kernel */
  for (int k = 0; k < a->neffects; k++) {
    const dtm_effect *ef = &a->effects[k];
    if (!(ef->cls->role & DTM_ROLE_LIMITS)) continue;
    int r = ef->cls->element_dt(ef->state, &bt, a->dt_effect[k] + g0, w->lens + (size_t)k * CHUNK);
    if (r) return name_failure(a, ef, &bt, b, e0, r);
  }
  for (int k = 0; k < a->neffects; k++)
    if (a->dt_bare[k]) memcpy(a->dt_bare[k] + g0, a->dt_effect[k] + g0, n * sizeof(double));
  DTM_CHECK(apply_modifiers(a, &bt, g0, w->lens));
  DTM_CHECK(accuracy_chunk(a, &bt, g0));
  reduce_chunk(a, &bt, g0, w->lens, a->level && a->level[b] ? a->level[b] + e0 : NULL);
  return DTM_OK;
}

static int compute_block(const dtm_analysis *a, int b) {
  const dtm_block *blk = &a->mesh->blocks[b];
  long nchunks = (long)((blk->n + CHUNK - 1) / CHUNK);
  dtm_par_error pe = {0, ""};
#pragma omp parallel
  {
    scratch w = {malloc(CHUNK * (size_t)blk->nn * 3 * sizeof(double)), malloc(CHUNK * sizeof(dtm_material *)),
                 malloc(CHUNK * sizeof(dtm_section *)), malloc(CHUNK * ((size_t)a->neffects + 1) * sizeof(double))};
    int ok = w.x && w.mat && w.sec && w.lens;
    if (!ok) dtm_par_error_keep(&pe, DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
#pragma omp for schedule(dynamic, 4)
    for (long c = 0; c < nchunks; c++) {
      if (!ok || pe.code) continue;
      int r = compute_chunk(a, b, (size_t)c * CHUNK, &w);
      if (r) dtm_par_error_keep(&pe, r);
    }
    free(w.x);
    free((void *)w.mat);
    free((void *)w.sec);
    free(w.lens);
  }
  return dtm_par_error_raise(&pe);
}

/* Drop the accuracy rows of effects whose bound applies nowhere (e.g. the
 * elastic wavelength bound without <time f-max>), on any part. */
static int drop_empty_accuracy(dtm_analysis *a) {
  double *any = calloc((size_t)a->neffects + 1, sizeof *any);
  for (int k = 0; k < a->neffects && any; k++)
    for (size_t i = 0; a->resolution[k] && i < a->nel && !any[k]; i++) any[k] = !isnan(a->resolution[k][i]);
  int r = dtm_x_reduce(a, any ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"), any, a->neffects, DTM_X_MAX);
  for (int k = 0; k < a->neffects && r == DTM_OK; k++)
    if (a->resolution[k] && !any[k])
      free(a->resolution[k]), a->resolution[k] = NULL, free(a->hmax_effect[k]), a->hmax_effect[k] = NULL;
  free(any);
  return r;
}

/* Whether element i's step v comes before the best so far (best at j):
 * smaller, or equal with a smaller Gmsh tag, so that ties do not depend on
 * the internal element order (dtm_mesh_reorder). */
static int before(const dtm_analysis *a, double v, size_t i, double best, size_t j) {
  return v < best || (v == best && dtm_analysis_tag(a, i) < dtm_analysis_tag(a, j));
}

/* The smallest element step and each effect's, over every part, and the
 * top frequency of the part that holds each effect's minimum (the indices
 * stay those of this part's own minima). */
static int global_minima(dtm_analysis *a) {
  int n = a->neffects + 1;
  double *v = malloc((size_t)n * sizeof *v);
  for (int k = 0; k < a->neffects && v; k++) v[k + 1] = a->dt_effect[k] ? a->per_effect[k].min : INFINITY;
  if (v) v[0] = a->dt_min;
  int r = dtm_x_reduce(a, v ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"), v, n, DTM_X_MIN);
  if (r == DTM_OK) a->dt_min = v[0];
  for (int k = 0; k < a->neffects && r == DTM_OK; k++) {
    if (!a->dt_effect[k]) continue;
    if (dtm_analysis_is_wave(a, k)) r = dtm_x_at_min(a, r, a->per_effect[k].min, v[k + 1], &a->per_effect[k].omega);
    a->per_effect[k].min = v[k + 1];
  }
  free(v);
  return r;
}

/* The 1 % quantile of the finite element steps (this part's), NaN when
 * none is finite: the outlier warning and the views' "smallest 1 %" read it. */
static int quantile_1pc(dtm_analysis *a) {
  double *v = malloc((a->nel + 1) * sizeof *v);
  size_t n = 0;
  if (!v) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < a->nel; i++)
    if (isfinite(a->dt[i])) v[n++] = a->dt[i];
  a->dt_q1 = n ? dtm_select_kth(v, n, (n - 1) / 100) : NAN;
  free(v);
  return DTM_OK;
}

static int summarize(dtm_analysis *a) {
  DTM_CHECK(drop_empty_accuracy(a));
  a->dt_min = INFINITY;
  for (size_t i = 0; i < a->nel; i++)
    if (before(a, a->dt[i], i, a->dt_min, a->el_min)) a->dt_min = a->dt[i], a->el_min = i;
  DTM_CHECK(quantile_1pc(a));
  for (int k = 0; k < a->neffects; k++) {
    a->per_effect[k].min = a->per_effect[k].nodal = a->per_effect[k].global = a->per_effect[k].certified = NAN;
    a->per_effect[k].element_rigorous = 1; /* nodal.c lowers it for length rules */
    a->per_effect[k].omega = NAN;
    if (!a->dt_effect[k]) continue;
    double best = INFINITY;
    for (size_t i = 0; i < a->nel; i++)
      if (before(a, a->dt_effect[k][i], i, best, a->per_effect[k].element))
        best = a->dt_effect[k][i], a->per_effect[k].element = i;
    a->per_effect[k].min = best;
    const double *bare = a->dt_bare[k] ? a->dt_bare[k] : a->dt_effect[k];
    if (dtm_analysis_is_wave(a, k)) a->per_effect[k].omega = 2.0 / bare[a->per_effect[k].element];
  }
  return global_minima(a);
}

int dtm_analysis_compute(const dtm_scene *s, dtm_mesh *mesh, dtm_effect *effects, int neffects, dtm_analysis **out) {
  return dtm_analysis_compute_shared(s, mesh, effects, neffects, NULL, out);
}

/* The space the nodes span, agreed over the parts of a distributed run (a
 * part of a curved surface may be flat), and kept in the mesh for the
 * operator; shells and beams bend out of any plane, so with them it is 3.
 * status is the caller's, agreed with the other parts. */
static int space_dim(dtm_analysis *a, int status) {
  int mine = 0, r = status == DTM_OK ? dtm_mesh_space_dim(a->mesh, &mine) : status;
  double d = r == DTM_OK && dtm_analysis_has_rotations(a) ? 3 : mine;
  r = dtm_x_reduce(a, r, &d, 1, DTM_X_MAX); /* every part takes part, whatever its status */
  a->mesh->space_dim = (int)d;
  return r;
}

int dtm_analysis_compute_shared(const dtm_scene *s, dtm_mesh *mesh, dtm_effect *effects, int neffects,
                                const dtm_exchange *x, dtm_analysis **out) {
  dtm_analysis *a = calloc(1, sizeof *a);
  if (!a) { /* the other parts wait at the first agreement below */
    int r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    return x ? x->reduce(x->ctx, r, NULL, 0, DTM_X_MAX) : r;
  }
  a->scene = s;
  a->mesh = mesh;
  a->effects = effects;
  a->neffects = neffects;
  a->threads = omp_get_max_threads();
  a->mesher = (dtm_mesher_info){0, 0, 1};
  a->x = x;
  int r = setup(a);
  r = space_dim(a, r);
  if (r == DTM_OK) r = dtm_analysis_check_planar(a);
  double t0 = dtm_wtime();
  if (r == DTM_OK) r = dtm_analysis_levels(a);
  for (int b = 0; b < mesh->nblocks && r == DTM_OK; b++) r = compute_block(a, b);
  r = dtm_x_agree(a, r);
  if (r == DTM_OK) r = summarize(a);
  if (r == DTM_OK) r = dtm_analysis_curvature_pass(a);
  if (r == DTM_OK && !isfinite(a->dt_min))
    r = DTM_ERR(DTM_ERR_INPUT, "%s: no element is limited by any of the scene's effects", s->path);
  a->timings[DTM_T_EFFECTS] = dtm_wtime() - t0;
  t0 = dtm_wtime();
  if (r == DTM_OK) r = dtm_analysis_rotary(a);
  if (r == DTM_OK) r = dtm_nodal_bounds(a);
  if (r == DTM_OK) dtm_recommend(a);
  if (r == DTM_OK) r = dtm_x_agree(a, dtm_local_steps(a));
  a->timings[DTM_T_NODAL] = dtm_wtime() - t0;
  t0 = dtm_wtime();
  if (r == DTM_OK) r = dtm_size_suggest(a);
  if (r == DTM_OK) r = dtm_x_agree(a, dtm_analysis_section_stats(a));
  if (r == DTM_OK) r = dtm_shape_classify(a);
  a->timings[DTM_T_ADVICE] = dtm_wtime() - t0;
  if (r) {
    dtm_analysis_destroy(&a);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = a;
  return DTM_OK;
}

void dtm_analysis_destroy(dtm_analysis **pa) {
  dtm_analysis *a = *pa;
  if (!a) return;
  for (int k = 0; a->dt_effect && k < a->neffects; k++) free(a->dt_effect[k]);
  for (int k = 0; a->resolution && k < a->neffects; k++) free(a->resolution[k]);
  for (int k = 0; a->hmax_effect && k < a->neffects; k++) free(a->hmax_effect[k]);
  free(a->hmax_effect);
  free(a->curv_ratio);
  free(a->curv_offset);
  free(a->local);
  free(a->forced);
  free(a->shape);
  free(a->layers);
  free(a->sec_stats);
  for (int b = 0; a->level && b < a->mesh->nblocks; b++) free(a->level[b]);
  free(a->level);
  for (int b = 0; a->level_rem && b < a->mesh->nblocks; b++) free(a->level_rem[b]);
  free(a->level_rem);
  for (int b = 0; a->rot && b < a->mesh->nblocks; b++) free(a->rot[b]);
  free(a->rot);
  dtm_gmsh_geo_destroy(&a->geo);
  for (int k = 0; a->dt_bare && k < a->neffects; k++) free(a->dt_bare[k]);
  free(a->dt_bare);
  free(a->resolution);
  free(a->hmax);
  free(a->hmax_by);
  dtm_effects_destroy(&a->effects, a->neffects);
  dtm_mesh_destroy(&a->mesh);
  free(a->dt_effect);
  free(a->per_effect);
  free(a->offset);
  dtm_mesh_node_parts_free(&a->parts);
  if (!a->dt_shared) free(a->dt);
  free(a->len);
  free(a->limiting);
  free(a->h);
  free(a->meas);
  free(a->size_node);
  free(a->nodal_node);
  for (int k = 0; a->node_dt && k < a->neffects; k++) free(a->node_dt[k]);
  free(a->node_dt);
  for (int k = 0; a->global && k < a->neffects; k++) free(a->global[k].mode);
  free(a->global);
  free(a);
  *pa = NULL;
}
