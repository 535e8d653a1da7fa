/* Reading one <material> element of a scene: its name, physical groups,
 * default flag and property values. Values are parsed strictly and checked
 * for physical admissibility against the declaring effect's range
 * (dtm_property_check); names must be unique, at most
 * one material may be the default, and no physical group may be given to
 * two materials. Every error names the scene file and line. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/registry.h"
#include "scene-impl.h"

static char *trim(char *s) {
  char *end = s + strlen(s);
  while (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r') s++;
  while (end > s && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\n' || end[-1] == '\r')) *--end = '\0';
  return s;
}

static int read_name(const dtm_scene *s, const xmlNode *n, dtm_material *m) {
  char *raw;
  DTM_CHECK(dtm_scene_attr(n, "name", &raw));
  if (!raw) return DTM_SCENE_ERR(s, n, "<material> has no name");
  const char *name = trim(raw);
  int rc = *name ? dtm_scene_strdup(name, &m->name) : DTM_SCENE_ERR(s, n, "<material> has an empty name");
  free(raw);
  return rc;
}

static int read_default(const dtm_scene *s, const xmlNode *n, dtm_scene_material *sm) {
  char *raw;
  DTM_CHECK(dtm_scene_attr(n, "default", &raw));
  if (!raw) return DTM_OK;
  const char *v = trim(raw);
  int rc = DTM_OK;
  if (!strcmp(v, "true") || !strcmp(v, "1"))
    sm->is_default = 1;
  else if (strcmp(v, "false") && strcmp(v, "0"))
    rc = DTM_SCENE_ERR(s, n, "material '%s': default=\"%s\" is not true or false", sm->m.name, raw);
  free(raw);
  return rc;
}

static int read_groups(const dtm_scene *s, const xmlNode *n, dtm_scene_material *sm) {
  char *raw;
  DTM_CHECK(dtm_scene_attr(n, "groups", &raw));
  if (!raw) return DTM_OK;
  int rc = dtm_scene_split(raw, &sm->ngroups, &sm->groups);
  if (!rc && sm->ngroups == 0)
    rc = DTM_SCENE_ERR(s, n, "material '%s': groups=\"\" lists no physical group", sm->m.name);
  free(raw);
  return rc;
}

/* The material attributes that are not properties. */
int dtm_scene_material_keyword(const char *attr) {
  return !strcmp(attr, "name") || !strcmp(attr, "groups") || !strcmp(attr, "default") || !strcmp(attr, "plausible");
}

/* An attribute that reads as a unit ("unit", "units", "E-unit"): dtmap
 * takes units once, for the whole scene. */
static int is_unit_word(const char *attr) {
  size_t n = strlen(attr);
  return !strcmp(attr, "unit") || !strcmp(attr, "units") || (n > 5 && !strcmp(attr + n - 5, "-unit")) ||
         (n > 5 && !strcmp(attr + n - 5, "_unit"));
}

/* One property attribute: a strict number, admissible for the effect that
 * declares it (when a built-in one does; an external effect's own property
 * is checked when the effect is created). */
static int read_prop(const dtm_scene *s, const xmlNode *n, dtm_material *m, const char *attr) {
  char *raw;
  double v;
  int i = dtm_scene_property_index(s, attr);
  DTM_CHECK(dtm_scene_attr(n, attr, &raw));
  if (i < 0 || !raw) return free(raw), DTM_ERR(DTM_ERR_INTERNAL, "property '%s' is not in the catalogue", attr);
  const dtm_property *decl = dtm_registry_property(attr, NULL);
  int rc = dtm_scene_parse_double(raw, &v) && is_unit_word(attr)
               ? DTM_SCENE_ERR(s, n,
                               "material '%s': %s=\"%s\" is no attribute of <material>: a material's values are in the "
                               "scene's unit system, SI (E in Pa, rho in kg/m^3) unless <dtmap-scene units=\"mm-t-s\"> "
                               "says mm-t-s (E in MPa, rho in t/mm^3); write the values in it",
                               m->name, attr, raw)
           : dtm_scene_parse_double(raw, &v)
               ? DTM_SCENE_ERR(s, n, "material '%s': %s = '%s' is not a number", m->name, attr, raw)
           : decl         ? dtm_property_check(decl, m, v)
           : !isfinite(v) ? DTM_SCENE_ERR(s, n, "material '%s': %s = '%s' is not a finite number", m->name, attr, raw)
                          : DTM_OK;
  free(raw);
  if (rc) return dtm_error_trace(rc, __FILE__, __LINE__, __func__);
  m->prop[i] = v;
  return DTM_OK;
}

static int read_props(dtm_scene *s, const xmlNode *n, dtm_material *m) {
  m->nprops = s->nprops;
  m->prop_names = s->prop_names;
  m->prop = malloc(((size_t)s->nprops + 1) * sizeof *m->prop);
  if (!m->prop) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < s->nprops; i++) m->prop[i] = NAN;
  for (const xmlAttr *a = n->properties; a; a = a->next)
    if (!dtm_scene_material_keyword((const char *)a->name)) DTM_CHECK(read_prop(s, n, m, (const char *)a->name));
  return DTM_OK;
}

static int has_group(const dtm_scene_material *sm, int upto, const char *g) {
  for (int i = 0; i < upto && i < sm->ngroups; i++)
    if (!strcmp(sm->groups[i], g)) return 1;
  return 0;
}

/* Compare the material just read (last) with those before it. */
static int check_against(const dtm_scene *s, const xmlNode *n, const dtm_scene_material *a,
                         const dtm_scene_material *b) {
  if (!strcmp(a->m.name, b->m.name))
    return DTM_SCENE_ERR(s, n, "material '%s' is defined twice (first at line %d)", b->m.name, a->m.line);
  if (a->is_default && b->is_default)
    return DTM_SCENE_ERR(s, n,
                         "material '%s' is a second default material (the first is '%s' "
                         "at line %d); only one may have default=\"true\"",
                         b->m.name, a->m.name, a->m.line);
  for (int g = 0; g < b->ngroups; g++)
    if (has_group(a, a->ngroups, b->groups[g]))
      return DTM_SCENE_ERR(s, n,
                           "group '%s' is given to material '%s' (line %d) and to "
                           "material '%s'; a group can have only one material",
                           b->groups[g], a->m.name, a->m.line, b->m.name);
  return DTM_OK;
}

static int check_unique(const dtm_scene *s, const xmlNode *n) {
  const dtm_scene_material *last = &s->materials[s->nmaterials - 1];
  for (int g = 1; g < last->ngroups; g++)
    if (has_group(last, g, last->groups[g]))
      return DTM_SCENE_ERR(s, n, "material '%s' lists group '%s' twice", last->m.name, last->groups[g]);
  for (int i = 0; i < s->nmaterials - 1; i++) DTM_CHECK(check_against(s, n, &s->materials[i], last));
  return DTM_OK;
}

int dtm_scene_read_material(dtm_scene *s, const xmlNode *n) {
  dtm_scene_material *sm = &s->materials[s->nmaterials++];
  sm->m.file = s->path;
  sm->m.line = dtm_scene_line(n);
  DTM_CHECK(read_name(s, n, &sm->m));
  DTM_CHECK(read_default(s, n, sm));
  DTM_CHECK(read_groups(s, n, sm));
  DTM_CHECK(dtm_scene_read_plausible(s, n, &sm->no_plausible_check));
  DTM_CHECK(read_props(s, n, &sm->m));
  return check_unique(s, n);
}
