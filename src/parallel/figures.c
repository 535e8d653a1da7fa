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

/* Under-resolved and conflicting elements summed; the tightest cap. */
static int accuracy(const dtm_par *p, dtm_par_figures *f) {
  dtm_accuracy ac;
  dtm_analysis_accuracy(p->analysis, &ac);
  double v[2] = {(double)ac.under_resolved, (double)ac.conflicts}, cap = isnan(ac.dt_cap) ? INFINITY : ac.dt_cap;
  MPI_Allreduce(MPI_IN_PLACE, v, 2, MPI_DOUBLE, MPI_SUM, p->comm);
  MPI_Allreduce(&cap, &f->dt_cap, 1, MPI_DOUBLE, MPI_MIN, p->comm);
  f->under_resolved = v[0], f->conflicts = v[1];
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

static void subcycling(const dtm_par *p, dtm_par_figures *f) {
  const dtm_subcycling *sc = &p->cost->subcycling;
  double work = 0;
  for (int k = 0; k < DTM_MAX_LEVELS; k++) f->levels[k] = (double)sc->count[k];
  MPI_Allreduce(MPI_IN_PLACE, f->levels, DTM_MAX_LEVELS, MPI_DOUBLE, MPI_SUM, p->comm);
  for (int k = 0; k < DTM_MAX_LEVELS; k++)
    if (f->levels[k] > 0) f->nlevels = k + 1, work += ldexp(f->levels[k], -k);
  f->speedup = work > 0 ? f->elements / work : 1.0; /* as src/cost/subcycling.c, over every part */
}

/* Mass scaling totals and per-group sums (the parts name the same groups). */
static int mass(dtm_par *p, dtm_par_figures *f) {
  const dtm_mass_scaling *ms = p->cost->mass;
  if (!ms) return DTM_OK;
  int n = 3 + 2 * ms->ngroups;
  f->mass = malloc((size_t)n * sizeof *f->mass);
  int r = dtm_par_agree(p, f->mass ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
  if (r) return r;
  f->mass[0] = ms->total_mass, f->mass[1] = ms->total_added, f->mass[2] = (double)ms->scaled;
  for (int g = 0; g < ms->ngroups; g++)
    f->mass[3 + g] = ms->group_mass[g], f->mass[3 + ms->ngroups + g] = ms->group_added[g];
  MPI_Allreduce(MPI_IN_PLACE, f->mass, n, MPI_DOUBLE, MPI_SUM, p->comm);
  return DTM_OK;
}

/* Each rank's counts, peak memory and stage times, gathered on rank 0. */
static int rows(dtm_par *p, dtm_par_figures *f) {
  struct rusage ru;
  double row[ROW_COUNT];
  getrusage(RUSAGE_SELF, &ru);
  row[ROW_ELEMENTS] = (double)dtm_analysis_nelements(p->analysis);
  row[ROW_NODES] = (double)p->mesh->nnodes;
  row[ROW_OWNED] = (double)p->nowned, row[ROW_GHOSTS] = (double)p->nghost;
  row[ROW_MEMORY] = (double)ru.ru_maxrss / 1024.0; /* ru_maxrss is in KiB on Linux */
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
  return rows(p, f);
}

void dtm_par_figures_free(dtm_par_figures *f) {
  free(f->element), free(f->node), free(f->mass), free(f->rows);
  memset(f, 0, sizeof *f);
}
