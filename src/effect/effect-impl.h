/* Private to src/effect/ (and its tests): the layout of dtm_effect_args,
 * what an effect may look at while it is created (its scene element and
 * class, the scene, and the mesh's groups). */
#ifndef DTM_EFFECT_ARGS_H
#define DTM_EFFECT_ARGS_H

#include "dtmap/effect.h"
#include "dtmap/mesh.h"
#include "dtmap/scene.h"

struct dtm_effect_args {
  const dtm_scene *scene;      /* the scene (not owned) */
  const dtm_scene_effect *se;  /* the effect's element (not owned) */
  const dtm_mesh *mesh;        /* the mesh being analysed (not owned) */
  const dtm_effect_class *cls; /* the effect's class, for declared defaults (not owned) */
};

#endif
