/* The seeded random generator behind the Lanczos start vector and the
 * random part of `dtmap verify`'s initial field: splitmix64 (Steele, Lea and
 * Flood), which is fast, passes BigCrush, and needs one word of state, so a
 * seed reproduces a run exactly. dtm_rng_uniform_at draws the value of one
 * key (a Gmsh node tag and a component) without a sequence, so a field
 * drawn per node does not depend on the order the nodes are stored in.
 * dtm_rng_normal_at draws a standard normal value per key the same way
 * (Box-Muller on two successive outputs of the key's stream), so that a
 * vector of them, normalised, is uniform on the unit sphere (the Lanczos
 * start the Kuczynski-Wozniakowski bound asks for). */
#include <math.h>

#include "base.h"

uint64_t dtm_rng_next(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15u);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  return z ^ (z >> 31);
}

double dtm_rng_uniform(uint64_t *state, double lo, double hi) {
  return lo + (hi - lo) * ((double)(dtm_rng_next(state) >> 11) * 0x1.0p-53);
}

double dtm_rng_uniform_at(uint64_t seed, uint64_t key, double lo, double hi) {
  uint64_t state = seed ^ (key * 0xd1b54a32d192ed03u); /* a distinct stream start per key */
  dtm_rng_next(&state);
  return dtm_rng_uniform(&state, lo, hi);
}

double dtm_rng_normal_at(uint64_t seed, uint64_t key) {
  uint64_t state = seed ^ (key * 0xd1b54a32d192ed03u);
  dtm_rng_next(&state);
  double u1 = dtm_rng_uniform(&state, 0, 1), u2 = dtm_rng_uniform(&state, 0, 1);
  return sqrt(-2 * log(1 - u1)) * cos(6.283185307179586 * u2); /* 1 - u1 in (0, 1] */
}
