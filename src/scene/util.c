/* Small helpers of the scene reader: "file:line:" error messages, attribute
 * access on the libxml2 tree, strict number parsing, white-space lists and
 * path resolution against the scene file's directory. Shared by the
 * src/scene*.c files through scene-impl.h and not exported. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/units.h"
#include "scene-impl.h"

int dtm_scene_fail(const dtm_scene *s, const xmlNode *n, const char *file, int line, const char *func, const char *fmt,
                   ...) {
  char msg[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return dtm_error_raise(DTM_ERR_INPUT, file, line, func, "%s:%d: %s", s->path, dtm_scene_line(n), msg);
}

int dtm_scene_line(const xmlNode *n) { return n ? (int)xmlGetLineNo(n) : 0; }

int dtm_scene_is(const xmlNode *n, const char *tag) {
  return n && n->type == XML_ELEMENT_NODE && strcmp((const char *)n->name, tag) == 0;
}

int dtm_scene_count_children(const xmlNode *n) {
  int count = 0;
  for (const xmlNode *c = n->children; c; c = c->next) count += c->type == XML_ELEMENT_NODE;
  return count;
}

int dtm_scene_strdup(const char *s, char **out) {
  *out = strdup(s);
  return *out ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
}

int dtm_scene_attr(const xmlNode *n, const char *key, char **out) {
  *out = NULL;
  xmlChar *v = xmlGetNoNsProp(n, (const xmlChar *)key);
  if (!v) return DTM_OK;
  int rc = dtm_scene_strdup((const char *)v, out);
  xmlFree(v);
  return rc;
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

int dtm_scene_parse_double(const char *text, double *v) {
  char *end;
  while (is_space(*text)) text++;
  if (*text == '\0') return -1;
  *v = strtod(text, &end);
  if (end == text) return -1;
  while (is_space(*end)) end++;
  return *end == '\0' ? 0 : -1;
}

int dtm_scene_attr_positive(const dtm_scene *s, const xmlNode *n, const char *key, double def, double *out) {
  char *text;
  *out = def;
  DTM_CHECK(dtm_scene_attr(n, key, &text));
  if (!text) return DTM_OK;
  int bad = dtm_scene_parse_double(text, out) || !isfinite(*out) || *out <= 0;
  int rc = bad ? DTM_SCENE_ERR(s, n, "<%s> %s=\"%s\" is not admissible (need a finite number > 0)",
                               (const char *)n->name, key, text)
               : DTM_OK;
  free(text);
  return rc;
}

int dtm_scene_attr_bool(const dtm_scene *s, const xmlNode *n, const char *key, int *out) {
  char *text;
  DTM_CHECK(dtm_scene_attr(n, key, &text));
  if (!text) return DTM_OK;
  int rc = DTM_OK;
  if (!strcmp(text, "true") || !strcmp(text, "1"))
    *out = 1;
  else if (!strcmp(text, "false") || !strcmp(text, "0"))
    *out = 0;
  else
    rc = DTM_SCENE_ERR(s, n, "<%s> %s=\"%s\" is not true or false", (const char *)n->name, key, text);
  free(text);
  return rc;
}

int dtm_scene_attr_percent(const dtm_scene *s, const xmlNode *n, const char *key, double *out) {
  char *text;
  DTM_CHECK(dtm_scene_attr(n, key, &text));
  if (!text) return DTM_OK;
  int bad = dtm_scene_parse_double(text, out) || !(*out >= 0 && *out <= 100);
  int rc = bad ? DTM_SCENE_ERR(s, n, "<%s> %s=\"%s\" is not admissible (need a percentage from 0 to 100)",
                               (const char *)n->name, key, text)
               : DTM_OK;
  free(text);
  return rc;
}

int dtm_scene_resolve(const dtm_scene *s, const char *rel, char **out) {
  if (rel[0] == '/' || strcmp(s->dir, ".") == 0) return dtm_scene_strdup(rel, out);
  size_t nd = strlen(s->dir), nr = strlen(rel);
  int slash = s->dir[nd - 1] != '/';
  *out = malloc(nd + slash + nr + 1);
  if (!*out) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  memcpy(*out, s->dir, nd);
  if (slash) (*out)[nd] = '/';
  memcpy(*out + nd + slash, rel, nr + 1);
  return DTM_OK;
}

static int count_tokens(const char *t) {
  int n = 0;
  for (; *t; t++) n += !is_space(*t) && (t[1] == '\0' || is_space(t[1]));
  return n;
}

int dtm_scene_split(const char *text, int *n, char ***items) {
  int count = count_tokens(text);
  *n = 0;
  *items = count ? calloc((size_t)count, sizeof **items) : NULL;
  if (count && !*items) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (const char *t = text; *t;) {
    while (is_space(*t)) t++;
    size_t len = 0;
    while (t[len] && !is_space(t[len])) len++;
    if (!len) break;
    (*items)[*n] = strndup(t, len);
    if (!(*items)[*n]) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    ++*n;
    t += len;
  }
  return DTM_OK;
}

void dtm_scene_free_strings(int n, char **v) {
  for (int i = 0; v && i < n; i++) free(v[i]);
  free(v);
}

const char *dtm_scene_units(const dtm_scene *s) {
  return s && s->units && !strcmp(s->units, "mm-t-s") ? "mm-t-s" : "SI";
}

const char *dtm_scene_mass_unit(const dtm_scene *s, int dim) {
  return dtm_units_name(s->units, dim < 3 && !s->nsections ? DTM_UNIT_LINE_MASS : DTM_UNIT_MASS);
}
