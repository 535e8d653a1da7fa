/* The warning for a step set by a few elements alone: when the smallest
 * element step lies 10 times or more below the 1 % quantile of the element
 * steps, those few elements (a CAD sliver, a short edge, a tiny face) cap
 * the step of the whole model while the rest of the mesh could run 10x
 * faster. The warning names the worst element (tag, type, group, centroid),
 * how many lie that far below, and where it sits on the model: its own
 * entity and the lower-dimensional entities its nodes lie on (the feature to
 * defeature), so that it is found in the CAD. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "output-impl.h"

#define OUTLIER_RATIO 10.0 /* the quantile over the smallest step that makes a warning */
#define OUTLIER_ENTITIES 6 /* lower-dimensional entities named at most */

static const char *entity_word(int dim) {
  return dim == 0 ? "point" : dim == 1 ? "curve" : dim == 2 ? "surface" : "volume";
}

/* Block b and index e of element i (in the analysis's order). */
static void locate(const dtm_mesh *m, size_t i, int *b, size_t *e) {
  for (*b = 0; *b < m->nblocks && i >= m->blocks[*b].n; (*b)++) i -= m->blocks[*b].n;
  *e = i;
}

/* "in model volume 1, its nodes on model surface 3, curve 7" into buf. */
static void where_on_model(const dtm_analysis *a, int b, size_t e, char *buf, size_t len) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  const dtm_block *bl = &m->blocks[b];
  const dtm_geo *g = dtm_analysis_geo(a);
  size_t k = 0;
  buf[0] = '\0';
  if (bl->entity && bl->entity[e] >= 0)
    k += (size_t)snprintf(buf, len, "in model %s %d", entity_word(m->dim), bl->entity[e]);
  int dims[OUTLIER_ENTITIES], tags[OUTLIER_ENTITIES], n = 0;
  for (int v = 0; g && g->node_dim && v < bl->nn; v++) {
    size_t node = bl->conn[e * (size_t)bl->nn + (size_t)v];
    int d = node < g->nnodes ? g->node_dim[node] : m->dim, t = node < g->nnodes ? g->node_tag[node] : -1, seen = 0;
    if (d >= m->dim || t < 0) continue;
    for (int j = 0; j < n; j++) seen |= dims[j] == d && tags[j] == t;
    if (!seen && n < OUTLIER_ENTITIES) dims[n] = d, tags[n++] = t;
  }
  for (int j = 0; j < n && k < len; j++)
    k += (size_t)snprintf(buf + k, len - k, "%s%s %d",
                          j   ? ", "
                          : k ? ", its nodes on model "
                              : "its nodes on model ",
                          entity_word(dims[j]), tags[j]);
}

void dtm_output_outlier_warning(const dtm_analysis *a, dtm_warnings *w) {
  size_t nel = dtm_analysis_nelements(a), imin = 0, below = 0;
  const double *dt = dtm_analysis_dt(a);
  double dmin = dtm_analysis_dt_min(a, &imin), q = dtm_analysis_dt_quantile(a);
  if (!(dmin > 0) || !isfinite(dmin) || imin >= nel) return;
  if (!(q >= OUTLIER_RATIO * dmin)) return;
  for (size_t i = 0; i < nel; i++) below += isfinite(dt[i]) && dt[i] * OUTLIER_RATIO <= q;
  int b;
  size_t e;
  char place[256], where[256];
  locate(dtm_analysis_mesh(a), imin, &b, &e);
  dtm_mesh_element_place(dtm_analysis_mesh(a), b, e, place, sizeof place);
  where_on_model(a, b, e, where, sizeof where);
  dtm_output_warn(w,
                  "%s caps the step: %.4e s, %.3gx below the 1 %% quantile of the element steps (%.4e s; %zu "
                  "element%s %gx or more below it)%s%s: a CAD sliver, short edge or tiny face there sets the step of "
                  "the whole model; defeature it",
                  place, dmin, q / dmin, q, below, below == 1 ? "" : "s", OUTLIER_RATIO, where[0] ? ", " : "", where);
}
