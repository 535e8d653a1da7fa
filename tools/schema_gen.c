/* Build tool: writes the scene schema from its template
 * (schema/dtmap-scene.xsd.in) and the declarations of the built-in effects,
 * so that a new effect needs its folder and one line in plugins/list.h and
 * nothing else. The template's marker lines are replaced:
 *   @MATERIAL_PROPERTIES@  one attribute per property the effects declare;
 *   @EFFECT_TYPES@         one complex type per effect, an attribute per
 *                          parameter (numbers with their range as facets,
 *                          choices as enumerations, groups as a group list);
 *   @EFFECT_ELEMENTS@      one element per effect under <effects>.
 * Every class is checked (dtm_registry_check_all) first, so an incomplete
 * built-in effect fails the build with the registry's message.
 * Usage: dtm_schema_gen TEMPLATE OUTPUT */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/registry.h"

/* The scene schema the library embeds; this tool runs before it exists. */
const unsigned char dtm_scene_xsd[] = {0};
const size_t dtm_scene_xsd_len = 0;

/* text with &, < and > escaped for XML. */
static void put_escaped(FILE *f, const char *text) {
  for (const char *p = text ? text : ""; *p; p++) {
    if (*p == '&')
      fputs("&amp;", f);
    else if (*p == '<')
      fputs("&lt;", f);
    else if (*p == '>')
      fputs("&gt;", f);
    else
      fputc(*p, f);
  }
}

static void documentation(FILE *f, const char *indent, const char *help, const char *unit) {
  fprintf(f, "%s<xs:annotation><xs:documentation>", indent);
  put_escaped(f, help);
  if (unit && unit[0]) fprintf(f, " (%s)", unit);
  fprintf(f, "</xs:documentation></xs:annotation>\n");
}

static void number_facets(FILE *f, const dtm_param *p) {
  fprintf(f, "      <xs:simpleType><xs:restriction base=\"xs:double\">");
  if (isfinite(p->lo)) fprintf(f, "<xs:min%sclusive value=\"%.17g\"/>", p->open & DTM_OPEN_LO ? "Ex" : "In", p->lo);
  if (isfinite(p->hi)) fprintf(f, "<xs:max%sclusive value=\"%.17g\"/>", p->open & DTM_OPEN_HI ? "Ex" : "In", p->hi);
  fprintf(f, "</xs:restriction></xs:simpleType>\n");
}

static void choice_facets(FILE *f, const dtm_param *p) {
  fprintf(f, "      <xs:simpleType><xs:restriction base=\"xs:token\">");
  for (int i = 0; p->choices[i]; i++) fprintf(f, "<xs:enumeration value=\"%s\"/>", p->choices[i]);
  fprintf(f, "</xs:restriction></xs:simpleType>\n");
}

static void attribute(FILE *f, const dtm_param *p) {
  static const char *const simple[] = {[DTM_PARAM_GROUPS] = "groupList", [DTM_PARAM_TEXT] = "name"};
  const char *use = p->required ? " use=\"required\"" : "";
  int inline_type = p->type == DTM_PARAM_NUMBER || p->type == DTM_PARAM_CHOICE;
  if (inline_type)
    fprintf(f, "    <xs:attribute name=\"%s\"%s>\n", p->name, use);
  else
    fprintf(f, "    <xs:attribute name=\"%s\" type=\"%s\"%s>\n", p->name, simple[p->type], use);
  documentation(f, "      ", p->help, p->unit);
  if (p->type == DTM_PARAM_NUMBER) number_facets(f, p);
  if (p->type == DTM_PARAM_CHOICE) choice_facets(f, p);
  fprintf(f, "    </xs:attribute>\n");
}

static void effect_types(FILE *f) {
  for (int i = 0; i < dtm_registry_count(); i++) {
    const dtm_effect_class *c = dtm_registry_get(i);
    fprintf(f, "  <xs:complexType name=\"effect-%s\">\n", c->name);
    documentation(f, "    ", c->summary, NULL);
    for (const dtm_param *p = c->params; p && p->name; p++) attribute(f, p);
    fprintf(f, "  </xs:complexType>\n");
  }
}

static void effect_elements(FILE *f) {
  for (int i = 0; i < dtm_registry_count(); i++) {
    const char *name = dtm_registry_get(i)->name;
    fprintf(f, "      <xs:element name=\"%s\" type=\"effect-%s\"/>\n", name, name);
  }
}

/* Material values are checked by the reader (clearer messages than facets). */
static void material_properties(FILE *f) {
  int n;
  const dtm_property *const *props = dtm_registry_properties(&n);
  for (int i = 0; i < n; i++) {
    fprintf(f, "    <xs:attribute name=\"%s\" type=\"xs:double\">\n", props[i]->name);
    documentation(f, "      ", props[i]->help, props[i]->unit);
    fprintf(f, "    </xs:attribute>\n");
  }
}

static int expand(FILE *in, FILE *out) {
  char line[4096];
  while (fgets(line, sizeof line, in)) {
    if (strstr(line, "@MATERIAL_PROPERTIES@"))
      material_properties(out);
    else if (strstr(line, "@EFFECT_TYPES@"))
      effect_types(out);
    else if (strstr(line, "@EFFECT_ELEMENTS@"))
      effect_elements(out);
    else
      fputs(line, out);
  }
  return ferror(in) || ferror(out);
}

int main(int argc, char **argv) {
  if (argc != 3) return fprintf(stderr, "usage: dtm_schema_gen TEMPLATE OUTPUT\n"), 2;
  if (dtm_registry_check_all()) return fprintf(stderr, "dtm_schema_gen: %s\n", dtm_error_message()), 1;
  FILE *in = fopen(argv[1], "r"), *out = fopen(argv[2], "w");
  if (!in || !out) return fprintf(stderr, "dtm_schema_gen: cannot open %s or %s\n", argv[1], argv[2]), 1;
  int bad = expand(in, out);
  fclose(in);
  bad |= fclose(out) != 0;
  if (bad) return fprintf(stderr, "dtm_schema_gen: cannot write %s\n", argv[2]), remove(argv[2]), 1;
  return 0;
}
