/* The scene the panel describes, written as scene XML in the base scene's
 * system of units (units="mm-t-s" when it has it: the panel's lengths and
 * material values are in it): the source (the model, or the base scene's,
 * with its declared unit), its meshing options with the panel's size,
 * one <material> per distinct material chosen for the groups it analyses,
 * one <section> per curve or surface group given a truss or membrane section
 * in the panel (and the base scene's sections of the other groups, as they
 * are), the effects in the base scene's order (with the panel's switches,
 * formulation and damping ratio) followed by the switched-on effects it
 * lacks, and the time options.
 * dtmap reads it back with dtm_scene_load_memory, so the panel and a scene
 * file go through the same checks; "save as scene" writes the same text. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/units.h"
#include "onelab-impl.h"

static void esc(FILE *f, const char *s) {
  for (; *s; s++) {
    if (*s == '&')
      fputs("&amp;", f);
    else if (*s == '<')
      fputs("&lt;", f);
    else if (*s == '"')
      fputs("&quot;", f);
    else
      fputc(*s, f);
  }
}

static void attr(FILE *f, const char *key, const char *value) {
  fprintf(f, " %s=\"", key);
  esc(f, value);
  fputc('"', f);
}

static void attr_num(FILE *f, const char *key, double v) { fprintf(f, " %s=\"%.17g\"", key, v); }

static void source(FILE *f, const ol_model *m, const ol_panel *pn) {
  fprintf(f, "  <%s", m->source_is_mesh ? "mesh" : "geometry");
  attr(f, "file", m->source);
  const dtm_scene *b = m->base;
  if (b && b->source_unit && (m->source == b->mesh || m->source == b->geometry)) attr(f, "unit", b->source_unit);
  fprintf(f, "/>\n  <meshing");
  if (!m->source_is_mesh && pn->mesh_size > 0) attr_num(f, "size", pn->mesh_size);
  if (!m->source_is_mesh && b && b->mesh_min_size > 0)
    attr_num(f, "min-size", pn->mesh_size > 0 ? fmin(b->mesh_min_size, pn->mesh_size) : b->mesh_min_size);
  if (b && b->mesh_order > 1) fprintf(f, " order=\"%d\"", b->mesh_order);
  fprintf(f, " dim=\"%d\"/>\n", m->dim);
}

/* The material name group g gets in the generated scene. */
static void material_name(const ol_group *g, int nlib, char *out, size_t n) {
  if (g->choice == 0)
    snprintf(out, n, "custom %s", g->ref[0] ? g->ref : "default");
  else if (g->choice <= nlib)
    snprintf(out, n, "%s (library)", dtm_ol_materials[g->choice - 1].name);
  else
    snprintf(out, n, "%s", g->scene_name);
}

/* Whether group j of the scene has the material called name. */
static int has_material(const ol_panel *pn, int j, int nlib, const char *name) {
  char other[160];
  if (!dtm_ol_group_in_scene(pn, j)) return 0;
  material_name(&pn->groups[j], nlib, other, sizeof other);
  return !strcmp(name, other);
}

static void material(FILE *f, const ol_panel *pn, int i, int nlib) {
  char name[160];
  if (!dtm_ol_group_in_scene(pn, i)) return;
  material_name(&pn->groups[i], nlib, name, sizeof name);
  for (int j = 0; j < i; j++)
    if (has_material(pn, j, nlib, name)) return; /* written with the first group that has it */
  int named = 0;
  for (int j = i; j < pn->ngroups; j++) named |= has_material(pn, j, nlib, name) && pn->groups[j].ref[0];
  fprintf(f, "  <material");
  attr(f, "name", name);
  if (!pn->groups[i].ref[0]) fprintf(f, " default=\"true\"");
  if (named) {
    fprintf(f, " groups=\"");
    for (int j = i, first = 1; j < pn->ngroups; j++)
      if (has_material(pn, j, nlib, name) && pn->groups[j].ref[0])
        fprintf(f, "%s", first ? "" : " "), esc(f, pn->groups[j].ref), first = 0;
    fputc('"', f);
  }
  for (int p = 0; p < OL_NPROPS; p++)
    if (isfinite(pn->groups[i].prop[p])) attr_num(f, dtm_ol_prop_names[p], pn->groups[i].prop[p]);
  fprintf(f, "/>\n");
}

/* A scene's beam profile and orientation, and a shell's or beam's rotary
 * convention and shear factor, as the scene gave them. */
static void structural_rest(FILE *f, const dtm_section *s) {
  if (s->kind == DTM_SECTION_BEAM) {
    attr_num(f, "area", s->area), attr_num(f, "iy", s->iy), attr_num(f, "iz", s->iz), attr_num(f, "j", s->jt);
    if (s->orient[0] != 0 || s->orient[1] != 0 || s->orient[2] != 0)
      fprintf(f, " orientation=\"%.17g %.17g %.17g\"", s->orient[0], s->orient[1], s->orient[2]);
  }
  if (s->rotary == DTM_ROTARY_PHYSICAL_INERTIA) attr(f, "rotary", "physical");
  if (s->shear > 0) attr_num(f, "shear-factor", s->shear);
}

/* The rest of a <section> after its groups: the default flag, kind k, and
 * the area of a truss, the thickness of a membrane or shell (from the
 * panel: what was entered, the reader says what is wrong with it) or of a
 * plane kind; a beam's profile: the scene's (base, not NULL) or a circle of
 * radius `radius`. */
static void section_rest(FILE *f, int k, int is_default, double thickness, double area, const dtm_section *base) {
  if (is_default) fprintf(f, " default=\"true\"");
  attr(f, "kind", dtm_section_kind_name(k));
  if (k == DTM_SECTION_TRUSS)
    attr_num(f, "area", area);
  else if (k == DTM_SECTION_BEAM && !(base && base->kind == DTM_SECTION_BEAM))
    attr_num(f, "radius", area);
  else if (k == DTM_SECTION_MEMBRANE || k == DTM_SECTION_SHELL || thickness > 0)
    attr_num(f, "thickness", thickness);
  if (base && dtm_section_has_rotations(k)) structural_rest(f, base);
  fprintf(f, "/>\n");
}

/* Whether ref is a group the panel gives (or denies) a section. */
static int panel_sections(const ol_panel *pn, const char *ref) {
  for (int i = pn->nanalysed; i < pn->ngroups; i++)
    if (!strcmp(pn->groups[i].ref, ref)) return 1;
  return 0;
}

/* A base scene's section, for its groups the panel does not list. */
static void base_section(FILE *f, const ol_panel *pn, const dtm_section *s) {
  int n = 0;
  for (int g = 0; g < s->ngroups; g++) n += !panel_sections(pn, s->groups[g]);
  if (!n && !s->is_default) return;
  fprintf(f, "  <section");
  if (n) {
    fprintf(f, " groups=\"");
    for (int g = 0, first = 1; g < s->ngroups; g++)
      if (!panel_sections(pn, s->groups[g])) fputs(first ? "" : " ", f), esc(f, s->groups[g]), first = 0;
    fputc('"', f);
  }
  section_rest(f, s->kind, s->is_default, s->thickness, s->area, s);
}

static void sections(FILE *f, const ol_model *m, const ol_panel *pn) {
  for (int i = pn->nanalysed; i < pn->ngroups; i++) {
    const ol_group *g = &pn->groups[i];
    if (g->kind < 0) continue;
    fprintf(f, "  <section");
    attr(f, "groups", g->ref);
    const dtm_section *keep = g->scene_sec && g->scene_sec->kind == g->kind ? g->scene_sec : NULL;
    section_rest(f, g->kind, 0, g->measure, g->measure, keep);
  }
  for (int i = 0; m->base && i < m->base->nsections; i++) base_section(f, pn, &m->base->sections[i]);
}

static int builtin_index(const char *name) {
  for (int k = 0; k < OL_NEFFECTS; k++)
    if (!strcmp(name, dtm_ol_effect_names[k])) return k;
  return -1;
}

static const char *const formulations[] = {"3d", "plane-strain", "plane-stress", "bar"};

/* A built-in effect k with the base scene's attributes e (or none). */
static void builtin(FILE *f, const ol_model *m, const ol_panel *pn, int k, const dtm_scene_effect *e) {
  int rayleigh = e && (dtm_scene_effect_attr(e, "alpha") || dtm_scene_effect_attr(e, "beta"));
  fprintf(f, "    <%s", dtm_ol_effect_names[k]);
  for (int i = 0; e && i < e->nattr; i++)
    if (!(k == 0 && !strcmp(e->keys[i], "formulation")) && !(k == 1 && !strcmp(e->keys[i], "xi")))
      attr(f, e->keys[i], e->values[i]);
  if (k == 0) attr(f, "formulation", formulations[pn->formulation]);
  if (k == 1 && !rayleigh) attr_num(f, "xi", pn->xi);
  if (k == 4 && !e) {
    fprintf(f, " groups=\"");
    for (int i = 0; i < pn->nanalysed; i++) esc(f, pn->groups[i].ref), fputs(i + 1 < pn->nanalysed ? " " : "", f);
    fputc('"', f);
  }
  fprintf(f, "/>\n");
  (void)m;
}

static void external(FILE *f, const dtm_scene_effect *e) {
  fprintf(f, "    <effect");
  for (int i = 0; i < e->nattr; i++) attr(f, e->keys[i], !strcmp(e->keys[i], "library") ? e->library : e->values[i]);
  fprintf(f, "/>\n");
}

static void effects(FILE *f, const ol_model *m, const ol_panel *pn) {
  int written[OL_NEFFECTS] = {0};
  fprintf(f, "  <effects>\n");
  for (int i = 0; m->base && i < m->base->neffects; i++) {
    const dtm_scene_effect *e = &m->base->effects[i];
    int k = e->library ? -1 : builtin_index(e->name);
    if (k < 0)
      external(f, e);
    else if (pn->effect_on[k] && !written[k])
      builtin(f, m, pn, k, e), written[k] = 1;
  }
  for (int k = 0; k < OL_NEFFECTS; k++)
    if (pn->effect_on[k] && !written[k]) builtin(f, m, pn, k, NULL);
  fprintf(f, "  </effects>\n");
}

static void times(FILE *f, const ol_model *m, const ol_panel *pn) {
  fprintf(f, "  <time");
  attr_num(f, "safety", pn->safety);
  if (pn->target > 0) attr_num(f, "target", pn->target);
  if (pn->duration > 0) attr_num(f, "duration", pn->duration);
  if (m->base && m->base->f_max > 0) attr_num(f, "f-max", m->base->f_max);
  if (m->base && m->base->f_max > 0) attr_num(f, "elements-per-wavelength", m->base->elements_per_wavelength);
  if (pn->posterior) fprintf(f, " posterior=\"true\"");
  if (m->base && m->base->max_added_mass > 0) attr_num(f, "max-added-mass", m->base->max_added_mass);
  fprintf(f, "/>\n");
}

int dtm_ol_scene_text(const ol_model *m, const ol_panel *pn, char **xml) {
  size_t len;
  FILE *f = open_memstream(xml, &len);
  if (!f) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int nlib = dtm_ol_material_count();
  fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
  fprintf(f, "<!-- Written by dtmap from Gmsh's ONELAB panel. -->\n<dtmap-scene version=\"1\"");
  if (dtm_units_mm(pn->units)) attr(f, "units", "mm-t-s");
  if (m->base && m->base->no_plausible_check) attr(f, "plausible", "no-check");
  fprintf(f, ">\n");
  source(f, m, pn);
  for (int i = 0; i < pn->ngroups; i++) material(f, pn, i, nlib);
  sections(f, m, pn);
  effects(f, m, pn);
  times(f, m, pn);
  fprintf(f, "</dtmap-scene>\n");
  if (fclose(f)) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  return DTM_OK;
}
