/* The levelled rules of the second-order types with their shape functions
 * evaluated at their points, once per type and level for the whole
 * process: a curved element is integrated at 125 to 512 points (curved.c),
 * and evaluating the same reference shape functions there again for every
 * element, in the level search, the element stiffness and the lumped
 * masses, cost more than the element's own geometry. The values are those
 * of dtm_ref_eval at the rule's points, so every result is bitwise the same
 * as when they were evaluated on the spot. A table is built on first use
 * under a lock (the element loops run on OpenMP threads) and then read
 * without one; it lives until the process ends. */
#include <pthread.h>
#include <stdlib.h>

#include "kernel-impl.h"

#define NTYPES 20 /* element type numbers below this (include/dtmap/kernel.h) */

static const dtm_ref_table *tables[NTYPES][DTM_K_LEVEL_MAX + 1];
static pthread_mutex_t building = PTHREAD_MUTEX_INITIALIZER;

static dtm_ref_table *build(int type, int level) {
  dtm_ref_table *t = malloc(sizeof *t);
  if (!t) return NULL;
  if (!dtm_ref_rule_level(type, level, &t->q)) return free(t), NULL;
  for (int k = 0; k < t->q.n; k++) dtm_ref_eval(type, t->q.p[k], t->N[k], t->dN[k]);
  return t;
}

const dtm_ref_table *dtm_ref_level_table(int type, int level) {
  if (type < 0 || type >= NTYPES || level < 1 || level > DTM_K_LEVEL_MAX || !dtm_ref_levelled(type)) return NULL;
  const dtm_ref_table *t = __atomic_load_n(&tables[type][level], __ATOMIC_ACQUIRE);
  if (t) return t;
  pthread_mutex_lock(&building);
  t = tables[type][level];
  if (!t) t = build(type, level), __atomic_store_n(&tables[type][level], t, __ATOMIC_RELEASE);
  pthread_mutex_unlock(&building);
  return t;
}
