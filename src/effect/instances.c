/* Creating and destroying the effects a scene names, in scene order, and
 * checking that the materials in use carry what each effect needs. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    if (used[i]) r = dtm_material_require(&s->materials[i].m, c->needs, c->name);
  free(used);
  return r;
}

static int create_one(const dtm_scene *s, const dtm_mesh *m, int i, dtm_effect *e) {
  const dtm_scene_effect *se = &s->effects[i];
  e->se = se;
  DTM_CHECK(find_class(s, se, &e->cls, &e->handle));
  DTM_CHECK(check_needs(s, m, e->cls));
  dtm_effect_args a = {s, se, m};
  if (e->cls->create) DTM_CHECK(e->cls->create(&a, &e->state));
  return DTM_OK;
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
