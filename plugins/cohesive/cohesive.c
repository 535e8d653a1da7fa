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
#include "dtmap/topology.h"

#define LITERATURE_FACTOR 30.0        /* Baylor (1997), via the CVFE review in shared/seeds */
#define PI_OVER_8 0.39269908169872414 /* M_PI is not C11 */

typedef struct {
  dtm_formulation form;    /* elastic formulation for E' and the elastic step */
  double n_per_zone;       /* elements across the process zone */
  double stiffness;        /* interface stiffness, Pa/m; 0 = use the 1/30 rule */
  int ngroups;             /* physical groups of the analysed dimension */
  char *in;                /* [ngroups] 1 where the group has cohesive elements */
  unsigned long long mask; /* the same groups as a bit mask */
  int iE, inu, irho;       /* catalogue indices of E, nu, rho */
  int igc, isig;           /* ... of fracture-energy and strength */
} cohesive_state;

static const char *const form_names[] = DTM_FORMULATION_NAMES;

static int parse_form(const dtm_effect_args *a, dtm_formulation *f) {
  const char *v;
  DTM_CHECK(dtm_effect_args_text(a, "formulation", &v));
  *f = dtm_formulation_default(dtm_effect_args_dim(a));
  for (int i = 0; v && form_names[i]; i++)
    if (!strcmp(v, form_names[i])) *f = (dtm_formulation)i;
  return DTM_OK;
}

/* groups="a b c": mark each named group. */
static int parse_groups(const dtm_effect_args *a, cohesive_state *s) {
  const char *list;
  DTM_CHECK(dtm_effect_args_text(a, "groups", &list));
  char buf[4096];
  snprintf(buf, sizeof buf, "%s", list ? list : "");
  for (char *save = NULL, *tok = strtok_r(buf, " \t\n", &save); tok; tok = strtok_r(NULL, " \t\n", &save)) {
    int g;
    DTM_CHECK(dtm_effect_args_group(a, tok, &g));
    if (g >= DTM_EFFECT_MAX_GROUPS)
      return dtm_effect_args_error(a, "group '%s' is number %d of the mesh's groups; cohesive handles the first %d",
                                   tok, g + 1, DTM_EFFECT_MAX_GROUPS);
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

static void property_indices(const dtm_effect_args *a, cohesive_state *s) {
  s->iE = dtm_effect_args_property(a, "E");
  s->inu = dtm_effect_args_property(a, "nu");
  s->irho = dtm_effect_args_property(a, "rho");
  s->igc = dtm_effect_args_property(a, "fracture-energy");
  s->isig = dtm_effect_args_property(a, "strength");
}

static int cohesive_create(const dtm_effect_args *a, void **state) {
  cohesive_state *s = calloc(1, sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  s->ngroups = dtm_effect_args_ngroups(a);
  s->in = calloc((size_t)s->ngroups + 1, 1);
  property_indices(a, s);
  *state = s;
  int r = s->in ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (!r) r = parse_form(a, &s->form);
  if (!r) r = dtm_effect_args_number(a, "elements-per-zone", &s->n_per_zone);
  if (!r) r = dtm_effect_args_number(a, "stiffness", &s->stiffness);
  if (!r && isnan(s->stiffness)) s->stiffness = 0.0; /* not given: the 1/30 rule */
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
  double nu = s->form == DTM_FORM_BAR ? 0.0 : dtm_material_get(m, s->inu), lambda;
  DTM_CHECK(dtm_elastic_moduli_init(s->form, dtm_material_get(m, s->iE), nu, dtm_material_get(m, s->irho), &mod));
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
  double E = dtm_material_get(m, s->iE), nu = dtm_material_get(m, s->inu);
  double Ep = (s->form == DTM_FORM_PLANE_STRESS || s->form == DTM_FORM_BAR) ? E : E / (1.0 - nu * nu);
  double sig = dtm_material_get(m, s->isig);
  return PI_OVER_8 * Ep * dtm_material_get(m, s->igc) / (sig * sig);
}

static int cohesive_accuracy(void *state, const dtm_batch *b, double *hmax, double *res) {
  const cohesive_state *s = state;
  for (size_t e = 0; e < b->n; e++) {
    hmax[e] = INFINITY, res[e] = NAN;
    if (!in_groups(s, b, e)) continue;
    DTM_CHECK(dtm_material_require_one(b->mat[e], "fracture-energy", "cohesive"));
    DTM_CHECK(dtm_material_require_one(b->mat[e], "strength", "cohesive"));
    double R = zone_length(s, b->mat[e]);
    hmax[e] = R / s->n_per_zone;
    res[e] = R / dtm_elem_mean_edge(b->type, b->x + 3 * (size_t)b->nn * e);
  }
  return DTM_OK;
}

static const dtm_param params[] = {
    {"groups", DTM_PARAM_GROUPS, NULL, 0, 0, 0, NULL, 1, "", "the physical groups where cracks may open"},
    {"elements-per-zone", DTM_PARAM_NUMBER, "5", 0, HUGE_VAL, DTM_OPEN_LO, NULL, 0, "",
     "elements across the process zone R (5 to 10 in the literature)"},
    {"stiffness", DTM_PARAM_NUMBER, NULL, 0, HUGE_VAL, DTM_OPEN_LO, NULL, 0, "Pa/m",
     "interface stiffness; omit it for 1/30 of the elastic step"},
    {"formulation", DTM_PARAM_CHOICE, NULL, 0, 0, 0, form_names, 0, "",
     "elastic formulation for E' (default by the mesh's dimension)"},
    {NULL, 0, NULL, 0, 0, 0, NULL, 0, NULL, NULL}};

static const dtm_property properties[] = {
    {"E", "Pa", 0, HUGE_VAL, DTM_OPEN_LO, 1, "Young's modulus"},
    {"nu", "", -1, 0.5, DTM_OPEN_LO | DTM_OPEN_HI, 1, "Poisson's ratio"},
    {"rho", "kg/m^3", 0, HUGE_VAL, DTM_OPEN_LO, 1, "density"},
    {"fracture-energy", "J/m^2", 0, HUGE_VAL, DTM_OPEN_LO, 0, "G_c (needed where cohesive elements are)"},
    {"strength", "Pa", 0, HUGE_VAL, DTM_OPEN_LO, 0, "cohesive strength (needed where cohesive elements are)"},
    {NULL, NULL, 0, 0, 0, 0, NULL}};

const dtm_effect_class dtm_effect_cohesive = {
    .api_version = DTM_EFFECT_API_VERSION,
    .name = "cohesive",
    .summary = "cohesive zones in groups=...: h <= R/N with R = (pi/8) E' Gc/strength^2; step from "
               "stiffness= springs, else 1/30 of the elastic step",
    .role = DTM_ROLE_LIMITS,
    .scheme = DTM_SCHEME_CENTRAL_DIFFERENCE,
    .exponent = 1.0,
    .params = params,
    .properties = properties,
    .indicator = {"elements_per_zone", "cohesive zone resolution",
                  "process-zone length R / element size; enough: elements-per-zone"},
    .create = cohesive_create,
    .element_dt = cohesive_element_dt,
    .accuracy = cohesive_accuracy,
    .destroy = cohesive_destroy,
};
