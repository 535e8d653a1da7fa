/* What mass scaling costs in accuracy, in the model's own natural
 * frequencies: the lowest elastic modes of the model as meshed, and of each
 * modified model a caller adds (conventional point masses reaching a
 * target, by the nodal rule `deck --target` adds, dtm_mass_scaling_nodal:
 * each node below the target gets m_a ((T / dt_a)^2 - 1), which lifts every
 * nodal bound, hence the recommended step, to the target; or any added
 * mass matrix, such as selective mass scaling's), each mode matched to the model's by shape (MAC) and its
 * frequency shift in percent. The modes are those of dtm_modes_lowest on
 * the first elastic effect's operator (src/spectral/modes.c); every extra
 * mass is a dtm_csr over that operator's unknowns. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"

/* The first elastic effect's operator into p (op, effect). */
static int elastic_operator(const dtm_analysis *a, dtm_modes_price *p) {
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    dtm_operator *op = NULL;
    if (dtm_analysis_operator(a, k, 0.0, &op) || dtm_operator_kind(op) != DTM_OP_ELASTIC) {
      dtm_operator_destroy(&op);
      dtm_error_clear(); /* not a spectral effect, or not elastic: the next one */
      continue;
    }
    p->op = op, p->effect = k;
    return DTM_OK;
  }
  return DTM_ERR(DTM_ERR_INPUT, "%s: natural modes need an elastic effect; the scene has none",
                 dtm_analysis_scene(a)->path);
}

int dtm_modes_price_base(const dtm_analysis *a, int n, dtm_modes_price *p) {
  memset(p, 0, sizeof *p);
  p->n = n;
  DTM_CHECK(elastic_operator(a, p));
  const double *m = dtm_operator_mass(p->op);
  size_t nd = dtm_operator_ndof(p->op), nc = (size_t)dtm_operator_ncomp(p->op);
  for (size_t i = 0; i < nd; i += nc) p->model_mass += m[i];
  int r = dtm_modes_lowest(p->op, NULL, n, &p->base);
  if (r != DTM_ERR_INPUT) return r;
  char why[512];
  snprintf(why, sizeof why, "%s", dtm_error_message());
  dtm_error_clear();
  return DTM_ERR(DTM_ERR_INPUT, "%s: %s", dtm_analysis_scene(a)->path, why);
}

/* A variant's slot, named, or an error when all are taken. */
static int new_variant(dtm_modes_price *p, const char *name, dtm_modes_variant **v) {
  if (p->nvariants == DTM_PRICE_VARIANTS)
    return DTM_ERR(DTM_ERR_INTERNAL, "more than %d modified models compared", DTM_PRICE_VARIANTS);
  *v = &p->variant[p->nvariants++];
  memset(*v, 0, sizeof **v);
  (*v)->name = name;
  return DTM_OK;
}

int dtm_modes_price_add(dtm_modes_price *p, const char *name, const dtm_csr *extra, double added_mass) {
  dtm_modes_variant *v = NULL;
  DTM_CHECK(new_variant(p, name, &v));
  v->added_mass = added_mass, v->added_percent = 100.0 * added_mass / p->model_mass;
  DTM_CHECK(dtm_modes_lowest(p->op, extra, p->n + DTM_PRICE_SPARE, &v->modes));
  v->shift = malloc(((size_t)p->base.nelastic + 1) * sizeof *v->shift);
  if (!v->shift) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  DTM_CHECK(dtm_modes_compare(p->op, &p->base, &v->modes, v->shift));
  v->computed = 1;
  return DTM_OK;
}

int dtm_modes_price_conventional(const dtm_analysis *a, double target, dtm_modes_price *p) {
  dtm_mass_scaling ms;
  p->target = target;
  if (!isfinite(dtm_analysis_dt_nodal(a))) {
    dtm_modes_variant *v = NULL;
    DTM_CHECK(new_variant(p, "conventional mass", &v));
    v->why = "no nodal bound to add point masses on", v->added_mass = v->added_percent = NAN;
    return DTM_OK;
  }
  DTM_CHECK(dtm_mass_scaling_nodal(a, target / dtm_analysis_scene(a)->safety, NULL, &ms));
  dtm_csr extra = {0};
  int r = dtm_csr_point_masses(p->op, ms.node_added, dtm_analysis_mesh(a)->nnodes, &extra);
  if (r == DTM_OK) r = dtm_modes_price_add(p, "conventional mass", &extra, ms.total_added);
  if (r == DTM_OK) p->variant[p->nvariants - 1].nodes = ms.nodes;
  dtm_csr_free(&extra);
  dtm_mass_scaling_free(&ms);
  return r;
}

int dtm_modes_price_selective(const dtm_analysis *a, const dtm_selective_mass *m, dtm_modes_price *p) {
  if (m->effect != p->effect) {
    dtm_modes_variant *v = NULL;
    DTM_CHECK(new_variant(p, "selective mass", &v));
    v->why = "the scaled effect is not the one whose modes are computed", v->added_mass = v->added_percent = NAN;
    return DTM_OK;
  }
  if (!(p->target > 0)) p->target = m->target;
  dtm_csr add = {0};
  int r = dtm_analysis_selective_added(a, m, &add);
  if (r == DTM_OK) r = dtm_modes_price_add(p, "selective mass", &add, 0.0);
  if (r == DTM_OK) p->variant[p->nvariants - 1].deformation = m->stats.trace_add[0];
  dtm_csr_free(&add);
  return r;
}

void dtm_modes_price_free(dtm_modes_price *p) {
  if (!p) return;
  for (int i = 0; i < p->nvariants; i++) dtm_modes_free(&p->variant[i].modes), free(p->variant[i].shift);
  dtm_modes_free(&p->base);
  dtm_operator_destroy(&p->op);
  memset(p, 0, sizeof *p);
}
