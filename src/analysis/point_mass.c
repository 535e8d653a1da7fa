/* Point masses added to an analysed mesh after the fact (refine's mass
 * where no mesh reaches the target): the mesh takes them as its node_mass
 * and everything that reads the lumped mass is computed again, the nodal
 * bound, the recommendation, each element's own step, the size suggestion
 * and the elements below the target. The element steps stay those of the
 * elements alone. A global estimate made before is dropped (it was for
 * the old masses): the caller estimates again. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"

/* Drop what the masses change. */
static void drop_mass_dependent(dtm_analysis *a) {
  for (int k = 0; a->node_dt && k < a->neffects; k++) free(a->node_dt[k]);
  free(a->node_dt), free(a->nodal_node), free(a->local), free(a->size_node), free(a->forced);
  a->node_dt = NULL, a->nodal_node = a->local = a->size_node = a->forced = NULL;
  for (int k = 0; a->global && k < a->neffects; k++) free(a->global[k].mode);
  free(a->global);
  a->global = NULL, a->global_basis = 0;
  for (int k = 0; k < a->neffects; k++) a->per_effect[k].global = a->per_effect[k].certified = NAN;
}

int dtm_analysis_set_point_masses(dtm_analysis *a, const double *kg) {
  size_t nn = a->mesh->nnodes;
  if (a->x) return DTM_ERR(DTM_ERR_INPUT, "point masses are not taken by a distributed run yet");
  double *m = NULL;
  if (kg) {
    m = malloc((nn + 1) * sizeof *m);
    if (!m) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    for (size_t v = 0; v < nn; v++)
      if (!(isfinite(kg[v]) && kg[v] >= 0)) return free(m), DTM_ERR(DTM_ERR_INTERNAL, "a point mass of %g kg", kg[v]);
    memcpy(m, kg, nn * sizeof *m);
  }
  free(a->mesh->node_mass);
  a->mesh->node_mass = m;
  drop_mass_dependent(a);
  double t0 = dtm_wtime();
  DTM_CHECK(dtm_nodal_bounds(a));
  dtm_recommend(a);
  DTM_CHECK(dtm_local_steps(a));
  a->timings[DTM_T_NODAL] += dtm_wtime() - t0;
  t0 = dtm_wtime();
  DTM_CHECK(dtm_size_suggest(a));
  DTM_CHECK(dtm_shape_classify(a));
  a->timings[DTM_T_ADVICE] += dtm_wtime() - t0;
  return DTM_OK;
}

const double *dtm_analysis_point_masses(const dtm_analysis *a) { return a->mesh->node_mass; }
