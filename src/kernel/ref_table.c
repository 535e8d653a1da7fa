/* The levelled rules of the second-order types with their shape functions
 * evaluated at their points, once per type and level for the whole
 * process: a curved element is integrated at 125 to 512 points (curved.c),
 * and evaluating the same reference shape functions there again for every
 * element, in the level search, the element stiffness and the lumped
 * masses, cost more than the element's own geometry. The values are those
 * of dtm_ref_eval at the rule's points, so every result is bitwise the same
 * as when they were evaluated on the spot. A table is built on first use
 * under a lock (the element loops run on OpenMP threads) and then read
 * without one; it lives until the process ends. The full rules (level 0)
 * and CalculiX's C3D10 rule have tables too (dtm_ref_rule_table), for the
 * element bound's single pass over its points (generic.c). */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "kernel-impl.h"

#define NTYPES 20 /* element type numbers below this (include/dtmap/kernel.h) */

#define NODES (DTM_K_RULE_C3D10 + 1) /* the slot of the nodes' table */

static const dtm_ref_table *tables[NTYPES][NODES + 1];
static pthread_mutex_t building = PTHREAD_MUTEX_INITIALIZER;

static dtm_ref_table *build(int type, int level) {
  size_t bytes = (sizeof(dtm_ref_table) + 31) / 32 * 32; /* aligned_alloc's size: a multiple of the alignment */
  dtm_ref_table *t = aligned_alloc(32, bytes);           /* dN4's vectors */
  if (!t) return NULL;
  memset(t, 0, bytes); /* the rows' entries beyond the type's nodes read as zeros (curved.c's masses) */
  if (level == NODES) {
    dtm_elem_info(type, NULL, &t->q.n);
    for (int a = 0; a < t->q.n; a++) dtm_ref_node(type, a, t->q.p[a]), t->q.w[a] = 0;
  } else if (level == 0)
    dtm_ref_rule(type, &t->q);
  else if (level == DTM_K_RULE_C3D10)
    dtm_ref_rule_c3d10(&t->q);
  else if (!dtm_ref_rule_level(type, level, &t->q))
    return free(t), NULL;
  for (int k = 0; k < t->q.n; k++) dtm_ref_eval(type, t->q.p[k], t->N[k], t->dN[k]);
  for (int k = 0; k + 4 <= t->q.n; k += 4)
    for (int a = 0; a < DTM_K_NODES; a++)
      for (int j = 0; j < 3; j++)
        t->dN4[k / 4][a][j] = (dtm_v4d){t->dN[k][a][j], t->dN[k + 1][a][j], t->dN[k + 2][a][j], t->dN[k + 3][a][j]};
  return t;
}

static const dtm_ref_table *table(int type, int level) {
  const dtm_ref_table *t = __atomic_load_n(&tables[type][level], __ATOMIC_ACQUIRE);
  if (t) return t;
  pthread_mutex_lock(&building);
  t = tables[type][level];
  if (!t) t = build(type, level), __atomic_store_n(&tables[type][level], t, __ATOMIC_RELEASE);
  pthread_mutex_unlock(&building);
  return t;
}

const dtm_ref_table *dtm_ref_level_table(int type, int level) {
  if (type < 0 || type >= NTYPES || level < 1 || level > DTM_K_LEVEL_MAX || !dtm_ref_levelled(type)) return NULL;
  return table(type, level);
}

const dtm_ref_table *dtm_ref_rule_table(int type, int id) {
  if (type < 0 || type >= NTYPES || !dtm_elem_topology(type)) return NULL;
  if (id == 0 || (id == DTM_K_RULE_C3D10 && type == DTM_TET10)) return table(type, id);
  return dtm_ref_level_table(type, id);
}

const dtm_ref_table *dtm_ref_node_table(int type) {
  if (type < 0 || type >= NTYPES || !dtm_elem_topology(type)) return NULL;
  return table(type, NODES);
}
