/* The diffusion kernel loop shared by the thermal and hydraulic effects:
 * per element 2/lambda_max(Ce^-1 Ke) with the material's diffusivity, the
 * characteristic length sqrt(2 D dt), and the operator coefficients. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "diffusion.h"

int dtm_diffusion_create(const dtm_effect_args *a, const dtm_property *props, dtm_diffusion_combine_fn combine,
                         void **state) {
  dtm_diffusion_state *s = malloc(sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < 3; i++) s->idx[i] = dtm_effect_args_property(a, props[i].name);
  s->combine = combine;
  *state = s;
  return DTM_OK;
}

static void material_coeffs(const dtm_diffusion_state *s, const dtm_material *m, double *k, double *c) {
  double v[3];
  for (int i = 0; i < 3; i++) v[i] = dtm_material_get(m, s->idx[i]);
  s->combine(v, k, c);
}

int dtm_diffusion_element_dt(void *state, const dtm_batch *b, double *dt, double *len) {
  const dtm_material *last = NULL;
  double D = 0, k, c;
  for (size_t e = 0; e < b->n; e++) {
    if (b->mat[e] != last) last = b->mat[e], material_coeffs(state, last, &k, &c), D = k / c;
    double lambda;
    if (dtm_kernel_diffusion_lambda(b->type, D, b->x + 3 * (size_t)b->nn * e, &lambda))
      return DTM_ERR(DTM_ERR_INPUT, "element %zu (%s): %s", b->tags[e], dtm_elem_name(b->type), dtm_error_message());
    dt[e] = 2.0 / lambda;
    len[e] = sqrt(2.0 * D * dt[e]);
  }
  return DTM_OK;
}

int dtm_diffusion_coefficients(void *state, const dtm_material *m, const dtm_section *sec, dtm_operator_coeffs *c) {
  (void)sec; /* scalar diffusion is the same in every kind of element */
  memset(c, 0, sizeof *c);
  c->kind = DTM_OP_DIFFUSION;
  c->dt_is_bound = 1;
  material_coeffs(state, m, &c->conductivity, &c->capacity);
  return DTM_OK;
}
