/* Reading one <section> element of a scene: the element kind of its
 * physical groups (solid, plane-strain, plane-stress, membrane, truss,
 * shell, beam), the thickness, cross-section area or beam profile that kind
 * needs (area, iy, iz, j; or radius; or width and height, with an
 * orientation), the rotary-inertia convention and shear factor of shells
 * and beams, and whether it is the default for elements of the analysed
 * dimension in no sectioned group.
 * A kind that needs a thickness or area without one, a value that is not a
 * finite number > 0, a value the kind does not use, a group listed twice
 * and a second default are errors naming the scene file and line. Whether
 * the groups exist and hold elements of the kind's dimension is checked
 * against the mesh when it is read (src/analysis/run.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/units.h"
#include "scene-impl.h"
#include "structural.h"

#define KIND_LIST "solid, plane-strain, plane-stress, membrane, truss, shell, beam"

static const char *const kind_names[] = DTM_SECTION_NAMES;

static int read_kind(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  char *raw;
  DTM_CHECK(dtm_scene_attr(n, "kind", &raw));
  if (!raw) return DTM_SCENE_ERR(s, n, "<section> has no kind (" KIND_LIST ")");
  sec->kind = -1;
  for (int k = 0; kind_names[k]; k++)
    if (!strcmp(raw, kind_names[k])) sec->kind = k;
  int rc = sec->kind < 0 ? DTM_SCENE_ERR(s, n, "<section kind=\"%s\">: unknown kind (" KIND_LIST ")", raw) : DTM_OK;
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

/* The beam profile: area, iy, iz and j given together, or radius, or
 * width and height (the section's y and z sides). */
static int beam_profile(const dtm_scene *s, const xmlNode *n, dtm_section *sec, const double *r, const double *bh) {
  int general = sec->area > 0 || sec->iy > 0 || sec->iz > 0 || sec->jt > 0, circle = *r > 0,
      rect = bh[0] > 0 || bh[1] > 0;
  if (general + circle + rect != 1)
    return DTM_SCENE_ERR(s, n,
                         "<section kind=\"beam\"> needs one profile: area, iy, iz and j; or radius; "
                         "or width and height");
  if (general && !(sec->area > 0 && sec->iy > 0 && sec->iz > 0 && sec->jt > 0))
    return DTM_SCENE_ERR(s, n, "<section kind=\"beam\">: area, iy, iz and j go together (%s, %s)",
                         dtm_units_name(s->units, DTM_UNIT_AREA), dtm_units_name(s->units, DTM_UNIT_MOMENT));
  if (rect && !(bh[0] > 0 && bh[1] > 0))
    return DTM_SCENE_ERR(s, n, "<section kind=\"beam\">: width and height go together (%s)",
                         dtm_units_name(s->units, DTM_UNIT_LENGTH));
  dtm_beam_section b = {0};
  if (circle) dtm_beam_section_circle(*r, &b);
  if (rect) dtm_beam_section_rect(bh[0], bh[1], &b);
  if (!general) sec->area = b.area, sec->iy = b.iy, sec->iz = b.iz, sec->jt = b.jt;
  return DTM_OK;
}

/* The thickness or area the kind needs, and none it does not use. */
static int check_measures(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  const char *kind = dtm_section_kind_name(sec->kind);
  int truss = sec->kind == DTM_SECTION_TRUSS, solid = sec->kind == DTM_SECTION_SOLID;
  int beam = sec->kind == DTM_SECTION_BEAM, shell = sec->kind == DTM_SECTION_SHELL;
  if (truss && !(sec->area > 0))
    return DTM_SCENE_ERR(s, n, "<section kind=\"truss\"> needs area=\"...\" (cross-section, %s)",
                         dtm_units_name(s->units, DTM_UNIT_AREA));
  if ((sec->kind == DTM_SECTION_MEMBRANE || shell) && !(sec->thickness > 0))
    return DTM_SCENE_ERR(s, n, "<section kind=\"%s\"> needs thickness=\"...\" (%s)", kind,
                         dtm_units_name(s->units, DTM_UNIT_LENGTH));
  if ((truss || solid || beam) && sec->thickness > 0)
    return DTM_SCENE_ERR(s, n, "<section kind=\"%s\"> takes no thickness", kind);
  if (!truss && !beam && sec->area > 0) return DTM_SCENE_ERR(s, n, "<section kind=\"%s\"> takes no area", kind);
  if (!truss && !solid && !beam && !(sec->thickness > 0)) sec->thickness = 1.0; /* plane kinds: per metre */
  return DTM_OK;
}

/* Attributes only some kinds take: present on another kind is an error. */
static int refuse_unused(const dtm_scene *s, const xmlNode *n, const dtm_section *sec) {
  static const char *const beam_only[] = {"iy", "iz", "j", "radius", "width", "height", "orientation", NULL};
  static const char *const structural[] = {"rotary", "shear-factor", NULL};
  int beam = sec->kind == DTM_SECTION_BEAM, rot = dtm_section_has_rotations(sec->kind);
  for (int pass = 0; pass < 2; pass++) {
    const char *const *keys = pass ? structural : beam_only;
    if (pass ? rot : beam) continue;
    for (int i = 0; keys[i]; i++)
      if (xmlHasProp(n, (const xmlChar *)keys[i]))
        return DTM_SCENE_ERR(s, n, "<section kind=\"%s\"> takes no %s (%s)", dtm_section_kind_name(sec->kind), keys[i],
                             pass ? "shells and beams only" : "beams only");
  }
  return DTM_OK;
}

/* rotary="scaled" (default) or "physical". */
static int read_rotary(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  char *raw;
  DTM_CHECK(dtm_scene_attr(n, "rotary", &raw));
  sec->rotary = DTM_ROTARY_SCALED_INERTIA;
  if (!raw) return DTM_OK;
  int rc = DTM_OK;
  if (!strcmp(raw, "physical"))
    sec->rotary = DTM_ROTARY_PHYSICAL_INERTIA;
  else if (strcmp(raw, "scaled"))
    rc = DTM_SCENE_ERR(s, n, "<section>: rotary=\"%s\" is not scaled or physical", raw);
  free(raw);
  return rc;
}

/* orientation="x y z": three finite numbers, not all zero. */
static int read_orientation(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  char *raw, **items = NULL;
  int count = 0, rc = DTM_OK;
  DTM_CHECK(dtm_scene_attr(n, "orientation", &raw));
  if (!raw) return DTM_OK;
  rc = dtm_scene_split(raw, &count, &items);
  int bad = rc || count != 3;
  for (int i = 0; !bad && i < 3; i++)
    bad = dtm_scene_parse_double(items[i], &sec->orient[i]) || !isfinite(sec->orient[i]);
  if (!bad) bad = sec->orient[0] == 0 && sec->orient[1] == 0 && sec->orient[2] == 0;
  if (bad && rc == DTM_OK)
    rc = DTM_SCENE_ERR(s, n, "<section>: orientation=\"%s\" is not three finite numbers, not all 0", raw);
  dtm_scene_free_strings(count, items);
  free(raw);
  return rc;
}

/* Everything shells and beams add: profile, orientation, convention, k. */
static int read_structural(const dtm_scene *s, const xmlNode *n, dtm_section *sec) {
  DTM_CHECK(refuse_unused(s, n, sec));
  if (!dtm_section_has_rotations(sec->kind)) return DTM_OK;
  DTM_CHECK(read_rotary(s, n, sec));
  DTM_CHECK(read_measure(s, n, "shear-factor", &sec->shear));
  if (sec->kind == DTM_SECTION_SHELL) return DTM_OK;
  double r, bh[2];
  DTM_CHECK(read_measure(s, n, "iy", &sec->iy));
  DTM_CHECK(read_measure(s, n, "iz", &sec->iz));
  DTM_CHECK(read_measure(s, n, "j", &sec->jt));
  DTM_CHECK(read_measure(s, n, "radius", &r));
  DTM_CHECK(read_measure(s, n, "width", &bh[0]));
  DTM_CHECK(read_measure(s, n, "height", &bh[1]));
  DTM_CHECK(beam_profile(s, n, sec, &r, bh));
  return read_orientation(s, n, sec);
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
  DTM_CHECK(read_structural(s, n, sec));
  DTM_CHECK(check_measures(s, n, sec));
  DTM_CHECK(read_flag(s, n, sec));
  DTM_CHECK(read_groups(s, n, sec));
  return check_unique(s, n, sec);
}
