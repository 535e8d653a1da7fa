/* The effects of one scene, created: only those the scene names, in scene
 * order, each from its class (built in or loaded from a library), with its
 * attributes validated against the class's declarations, its state made by
 * create(), and every material in use checked for the properties it needs. */
#ifndef DTMAP_EFFECT_SET_H
#define DTMAP_EFFECT_SET_H

#include "dtmap/effect.h"
#include "dtmap/export.h"
#include "dtmap/mesh.h"
#include "dtmap/scene.h"

/* One created effect of a scene. */
typedef struct {
  const dtm_effect_class *cls; /* its class (not owned) */
  void *state;                 /* created by cls->create (owned) */
  void *handle;                /* dlopen handle of an external effect, or NULL */
  const dtm_scene_effect *se;  /* its scene element (not owned) */
} dtm_effect;

/* Create the scene's effects, in scene order, against mesh m (for group
 * look-ups and the analysed dimension). Checks that every material used by
 * an element has what every effect needs, and that every property the
 * scene's materials give is declared by some effect. */
DTM_EXPORT int dtm_effects_create(const dtm_scene *s, const dtm_mesh *m, dtm_effect **out, int *n);
DTM_EXPORT void dtm_effects_destroy(dtm_effect **e, int n);

#endif
