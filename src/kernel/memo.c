/* A per-thread memo of what the level search of a curved element
 * (curved.c) has already integrated at the level it keeps: the Gram tensor
 * U = integral g g^T dv (its upper triangle), the lumped masses per unit
 * density and the measure. The element map then integrates the same
 * element with the same rule again (dtm_elem_assemble), and so does its
 * measure (measure.c): with the search run just before them on the same
 * thread (src/analysis/compute.c searches a chunk of elements, then maps
 * it), both read the memo instead. The key is everything the values depend
 * on, compared exactly: the type, the rule's table and the node
 * coordinates in the element's frame, so a hit returns the very bits the
 * integration would give, and a miss only costs the integration.
 * Open addressing over SLOTS entries (a chunk's 512 elements fill at most
 * a quarter), PROBE slots per key; a put takes an empty slot or the oldest,
 * so entries of earlier chunks go first. An entry of the chunk is lost only
 * when PROBE slots from its hash all hold younger entries of the same
 * chunk: with 1024 slots and 16 probes that happened in one run in 40
 * (the hash takes the rule table's address, so it changes from run to run,
 * and tests/t115, which checks that none is lost, failed that often). At a
 * quarter full, a simulation of 3,000 chunks never saw a run of even 20
 * such slots, so a loss with 32 probes is left to a remote chance; and a
 * loss costs one integration, never a different number.
 * Elements with more than MAX_DOF unknowns (the 3D types above tet10) are
 * not kept: an entry is sized for tet10 (4 kB; 8 MB per thread, allocated
 * at the first put, touched as it fills, and freed when the thread ends). */
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "kernel-impl.h"

#define SLOTS 2048
#define PROBE 32
#define MAX_DOF 30
#define MAX_NODES 10
#define PACKED (MAX_DOF * (MAX_DOF + 1) / 2)

typedef struct {
  const dtm_ref_table *t; /* NULL: empty */
  int type, nn, nd;
  uint64_t stamp;
  double x[MAX_NODES][3];
  double U[PACKED];
  double m[MAX_NODES];
  double vol;
} entry;

static _Thread_local entry *slots;
static _Thread_local uint64_t clock_now;
static _Thread_local long hits;
static pthread_key_t owner; /* frees a thread's slots when it ends */
static int owner_made;
static pthread_once_t owner_once = PTHREAD_ONCE_INIT;

static void owner_make(void) { owner_made = !pthread_key_create(&owner, free); }

/* This thread's slots, made on first use; NULL without memory. Without the
 * key (or if it cannot be set) they live until the process ends. */
static entry *slots_made(void) {
  if (slots) return slots;
  pthread_once(&owner_once, owner_make);
  if ((slots = calloc(SLOTS, sizeof *slots)) && owner_made) (void)pthread_setspecific(owner, slots);
  return slots;
}

int dtm_memo_fits(int nn, int nd) { return nn <= MAX_NODES && nd <= MAX_DOF; }

static size_t hash_of(int type, const dtm_ref_table *t, int nn, const double (*xl)[3]) {
  uint64_t h = (uint64_t)type * 0x9E3779B97F4A7C15ull ^ (uint64_t)(uintptr_t)t;
  for (int a = 0; a < nn; a++)
    for (int i = 0; i < 3; i++) {
      uint64_t w;
      memcpy(&w, &xl[a][i], sizeof w);
      h = (h ^ w) * 0xFF51AFD7ED558CCDull;
      h ^= h >> 29;
    }
  return (size_t)(h % SLOTS);
}

static int same(const entry *s, int type, const dtm_ref_table *t, int nn, int nd, const double (*xl)[3]) {
  return s->t == t && s->type == type && s->nn == nn && s->nd == nd && !memcmp(s->x, xl, (size_t)nn * sizeof xl[0]);
}

void dtm_memo_put(int type, const dtm_ref_table *t, int nn, int nd, const double (*xl)[3], const double *U,
                  const double *m, double vol) {
  if (!dtm_memo_fits(nn, nd) || !slots_made()) return;
  size_t h = hash_of(type, t, nn, xl);
  entry *s = &slots[h];
  for (int p = 0; p < PROBE; p++) { /* the key's own slot, an empty one, else the oldest */
    entry *c = &slots[(h + (size_t)p) % SLOTS];
    if (!c->t || same(c, type, t, nn, nd, xl)) {
      s = c;
      break;
    }
    if (c->stamp < s->stamp) s = c;
  }
  s->t = t, s->type = type, s->nn = nn, s->nd = nd, s->stamp = ++clock_now, s->vol = vol;
  memcpy(s->x, xl, (size_t)nn * sizeof xl[0]);
  memcpy(s->m, m, (size_t)nn * sizeof *m);
  for (int x = 0, k = 0; x < nd; x++)
    for (int y = x; y < nd; y++) s->U[k++] = U[x * nd + y];
}

int dtm_memo_get(int type, const dtm_ref_table *t, int nn, int nd, const double (*xl)[3], double *U, double *m,
                 double *vol) {
  if (!slots || !dtm_memo_fits(nn, nd)) return 0;
  size_t h = hash_of(type, t, nn, xl);
  for (int p = 0; p < PROBE; p++) {
    const entry *s = &slots[(h + (size_t)p) % SLOTS];
    if (!s->t) return 0;
    if (!same(s, type, t, nn, nd, xl)) continue;
    for (int x = 0, k = 0; U && x < nd; x++)
      for (int y = x; y < nd; y++) U[x * nd + y] = s->U[k++];
    memcpy(m, s->m, (size_t)nn * sizeof *m);
    *vol = s->vol;
    hits++;
    return 1;
  }
  return 0;
}

void dtm_memo_clear(void) {
  if (slots) memset(slots, 0, SLOTS * sizeof *slots);
}

long dtm_memo_hits(void) { return hits; }
