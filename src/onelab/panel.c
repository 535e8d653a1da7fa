/* dtmap's parameters in Gmsh's left panel, under "NAME/": the effects
 * (switches, the elastic formulation, the damping ratio), the time options
 * (safety, target, duration, the global estimate), the mesh size of a
 * geometry, and for every physical group of the analysed dimension its
 * material: a named material of the library (its values shown read-only),
 * the scene's own, or custom values. Every group of curves or surfaces below
 * that dimension gets a section menu: none (the default: not analysed),
 * truss or beam for curves, membrane or shell for surfaces, with the
 * cross-section area, the radius of a beam's circular profile (a beam the
 * scene gives keeps the scene's profile) or the thickness; with a section
 * it gets a material menu too. (The plane
 * kinds of a 2D model's surfaces are the elastic formulation's choices.)
 * Every length and material value is in the base scene's system of units
 * (SI, or mm-t-s: mm, MPa, t/mm^3), with that unit shown beside it: the
 * library's SI values are converted into it, and what the user types is
 * read in it. Without a base scene the system is the panel's own choice
 * ("0Units": SI, or mm-t-s for a model drawn in mm), and the scene the
 * panel writes says it. Defaults come from the scene beside the model; a value the
 * user changed in the panel stays in force (the server keeps it) until the
 * panel is reset. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/registry.h"
#include "dtmap/units.h"
#include "onelab-impl.h"

const char *const dtm_ol_effect_names[OL_NEFFECTS] = {"elastic", "damping", "thermal", "hydraulic", "cohesive"};
static const char *const formulations[] = {"3d", "plane-strain", "plane-stress", "bar"};

static void path(char *out, size_t n, const ol_conn *c, const char *rest) { snprintf(out, n, "%s/%s", c->name, rest); }

/* A number under NAME/rest; *value holds the default in and the value in force out. */
static int number(ol_conn *c, const char *rest, const char *label, const char *units, double *value) {
  ol_param p;
  char name[256];
  path(name, sizeof name, c, rest);
  dtm_ol_number(&p, name, *value, label);
  if (units) dtm_ol_attr(&p, "Units", units);
  DTM_CHECK(dtm_ol_define(c, &p));
  *value = p.value;
  return DTM_OK;
}

/* A switch (a number with the choices 0 and 1: a check box). */
static int toggle(ol_conn *c, const char *rest, const char *label, int *on) {
  ol_param p;
  char name[256];
  path(name, sizeof name, c, rest);
  dtm_ol_number(&p, name, *on, label);
  dtm_ol_choice(&p, 0, ""), dtm_ol_choice(&p, 1, "");
  DTM_CHECK(dtm_ol_define(c, &p));
  *on = p.value != 0;
  return DTM_OK;
}

static const dtm_scene_effect *scene_effect(const dtm_scene *s, const char *name) {
  for (int i = 0; s && i < s->neffects; i++)
    if (!s->effects[i].library && !strcmp(s->effects[i].name, name)) return &s->effects[i];
  return NULL;
}

static int default_formulation(const ol_model *m) {
  const dtm_scene_effect *e = scene_effect(m->base, "elastic");
  const char *f = e ? dtm_scene_effect_attr(e, "formulation") : NULL;
  for (int i = 0; f && i < 4; i++)
    if (!strcmp(f, formulations[i])) return i;
  return m->dim == 3 ? 0 : m->dim == 2 ? 1 : 3;
}

static int formulation(ol_conn *c, const ol_model *m, ol_panel *pn) {
  ol_param p;
  char name[256];
  path(name, sizeof name, c, "1Effects/1elastic formulation");
  dtm_ol_number(&p, name, default_formulation(m), "elastic formulation");
  for (int i = 0; i < 4; i++) dtm_ol_choice(&p, i, formulations[i]);
  DTM_CHECK(dtm_ol_define(c, &p));
  pn->formulation = (int)p.value >= 0 && (int)p.value < 4 ? (int)p.value : 0;
  return DTM_OK;
}

static int effects(ol_conn *c, const ol_model *m, ol_panel *pn) {
  static const char *const rest[OL_NEFFECTS] = {"1Effects/0elastic", "1Effects/2damping", "1Effects/4thermal",
                                                "1Effects/5hydraulic", "1Effects/6cohesive"};
  for (int k = 0; k < OL_NEFFECTS; k++) {
    pn->effect_on[k] = m->base ? scene_effect(m->base, dtm_ol_effect_names[k]) != NULL : k == 0;
    DTM_CHECK(toggle(c, rest[k], dtm_ol_effect_names[k], &pn->effect_on[k]));
  }
  DTM_CHECK(formulation(c, m, pn));
  const dtm_scene_effect *d = scene_effect(m->base, "damping");
  const char *xi = d ? dtm_scene_effect_attr(d, "xi") : NULL;
  pn->xi = xi ? atof(xi) : 0.05;
  return number(c, "1Effects/3damping ratio xi", "damping ratio xi", NULL, &pn->xi);
}

static int times(ol_conn *c, const ol_model *m, ol_panel *pn) {
  pn->safety = m->base ? m->base->safety : 0.9;
  pn->target = m->base ? m->base->target : 0;
  pn->duration = m->base ? m->base->duration : 0;
  pn->posterior = m->base ? m->base->posterior : 0; /* <time posterior="true">: the switch starts on */
  DTM_CHECK(number(c, "2Time/0safety", "safety factor", NULL, &pn->safety));
  DTM_CHECK(number(c, "2Time/1target", "target step (0: none)", "s", &pn->target));
  DTM_CHECK(number(c, "2Time/2duration", "duration (0: none)", "s", &pn->duration));
  return toggle(c, "2Time/3global", "global estimate (Lanczos)", &pn->posterior);
}

static int meshing(ol_conn *c, const ol_model *m, ol_panel *pn) {
  pn->mesh_size = m->base ? m->base->mesh_size : 0;
  if (m->source_is_mesh) return DTM_OK;
  return number(c, "3Mesh/0size", "mesh size (0: the geometry's)", dtm_units_name(pn->units, DTM_UNIT_LENGTH),
                &pn->mesh_size);
}

static int save_options(ol_conn *c, const ol_model *m, ol_panel *pn) {
  ol_param p;
  char name[256], def[4096];
  DTM_CHECK(toggle(c, "5Scene/0save", "save the panel as a scene after the run", &pn->save_scene));
  path(name, sizeof name, c, "5Scene/1file");
  const char *dot = strrchr(m->model, '.');
  snprintf(def, sizeof def, "%.*s.xml", dot ? (int)(dot - m->model) : (int)strlen(m->model), m->model);
  dtm_ol_string(&p, name, m->scene[0] ? m->scene : def, "scene file");
  snprintf(p.kind, sizeof p.kind, "file");
  DTM_CHECK(dtm_ol_define(c, &p));
  snprintf(pn->scene_out, sizeof pn->scene_out, "%s", p.svalue);
  return DTM_OK;
}

static int prop_index(const char *name) {
  for (int p = 0; p < OL_NPROPS; p++)
    if (!strcmp(name, dtm_ol_prop_names[p])) return p;
  return -1;
}

/* Properties (bit p: dtm_ol_prop_names[p]) the switched-on effects read. */
static unsigned needed(const ol_panel *pn) {
  unsigned needs = 0;
  for (int k = 0; k < OL_NEFFECTS; k++) {
    const dtm_effect_class *cl = NULL;
    if (!pn->effect_on[k] || dtm_registry_find(dtm_ol_effect_names[k], &cl) != DTM_OK) continue;
    for (const dtm_property *q = cl->properties; q && q->name; q++)
      if (prop_index(q->name) >= 0) needs |= 1u << prop_index(q->name);
  }
  return needs;
}

/* The scene's material for group reference ref (or its default one). */
static const dtm_scene_material *scene_material(const dtm_scene *s, const char *ref) {
  const dtm_scene_material *def = NULL;
  for (int i = 0; s && i < s->nmaterials; i++) {
    const dtm_scene_material *sm = &s->materials[i];
    for (int g = 0; g < sm->ngroups; g++)
      if (!strcmp(sm->groups[g], ref)) return sm;
    if (sm->is_default) def = sm;
  }
  return def;
}

/* The values of g's material in the scene's units (a library entry's SI values converted). */
static void fill_values(ol_group *g, const dtm_scene_material *sm, int nlib, const char *units) {
  for (int p = 0; p < OL_NPROPS; p++) g->prop[p] = NAN;
  if (g->choice >= 1 && g->choice <= nlib)
    for (int p = 0; p < OL_NPROPS; p++) g->prop[p] = dtm_ol_materials[g->choice - 1].prop[p] / dtm_ol_prop_si(units, p);
  if (g->choice == nlib + 1 && sm)
    for (int p = 0; p < OL_NPROPS; p++) g->prop[p] = dtm_material_value(&sm->m, dtm_ol_prop_names[p]);
}

/* The scene's section naming group reference ref, or NULL. */
static const dtm_section *scene_section(const dtm_scene *s, const char *ref) {
  for (int i = 0; s && i < s->nsections; i++)
    for (int g = 0; g < s->sections[i].ngroups; g++)
      if (!strcmp(s->sections[i].groups[g], ref)) return &s->sections[i];
  return NULL;
}

/* The section kinds the panel offers a group of dimension dim below the
 * analysed one (choices 1 and 2; 0 is none): trusses and beams for
 * curves, membranes and shells for surfaces. */
static int lower_kind(int dim, int choice) {
  if (dim == 1) return choice == 2 ? DTM_SECTION_BEAM : DTM_SECTION_TRUSS;
  return choice == 2 ? DTM_SECTION_SHELL : DTM_SECTION_MEMBRANE;
}

/* One measure field of a section menu, visible when shown; *value holds
 * the default in and the value in force out. */
static int measure_field(ol_conn *c, const char *dir, const char *key, const char *label, const char *units, int shown,
                         double *value) {
  char name[512];
  ol_param p;
  snprintf(name, sizeof name, "%s/01%s", dir, key);
  dtm_ol_number(&p, name, *value, label);
  dtm_ol_attr(&p, "Units", units);
  p.visible = shown;
  DTM_CHECK(dtm_ol_define(c, &p));
  *value = p.value;
  return DTM_OK;
}

/* The measures of a curve's (area; radius) or a surface's (thickness)
 * sections; the one of the chosen kind goes to g->measure. A beam the base
 * scene gives keeps the scene's profile: no radius field. */
static int measures(ol_conn *c, const char *dir, const dtm_section *sec, const char *units, ol_group *g) {
  const char *length = dtm_units_name(units, DTM_UNIT_LENGTH);
  if (g->dim == 2) {
    double t = sec && sec->thickness > 0 ? sec->thickness : 0;
    DTM_CHECK(measure_field(c, dir, "thickness", "thickness", length, g->kind >= 0, &t));
    g->measure = t;
    return DTM_OK;
  }
  double area = sec && sec->kind == DTM_SECTION_TRUSS ? sec->area : 0, radius = 0;
  DTM_CHECK(measure_field(c, dir, "area", "cross-section area", dtm_units_name(units, DTM_UNIT_AREA),
                          g->kind == DTM_SECTION_TRUSS, &area));
  if (!(g->scene_sec && g->scene_sec->kind == DTM_SECTION_BEAM))
    DTM_CHECK(
        measure_field(c, dir, "radius", "radius (circular profile)", length, g->kind == DTM_SECTION_BEAM, &radius));
  g->measure = g->kind == DTM_SECTION_BEAM ? radius : area;
  return DTM_OK;
}

/* The section menu of a group below the analysed dimension: none (not
 * analysed) or one of its dimension's kinds, default the scene's; g->kind
 * and g->measure receive the values in force. */
static int section_menu(ol_conn *c, const char *dir, const dtm_scene *base, const char *units, ol_group *g) {
  const dtm_section *sec = scene_section(base, g->ref);
  int given = sec && (sec->kind == lower_kind(g->dim, 1) || sec->kind == lower_kind(g->dim, 2));
  char name[512];
  ol_param p;
  snprintf(name, sizeof name, "%s/00section", dir);
  dtm_ol_number(&p, name, given ? (sec->kind == lower_kind(g->dim, 2) ? 2 : 1) : 0, "section");
  dtm_ol_choice(&p, 0, "none (not analysed)");
  dtm_ol_choice(&p, 1, dtm_section_kind_name(lower_kind(g->dim, 1)));
  dtm_ol_choice(&p, 2, dtm_section_kind_name(lower_kind(g->dim, 2)));
  DTM_CHECK(dtm_ol_define(c, &p));
  g->kind = p.value == 1 || p.value == 2 ? lower_kind(g->dim, (int)p.value) : -1;
  g->scene_sec = sec;
  return measures(c, dir, given ? sec : NULL, units, g);
}

/* The material menu of one group; g->choice receives the choice in force. */
static int material_menu(ol_conn *c, const char *dir, const dtm_scene_material *sm, int shown, ol_group *g) {
  int nlib = dtm_ol_material_count();
  char name[512], label[64];
  ol_param p;
  snprintf(name, sizeof name, "%s/0material", dir);
  dtm_ol_number(&p, name, sm ? nlib + 1 : 1, "material");
  p.visible = shown;
  dtm_ol_choice(&p, 0, "custom");
  for (int i = 0; i < nlib; i++) dtm_ol_choice(&p, i + 1, dtm_ol_materials[i].name);
  if (sm) snprintf(label, sizeof label, "%s (scene)", sm->m.name), dtm_ol_choice(&p, nlib + 1, label);
  DTM_CHECK(dtm_ol_define(c, &p));
  g->choice = (int)p.value;
  if (g->choice < 0 || g->choice > nlib + (sm ? 1 : 0)) g->choice = sm ? nlib + 1 : 1;
  snprintf(g->scene_name, sizeof g->scene_name, "%s", sm ? sm->m.name : "");
  return DTM_OK;
}

/* One property field: read-only with the material's value, or editable for
 * a custom material (then the user's value stays in force). */
static int property(ol_conn *c, const char *dir, int p, int shown, const char *units, ol_group *g) {
  char name[512];
  ol_param q;
  snprintf(name, sizeof name, "%s/%d%s", dir, p + 1, dtm_ol_prop_names[p]);
  dtm_ol_number(&q, name, isfinite(g->prop[p]) ? g->prop[p] : 0, dtm_ol_prop_names[p]);
  if (dtm_ol_prop_unit(units, p)[0]) dtm_ol_attr(&q, "Units", dtm_ol_prop_unit(units, p));
  q.visible = shown;
  if (g->choice != 0) {
    if (!isfinite(g->prop[p])) return DTM_OK; /* the run names what is missing */
    q.read_only = 1;
    return dtm_ol_set(c, &q);
  }
  DTM_CHECK(dtm_ol_define(c, &q));
  g->prop[p] = q.value;
  return DTM_OK;
}

static int group_panel(ol_conn *c, const ol_model *m, const ol_panel *pn, unsigned needs, ol_group *g) {
  char dir[512], clean[128];
  snprintf(clean, sizeof clean, "%s", g->ref[0] ? g->ref : "elements in no group");
  for (char *s = clean; *s; s++)
    if (*s == '/') *s = '_';
  snprintf(dir, sizeof dir, "%s/4Materials/%s", c->name, clean);
  if (g->dim < m->dim) DTM_CHECK(section_menu(c, dir, m->base, pn->units, g));
  int shown = g->dim == m->dim || g->kind >= 0; /* a group below it needs a material only with a section */
  const dtm_scene_material *sm = scene_material(m->base, g->ref);
  DTM_CHECK(material_menu(c, dir, sm, shown, g));
  fill_values(g, sm, dtm_ol_material_count(), pn->units);
  for (int p = 0; p < OL_NPROPS; p++)
    if (needs & (1u << p)) DTM_CHECK(property(c, dir, p, shown, pn->units, g));
  return DTM_OK;
}

int dtm_ol_group_in_scene(const ol_panel *pn, int i) { return i < pn->nanalysed || pn->groups[i].kind >= 0; }

/* The panel's groups: those of the analysed dimension (or one for the
 * elements in no group), then those below it. */
static int list_groups(const ol_model *m, ol_panel *pn) {
  pn->nanalysed = m->ngroups ? m->ngroups : 1;
  pn->ngroups = pn->nanalysed + m->nlower;
  pn->groups = calloc((size_t)pn->ngroups, sizeof *pn->groups);
  if (!pn->groups) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < pn->ngroups; i++) {
    ol_group *g = &pn->groups[i];
    const dtm_group *from = i < m->ngroups ? &m->groups[i] : i >= pn->nanalysed ? &m->lower[i - pn->nanalysed] : NULL;
    if (from) dtm_ol_group_ref(from, g->ref, sizeof g->ref);
    g->dim = from ? from->dim : m->dim;
    g->kind = -1;
  }
  return DTM_OK;
}

static int materials(ol_conn *c, const ol_model *m, ol_panel *pn) {
  DTM_CHECK(list_groups(m, pn));
  unsigned needs = needed(pn);
  for (int i = 0; i < pn->ngroups; i++) DTM_CHECK(group_panel(c, m, pn, needs, &pn->groups[i]));
  return DTM_OK;
}

static int source(ol_conn *c, const ol_model *m) {
  ol_param p;
  char name[256];
  path(name, sizeof name, c, "0Scene");
  dtm_ol_string(&p, name, m->scene[0] ? m->scene : "(none beside the model: defaults)", "starts from scene");
  p.read_only = 1;
  return dtm_ol_set(c, &p);
}

/* The system of units: the base scene's (shown read-only), else the
 * user's choice, SI by default. */
static int units(ol_conn *c, const ol_model *m, ol_panel *pn) {
  ol_param p;
  char name[256];
  int mm = dtm_units_mm(dtm_scene_units(m->base));
  path(name, sizeof name, c, "0Units");
  dtm_ol_number(&p, name, mm, m->base ? "system of units (the scene's)" : "system of units");
  dtm_ol_choice(&p, 0, "SI (m, kg, Pa)"), dtm_ol_choice(&p, 1, "mm-t-s (mm, t, MPa)");
  if (m->base) {
    p.read_only = 1;
    DTM_CHECK(dtm_ol_set(c, &p)); /* the scene's, whatever the panel held */
  } else {
    DTM_CHECK(dtm_ol_define(c, &p));
    mm = p.value != 0;
  }
  pn->units = mm ? "mm-t-s" : "SI";
  return DTM_OK;
}

int dtm_ol_panel_declare(ol_conn *c, const ol_model *m, ol_panel *pn) {
  memset(pn, 0, sizeof *pn);
  DTM_CHECK(units(c, m, pn));
  DTM_CHECK(source(c, m));
  DTM_CHECK(effects(c, m, pn));
  DTM_CHECK(times(c, m, pn));
  DTM_CHECK(meshing(c, m, pn));
  DTM_CHECK(materials(c, m, pn));
  return save_options(c, m, pn);
}

void dtm_ol_panel_free(ol_panel *pn) {
  free(pn->groups);
  pn->groups = NULL;
  pn->ngroups = pn->nanalysed = 0;
}
