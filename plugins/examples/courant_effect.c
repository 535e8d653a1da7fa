/* An example external effect, built as a shared library and loaded by
 * <effect library="libdtmap_example_courant.so" name="courant" speed="..."/>.
 * It limits the step by the Courant rule dt = shortest edge / speed for a
 * user-given signal speed (m/s), and shows everything an effect author
 * needs: the class table, attribute parsing, and the entry symbol.
 * The tests also build it with EXAMPLE_API_VERSION=99 (a version mismatch),
 * with EXAMPLE_NO_ENTRY (a library without the entry symbol) and with
 * EXAMPLE_NO_STEP (a class that limits the step but has no element_dt). */
#include <math.h>
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
  DTM_CHECK(dtm_effect_args_number(a, "speed", &c)); /* required, > 0: validated before create() */
  courant_state *s = malloc(sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  s->speed = c;
  *state = s;
  return DTM_OK;
}

#ifndef EXAMPLE_NO_STEP
static int courant_element_dt(void *state, const dtm_batch *b, double *dt, double *len) {
  const courant_state *s = state;
  for (size_t e = 0; e < b->n; e++) {
    len[e] = dtm_kernel_length(b->type, DTM_LEN_MIN_EDGE, b->x + 3 * (size_t)b->nn * e);
    dt[e] = len[e] / s->speed;
  }
  return DTM_OK;
}
#endif

/* What the scene element takes: the core refuses any other attribute and a
 * speed that is missing, not a number or not positive, naming the scene
 * file and line, before create() runs. */
static const dtm_param params[] = {
    {"speed", DTM_PARAM_NUMBER, NULL, 0, HUGE_VAL, DTM_OPEN_LO, NULL, 1, "m/s", "signal speed"},
    {NULL, 0, NULL, 0, 0, 0, NULL, 0, NULL, NULL}};

static const dtm_effect_class courant_class = {
    .api_version = EXAMPLE_API_VERSION,
    .name = "courant",
    .summary = "example external effect: shortest edge / speed",
    .role = DTM_ROLE_LIMITS,
    .scheme = DTM_SCHEME_CENTRAL_DIFFERENCE,
    .exponent = 1.0,
    .params = params,
    .create = courant_create,
#ifndef EXAMPLE_NO_STEP
    .element_dt = courant_element_dt,
#endif
    .destroy = dtm_effect_free,
};

#ifndef EXAMPLE_NO_ENTRY
const dtm_effect_class *dtm_effect_entry(void) { return &courant_class; }
#else
const dtm_effect_class *example_unused(void) { return &courant_class; }
#endif
