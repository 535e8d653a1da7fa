/* Reading the <effects> element of a scene: every child, in file order,
 * becomes a dtm_scene_effect holding its name, line and all its attributes
 * as written, so that each effect (built in or loaded from a library) reads
 * its own options. A built-in effect's attributes are checked here against
 * what its class declares (an unknown or misspelt attribute is an error at
 * its line, listing the known ones). <effect name="x" library="y"/> names an effect; its
 * library path is resolved against the scene file's directory. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/registry.h"
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

/* A built-in effect (by element or by <effect name=...>): its attributes
 * against the class's declarations, with the element's line. External
 * effects are checked once loaded (dtm_effects_create). */
static int check_builtin(const dtm_scene *s, const dtm_scene_effect *e) {
  static const char *const core[] = {"name", NULL};
  const dtm_effect_class *c;
  char where[4200];
  snprintf(where, sizeof where, "%s:%d: ", s->path, e->line);
  if (dtm_registry_find(e->name, &c)) {
    char msg[2048];
    snprintf(msg, sizeof msg, "%s", dtm_error_message());
    dtm_error_clear();
    return DTM_ERR(DTM_ERR_INPUT, "%s%s", where, msg);
  }
  return dtm_registry_check_attributes(c, e->nattr, e->keys, e->values, core, where);
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
  if (library) return dtm_scene_resolve(s, library, &e->library);
  return check_builtin(s, e);
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
