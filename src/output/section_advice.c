/* Warnings about a model's sections and what they leave out, for the
 * summary and the report:
 * - groups below the analysed dimension without a section whose elements
 *   extraction left out (dtm_gmsh_left_out): which, how many, and the
 *   section that would include them;
 * - a rotary-inertia scale above DTM_ROTARY_WARN: the step with physical
 *   inertia beside the one used, and the bending waves the scaling slows.
 *   Rayleigh's rotary-inertia term gives a bending wave of wavenumber k the
 *   speed c0 k / sqrt(1 + s r^2 k^2) with the inertia scaled by s (r the
 *   radius of gyration: t/sqrt(12) for a shell, sqrt(I/A) for a beam), so
 *   waves shorter than 2 pi r sqrt(s) travel at less than 1/sqrt(2) of
 *   their speed; longer ones, and membrane and axial waves, keep it. At
 *   s = 100 that length is 18 thicknesses of a shell, where the shell's own
 *   bending theory is still sound: hence the factor (docs/sections.md);
 * - a thickness, area or profile larger than the model itself (a typo such
 *   as thickness="1e30"): it weighs the mass and stiffness at the nodes
 *   the section shares, though it cancels from its own elements' steps. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "output-impl.h"

#define PI 3.14159265358979323846

static void add(dtm_warnings *w, const char *text) {
  if (w->n < DTM_WARN_MAX) snprintf(w->text[w->n++], sizeof w->text[0], "%s", text);
}

/* item after sep at the end of buf, or "..." once when it does not fit. */
static void append(char *buf, size_t len, const char *sep, const char *item) {
  size_t used = strlen(buf), need = strlen(sep) + strlen(item) + 4;
  if (used >= 3 && !strcmp(buf + used - 3, "...")) return;
  snprintf(buf + used, len - used, "%s%s", used ? sep : "", used + need < len ? item : "...");
}

/* The groups of dimension d left out: "a (n), b (n)" into list, "a b" into
 * refs (as a section names them). */
static void left_groups(const dtm_mesh *m, int d, char *list, size_t ll, char *refs, size_t rl) {
  char ref[72], one[96];
  list[0] = refs[0] = '\0';
  for (int i = 0; i < m->nleft; i++) {
    const dtm_left_out *g = &m->left[i];
    if (g->dim != d) continue;
    if (g->name[0])
      snprintf(ref, sizeof ref, "%s", g->name);
    else
      snprintf(ref, sizeof ref, "%d", g->tag);
    if (g->tag < 0)
      snprintf(one, sizeof one, "in no physical group (%zu)", g->elements);
    else
      snprintf(one, sizeof one, "%s (%zu)", ref, g->elements);
    append(list, ll, ", ", one);
    if (g->tag >= 0) append(refs, rl, " ", ref);
  }
}

static void left_out_warning(const dtm_mesh *m, dtm_warnings *w) {
  for (int d = 1; d <= 2; d++) {
    char list[160], refs[80], text[400];
    size_t n = m->nleft_dim[d];
    if (!n) continue;
    left_groups(m, d, list, sizeof list, refs, sizeof refs);
    snprintf(text, sizeof text,
             "%zu %s elements left out (not analysed): the %s groups %s have no section and reach nodes no analysed "
             "element has; to include them, give them a %s section (<section groups=\"%s\" kind=\"%s\" %s=\"...\"/>)",
             n, d == 1 ? "line" : "surface", d == 1 ? "curve" : "surface", list,
             d == 1 ? "truss or beam" : "membrane or shell", refs, d == 1 ? "truss" : "membrane",
             d == 1 ? "area" : "thickness");
    add(w, text);
  }
}

/* "section (kind) on a b" or "section (kind, the default)" for messages. */
static const char *section_name(const dtm_section *sec, char *buf, size_t len) {
  char groups[160] = "";
  for (int g = 0; g < sec->ngroups; g++) append(groups, sizeof groups, " ", sec->groups[g]);
  if (sec->ngroups)
    snprintf(buf, len, "section (%s) on %s", dtm_section_kind_name(sec->kind), groups);
  else
    snprintf(buf, len, "section (%s, the default)", dtm_section_kind_name(sec->kind));
  return buf;
}

/* Radius of gyration of a shell's or beam's profile, m. */
static double gyration(const dtm_section *sec) {
  if (sec->kind == DTM_SECTION_SHELL) return sec->thickness / sqrt(12.0);
  return sqrt(fmax(sec->iy, sec->iz) / sec->area);
}

static void rotary_warning(const dtm_section *sec, const dtm_section_stats *st, const char *units, dtm_warnings *w) {
  char name[200], text[400];
  const char *L = dtm_units_name(units, DTM_UNIT_LENGTH);
  if (sec->rotary != DTM_ROTARY_SCALED_INERTIA || !(st->scale_max > DTM_ROTARY_WARN)) return;
  snprintf(text, sizeof text,
           "%s: rotary inertia scaled by up to %.3g (above %g): the step rests on it; with physical rotary inertia it "
           "is %.4e s (element %zu). Bending waves shorter than %.3g %s (2 pi r sqrt(scale), r = %.3g %s the radius of "
           "gyration) travel below 0.71 of their speed; longer ones, membrane and axial waves keep it",
           section_name(sec, name, sizeof name), st->scale_max, DTM_ROTARY_WARN, st->dt_physical_min,
           st->physical_element, 2 * PI * gyration(sec) * sqrt(st->scale_max), L, gyration(sec), L);
  add(w, text);
}

/* What of section sec exceeds the model's extent L ("" when nothing). */
static void oversize(const dtm_section *sec, double L, const char *units, char *what, size_t len) {
  int k = sec->kind;
  const char *u = dtm_units_name(units, DTM_UNIT_LENGTH);
  double rg = sec->area > 0 ? sqrt(fmax(sec->iy, sec->iz) / sec->area) : 0;
  what[0] = '\0';
  if ((k == DTM_SECTION_MEMBRANE || k == DTM_SECTION_SHELL) && sec->thickness > L)
    snprintf(what, len, "thickness %.4g %s", sec->thickness, u);
  else if (sqrt(sec->area) > L)
    snprintf(what, len, "area %.4g %s (a profile %.4g %s across)", sec->area, dtm_units_name(units, DTM_UNIT_AREA),
             sqrt(sec->area), u);
  else if (rg > L)
    snprintf(what, len, "radius of gyration %.4g %s (of its second moments of area over its area)", rg, u);
}

/* A thickness, area (its square root) or radius of gyration above the
 * model's own extent L. */
static void size_warning(const dtm_section *sec, double L, const char *units, dtm_warnings *w) {
  char name[200], what[96], text[400];
  oversize(sec, L, units, what, sizeof what);
  if (!what[0]) return;
  snprintf(
      text, sizeof text,
      "%s: %s exceeds the model's own extent (%.4g %s, the largest side of its bounding box): a typo? It weighs the "
      "mass and stiffness its elements bring to the nodes they share",
      section_name(sec, name, sizeof name), what, L, dtm_units_name(units, DTM_UNIT_LENGTH));
  add(w, text);
}

void dtm_output_section_warnings(const dtm_analysis *a, dtm_warnings *w) {
  const dtm_scene *s = dtm_analysis_scene(a);
  const dtm_mesh *m = dtm_analysis_mesh(a);
  double ext[3] = {0, 0, 0};
  left_out_warning(m, w);
  dtm_section_stats *st = s->nsections ? calloc((size_t)s->nsections, sizeof *st) : NULL;
  if (st && dtm_mesh_extent(m, ext)) dtm_error_clear(), free(st), st = NULL;
  if (st) dtm_analysis_sections(a, st);
  for (int i = 0; st && i < s->nsections; i++) {
    rotary_warning(&s->sections[i], &st[i], s->units, w);
    size_warning(&s->sections[i], fmax(ext[0], fmax(ext[1], ext[2])), s->units, w);
  }
  free(st);
}
