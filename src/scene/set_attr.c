/* Changing a scene's effect after it was read: a program that hands the
 * scene to a solver's element (dtm_deck_adapt: CalculiX's C3D10 needs
 * integration="calculix") sets one attribute before the analysis creates
 * the effects, which read their attributes then. */
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/scene.h"

static char *dup_text(const char *t) {
  char *d = malloc(strlen(t) + 1);
  return d ? strcpy(d, t) : NULL;
}

int dtm_scene_effect_set(dtm_scene_effect *e, const char *key, const char *value) {
  char *v = dup_text(value);
  if (!v) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int i = 0; i < e->nattr; i++)
    if (e->keys[i] && !strcmp(e->keys[i], key)) return free(e->values[i]), e->values[i] = v, DTM_OK;
  char *k = dup_text(key), **nk = realloc(e->keys, ((size_t)e->nattr + 1) * sizeof *nk);
  if (nk) e->keys = nk;
  char **nv = nk ? realloc(e->values, ((size_t)e->nattr + 1) * sizeof *nv) : NULL;
  if (nv) e->values = nv;
  if (!k || !nk || !nv) return free(k), free(v), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  e->keys[e->nattr] = k, e->values[e->nattr++] = v;
  return DTM_OK;
}
