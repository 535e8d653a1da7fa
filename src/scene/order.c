/* The order of <dtmap-scene>'s children, as a schema error about them
 * states it: read from the embedded schema itself (the xs:sequence of the
 * element dtmap-scene), so that the message follows the schema when it
 * changes. "(geometry | mesh | model), meshing?, (material | section)+,
 * effects, time?, output?": a choice in parentheses, ? optional, + one or
 * more, * any number. */
#include <stdio.h>
#include <string.h>

#include <libxml/parser.h>
#include <libxml/tree.h>

#include "scene-impl.h"

extern const unsigned char dtm_scene_xsd[];
extern const size_t dtm_scene_xsd_len;

static int is_xs(const xmlNode *n, const char *name) {
  return n->type == XML_ELEMENT_NODE && !strcmp((const char *)n->name, name);
}

/* The attribute as text, or def. */
static const char *attr(const xmlNode *n, const char *name, char *buf, size_t len, const char *def) {
  xmlChar *v = xmlGetProp(n, (const xmlChar *)name);
  snprintf(buf, len, "%s", v ? (const char *)v : def);
  xmlFree(v);
  return buf;
}

/* "?", "+", "*" or "" from minOccurs and maxOccurs. */
static const char *occurs(const xmlNode *n) {
  char lo[32], hi[32];
  int optional = !strcmp(attr(n, "minOccurs", lo, sizeof lo, "1"), "0");
  int many = strcmp(attr(n, "maxOccurs", hi, sizeof hi, "1"), "1") != 0;
  return optional ? (many ? "*" : "?") : (many ? "+" : "");
}

/* Append text to buf[len] at *k, keeping it terminated. */
static void put(char *buf, size_t len, size_t *k, const char *text) {
  if (*k >= len) return;
  int w = snprintf(buf + *k, len - *k, "%s", text);
  *k += w > 0 ? (size_t)w : 0;
}

/* One particle of the sequence: an element's name or a choice of them. */
static void particle(const xmlNode *n, char *buf, size_t len, size_t *k) {
  char name[128];
  if (is_xs(n, "element")) {
    put(buf, len, k, attr(n, "name", name, sizeof name, "?"));
  } else if (is_xs(n, "choice")) {
    int first = 1;
    put(buf, len, k, "(");
    for (const xmlNode *c = n->children; c; c = c->next)
      if (is_xs(c, "element")) {
        put(buf, len, k, first ? "" : " | ");
        put(buf, len, k, attr(c, "name", name, sizeof name, "?"));
        first = 0;
      }
    put(buf, len, k, ")");
  } else {
    return;
  }
  put(buf, len, k, occurs(n));
}

/* The xs:sequence of the element named root, or NULL. */
static const xmlNode *root_sequence(const xmlNode *schema, const char *root) {
  char name[128];
  for (const xmlNode *e = schema->children; e; e = e->next) {
    if (!is_xs(e, "element") || strcmp(attr(e, "name", name, sizeof name, ""), root)) continue;
    for (const xmlNode *t = e->children; t; t = t->next)
      for (const xmlNode *s = is_xs(t, "complexType") ? t->children : NULL; s; s = s->next)
        if (is_xs(s, "sequence")) return s;
  }
  return NULL;
}

int dtm_scene_child_order(char *buf, size_t len) {
  buf[0] = '\0';
  xmlDoc *d = xmlReadMemory((const char *)dtm_scene_xsd, (int)dtm_scene_xsd_len, "dtmap-scene.xsd", NULL,
                            XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
  const xmlNode *seq = d ? root_sequence(xmlDocGetRootElement(d), "dtmap-scene") : NULL;
  size_t k = 0;
  for (const xmlNode *c = seq ? seq->children : NULL; c; c = c->next) {
    if (!is_xs(c, "element") && !is_xs(c, "choice")) continue;
    put(buf, len, &k, k ? ", " : "");
    particle(c, buf, len, &k);
  }
  xmlFreeDoc(d);
  return buf[0] ? 0 : -1;
}
