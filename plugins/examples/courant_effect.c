/* An example external effect, built as a shared library and loaded by
 * <effect library="libdtmap_example_courant.so" name="courant" speed="..."/>.
 * It limits the step by the Courant rule dt = shortest edge / speed for a
 * user-given signal speed (m/s), and shows everything an effect author
 * needs: the class table, attribute parsing, and the entry symbol.
 * The tests also build it with EXAMPLE_API_VERSION=99 (a version mismatch)
 * and with EXAMPLE_NO_ENTRY (a library without the entry symbol). */
#include <stdlib.h>

#include "dtmap/effect.h"

#ifndef EXAMPLE_API_VERSION
#define EXAMPLE_API_VERSION DTM_EFFECT_API_VERSION
#endif

typedef struct {
  double speed; /* signal speed, m/s */
} courant_state;

static int courant_create(const dtm_effect_args *a, void **state) {
  double c;
  DTM_CHECK(dtm_effect_args_double(a, "speed", 0.0, &c));
  if (!(c > 0)) return dtm_effect_args_error(a, "speed= must be a positive signal speed in m/s");
  courant_state *s = malloc(sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  s->speed = c;
  *state = s;
  return DTM_OK;
}

static int courant_element_dt(void *state, const dtm_batch *b, double *dt, double *len) {
  const courant_state *s = state;
  for (size_t e = 0; e < b->n; e++) {
    len[e] = dtm_kernel_length(b->type, DTM_LEN_MIN_EDGE, b->x + 3 * (size_t)b->nn * e);
    dt[e] = len[e] / s->speed;
  }
  return DTM_OK;
}

static const dtm_effect_class courant_class = {
    .api_version = EXAMPLE_API_VERSION,
    .name = "courant",
    .summary = "example external effect: shortest edge / speed",
    .role = DTM_ROLE_LIMITS,
    .needs = 0,
    .exponent = 1.0,
    .create = courant_create,
    .element_dt = courant_element_dt,
    .destroy = dtm_effect_free,
};

#ifndef EXAMPLE_NO_ENTRY
const dtm_effect_class *dtm_effect_entry(void) { return &courant_class; }
#else
const dtm_effect_class *example_unused(void) { return &courant_class; }
#endif
