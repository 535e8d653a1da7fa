/* The property catalogue of a scene: the properties the built-in effects
 * declare (dtm_registry_properties), then any other property attribute the
 * scene's materials give, for an external effect to declare. Every
 * material holds one value per catalogue entry, so effects find a property
 * once by name and read it by index. A property no effect declares is an
 * error at the material's line; when the scene loads external effects, that
 * check waits until they are created (dtm_effects_create). */
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "dtmap/registry.h"
#include "scene-impl.h"

int dtm_scene_property_index(const dtm_scene *s, const char *name) {
  for (int i = 0; name && i < s->nprops; i++)
    if (!strcmp(s->prop_names[i], name)) return i;
  return -1;
}

static int add_name(dtm_scene *s, const char *name, int cap) {
  if (dtm_scene_property_index(s, name) >= 0) return DTM_OK;
  if (s->nprops == cap) return DTM_ERR(DTM_ERR_INTERNAL, "property catalogue overflow");
  return dtm_scene_strdup(name, &s->prop_names[s->nprops++]);
}

static int count_attributes(const xmlNode *root) {
  int n = 0;
  for (const xmlNode *c = root->children; c; c = c->next)
    for (const xmlAttr *a = dtm_scene_is(c, "material") ? c->properties : NULL; a; a = a->next) n++;
  return n;
}

int dtm_scene_build_catalogue(dtm_scene *s, const xmlNode *root) {
  int nbuiltin;
  const dtm_property *const *builtin = dtm_registry_properties(&nbuiltin);
  int cap = nbuiltin + count_attributes(root);
  s->prop_names = calloc((size_t)cap + 1, sizeof *s->prop_names);
  if (!s->prop_names) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < nbuiltin; i++) DTM_CHECK(add_name(s, builtin[i]->name, cap));
  s->nknown = s->nprops;
  for (const xmlNode *c = root->children; c; c = c->next)
    for (const xmlAttr *a = dtm_scene_is(c, "material") ? c->properties : NULL; a; a = a->next)
      if (!dtm_scene_material_keyword((const char *)a->name)) DTM_CHECK(add_name(s, (const char *)a->name, cap));
  return DTM_OK;
}

static int has_library_effect(const dtm_scene *s) {
  for (int i = 0; i < s->neffects; i++)
    if (s->effects[i].library) return 1;
  return 0;
}

int dtm_scene_check_properties(const dtm_scene *s, const dtm_property *const *extra, int nextra) {
  if (s->nprops == s->nknown || (!extra && has_library_effect(s))) return DTM_OK;
  for (int i = s->nknown; i < s->nprops; i++) {
    int declared = 0;
    for (int k = 0; k < nextra; k++) declared |= extra[k] && !strcmp(extra[k]->name, s->prop_names[i]);
    if (declared) continue;
    char known[2048] = "";
    for (int k = 0; k < s->nknown; k++) dtm_strlist_add(known, sizeof known, s->prop_names[k], 0);
    for (int k = 0; k < nextra; k++) dtm_strlist_add(known, sizeof known, extra[k]->name, 0);
    for (int m = 0; m < s->nmaterials; m++)
      if (dtm_material_has(&s->materials[m].m, i))
        return DTM_ERR(DTM_ERR_INPUT, "%s:%d: material '%s': no effect declares the property '%s' (known: %s)", s->path,
                       s->materials[m].m.line, s->materials[m].m.name, s->prop_names[i], known);
  }
  return DTM_OK;
}
