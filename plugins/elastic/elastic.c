/* The elastic-wave effect: per-element critical step of central differences
 * with lumped mass. By default dt_e = 2/sqrt(lambda_max(Me^-1 Ke)), the
 * element eigenvalue bound, which is provably safe; the length formulas users
 * know (`length=`) give dt_e = L_e / C_D instead, and most of them are unsafe
 * on some shapes (see DESIGN.md). The characteristic length is C_D dt_e.
 * With <time f-max=f>, waves up to f must be resolved by N elements per
 * wavelength (elements-per-wavelength, default 10): the shortest body wave,
 * the shear wave (speed sqrt(mu/rho); sqrt(E/rho) for a bar), gives the
 * accuracy bound h <= C_S/(N f) and the view "elements per wavelength".
 * An element with a section takes its kind's formulation (truss: the bar;
 * membrane: plane stress in the element's own plane; solid, plane-strain,
 * plane-stress) instead of the effect's `formulation`; its thickness or
 * area cancels from the element's own step. Shell and beam sections take
 * their structural kernels' bound (dtm_section_element: membrane, bending
 * and transverse shear, with the section's rotary-inertia convention). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/effect.h"
#include "dtmap/error.h"
#include "dtmap/topology.h"

typedef struct {
  dtm_formulation form; /* wave formulation */
  dtm_length_kind kind; /* how dt_e is obtained */
  double fmax;          /* highest frequency of interest, Hz (0: none) */
  double per_wave;      /* elements per wavelength required */
  int iE, inu, irho;    /* catalogue indices of E, nu and rho */
  int integration;      /* DTM_INTEGRATION_*: the discrete model of second-order elements */
} elastic_state;

static const char *const form_names[] = DTM_FORMULATION_NAMES;
static const char *const length_names[] = DTM_LENGTH_NAMES;
/* In DTM_INTEGRATION_* order (src/kernel/curved.c). */
static const char *const integration_names[] = {"converged", "full", "calculix", NULL};
static const int form_dims[] = {3, 2, 2, 1}; /* element dimension of each formulation */

static int lookup(const char *v, const char *const *names) {
  for (int i = 0; names[i]; i++)
    if (strcmp(v, names[i]) == 0) return i;
  return -1;
}

/* A formulation for elements of dimension fd on a mesh of dimension dim: it
 * applies only to the elements without a section (a section sets its
 * groups' formulation), so say what those are. */
static int formulation_error(const dtm_effect_args *a, const char *name, int fd, int dim) {
  size_t n = dtm_effect_args_unsectioned(a);
  if (!n)
    return dtm_effect_args_error(a,
                                 "formulation '%s' applies only to elements without a <section>, and every element "
                                 "has one here (a section sets the formulation of its groups' elements): remove the "
                                 "attribute",
                                 name);
  return dtm_effect_args_error(a,
                               "formulation '%s' is for elements of dimension %d, but the %zu elements it applies to "
                               "(those without a <section>; a section sets the formulation of its groups' elements) "
                               "are of dimension %d: use %s for them, or give them a section",
                               name, fd, n, dim,
                               dim == 3   ? "3d"
                               : dim == 2 ? "plane-strain or plane-stress"
                                          : "bar");
}

static int elastic_create(const dtm_effect_args *a, void **state) {
  const char *f;
  int dim = dtm_effect_args_dim(a), li, ii;
  DTM_CHECK(dtm_effect_args_text(a, "formulation", &f));
  DTM_CHECK(dtm_effect_args_choice(a, "length", &li));
  DTM_CHECK(dtm_effect_args_choice(a, "integration", &ii));
  int fi = f ? lookup(f, form_names) : (int)dtm_formulation_default(dim);
  if (fi < 0) return dtm_effect_args_error(a, "unknown formulation '%s'", f);
  if (form_dims[fi] != dim) return formulation_error(a, form_names[fi], form_dims[fi], dim);
  elastic_state *s = malloc(sizeof *s);
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  *s = (elastic_state){(dtm_formulation)fi,
                       (dtm_length_kind)li,
                       dtm_effect_args_fmax(a),
                       dtm_effect_args_per_wavelength(a),
                       dtm_effect_args_property(a, "E"),
                       dtm_effect_args_property(a, "nu"),
                       dtm_effect_args_property(a, "rho"),
                       ii};
  *state = s;
  return DTM_OK;
}

/* Moduli of material m in section sec (NULL: the effect's formulation). */
static int moduli_of(const elastic_state *s, const dtm_material *m, const dtm_section *sec, dtm_elastic_moduli *mod) {
  dtm_formulation f = sec ? dtm_section_formulation(sec->kind) : s->form;
  int rot = sec && dtm_section_has_rotations(sec->kind);
  if (f != DTM_FORM_BAR || rot) DTM_CHECK(dtm_material_require_one(m, "nu", "elastic"));
  double nu = f == DTM_FORM_BAR ? 0.0 : dtm_material_get(m, s->inu);
  double nu_rot = dtm_material_get(m, s->inu); /* a bar's moduli do not check it; a beam's shear needs it */
  if (rot && !(nu_rot > -1 && nu_rot < 0.5))
    return DTM_ERR(DTM_ERR_INPUT, "material '%s': Poisson's ratio %g outside (-1, 0.5) for a %s section", m->name,
                   nu_rot, dtm_section_kind_name(sec->kind));
  int r = dtm_elastic_moduli_init(f, dtm_material_get(m, s->iE), nu, dtm_material_get(m, s->irho), mod);
  if (r) return DTM_ERR(r, "material '%s': invalid elastic properties", m->name);
  mod->integration = s->integration;
  return DTM_OK;
}

/* The moduli of element e of b into *mod, recomputed only when its material
 * or section differs from the last element's (*mat, *sec). */
static int element_moduli(const elastic_state *s, const dtm_batch *b, size_t e, const dtm_material **mat,
                          const dtm_section **sec, dtm_elastic_moduli *mod) {
  const dtm_section *se = b->section ? b->section[e] : NULL;
  if (b->mat[e] == *mat && se == *sec) return DTM_OK;
  DTM_CHECK(moduli_of(s, b->mat[e], se, mod));
  *mat = b->mat[e], *sec = se;
  return DTM_OK;
}

/* The bound of a shell or beam element: its structural kernel's, under its
 * section's rotary-inertia convention. */
static int structural_element(const elastic_state *s, const dtm_batch *b, size_t e, double *dt) {
  const dtm_material *m = b->mat[e];
  double lambda;
  if (dtm_section_element_lambda(b->section[e], b->type, dtm_material_get(m, s->iE), dtm_material_get(m, s->inu),
                                 dtm_material_get(m, s->irho), b->x + 3 * (size_t)b->nn * e, &lambda))
    return DTM_ERR(DTM_ERR_INPUT, "element %zu (%s): %s", b->tags[e], dtm_elem_name(b->type), dtm_error_message());
  *dt = 2.0 / sqrt(lambda);
  return DTM_OK;
}

static int one_element(const elastic_state *s, const dtm_batch *b, size_t e, const dtm_elastic_moduli *mod,
                       double *dt) {
  const double *x = b->x + 3 * (size_t)b->nn * e;
  if (s->kind == DTM_LEN_EIGEN && b->section && b->section[e] && dtm_section_has_rotations(b->section[e]->kind))
    return structural_element(s, b, e, dt);
  if (s->kind != DTM_LEN_EIGEN) {
    double L = dtm_kernel_length(b->type, s->kind, x);
    if (!(L > 0)) return DTM_ERR(DTM_ERR_INPUT, "element %zu: degenerate element (length %g)", b->tags[e], L);
    *dt = L / mod->cd;
    return DTM_OK;
  }
  double lambda;
  if (dtm_kernel_elastic_lambda_at(b->type, mod, x, b->level ? b->level[e] : -1, &lambda))
    return DTM_ERR(DTM_ERR_INPUT, "element %zu (%s): %s", b->tags[e], dtm_elem_name(b->type), dtm_error_message());
  *dt = 2.0 / sqrt(lambda);
  return DTM_OK;
}

/* 1 when element e takes the plain element bound (no length rule, no
 * structural section): the elements the lanes may batch. */
static int plain_bound(const elastic_state *s, const dtm_batch *b, size_t e) {
  return s->kind == DTM_LEN_EIGEN && !(b->section && b->section[e] && dtm_section_has_rotations(b->section[e]->kind));
}

/* The plain bounds of the elements e[0 .. count) (moduli mod[k]) side by
 * side (dtm_kernel_elastic_lambda_lanes): their steps and lengths. */
static int lane_elements(const dtm_batch *b, const size_t *e, int count, const dtm_elastic_moduli *mod, double *dt,
                         double *len) {
  const double *x[DTM_KERNEL_LANES] = {NULL};
  const dtm_elastic_moduli *m[DTM_KERNEL_LANES] = {NULL};
  int level[DTM_KERNEL_LANES] = {0}, failed = 0;
  double lambda[DTM_KERNEL_LANES];
  for (int k = 0; k < count; k++)
    x[k] = b->x + 3 * (size_t)b->nn * e[k], m[k] = &mod[k], level[k] = b->level ? b->level[e[k]] : -1;
  if (dtm_kernel_elastic_lambda_lanes(b->type, count, m, x, level, lambda, &failed))
    return DTM_ERR(DTM_ERR_INPUT, "element %zu (%s): %s", b->tags[e[failed]], dtm_elem_name(b->type),
                   dtm_error_message());
  for (int k = 0; k < count; k++) dt[e[k]] = 2.0 / sqrt(lambda[k]), len[e[k]] = mod[k].cd * dt[e[k]];
  return DTM_OK;
}

/* Elements with the plain bound go DTM_KERNEL_LANES at a time, in their
 * order (the last group may be short); the others one by one. */
static int elastic_element_dt(void *state, const dtm_batch *b, double *dt, double *len) {
  const elastic_state *s = state;
  const dtm_material *last = NULL;
  const dtm_section *sec = NULL;
  dtm_elastic_moduli mod, lane_mod[DTM_KERNEL_LANES];
  size_t lane_e[DTM_KERNEL_LANES];
  int count = 0;
  for (size_t e = 0; e < b->n; e++) {
    DTM_CHECK(element_moduli(s, b, e, &last, &sec, &mod));
    if (!plain_bound(s, b, e)) { /* the elements before it first: errors come in element order */
      if (count) DTM_CHECK(lane_elements(b, lane_e, count, lane_mod, dt, len));
      count = 0;
      DTM_CHECK(one_element(s, b, e, &mod, &dt[e]));
      len[e] = mod.cd * dt[e];
      continue;
    }
    lane_mod[count] = mod, lane_e[count++] = e;
    if (count < DTM_KERNEL_LANES) continue;
    DTM_CHECK(lane_elements(b, lane_e, count, lane_mod, dt, len));
    count = 0;
  }
  if (count) DTM_CHECK(lane_elements(b, lane_e, count, lane_mod, dt, len));
  return DTM_OK;
}

static int elastic_coefficients(void *state, const dtm_material *m, const dtm_section *sec, dtm_operator_coeffs *c) {
  memset(c, 0, sizeof *c);
  c->kind = DTM_OP_ELASTIC;
  c->capacity = dtm_material_get(m, ((const elastic_state *)state)->irho);
  c->dt_is_bound = ((const elastic_state *)state)->kind == DTM_LEN_EIGEN;
  DTM_CHECK(moduli_of(state, m, sec, &c->mod));
  c->E = dtm_material_get(m, ((const elastic_state *)state)->iE);
  c->nu = c->mod.form == DTM_FORM_BAR && !(sec && dtm_section_has_rotations(sec->kind))
              ? 0.0
              : dtm_material_get(m, ((const elastic_state *)state)->inu);
  return DTM_OK;
}

/* Speed of the shortest body wave: shear (bar: the bar wave). */
static double shear_speed(const dtm_elastic_moduli *m) {
  return m->form == DTM_FORM_BAR ? m->cd : sqrt(m->mu / m->rho);
}

static int elastic_accuracy(void *state, const dtm_batch *b, double *hmax, double *res) {
  const elastic_state *s = state;
  const dtm_material *last = NULL;
  const dtm_section *sec = NULL;
  dtm_elastic_moduli mod;
  for (size_t e = 0; e < b->n; e++) {
    hmax[e] = INFINITY, res[e] = NAN;
    if (!(s->fmax > 0)) continue;
    DTM_CHECK(element_moduli(s, b, e, &last, &sec, &mod));
    double wavelength = shear_speed(&mod) / s->fmax;
    hmax[e] = wavelength / s->per_wave;
    res[e] = wavelength / dtm_elem_mean_edge(b->type, b->x + 3 * (size_t)b->nn * e);
  }
  return DTM_OK;
}

static const dtm_param params[] = {
    {"formulation", DTM_PARAM_CHOICE, NULL, 0, 0, 0, form_names, 0, "",
     "default by the mesh's dimension: 3d, plane-strain, bar"},
    {"length", DTM_PARAM_CHOICE, "eigen", 0, 0, 0, length_names, 0, "",
     "element step: the element eigenvalue bound (eigen, safe) or a length rule / C_D (see dtmap --help)"},
    {"integration", DTM_PARAM_CHOICE, "converged", 0, 0, 0, integration_names, 0, "",
     "discrete model of second-order elements the steps are for: converged (curved elements integrated until "
     "their matrices settle), full (the full rules, exact only on straight-sided elements) or calculix (tet10 with "
     "CalculiX's 4-point C3D10 rule and its own lumping, as its explicit dynamics; other types as converged)"},
    {NULL, 0, NULL, 0, 0, 0, NULL, 0, NULL, NULL}};

static const dtm_property properties[] = {
    {"E", "Pa", 0, HUGE_VAL, DTM_OPEN_LO, 1, "Young's modulus"},
    {"nu", "", -1, 0.5, DTM_OPEN_LO | DTM_OPEN_HI, 0, "Poisson's ratio (not needed by the bar)"},
    {"rho", "kg/m^3", 0, HUGE_VAL, DTM_OPEN_LO, 1, "density"},
    {NULL, NULL, 0, 0, 0, 0, NULL}};

const dtm_effect_class dtm_effect_elastic = {
    .api_version = DTM_EFFECT_API_VERSION,
    .name = "elastic",
    .summary = "elastic waves, central differences with lumped mass",
    .role = DTM_ROLE_LIMITS,
    .scheme = DTM_SCHEME_CENTRAL_DIFFERENCE,
    .exponent = 1.0,
    .params = params,
    .properties = properties,
    .indicator = {"elements_per_wavelength", "elements per wavelength",
                  "shear wavelength at <time f-max> / element size; enough: <time elements-per-wavelength>"},
    .create = elastic_create,
    .element_dt = elastic_element_dt,
    .coefficients = elastic_coefficients,
    .accuracy = elastic_accuracy,
    .destroy = dtm_effect_free,
};
