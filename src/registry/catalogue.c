/* The catalogue of material properties the built-in effects declare: each
 * name once, in registration order, with its first declaration (the others
 * must agree, dtm_registry_check_all). It is what the scene reader checks
 * material attributes against and what the generated schema lists. */
#include <string.h>

#include "registry-impl.h"

#define MAX_PROPS 128 /* distinct properties over all built-in effects */

static const dtm_property *catalogue[MAX_PROPS];
static int ncatalogue = -1;

static int find(const char *name) {
  for (int i = 0; i < ncatalogue; i++)
    if (!strcmp(catalogue[i]->name, name)) return i;
  return -1;
}

/* Built once; the registry is constant, so every call sees the same list.
 * Called before any thread starts (scene loading). */
static void build(void) {
  if (ncatalogue >= 0) return;
  ncatalogue = 0;
  for (int i = 0; i < dtm_registry_count(); i++)
    for (const dtm_property *p = dtm_registry_get(i)->properties; p && p->name; p++)
      if (find(p->name) < 0 && ncatalogue < MAX_PROPS) catalogue[ncatalogue++] = p;
}

const dtm_property *const *dtm_registry_properties(int *n) {
  build();
  *n = ncatalogue;
  return catalogue;
}

const dtm_property *dtm_registry_property(const char *name, const dtm_effect_class *extra) {
  if (!name) return NULL;
  build();
  int i = find(name);
  if (i >= 0) return catalogue[i];
  for (const dtm_property *p = extra ? extra->properties : NULL; p && p->name; p++)
    if (!strcmp(p->name, name)) return p;
  return NULL;
}
