/* Thin layers: the shape-limited elements whose feature is a thin part (two
 * boundaries that do not touch, closer than the size the target needs; see
 * shape.c), gathered per physical group. A lining, a coating or a thin
 * wall caps every element across it near its thickness: no size
 * suggestion lifts them, so the advice names the group, its local
 * thickness, how many elements, the best step any mesh of the layer can
 * reach there, and the step LS-DYNA's shell rule (L_s / c_p; in 2D the
 * same for a beam along the layer) would give the layer at its present
 * in-plane size if it were modelled as its mid-surface. The mass and the
 * subcycling remedies are the cost module's. Without a target the same is
 * said of the elements at the smallest steps (at_minimum): the layer they
 * cross and the best step a fresh mesh of it reaches there. */
#include <math.h>
#include <stdlib.h>

#include "analysis-impl.h"

static dtm_layer *layer_of(dtm_analysis *a, int g, int at_minimum) {
  for (size_t k = 0; k < a->nlayers; k++)
    if (a->layers[k].group == g) return &a->layers[k];
  dtm_layer *l = &a->layers[a->nlayers++];
  *l = (dtm_layer){g, 0, INFINITY, INFINITY, 0, 0, NAN, at_minimum};
  return l;
}

static void add_element(dtm_analysis *a, dtm_layer *l, const dtm_shape_limited *s) {
  size_t i = s->element;
  if (!l->elements || a->local[i] < a->local[l->worst]) l->worst = i;
  l->elements++;
  l->thickness = fmin(l->thickness, s->size);
  l->reach = fmin(l->reach, s->reach);
  l->size += a->h[i];
}

/* LS-DYNA's rule for a shell (or beam) of the layer's material at the mean
 * size of its elements. */
static void shell_rule(dtm_analysis *a, dtm_layer *l) {
  int b;
  size_t e;
  dtm_analysis_locate(a, l->worst, &b, &e);
  const dtm_material *m = &a->scene->materials[a->mesh->blocks[b].mat[e]].m;
  double E = dtm_material_value(m, "E"), nu = dtm_material_value(m, "nu"), rho = dtm_material_value(m, "rho");
  l->size /= (double)l->elements;
  l->shell_step = l->size / sqrt(E / (rho * (1 - nu * nu)));
}

int dtm_layers_gather_from(dtm_analysis *a, const dtm_shape_limited *sl, size_t n, int at_minimum) {
  free(a->layers);
  a->layers = NULL, a->nlayers = 0;
  if (!n) return DTM_OK;
  a->layers = malloc((n + 1) * sizeof *a->layers);
  if (!a->layers) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t j = 0; j < n; j++)
    if (sl[j].feature == DTM_FEATURE_THIN)
      add_element(a, layer_of(a, dtm_analysis_group(a, sl[j].element), at_minimum), &sl[j]);
  for (size_t k = 0; k < a->nlayers; k++) shell_rule(a, &a->layers[k]);
  return DTM_OK;
}

int dtm_layers_gather(dtm_analysis *a) { return dtm_layers_gather_from(a, a->shape, a->nshape, 0); }

const dtm_layer *dtm_analysis_layers(const dtm_analysis *a, size_t *n) {
  *n = a->nlayers;
  return a->layers;
}
