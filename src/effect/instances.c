/* Creating and destroying the effects a scene names, in scene order: each
 * class found (built in) or loaded (external, whose attributes and
 * properties are validated here, as the scene reader could not know them),
 * the materials in use checked for what each effect needs, and every
 * property the materials give checked to be declared by some effect. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/effect_set.h"
#include "dtmap/registry.h"
#include "effect-impl.h"

static int find_class(const dtm_scene *s, const dtm_scene_effect *se, const dtm_effect_class **cls, void **handle) {
  int r = se->library ? dtm_registry_load(se->library, se->name, cls, handle) : dtm_registry_find(se->name, cls);
  if (r == DTM_OK) return DTM_OK;
  char msg[2048];
  snprintf(msg, sizeof msg, "%s", dtm_error_message());
  dtm_error_clear();
  return DTM_ERR(r, "%s:%d: %s", s->path, se->line, msg);
}

/* Every material that some element uses must have the effect's needs. */
static int check_needs(const dtm_scene *s, const dtm_mesh *m, const dtm_effect_class *c) {
  char *used = calloc((size_t)s->nmaterials + 1, 1);
  if (!used) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  dtm_mesh_materials_used(m, s->nmaterials, used);
  int r = DTM_OK;
  for (int i = 0; i < s->nmaterials && r == DTM_OK; i++)
    if (used[i]) r = dtm_material_require(&s->materials[i].m, c->properties, c->name);
  free(used);
  return r;
}

/* An external effect: its attributes against its declarations, and the
 * values its own properties (those no built-in effect declares) take. */
static int check_external(const dtm_scene *s, const dtm_scene_effect *se, const dtm_effect_class *c) {
  static const char *const core[] = {"name", "library", NULL};
  char where[4200];
  snprintf(where, sizeof where, "%s:%d: ", s->path, se->line);
  DTM_CHECK(dtm_registry_check_attributes(c, se->nattr, se->keys, se->values, core, where));
  for (const dtm_property *p = c->properties; p && p->name; p++) {
    if (dtm_registry_property(p->name, NULL)) continue; /* built in: checked when the scene was read */
    int k = dtm_scene_property_index(s, p->name);
    for (int i = 0; k >= 0 && i < s->nmaterials; i++)
      if (dtm_material_has(&s->materials[i].m, k))
        DTM_CHECK(dtm_property_check(p, &s->materials[i].m, dtm_material_get(&s->materials[i].m, k)));
  }
  return DTM_OK;
}

static int create_one(const dtm_scene *s, const dtm_mesh *m, int i, dtm_effect *e) {
  const dtm_scene_effect *se = &s->effects[i];
  e->se = se;
  DTM_CHECK(find_class(s, se, &e->cls, &e->handle));
  if (se->library) DTM_CHECK(check_external(s, se, e->cls));
  DTM_CHECK(check_needs(s, m, e->cls));
  dtm_effect_args a = {s, se, m, e->cls};
  if (e->cls->create) DTM_CHECK(e->cls->create(&a, &e->state));
  return DTM_OK;
}

/* Every property the materials give must be declared by a built-in effect
 * or by one of the scene's external effects. */
static int check_declared(const dtm_scene *s, const dtm_effect *e) {
  const dtm_property *extra[256];
  int n = 0;
  for (int i = 0; i < s->neffects; i++)
    for (const dtm_property *p = e[i].handle ? e[i].cls->properties : NULL; p && p->name && n < 256; p++)
      extra[n++] = p;
  return dtm_scene_check_properties(s, extra, n);
}

static int any_limits(const dtm_effect *e, int n) {
  for (int i = 0; i < n; i++)
    if (e[i].cls->role & DTM_ROLE_LIMITS) return 1;
  return 0;
}

int dtm_effects_create(const dtm_scene *s, const dtm_mesh *m, dtm_effect **out, int *n) {
  dtm_effect *e = calloc((size_t)s->neffects + 1, sizeof *e);
  if (!e) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < s->neffects; i++) {
    int r = create_one(s, m, i, &e[i]);
    if (r) {
      dtm_effects_destroy(&e, i + 1);
      return dtm_error_trace(r, __FILE__, __LINE__, __func__);
    }
  }
  int r = check_declared(s, e);
  if (r) {
    dtm_effects_destroy(&e, s->neffects);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  if (!any_limits(e, s->neffects)) {
    dtm_effects_destroy(&e, s->neffects);
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s:%d: <effects> names no effect that limits the step (damping only scales "
                   "the wave effects; add <elastic/>, <thermal/>, ...)",
                   s->path, s->effects_line);
  }
  *out = e;
  *n = s->neffects;
  return DTM_OK;
}

void dtm_effects_destroy(dtm_effect **pe, int n) {
  dtm_effect *e = *pe;
  if (!e) return;
  for (int i = 0; i < n; i++) {
    if (e[i].cls && e[i].state && e[i].cls->destroy) e[i].cls->destroy(&e[i].state);
    if (e[i].handle) dlclose(e[i].handle);
  }
  free(e);
  *pe = NULL;
}
