/* Length units on import: every model dtmap analyses is in the scene's
 * length unit (metres, or millimetres for units="mm-t-s"), whatever unit its
 * file was drawn in.
 *  - STEP and IGES carry their unit. OpenCASCADE converts it when Gmsh's
 *    Geometry.OCCTargetUnit names the unit wanted ("M" or "MM"; it sets
 *    OpenCASCADE's xstep.cascade.unit, whose default is millimetres, so
 *    without it a STEP in metres came in 1000x too large). An IGES file
 *    cannot be given a target unit in Gmsh 4.8.4 before a STEP was read:
 *    it comes in the unit in force (mm) and Geometry.OCCScaling scales it. Gmsh does not say
 *    which unit the file had, so dtmap reads it itself for the summary and
 *    the report: in a STEP file the first LENGTH_UNIT entity, an SI_UNIT
 *    with its prefix (SI_UNIT(.MILLI.,.METRE.)) or a CONVERSION_BASED_UNIT
 *    by name ('INCH'); in an IGES file the global section's unit flag
 *    (field 14) and unit name (field 15).
 *  - A BREP carries none; <geometry unit> scales it on import with
 *    Geometry.OCCScaling. On a STEP or IGES, a <geometry unit> other than
 *    the one the file declares is an error naming both (a scene that
 *    silently overrode the file gave a model 1000x off); the same unit is
 *    allowed. A named unit dtmap does not know (a CONVERSION_BASED_UNIT
 *    'TEN MM') is read from its LENGTH_MEASURE_WITH_UNIT: "10 mm".
 *  - A .msh carries none; <mesh unit> scales its node coordinates in the
 *    Gmsh model after reading, so that what dtmap extracts, remeshes and
 *    writes is in the scene's unit.
 * A .msh without <mesh unit> is read as it is, and not mentioned.
 * The options are set back after the import: a later .geo that merges a
 * STEP keeps Gmsh's default. What was found and applied is kept for the
 * summary and the report (dtm_gmsh_import_units). */
#define _GNU_SOURCE /* memmem */
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "gmsh-impl.h"

static dtm_import_units last; /* the current model's import */

void dtm_gmsh_import_units(dtm_import_units *out) { *out = last; }

static const char *extension(const char *file) {
  const char *slash = strrchr(file, '/');
  const char *dot = strrchr(slash ? slash + 1 : file, '.');
  return dot ? dot : "";
}

static int is_step(const char *f) { return !strcasecmp(extension(f), ".step") || !strcasecmp(extension(f), ".stp"); }
static int is_iges(const char *f) { return !strcasecmp(extension(f), ".iges") || !strcasecmp(extension(f), ".igs"); }
static int is_brep(const char *f) { return !strcasecmp(extension(f), ".brep"); }
static int is_msh(const char *f) { return !strcasecmp(extension(f), ".msh"); }

/* The whole file, NUL-terminated (caller frees), or NULL. */
static char *slurp(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  char *buf = NULL;
  long n = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
  if (n >= 0 && fseek(f, 0, SEEK_SET) == 0) buf = malloc((size_t)n + 1);
  if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) free(buf), buf = NULL;
  fclose(f);
  if (buf) buf[n] = '\0', *len = (size_t)n;
  return buf;
}

static const struct {
  const char *name; /* an SI prefix as STEP writes it, or a unit's name */
  double metres;    /* metres per unit */
  const char *shown;
} step_prefixes[] = {{".MILLI.", 1e-3, "mm"}, {".CENTI.", 1e-2, "cm"}, {".DECI.", 0.1, "dm"},
                     {".KILO.", 1e3, "km"},   {".MICRO.", 1e-6, "um"}, {".NANO.", 1e-9, "nm"}},
  named_units[] = {{"INCH", 0.0254, "in"},     {"FOOT", 0.3048, "ft"},       {"MILLIMETRE", 1e-3, "mm"},
                   {"MILLIMETER", 1e-3, "mm"}, {"CENTIMETRE", 1e-2, "cm"},   {"CENTIMETER", 1e-2, "cm"},
                   {"METRE", 1.0, "m"},        {"METER", 1.0, "m"},          {"MIL", 2.54e-5, "mil"},
                   {"MILE", 1609.344, "mi"},   {"MICROINCH", 2.54e-8, "uin"}};

/* The text [*b, *e) of STEP entity #id in text[len]; 0 when there is none. */
static int step_entity(const char *text, size_t len, long id, const char **b, const char **e) {
  char key[32];
  int k = snprintf(key, sizeof key, "#%ld", id);
  for (const char *p = memmem(text, len, key, (size_t)k); p;
       p = memmem(p + 1, len - (size_t)(p + 1 - text), key, (size_t)k)) {
    const char *q = p + k;
    while (q < text + len && (*q == ' ' || *q == '\t')) q++;
    if (q >= text + len || *q != '=' || (p[k] >= '0' && p[k] <= '9')) continue;
    *b = p, *e = q;
    while (*e < text + len && **e != ';') (*e)++;
    return 1;
  }
  return 0;
}

static int step_entity_unit(const char *text, size_t len, const char *b, const char *e, dtm_import_units *u, int depth);

/* A CONVERSION_BASED_UNIT of a name dtmap does not know ('TEN MM'): its
 * LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(v), #ref) times the unit #ref,
 * shown as "v unit" ("10 mm"). */
static int step_conversion(const char *text, size_t len, const char *cb, dtm_import_units *u, int depth) {
  const char *q = strchr(cb, '\''), *q2 = q ? strchr(q + 1, '\'') : NULL, *h = q2 ? strchr(q2, '#') : NULL, *b, *e;
  if (!h || depth > 2 || !step_entity(text, len, strtol(h + 1, NULL, 10), &b, &e)) return 0;
  char ent[512];
  snprintf(ent, sizeof ent, "%.*s", (int)(e - b < 511 ? e - b : 511), b);
  const char *lm = strstr(ent, "LENGTH_MEASURE("), *r = lm ? strchr(lm + 15, ')') : NULL;
  const char *ref = r ? strchr(r, '#') : NULL;
  double v = lm ? strtod(lm + 15, NULL) : NAN;
  dtm_import_units base = *u;
  if (!ref || !(v > 0) || !step_entity(text, len, strtol(ref + 1, NULL, 10), &b, &e) ||
      !step_entity_unit(text, len, b, e, &base, depth + 1) || !(base.found_m > 0))
    return 0;
  char shown[64];
  snprintf(shown, sizeof shown, "%.4g %s", v, base.found);
  snprintf(u->found, sizeof u->found, "%.*s", (int)sizeof u->found - 1, shown); /* "10 mm"; cut past 7 */
  u->found_m = v * base.found_m;
  return 1;
}

/* The unit of one STEP entity text [b, e) of text[len] that holds
 * LENGTH_UNIT. */
static int step_entity_unit(const char *text, size_t len, const char *b, const char *e, dtm_import_units *u,
                            int depth) {
  char ent[512];
  snprintf(ent, sizeof ent, "%.*s", (int)(e - b < 511 ? e - b : 511), b);
  const char *si = strstr(ent, "SI_UNIT("), *cb = strstr(ent, "CONVERSION_BASED_UNIT(");
  if (si && strstr(si, ".METRE.")) {
    snprintf(u->found, sizeof u->found, "m"), u->found_m = 1.0;
    for (size_t i = 0; i < sizeof step_prefixes / sizeof *step_prefixes; i++)
      if (strstr(si, step_prefixes[i].name) && strstr(si, step_prefixes[i].name) < strstr(si, ".METRE."))
        snprintf(u->found, sizeof u->found, "%s", step_prefixes[i].shown), u->found_m = step_prefixes[i].metres;
    return 1;
  }
  const char *q = cb ? strchr(cb, '\'') : NULL, *q2 = q ? strchr(q + 1, '\'') : NULL;
  for (size_t i = 0; q2 && i < sizeof named_units / sizeof *named_units; i++)
    if ((size_t)(q2 - q - 1) == strlen(named_units[i].name) && !strncasecmp(q + 1, named_units[i].name, q2 - q - 1)) {
      snprintf(u->found, sizeof u->found, "%s", named_units[i].shown), u->found_m = named_units[i].metres;
      return 1;
    }
  return cb ? step_conversion(text, len, cb, u, depth) : 0;
}

static int ident_char(char c) { return c == '_' || (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }

/* The unit of a STEP text: its LENGTH_UNIT entities, a named
 * (CONVERSION_BASED_UNIT, 'INCH') one first, since it refers to an SI
 * unit entity of its own (LENGTH_MEASURE_WITH_UNIT(25.4, mm)); else the
 * first SI one. */
static void step_unit(const char *text, size_t len, dtm_import_units *u) {
  dtm_import_units first = *u;
  int have = 0;
  for (const char *p = strstr(text, "LENGTH_UNIT"); p; p = strstr(p + 1, "LENGTH_UNIT")) {
    if ((p > text && ident_char(p[-1])) || ident_char(p[11])) continue;
    const char *b = p, *e = p;
    while (b > text && b[-1] != ';') b--;
    while (e < text + len && *e != ';') e++;
    dtm_import_units one = *u;
    if (!step_entity_unit(text, len, b, e, &one, 0)) continue;
    if (memmem(b, (size_t)(e - b), "CONVERSION_BASED_UNIT", 21)) {
      *u = one;
      return;
    }
    if (!have++) first = one;
  }
  *u = first;
}

/* One parameter of an IGES global section at *p (Hollerith strings
 * "nH..." unwrapped) into out; *p moves past its delimiter. */
static void iges_field(const char **p, char delim, char rec, char *out, size_t len) {
  const char *s = *p;
  size_t n = 0;
  char *end;
  long h = strtol(s, &end, 10);
  if (end == s || (*end != 'H' && *end != 'h')) h = 0;
  if (h > 0) {
    for (long i = 0; i < h && end[1 + i]; i++)
      if (n + 1 < len) out[n++] = end[1 + i];
    s = end + 1 + strnlen(end + 1, (size_t)h);
  }
  while (*s && *s != delim && *s != rec) {
    if (!h && n + 1 < len && *s != ' ') out[n++] = *s;
    s++;
  }
  out[n] = '\0';
  *p = *s ? s + 1 : s;
}

/* IGES unit flags 1-11 (field 14), metres per unit. */
static const struct {
  double metres;
  const char *shown;
} iges_flags[12] = {{0, ""},    {0.0254, "in"}, {1e-3, "mm"},     {0, ""},      {0.3048, "ft"}, {1609.344, "mi"},
                    {1.0, "m"}, {1e3, "km"},    {2.54e-5, "mil"}, {1e-6, "um"}, {1e-2, "cm"},   {2.54e-8, "uin"}};

/* The unit of an IGES text: fields 14 and 15 of the global section (the
 * lines with 'G' in column 73). */
static void iges_unit(const char *text, dtm_import_units *u) {
  size_t cap = 4096, n = 0;
  char *g = malloc(cap), field[80];
  for (const char *l = text; g && *l;) {
    const char *nl = strchr(l, '\n');
    size_t ll = nl ? (size_t)(nl - l) : strlen(l);
    if (ll >= 73 && l[72] == 'G' && n + 72 < cap) memcpy(g + n, l, 72), n += 72;
    l = nl ? nl + 1 : l + ll;
  }
  if (!g || !n) {
    free(g);
    return;
  }
  g[n] = '\0';
  const char *p = g;
  char delim = ',', rec = ';';
  if (!strncmp(p, "1H", 2)) delim = p[2]; /* field 1: the parameter delimiter */
  iges_field(&p, delim, rec, field, sizeof field);
  iges_field(&p, delim, rec, field, sizeof field);
  if (field[0]) rec = field[0];
  int flag = 0;
  for (int i = 3; i <= 15; i++) {
    iges_field(&p, delim, rec, field, sizeof field);
    if (i == 14) flag = atoi(field);
  }
  if (flag >= 1 && flag <= 11 && flag != 3)
    snprintf(u->found, sizeof u->found, "%s", iges_flags[flag].shown), u->found_m = iges_flags[flag].metres;
  for (size_t i = 0; flag == 3 && i < sizeof named_units / sizeof *named_units; i++)
    if (!strcasecmp(field, named_units[i].name) || !strcasecmp(field, named_units[i].shown))
      snprintf(u->found, sizeof u->found, "%s", named_units[i].shown), u->found_m = named_units[i].metres;
  free(g);
}

/* What the file says of its unit (STEP, IGES), into u->found. */
static void file_unit(const char *path, dtm_import_units *u) {
  size_t len = 0;
  char *text = slurp(path, &len);
  if (!text) return;
  if (is_step(path)) step_unit(text, len, u);
  if (is_iges(path)) iges_unit(text, u);
  free(text);
}

static double scene_length(const dtm_scene *s) { return s->unit_length > 0 ? s->unit_length : 1.0; }

static char saved_target[32]; /* Geometry.OCCTargetUnit before the import */

/* Metres per unit of the unit OpenCASCADE converts to now (its
 * xstep.cascade.unit through Gmsh's Geometry.OCCTargetUnit; "": its
 * default, millimetres). */
static double occ_unit_metres(void) {
  static const struct {
    const char *name;
    double metres;
  } occ[] = {{"M", 1.0}, {"MM", 1e-3}, {"CM", 1e-2}, {"KM", 1e3}, {"UM", 1e-6}, {"INCH", 0.0254}, {"FT", 0.3048}};
  char *t = NULL;
  int ierr = 0;
  double m = 1e-3;
  gmshOptionGetString("Geometry.OCCTargetUnit", &t, &ierr);
  for (size_t i = 0; t && i < sizeof occ / sizeof *occ; i++)
    if (!strcasecmp(t, occ[i].name)) m = occ[i].metres;
  gmshFree(t);
  return m;
}

/* A STEP: OpenCASCADE converts it to the scene's unit (the option set
 * back after). The unit it held is kept. */
static int step_target(double L) {
  char *old = NULL;
  int ierr = 0;
  gmshOptionGetString("Geometry.OCCTargetUnit", &old, &ierr);
  snprintf(saved_target, sizeof saved_target, "%s", old && old[0] ? old : "MM");
  gmshFree(old);
  gmshOptionSetString("Geometry.OCCTargetUnit", L == 1.0 ? "M" : "MM", &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot set Geometry.OCCTargetUnit");
  return DTM_OK;
}

int dtm_gmsh_units_before(const dtm_scene *s, const char *path) {
  int ierr = 0;
  double L = scene_length(s);
  memset(&last, 0, sizeof last);
  last.factor = 1.0;
  snprintf(last.system, sizeof last.system, "%s", L == 1.0 ? "m" : "mm");
  if (s->source_unit) snprintf(last.given, sizeof last.given, "%s", s->source_unit);
  int cad = is_step(path) || is_iges(path);
  if (cad) file_unit(path, &last);
  if (cad && s->source_unit && last.found_m > 0 && fabs(s->source_unit_m / last.found_m - 1.0) > 1e-9)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s:%d: <geometry unit=\"%s\"> contradicts the unit the file declares, %s: %s holds its "
                   "lengths in %s, and dtmap converts them itself; remove unit=\"%s\" (or, if the file's own "
                   "declaration is wrong, correct it in the file)",
                   s->path, s->source_line, s->source_unit, last.found, path, last.found, s->source_unit);
  if (!cad && !is_brep(path) && !(is_msh(path) && s->source_unit)) return DTM_OK; /* nothing to say */
  last.active = 1;
  double from = s->source_unit ? s->source_unit_m : cad && last.found_m > 0 ? last.found_m : L;
  last.factor = from / L;
  if (!cad) {
    gmshOptionSetNumber("Geometry.OCCScaling", is_brep(path) ? last.factor : 1.0, &ierr);
    return DTM_OK;
  }
  /* Gmsh 4.8.4 cannot set the target unit for an IGES file in a process
   * that has read no STEP ("Could not set OpenCASCADE target unit"):
   * OpenCASCADE converts it to the unit in force, and OCCScaling does the
   * rest. A given unit overrides the file's. */
  double occ = L;
  if (is_step(path))
    DTM_CHECK(step_target(L));
  else
    occ = occ_unit_metres();
  double scaling = !s->source_unit    ? occ / L
                   : last.found_m > 0 ? occ / L * s->source_unit_m / last.found_m
                                      : s->source_unit_m / L;
  gmshOptionSetNumber("Geometry.OCCScaling", scaling, &ierr);
  return DTM_OK;
}

/* Scale the node coordinates of the current model's mesh by f. */
static int scale_nodes(double f) {
  size_t *tags = NULL, nt = 0, nx = 0, np = 0;
  double *xyz = NULL, *par = NULL;
  int ierr = 0;
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshModelMeshGetNodes(&tags, &nt, &xyz, &nx, &par, &np, -1, -1, 0, 0, &ierr);
  for (size_t i = 0; !ierr && i < nt && 3 * i + 2 < nx; i++) {
    double x[3] = {f * xyz[3 * i], f * xyz[3 * i + 1], f * xyz[3 * i + 2]};
    gmshModelMeshSetNode(tags[i], x, 3, NULL, 0, &ierr);
  }
  gmshFree(tags), gmshFree(xyz), gmshFree(par);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot scale the mesh's nodes to the scene's length unit");
  return DTM_OK;
}

int dtm_gmsh_units_after(const char *path) {
  int ierr = 0;
  if (is_step(path)) gmshOptionSetString("Geometry.OCCTargetUnit", saved_target, &ierr);
  gmshOptionSetNumber("Geometry.OCCScaling", 1, &ierr);
  if (is_msh(path) && last.factor != 1.0) DTM_CHECK(scale_nodes(last.factor));
  return DTM_OK;
}

void dtm_gmsh_units_none(void) { memset(&last, 0, sizeof last), last.factor = 1.0; }
