/* The figures a distributed run reports, gathered from the parts: counts
 * (elements, nodes counted once at their owner), where each global minimum
 * is (found on the rank holding it and broadcast), the accuracy
 * bookkeeping, the subcycling levels and the mass scaling (sums over the
 * parts, whose element steps already rest on the global minimum), and each
 * rank's own counts, times and memory. The analysis already holds the
 * global minima themselves (src/analysis/distributed.h). Collective: every
 * rank calls these in the same order. */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "dtmap/kernel.h"
#include "parallel-impl.h"
#include "report.h"

/* The holder of a minimum: the smallest tag among the ranks that have a
 * candidate, then the lowest such rank; -1 when none has one. */
static int pick(const dtm_par *p, int have, unsigned long long tag) {
  unsigned long long t = have ? tag : ULLONG_MAX, best = ULLONG_MAX;
  int me, who = p->size;
  MPI_Allreduce(&t, &best, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, p->comm);
  me = have && tag == best ? p->rank : p->size;
  MPI_Allreduce(&me, &who, 1, MPI_INT, MPI_MIN, p->comm);
  return best == ULLONG_MAX ? -1 : who;
}

static void element_record(const dtm_par *p, size_t i, dtm_par_where *w) {
  const dtm_analysis *a = p->analysis;
  int b;
  size_t l;
  char lbl[64];
  w->found = 1;
  w->tag = dtm_analysis_tag(a, i);
  snprintf(w->group, sizeof w->group, "%s",
           dtm_mesh_group_label(dtm_analysis_mesh(a), dtm_analysis_group(a, i), lbl, sizeof lbl));
  dtm_analysis_centroid(a, i, w->centroid);
  w->effect = dtm_analysis_limiting(a)[i];
  dtm_analysis_locate(a, i, &b, &l);
  snprintf(w->type, sizeof w->type, "%s", dtm_elem_name(dtm_analysis_mesh(a)->blocks[b].type));
}

/* Element i of this part (SIZE_MAX: none) is a candidate; *who the holder. */
static int where_index(const dtm_par *p, size_t i, dtm_par_where *w, int *who) {
  memset(w, 0, sizeof *w);
  int have = i != SIZE_MAX;
  *who = pick(p, have, have ? dtm_analysis_tag(p->analysis, i) : 0);
  if (*who == p->rank) element_record(p, i, w);
  if (*who >= 0 && MPI_Bcast(w, (int)sizeof *w, MPI_BYTE, *who, p->comm) != MPI_SUCCESS)
    return DTM_ERR(DTM_ERR_INTERNAL, "MPI_Bcast failed");
  return DTM_OK;
}

/* The element of v[nel] at the global minimum value with the smallest tag. */
static int where_element(const dtm_par *p, const double *v, double value, dtm_par_where *w) {
  size_t best = SIZE_MAX, n = dtm_analysis_nelements(p->analysis);
  unsigned long long tag = ULLONG_MAX;
  for (size_t i = 0; i < n && isfinite(value); i++) {
    if (v[i] != value) continue;
    unsigned long long t = dtm_analysis_tag(p->analysis, i);
    if (t < tag) tag = t, best = i;
  }
  int who;
  return where_index(p, best, w, &who);
}

/* The node of v[nnodes] at the global minimum value with the smallest tag. */
static int where_node(const dtm_par *p, const double *v, double value, dtm_par_where *w) {
  const dtm_mesh *m = p->mesh;
  unsigned long long tag = ULLONG_MAX;
  for (size_t i = 0; i < m->nnodes && isfinite(value); i++)
    if (v[i] == value && m->node_tags[i] < tag) tag = m->node_tags[i];
  memset(w, 0, sizeof *w);
  int who = pick(p, tag != ULLONG_MAX, tag);
  w->found = who >= 0, w->tag = tag;
  if (who >= 0 && MPI_Bcast(&w->tag, 1, MPI_UNSIGNED_LONG_LONG, who, p->comm) != MPI_SUCCESS)
    return DTM_ERR(DTM_ERR_INTERNAL, "MPI_Bcast failed");
  return DTM_OK;
}

static int minima(const dtm_par *p, dtm_par_figures *f) {
  const dtm_analysis *a = p->analysis;
  DTM_CHECK(where_element(p, dtm_analysis_dt(a), dtm_analysis_dt_min(a, NULL), &f->dt));
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const dtm_effect_min *pe = dtm_analysis_effect_min(a, k);
    if (dtm_analysis_effect_dt(a, k))
      DTM_CHECK(where_element(p, dtm_analysis_effect_dt(a, k), pe->min, &f->element[k]));
    if (isfinite(pe->nodal)) DTM_CHECK(where_node(p, dtm_analysis_effect_nodal(a, k), pe->nodal, &f->node[k]));
  }
  return DTM_OK;
}

/* Under-resolved, conflicting and below-target elements summed; the
 * tightest cap. */
static int accuracy(const dtm_par *p, dtm_par_figures *f) {
  dtm_accuracy ac;
  dtm_analysis_accuracy(p->analysis, &ac);
  double v[3] = {(double)ac.under_resolved, (double)ac.conflicts, (double)dtm_analysis_below_target(p->analysis)};
  double cap = isnan(ac.dt_cap) ? INFINITY : ac.dt_cap;
  MPI_Allreduce(MPI_IN_PLACE, v, 3, MPI_DOUBLE, MPI_SUM, p->comm);
  MPI_Allreduce(&cap, &f->dt_cap, 1, MPI_DOUBLE, MPI_MIN, p->comm);
  f->under_resolved = v[0], f->conflicts = v[1], f->below = v[2];
  if (!isfinite(f->dt_cap)) return f->dt_cap = NAN, DTM_OK;
  int who;
  DTM_CHECK(where_index(p, cap == f->dt_cap ? ac.cap_element : SIZE_MAX, &f->cap, &who));
  double bound[2] = {0, 0};
  if (who == p->rank)
    bound[0] = dtm_analysis_hmax(p->analysis)[ac.cap_element],
    bound[1] = dtm_analysis_hmax_by(p->analysis)[ac.cap_element];
  MPI_Bcast(bound, 2, MPI_DOUBLE, who, p->comm);
  f->cap_hmax = bound[0], f->cap_effect = (int)bound[1];
  return DTM_OK;
}

/* The levels' counts summed over the parts (each part's levels already
 * rest on the global smallest step), then the speed-up as
 * src/cost/subcycling.c defines it, over every part. */
static void subcycling(const dtm_par *p, dtm_par_figures *f) {
  double c[DTM_MAX_LEVELS], work = 0;
  for (int k = 0; k < DTM_MAX_LEVELS; k++) c[k] = (double)p->cost->subcycling.count[k];
  MPI_Allreduce(MPI_IN_PLACE, c, DTM_MAX_LEVELS, MPI_DOUBLE, MPI_SUM, p->comm);
  for (int k = 0; k < DTM_MAX_LEVELS; k++) {
    f->sub.count[k] = (size_t)c[k];
    if (c[k] > 0) f->sub.nlevels = k + 1, work += ldexp(c[k], -k);
  }
  f->sub.speedup = work > 0 ? f->elements / work : 1.0;
  f->sub.basis = p->cost->subcycling.basis;
}

/* Mass scaling totals and per-group sums (the parts name the same groups). */
static int mass(dtm_par *p, dtm_par_figures *f) {
  const dtm_mass_scaling *ms = p->cost->mass;
  if (!ms) return DTM_OK;
  int ng = ms->ngroups, n = 3 + 2 * ng;
  double *v = malloc((size_t)n * sizeof *v);
  f->mass = calloc(1, sizeof *f->mass);
  if (f->mass)
    f->mass->group_mass = malloc((size_t)ng * sizeof(double)),
    f->mass->group_added = malloc((size_t)ng * sizeof(double));
  int ok = v && f->mass && f->mass->group_mass && f->mass->group_added;
  int r = dtm_par_agree(p, ok ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
  if (r) return free(v), r;
  v[0] = ms->total_mass, v[1] = ms->total_added, v[2] = (double)ms->scaled;
  for (int g = 0; g < ng; g++) v[3 + g] = ms->group_mass[g], v[3 + ng + g] = ms->group_added[g];
  MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_SUM, p->comm);
  dtm_mass_scaling *m = f->mass;
  m->target = ms->target, m->nodal = ms->nodal, m->ngroups = ng, m->total_mass = v[0], m->total_added = v[1],
  m->scaled = (size_t)v[2];
  for (int g = 0; g < ng; g++) m->group_mass[g] = v[3 + g], m->group_added[g] = v[3 + ng + g];
  free(v);
  return DTM_OK;
}

/* Each rank's JSON array (taken over) gathered on rank 0 into *all, the
 * items in rank order; NULL elsewhere. */
static int gather_json(dtm_par *p, cJSON *mine, cJSON **all) {
  char *text = cJSON_PrintUnformatted(mine);
  int len = text ? (int)strlen(text) + 1 : 0, *lens = NULL, *at = NULL, total = 0;
  cJSON_Delete(mine);
  *all = NULL;
  if (p->rank == 0) lens = calloc((size_t)p->size, sizeof *lens), at = calloc((size_t)p->size, sizeof *at);
  int r = dtm_par_agree(p, text && (p->rank || (lens && at)) ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
  if (r == DTM_OK) MPI_Gather(&len, 1, MPI_INT, lens, 1, MPI_INT, 0, p->comm);
  for (int k = 0; r == DTM_OK && p->rank == 0 && k < p->size; k++) at[k] = total, total += lens[k];
  char *buf = r == DTM_OK && p->rank == 0 ? malloc((size_t)total + 1) : NULL;
  r = r ? r : dtm_par_agree(p, p->rank == 0 && !buf ? DTM_ERR(DTM_ERR_INTERNAL, "out of memory") : DTM_OK);
  if (r == DTM_OK) MPI_Gatherv(text, len, MPI_CHAR, buf, lens, at, MPI_CHAR, 0, p->comm);
  if (r == DTM_OK && p->rank == 0) *all = cJSON_CreateArray();
  for (int k = 0; r == DTM_OK && p->rank == 0 && k < p->size; k++) {
    cJSON *part = cJSON_Parse(buf + at[k]), *item;
    while (part && (item = cJSON_DetachItemFromArray(part, 0))) cJSON_AddItemToArray(*all, item);
    cJSON_Delete(part);
  }
  free(text), free(lens), free(at), free(buf);
  return r;
}

/* Keep the first n items of arr. */
static void truncate_array(cJSON *arr, int n) {
  while (arr && cJSON_GetArraySize(arr) > n) cJSON_DeleteItemFromArray(arr, n);
}

static double number(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItem(o, key);
  return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static int by_added(const void *x, const void *y) {
  double a = number(*(cJSON *const *)x, "added"), b = number(*(cJSON *const *)y, "added");
  return a > b ? -1 : a < b;
}

/* The smallest step first, then the smaller tag. */
static int by_dt(const void *x, const void *y) {
  const cJSON *a = *(cJSON *const *)x, *b = *(cJSON *const *)y;
  double da = number(a, "dt"), db = number(b, "dt"), ta = number(a, "element"), tb = number(b, "element");
  return da < db ? -1 : da > db ? 1 : (ta > tb) - (ta < tb);
}

/* arr sorted by cmp, its first keep items kept. */
static void sort_array(cJSON *arr, int (*cmp)(const void *, const void *), int keep) {
  int n = cJSON_GetArraySize(arr);
  cJSON **items = malloc(((size_t)n + 1) * sizeof *items);
  for (int i = 0; items && i < n; i++) items[i] = cJSON_DetachItemFromArray(arr, 0);
  if (items) qsort(items, (size_t)n, sizeof *items, cmp);
  for (int i = 0; items && i < n; i++) cJSON_AddItemToArray(arr, items[i]);
  free(items);
  truncate_array(arr, keep);
}

/* The index of the effect or the material an item names (-1: none). */
static int effect_index(const dtm_analysis *a, const cJSON *item) {
  const char *name = cJSON_GetStringValue(cJSON_GetObjectItem(item, "effect"));
  for (int k = 0; name && k < dtm_analysis_neffects(a); k++)
    if (!strcmp(dtm_analysis_effect(a, k)->name, name)) return k;
  return -1;
}

static int material_index(const dtm_analysis *a, const cJSON *item) {
  const char *name = cJSON_GetStringValue(cJSON_GetObjectItem(item, "material"));
  const dtm_scene *s = dtm_analysis_scene(a);
  for (int i = 0; name && i < s->nmaterials; i++)
    if (!strcmp(s->materials[i].m.name, name)) return i;
  return -1;
}

/* Each item's place in the serial rows' order: by effect, then material. */
static int row_key(const dtm_analysis *a, const cJSON *item) {
  return (effect_index(a, item) + 1) * (dtm_analysis_scene(a)->nmaterials + 1) + material_index(a, item) + 1;
}

/* The lower of two numbers or nulls (max: the higher), null when neither
 * is a number. */
static void widen(cJSON *into, const cJSON *from, const char *key, int max) {
  double a = number(into, key), b = number(from, key);
  double v = isnan(a) ? b : isnan(b) ? a : max ? fmax(a, b) : fmin(a, b);
  if (!isnan(v)) cJSON_ReplaceItemInObject(into, key, cJSON_CreateNumber(v));
}

/* The parts' rows merged, in the serial order: one row per effect and
 * material, the lowest part's (a cohesive zone's R is the material's, its
 * h_max the bound of the first element where it applies), the damping's
 * element range widened to every part's. */
static void merge_rows(const dtm_analysis *a, cJSON **arr) {
  cJSON *in = *arr, *out = cJSON_CreateArray(), *item;
  int n = cJSON_GetArraySize(in), best, key;
  while (out && (n = cJSON_GetArraySize(in)) > 0) {
    best = 0, key = row_key(a, cJSON_GetArrayItem(in, 0));
    for (int j = 1; j < n; j++)
      if (row_key(a, cJSON_GetArrayItem(in, j)) < key) best = j, key = row_key(a, cJSON_GetArrayItem(in, j));
    item = cJSON_DetachItemFromArray(in, best);
    for (int j = 0; j < cJSON_GetArraySize(in);) {
      cJSON *other = cJSON_GetArrayItem(in, j);
      if (row_key(a, other) != key) {
        j++;
        continue;
      }
      widen(item, other, "element_factor_min", 0), widen(item, other, "element_factor_max", 1);
      cJSON_DeleteItemFromArray(in, j);
    }
    cJSON_AddItemToArray(out, item);
  }
  cJSON_Delete(in);
  *arr = out;
}

/* The lists of individual elements and the rows per material: each part's
 * own, merged on rank 0. */
static int lists(dtm_par *p, dtm_par_figures *f) {
  dtm_results res = {p->analysis, p->cost, NULL, 0.0, 0.0, p->top, 0, {NULL}, {NULL}, NULL, NULL};
  DTM_CHECK(gather_json(p, dtm_report_under_resolved(p->analysis), &f->under_list));
  truncate_array(f->under_list, DTM_REPORT_LISTED);
  DTM_CHECK(gather_json(p, dtm_report_worst(&res), &f->worst));
  if (f->worst) sort_array(f->worst, by_dt, dtm_results_top(&res));
  DTM_CHECK(gather_json(p, dtm_report_zones(p->analysis), &f->zones));
  if (f->zones) merge_rows(p->analysis, &f->zones);
  DTM_CHECK(gather_json(p, dtm_report_damping(p->analysis), &f->damping));
  if (f->damping) merge_rows(p->analysis, &f->damping);
  if (!p->cost->mass) return DTM_OK;
  DTM_CHECK(gather_json(p, dtm_report_top_added(p->analysis, p->cost->mass->added), &f->most_added));
  if (f->most_added) sort_array(f->most_added, by_added, DTM_REPORT_TOP_ADDED);
  return DTM_OK;
}

/* Exact k-th smallest (from 0) of the finite positive values v[n] of every
 * part: bisection over the bit patterns of positive doubles, which order
 * as the values do, with the global count at or below each probe. */
static double kth_smallest(const dtm_par *p, const double *v, size_t n, unsigned long long k) {
  uint64_t lo = 0, hi = 0x7ff0000000000000ull; /* +inf */
  while (lo < hi) {
    uint64_t mid = lo + (hi - lo) / 2;
    double x;
    unsigned long long c = 0, all = 0;
    memcpy(&x, &mid, sizeof x);
    for (size_t i = 0; i < n; i++) c += v[i] > 0 && v[i] <= x;
    MPI_Allreduce(&c, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
    if (all > k)
      hi = mid;
    else
      lo = mid + 1;
  }
  double x;
  memcpy(&x, &lo, sizeof x);
  return x;
}

/* What the part's views and .opt take from the whole mesh: the 1 % smallest
 * step (without a target, as src/output/mesh.c takes it on one mesh), the
 * elements below it or the target, where the smallest step is. */
static void output_part(dtm_par *p, const dtm_par_figures *f) {
  const double *dt = dtm_analysis_dt(p->analysis), *own = dtm_analysis_local_step(p->analysis);
  size_t n = dtm_analysis_nelements(p->analysis);
  double target = dtm_analysis_advice_target(p->analysis), safety = p->scene->safety;
  unsigned long long fin = 0, all = 0, below = 0;
  for (size_t i = 0; i < n; i++) fin += isfinite(dt[i]) && dt[i] > 0;
  MPI_Allreduce(&fin, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
  dtm_output_part *o = &p->outpart;
  o->below_at = target > 0 || !all ? NAN : kth_smallest(p, dt, n, (all - 1) / 100);
  double at = target > 0 ? target : o->below_at;
  for (size_t i = 0; i < n && target > 0; i++) below += safety * own[i] < target;
  for (size_t i = 0; i < n && target <= 0; i++) below += dt[i] <= at;
  MPI_Allreduce(MPI_IN_PLACE, &below, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, p->comm);
  o->below = (size_t)below, o->elements = (size_t)f->elements;
  o->min_element = f->dt.tag, o->min_group = f->dt.group;
}

/* Each rank's counts, peak memory and stage times, gathered on rank 0. */
static int rows(dtm_par *p, dtm_par_figures *f) {
  struct rusage ru;
  double row[ROW_COUNT];
  getrusage(RUSAGE_SELF, &ru);
  row[ROW_ELEMENTS] = (double)dtm_analysis_nelements(p->analysis);
  row[ROW_NODES] = (double)p->mesh->nnodes;
  row[ROW_OWNED] = (double)p->nowned, row[ROW_GHOSTS] = (double)p->nghost;
  row[ROW_MEMORY] = 1024.0 * (double)ru.ru_maxrss; /* ru_maxrss is in KiB on Linux */
  row[ROW_PRODUCT_CPU] = p->product_cpu, row[ROW_EXCHANGE] = p->exchange;
  for (int t = 0; t < PAR_T_COUNT; t++) row[ROW_T + t] = p->t[t];
  f->rows = p->rank == 0 ? malloc((size_t)p->size * ROW_COUNT * sizeof *f->rows) : NULL;
  int r = dtm_par_agree(p, p->rank == 0 && !f->rows ? DTM_ERR(DTM_ERR_INTERNAL, "out of memory") : DTM_OK);
  if (r == DTM_OK) MPI_Gather(row, ROW_COUNT, MPI_DOUBLE, f->rows, ROW_COUNT, MPI_DOUBLE, 0, p->comm);
  return r;
}

int dtm_par_collect(dtm_par *p, dtm_par_figures *f) {
  int ne = dtm_analysis_neffects(p->analysis);
  memset(f, 0, sizeof *f);
  f->element = calloc((size_t)ne + 1, sizeof *f->element);
  f->node = calloc((size_t)ne + 1, sizeof *f->node);
  int r = dtm_par_agree(p, f->element && f->node ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
  if (r) return r;
  double count[2] = {(double)dtm_analysis_nelements(p->analysis), (double)p->nowned};
  MPI_Allreduce(MPI_IN_PLACE, count, 2, MPI_DOUBLE, MPI_SUM, p->comm);
  f->elements = count[0], f->nodes = count[1];
  DTM_CHECK(minima(p, f));
  DTM_CHECK(accuracy(p, f));
  subcycling(p, f);
  DTM_CHECK(mass(p, f));
  DTM_CHECK(lists(p, f));
  output_part(p, f);
  return DTM_OK;
}

int dtm_par_collect_rows(dtm_par *p, dtm_par_figures *f) { return rows(p, f); }

void dtm_par_figures_free(dtm_par_figures *f) {
  if (f->mass) free(f->mass->group_mass), free(f->mass->group_added);
  free(f->element), free(f->node), free(f->mass), free(f->rows);
  cJSON_Delete(f->under_list), cJSON_Delete(f->most_added), cJSON_Delete(f->worst);
  cJSON_Delete(f->zones), cJSON_Delete(f->damping);
  memset(f, 0, sizeof *f);
}

void dtm_par_whole_cost(const dtm_par *p, const dtm_par_figures *f, dtm_cost *c) {
  double seconds;
  if (dtm_cost_per_element_step_of(p->analysis, f->elements, &seconds, c->per_element_step_source,
                                   sizeof c->per_element_step_source) == DTM_OK)
    c->per_element_step = seconds;
  else
    dtm_error_clear();
}
