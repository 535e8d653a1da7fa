/* Reading the <effects> element of a scene: every child, in file order,
 * becomes a dtm_scene_effect holding its name, line and all its attributes
 * as written, so that each effect (built in or loaded from a library) parses
 * its own options. <effect name="x" library="y"/> names an effect; its
 * library path is resolved against the scene file's directory. */
#include <stdlib.h>
#include <string.h>

#include "scene-impl.h"

static int count_attributes(const xmlNode *n) {
  int count = 0;
  for (const xmlAttr *a = n->properties; a; a = a->next) count++;
  return count;
}

static int copy_attribute(const xmlNode *n, const xmlAttr *a, dtm_scene_effect *e) {
  int i = e->nattr++;
  DTM_CHECK(dtm_scene_strdup((const char *)a->name, &e->keys[i]));
  xmlChar *v = xmlNodeListGetString(n->doc, a->children, 1);
  int rc = dtm_scene_strdup(v ? (const char *)v : "", &e->values[i]);
  xmlFree(v);
  return rc;
}

static int copy_attributes(const xmlNode *n, dtm_scene_effect *e) {
  int count = count_attributes(n);
  if (!count) return DTM_OK;
  e->keys = calloc((size_t)count, sizeof *e->keys);
  e->values = calloc((size_t)count, sizeof *e->values);
  if (!e->keys || !e->values) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (const xmlAttr *a = n->properties; a; a = a->next) DTM_CHECK(copy_attribute(n, a, e));
  return DTM_OK;
}

static int read_effect(dtm_scene *s, const xmlNode *n) {
  dtm_scene_effect *e = &s->effects[s->neffects++];
  e->line = dtm_scene_line(n);
  DTM_CHECK(copy_attributes(n, e));
  const char *name = (const char *)n->name;
  if (dtm_scene_is(n, "effect")) name = dtm_scene_effect_attr(e, "name");
  if (!name || !*name) return DTM_SCENE_ERR(s, n, "<effect> needs a name=\"...\"");
  DTM_CHECK(dtm_scene_strdup(name, &e->name));
  const char *library = dtm_scene_effect_attr(e, "library");
  if (library && !*library) return DTM_SCENE_ERR(s, n, "effect '%s': library=\"\" names no file", e->name);
  if (library) DTM_CHECK(dtm_scene_resolve(s, library, &e->library));
  return DTM_OK;
}

int dtm_scene_read_effects(dtm_scene *s, const xmlNode *n) {
  int count = dtm_scene_count_children(n);
  s->effects_line = dtm_scene_line(n);
  if (!count) return DTM_SCENE_ERR(s, n, "<effects> lists no effect; nothing would run");
  if (s->effects) return DTM_SCENE_ERR(s, n, "<effects> appears twice");
  s->effects = calloc((size_t)count, sizeof *s->effects);
  if (!s->effects) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (const xmlNode *c = n->children; c; c = c->next)
    if (c->type == XML_ELEMENT_NODE) DTM_CHECK(read_effect(s, c));
  return DTM_OK;
}

const char *dtm_scene_effect_attr(const dtm_scene_effect *e, const char *key) {
  for (int i = 0; e && key && i < e->nattr; i++)
    if (e->keys[i] && !strcmp(e->keys[i], key)) return e->values[i];
  return NULL;
}
