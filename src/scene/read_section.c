/* Reading one <section> element of a scene: the element kind of its
 * physical groups (solid, plane-strain, plane-stress, membrane, truss), the
 * thickness or cross-section area that kind needs, and whether it is the
 * default for elements of the analysed dimension in no sectioned group.
 * A kind that needs a thickness or area without one, a value that is not a
 * finite number > 0, a value the kind does not use, a group listed twice
 * and a second default are errors naming the scene file and line. Whether
 * the groups exist and hold elements of the kind's dimension is checked
 * against the mesh when it is read (src/analysis/run.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene-impl.h"

static const char *const kind_names[] = DTM_SECTION_NAMES;

static int read_kind(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  char *raw;
  DTM_CHECK(dtm_scene_attr(n, "kind", &raw));
  if (!raw) return DTM_SCENE_ERR(s, n, "<section> has no kind (solid, plane-strain, plane-stress, membrane, truss)");
  sec->kind = -1;
  for (int k = 0; kind_names[k]; k++)
    if (!strcmp(raw, kind_names[k])) sec->kind = k;
  int rc = sec->kind < 0 ? DTM_SCENE_ERR(s, n,
                                         "<section kind=\"%s\">: unknown kind (solid, plane-strain, plane-stress, "
                                         "membrane, truss)",
                                         raw)
                         : DTM_OK;
  free(raw);
  return rc;
}

/* Attribute key as a finite number > 0 into *v; 0 when absent. */
static int read_measure(const dtm_scene *s, const xmlNode *n, const char *key, double *v) {
  char *raw;
  *v = 0;
  DTM_CHECK(dtm_scene_attr(n, key, &raw));
  if (!raw) return DTM_OK;
  int rc = dtm_scene_parse_double(raw, v) || !isfinite(*v) || !(*v > 0)
               ? DTM_SCENE_ERR(s, n, "<section>: %s=\"%s\" is not a finite number > 0", key, raw)
               : DTM_OK;
  free(raw);
  return rc;
}

/* The thickness or area the kind needs, and none it does not use. */
static int check_measures(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  const char *kind = dtm_section_kind_name(sec->kind);
  int truss = sec->kind == DTM_SECTION_TRUSS, solid = sec->kind == DTM_SECTION_SOLID;
  if (truss && !(sec->area > 0))
    return DTM_SCENE_ERR(s, n, "<section kind=\"truss\"> needs area=\"...\" (cross-section, m^2)");
  if (sec->kind == DTM_SECTION_MEMBRANE && !(sec->thickness > 0))
    return DTM_SCENE_ERR(s, n, "<section kind=\"membrane\"> needs thickness=\"...\" (m)");
  if ((truss || solid) && sec->thickness > 0)
    return DTM_SCENE_ERR(s, n, "<section kind=\"%s\"> takes no thickness", kind);
  if (!truss && sec->area > 0) return DTM_SCENE_ERR(s, n, "<section kind=\"%s\"> takes no area", kind);
  if (!truss && !solid && !(sec->thickness > 0)) sec->thickness = 1.0; /* plane kinds: per metre */
  return DTM_OK;
}

static int read_flag(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  char *raw;
  DTM_CHECK(dtm_scene_attr(n, "default", &raw));
  if (!raw) return DTM_OK;
  int rc = DTM_OK;
  if (!strcmp(raw, "true") || !strcmp(raw, "1"))
    sec->is_default = 1;
  else if (strcmp(raw, "false") && strcmp(raw, "0"))
    rc = DTM_SCENE_ERR(s, n, "<section>: default=\"%s\" is not true or false", raw);
  free(raw);
  return rc;
}

static int read_groups(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  char *raw;
  DTM_CHECK(dtm_scene_attr(n, "groups", &raw));
  int rc = raw ? dtm_scene_split(raw, &sec->ngroups, &sec->groups) : DTM_OK;
  free(raw);
  if (rc) return rc;
  if (!sec->ngroups && !sec->is_default)
    return DTM_SCENE_ERR(s, n, "<section kind=\"%s\"> names no physical group (groups=\"...\" or default=\"true\")",
                         dtm_section_kind_name(sec->kind));
  return DTM_OK;
}

/* Section sec (the last read) against those before it: a group in two
 * sections (or twice in one), two defaults. */
static int check_unique(const dtm_scene *s, const xmlNode *n, const dtm_section *sec) {
  for (int i = 0; i < s->nsections; i++) {
    const dtm_section *o = &s->sections[i];
    if (o != sec && o->is_default && sec->is_default)
      return DTM_SCENE_ERR(s, n, "a second default section (the first is at line %d)", o->line);
    for (int g = 0; g < sec->ngroups; g++)
      for (int h = 0; h < o->ngroups; h++)
        if ((o != sec || h < g) && !strcmp(sec->groups[g], o->groups[h]))
          return DTM_SCENE_ERR(s, n, "group '%s' already has a section (line %d); a group can have only one",
                               sec->groups[g], o->line);
  }
  return DTM_OK;
}

int dtm_scene_read_section(dtm_scene *s, const xmlNode *n) {
  dtm_section *sec = &s->sections[s->nsections++];
  sec->file = s->path;
  sec->line = dtm_scene_line(n);
  DTM_CHECK(read_kind(s, n, sec));
  DTM_CHECK(read_measure(s, n, "thickness", &sec->thickness));
  DTM_CHECK(read_measure(s, n, "area", &sec->area));
  DTM_CHECK(check_measures(s, n, sec));
  DTM_CHECK(read_flag(s, n, sec));
  DTM_CHECK(read_groups(s, n, sec));
  return check_unique(s, n, sec);
}
