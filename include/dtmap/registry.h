/* The effect registry and effect instances. Built-in effects are listed once
 * in plugins/list.h; external effects are shared libraries loaded by path.
 * Only the effects a scene names are created. */
#ifndef DTMAP_REGISTRY_H
#define DTMAP_REGISTRY_H

#include "dtmap/export.h"

#include "dtmap/effect.h"
#include "dtmap/mesh.h"
#include "dtmap/scene.h"

/* Number of built-in effects and the i-th one, in registration order. */
DTM_EXPORT int dtm_registry_count(void);
DTM_EXPORT const dtm_effect_class *dtm_registry_get(int i);
/* Built-in effect by name; DTM_ERR_INPUT listing the known names if none. */
DTM_EXPORT int dtm_registry_find(const char *name, const dtm_effect_class **out);
/* Load an external effect from a shared library: resolve
 * DTM_EFFECT_ENTRY_SYMBOL, check the API version and the name. *handle is
 * the dlopen handle, closed by dtm_effects_destroy. */
DTM_EXPORT int dtm_registry_load(const char *library, const char *name, const dtm_effect_class **out, void **handle);

/* One created effect of a scene. */
typedef struct {
  const dtm_effect_class *cls; /* its class (not owned) */
  void *state;                 /* created by cls->create (owned) */
  void *handle;                /* dlopen handle of an external effect, or NULL */
  const dtm_scene_effect *se;  /* its scene element (not owned) */
} dtm_effect;

/* Create the scene's effects, in scene order, against mesh m (for group
 * look-ups and the analysed dimension), and check that every material used
 * by an element has what every effect needs. */
DTM_EXPORT int dtm_effects_create(const dtm_scene *s, const dtm_mesh *m, dtm_effect **out, int *n);
DTM_EXPORT void dtm_effects_destroy(dtm_effect **e, int n);

#endif
