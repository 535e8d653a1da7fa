/* The cohesive-zone effect, for the physical groups where cohesive
 * (interface) elements can open.
 * Accuracy: the process-zone length R = (pi/8) E' Gc / strength^2, with
 * E' = E/(1-nu^2) in plane strain and 3D and E in plane stress, must be
 * spanned by N elements (elements-per-zone, default 5, the low end of the
 * usual 5-10), so h <= R/N; the view "cohesive zone resolution" is R/h.
 * Stability: with stiffness= K (Pa/m), each facet of the element carries
 * interface springs k = K A_f / n_f per facet node, between the node's lumped
 * mass m_a = rho V w_a on this side and, as the neighbour is not known here,
 * the same mass on the other side: dt = min 2/sqrt(k (1/m_a + 1/m_a)).
 * Without stiffness the literature rule is used: 1/30 of the element's
 * elastic (eigenvalue-bound) step. Elements outside the groups are not
 * limited (+inf). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/effect.h"
#include "dtmap/mesh.h"
#include "dtmap/topology.h"

#define LITERATURE_FACTOR 30.0        /* Baylor (1997), via the CVFE review in shared/seeds */
#define PI_OVER_8 0.39269908169872414 /* M_PI is not C11 */

typedef struct {
  dtm_formulation form; /* elastic formulation for E' and the elastic step */
  double n_per_zone;    /* elements across the process zone */
  double stiffness;     /* interface stiffness, Pa/m; 0 = use the 1/30 rule */
  int ngroups;
  char *in;                /* [ngroups] 1 where the group has cohesive elements */
  unsigned long long mask; /* the same groups as a bit mask */
} cohesive_state;

static int parse_form(const dtm_effect_args *a, dtm_formulation *f) {
  const char *v;
  int dim = dtm_effect_args_dim(a);
  DTM_CHECK(dtm_effect_args_string(a, "formulation", dim == 3 ? "3d" : dim == 2 ? "plane-strain" : "bar", &v));
  static const char *const names[] = {"3d", "plane-strain", "plane-stress", "bar"};
  for (int i = 0; i < 4; i++)
    if (!strcmp(v, names[i])) return *f = (dtm_formulation)i, DTM_OK;
  return dtm_effect_args_error(a, "unknown formulation '%s'", v);
}

/* groups="a b c": mark each named group. */
static int parse_groups(const dtm_effect_args *a, cohesive_state *s) {
  const char *list;
  DTM_CHECK(dtm_effect_args_string(a, "groups", NULL, &list));
  if (!list) return dtm_effect_args_error(a, "groups= is required (the physical groups where cracks may open)");
  char buf[4096];
  snprintf(buf, sizeof buf, "%s", list);
  for (char *save = NULL, *tok = strtok_r(buf, " \t\n", &save); tok; tok = strtok_r(NULL, " \t\n", &save)) {
    int g;
    DTM_CHECK(dtm_effect_args_group(a, tok, &g));
    if (g >= DTM_MAX_MASK_GROUPS)
      return dtm_effect_args_error(a, "group '%s' is number %d of the mesh's groups; cohesive handles the first %d",
                                   tok, g + 1, DTM_MAX_MASK_GROUPS);
    s->in[g] = 1;
    s->mask |= 1ull << g;
  }
  return DTM_OK;
}

static void cohesive_destroy(void **state) {
  cohesive_state *s = *state;
  if (s) free(s->in);
  free(s);
  *state = NULL;
}

static int cohesive_create(const dtm_effect_args *a, void **state) {
  cohesive_state *s = calloc(1, sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  s->ngroups = dtm_effect_args_ngroups(a);
  s->in = calloc((size_t)s->ngroups + 1, 1);
  *state = s;
  int r = s->in ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (!r) r = parse_form(a, &s->form);
  if (!r) r = dtm_effect_args_double(a, "elements-per-zone", 5.0, &s->n_per_zone);
  if (!r) r = dtm_effect_args_double(a, "stiffness", 0.0, &s->stiffness);
  if (!r && (s->n_per_zone <= 0 || s->stiffness < 0))
    r = dtm_effect_args_error(a, "elements-per-zone must be > 0 and stiffness >= 0");
  if (!r) r = parse_groups(a, s);
  if (r) cohesive_destroy(state);
  return r;
}

/* In any of the cohesive groups, through any of the element's groups. */
static int in_groups(const cohesive_state *s, const dtm_batch *b, size_t e) {
  if (b->gmask) return (b->gmask[e] & s->mask) != 0;
  int g = b->group[e];
  return g >= 0 && g < s->ngroups && s->in[g];
}

/* Interface-spring step of one element: the smallest over its facet nodes. */
static double spring_dt(const cohesive_state *s, const dtm_batch *b, const double *x, double rho) {
  const int(*fn)[DTM_MAX_FACET_NODES];
  const int *fc;
  double w[DTM_MAX_NODES], V = dtm_elem_measure(b->type, x), dt = INFINITY;
  dtm_elem_lumped_weights(b->type, x, w);
  int nf = dtm_elem_facets(b->type, &fn, &fc);
  for (int f = 0; f < nf; f++) {
    double k = s->stiffness * dtm_elem_facet_measure(b->type, f, x) / fc[f];
    for (int i = 0; i < fc[f]; i++) {
      double m = rho * V * w[fn[f][i]];
      dt = fmin(dt, 2.0 / sqrt(k * (2.0 / m)));
    }
  }
  return dt;
}

static int element_step(const cohesive_state *s, const dtm_batch *b, size_t e, double *dt, double *len) {
  const dtm_material *m = b->mat[e];
  const double *x = b->x + 3 * (size_t)b->nn * e;
  dtm_elastic_moduli mod;
  double nu = s->form == DTM_FORM_BAR ? 0.0 : m->prop[DTM_PROP_NU], lambda;
  DTM_CHECK(dtm_elastic_moduli_init(s->form, m->prop[DTM_PROP_E], nu, m->prop[DTM_PROP_RHO], &mod));
  if (s->stiffness > 0) {
    *dt = spring_dt(s, b, x, mod.rho);
  } else {
    if (dtm_kernel_elastic_lambda(b->type, &mod, x, &lambda))
      return DTM_ERR(DTM_ERR_INPUT, "element %zu (%s): %s", b->tags[e], dtm_elem_name(b->type), dtm_error_message());
    *dt = 2.0 / sqrt(lambda) / LITERATURE_FACTOR;
  }
  *len = mod.cd * *dt;
  return DTM_OK;
}

static int cohesive_element_dt(void *state, const dtm_batch *b, double *dt, double *len) {
  const cohesive_state *s = state;
  for (size_t e = 0; e < b->n; e++) {
    dt[e] = INFINITY, len[e] = NAN;
    if (in_groups(s, b, e)) DTM_CHECK(element_step(s, b, e, &dt[e], &len[e]));
  }
  return DTM_OK;
}

/* R = (pi/8) E' Gc / strength^2 of a material. */
static double zone_length(const cohesive_state *s, const dtm_material *m) {
  double E = m->prop[DTM_PROP_E], nu = m->prop[DTM_PROP_NU];
  double Ep = (s->form == DTM_FORM_PLANE_STRESS || s->form == DTM_FORM_BAR) ? E : E / (1.0 - nu * nu);
  double sig = m->prop[DTM_PROP_STRENGTH];
  return PI_OVER_8 * Ep * m->prop[DTM_PROP_FRACTURE_ENERGY] / (sig * sig);
}

static int cohesive_accuracy(void *state, const dtm_batch *b, double *hmax, double *res) {
  const cohesive_state *s = state;
  const unsigned need = DTM_PROP_BIT(DTM_PROP_FRACTURE_ENERGY) | DTM_PROP_BIT(DTM_PROP_STRENGTH);
  for (size_t e = 0; e < b->n; e++) {
    hmax[e] = INFINITY, res[e] = NAN;
    if (!in_groups(s, b, e)) continue;
    DTM_CHECK(dtm_material_require(b->mat[e], need, "cohesive"));
    double R = zone_length(s, b->mat[e]);
    hmax[e] = R / s->n_per_zone;
    res[e] = R / dtm_elem_mean_edge(b->type, b->x + 3 * (size_t)b->nn * e);
  }
  return DTM_OK;
}

const dtm_effect_class dtm_effect_cohesive = {
    .api_version = DTM_EFFECT_API_VERSION,
    .name = "cohesive",
    .summary = "cohesive zones in groups=...: h <= R/N with R = (pi/8) E' Gc/strength^2; step from "
               "stiffness= springs, else 1/30 of the elastic step",
    .role = DTM_ROLE_LIMITS,
    .needs = DTM_PROP_BIT(DTM_PROP_E) | DTM_PROP_BIT(DTM_PROP_NU) | DTM_PROP_BIT(DTM_PROP_RHO),
    .exponent = 1.0,
    .create = cohesive_create,
    .element_dt = cohesive_element_dt,
    .accuracy = cohesive_accuracy,
    .accuracy_view = "cohesive zone resolution",
    .destroy = cohesive_destroy,
};
