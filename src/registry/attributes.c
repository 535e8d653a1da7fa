/* Validation of a scene element's attributes against what its effect class
 * declares: no unknown (misspelt) attribute, numbers that parse whole and
 * lie in their range, words among their choices, non-empty group lists and
 * text, every required parameter present. Each message starts with the
 * caller's place (the scene file and line) and names the attribute and what
 * would be accepted. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "registry-impl.h"

const dtm_param *dtm_registry_param(const dtm_effect_class *c, const char *key) {
  for (const dtm_param *p = c->params; p && p->name; p++)
    if (!strcmp(p->name, key)) return p;
  return NULL;
}

static int skipped(const char *key, const char *const *skip) {
  for (int i = 0; skip && skip[i]; i++)
    if (!strcmp(skip[i], key)) return 1;
  return 0;
}

static int unknown(const dtm_effect_class *c, const char *key, const char *where) {
  char known[1024] = "";
  for (const dtm_param *p = c->params; p && p->name; p++) dtm_strlist_add(known, sizeof known, p->name, 0);
  return DTM_ERR(DTM_ERR_INPUT, "%seffect '%s': unknown attribute '%s' (%s takes: %s)", where, c->name, key, c->name,
                 known[0] ? known : "no attributes");
}

/* The whole text (surrounding spaces allowed) as a number; 0 on success. */
static int parse_number(const char *text, double *v) {
  char *end = NULL;
  while (isspace((unsigned char)*text)) text++;
  *v = strtod(text, &end);
  if (end == text) return -1;
  while (isspace((unsigned char)*end)) end++;
  return *end ? -1 : 0;
}

static int check_number(const dtm_effect_class *c, const dtm_param *p, const char *v, const char *where) {
  double x;
  if (parse_number(v, &x))
    return DTM_ERR(DTM_ERR_INPUT, "%seffect '%s': %s=\"%s\" is not a number", where, c->name, p->name, v);
  dtm_property range = {p->name, p->unit, p->lo, p->hi, p->open, 0, p->help};
  if (dtm_property_check(&range, NULL, x) == DTM_OK) return DTM_OK;
  char msg[512];
  snprintf(msg, sizeof msg, "%s", dtm_error_message());
  dtm_error_clear();
  return DTM_ERR(DTM_ERR_INPUT, "%seffect '%s': %s", where, c->name, msg);
}

static int check_choice(const dtm_effect_class *c, const dtm_param *p, const char *v, const char *where) {
  char known[512] = "";
  for (int i = 0; p->choices[i]; i++) {
    if (!strcmp(p->choices[i], v)) return DTM_OK;
    dtm_strlist_add(known, sizeof known, p->choices[i], 0);
  }
  return DTM_ERR(DTM_ERR_INPUT, "%seffect '%s': %s=\"%s\" is not one of: %s", where, c->name, p->name, v, known);
}

static int blank(const char *v) {
  while (isspace((unsigned char)*v)) v++;
  return *v == '\0';
}

static int check_value(const dtm_effect_class *c, const dtm_param *p, const char *v, const char *where) {
  switch (p->type) {
  case DTM_PARAM_NUMBER: return check_number(c, p, v, where);
  case DTM_PARAM_CHOICE: return check_choice(c, p, v, where);
  default:
    if (!blank(v)) return DTM_OK;
    return DTM_ERR(DTM_ERR_INPUT, "%seffect '%s': %s=\"\" is empty (%s)", where, c->name, p->name, p->help);
  }
}

static int given(const char *key, int n, char *const *keys) {
  for (int i = 0; i < n; i++)
    if (!strcmp(keys[i], key)) return 1;
  return 0;
}

int dtm_registry_check_attributes(const dtm_effect_class *c, int n, char *const *keys, char *const *values,
                                  const char *const *skip, const char *where) {
  where = where ? where : "";
  for (int i = 0; i < n; i++) {
    if (skipped(keys[i], skip)) continue;
    const dtm_param *p = dtm_registry_param(c, keys[i]);
    if (!p) return unknown(c, keys[i], where);
    DTM_CHECK(check_value(c, p, values[i], where));
  }
  for (const dtm_param *p = c->params; p && p->name; p++)
    if (p->required && !given(p->name, n, keys))
      return DTM_ERR(DTM_ERR_INPUT, "%seffect '%s' needs %s=\"...\" (%s)", where, c->name, p->name, p->help);
  return DTM_OK;
}
