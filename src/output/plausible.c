/* The numbers that show a unit error at a glance, as an explicit solver's
 * mass summary does: the model's mass (rho V summed over the analysed
 * elements, times a section's thickness or area; per unit thickness in 2D
 * without one), per physical group, and its bounding box; and the
 * plausibility warnings, in the scene's units (SI, or mm-t-s) with the SI
 * value beside:
 *  - a material whose density lies outside 1 to 25,000 kg/m^3 (aerogels to
 *    osmium), or whose dilatational wave speed c = sqrt(E (1 - nu) /
 *    ((1 + nu)(1 - 2 nu)) / rho) (sqrt(E/rho) without nu) lies outside
 *    10 m/s to 20 km/s (soft gels to diamond): E in MPa beside rho in
 *    kg/m^3 gives about 6 m/s for a steel;
 *  - a model larger than 1 km or smaller than 1 um;
 *  - a <meshing size> more than 10 times the model's extent (a size in mm
 *    on a model in metres: Gmsh then meshes with the geometry's own sizes).
 * Warnings, not refusals: foams and gels are real. */
#include <math.h>
#include <string.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/gmsh.h"
#include "dtmap/kernel.h"
#include "output-impl.h"

#define RHO_LO 1.0     /* kg/m^3 */
#define RHO_HI 25000.0 /* kg/m^3 */
#define C_LO 10.0      /* m/s */
#define C_HI 20000.0   /* m/s */
#define SIZE_LO 1e-6   /* m */
#define SIZE_HI 1000.0 /* m */
#define SIZE_OVER 10.0 /* a <meshing size> above this many times the model's extent looks like another unit */

static double unit_length(const dtm_scene *s) { return s->unit_length > 0 ? s->unit_length : 1.0; }
static double unit_mass(const dtm_scene *s) { return s->unit_mass > 0 ? s->unit_mass : 1.0; }
static int is_mm(const dtm_scene *s) { return unit_length(s) != 1.0; }

const char *dtm_unit_label(const dtm_scene *s, dtm_unit what) { return dtm_units_name(s->units, what); }

const char *dtm_output_unit(const dtm_analysis *a, dtm_unit what) {
  if (what == DTM_UNIT_MASS) return dtm_scene_mass_unit(dtm_analysis_scene(a), dtm_analysis_mesh(a)->dim);
  return dtm_units_name(dtm_analysis_scene(a)->units, what);
}

/* rho V of element e of block b (0 without a density): rho, the density
 * of each material (NaN without one), and sf, the factor of each section
 * (thickness or area), looked up once for the whole mesh; its measure from
 * the analysis (vol, may be NULL: computed here). */
static double element_mass(const dtm_mesh *m, const dtm_block *b, size_t e, const double *rho, const double *sf,
                           const double *vol) {
  int mi = b->mat[e];
  if (mi < 0 || isnan(rho[mi])) return 0.0;
  double x[DTM_MAX_NODES * 3], v;
  if (vol)
    v = *vol;
  else
    dtm_mesh_gather_one(m, b, e, x), v = fabs(dtm_elem_measure(b->type, x));
  double f = b->section && b->section[e] >= 0 ? sf[b->section[e]] : 1.0;
  return isfinite(v) ? rho[mi] * v * f : 0.0;
}

/* The bounding box of the mesh's nodes into x. */
static void bbox(const dtm_mesh *m, dtm_model_extent *x) {
  for (int c = 0; c < 3; c++) x->lo[c] = INFINITY, x->hi[c] = -INFINITY;
  for (size_t v = 0; v < m->nnodes; v++)
    for (int c = 0; c < 3; c++)
      x->lo[c] = fmin(x->lo[c], m->xyz[3 * v + c]), x->hi[c] = fmax(x->hi[c], m->xyz[3 * v + c]);
}

/* The density of each of the scene's materials into rho (NaN without
 * one), the factor of each of its sections into sf. */
static void mass_tables(const dtm_scene *s, double *rho, double *sf) {
  int irho = dtm_scene_property_index(s, "rho");
  for (int i = 0; i < s->nmaterials; i++)
    rho[i] = irho >= 0 && dtm_material_has(&s->materials[i].m, irho) ? dtm_material_get(&s->materials[i].m, irho) : NAN;
  for (int i = 0; i < s->nsections; i++) sf[i] = dtm_section_factor(&s->sections[i]);
}

int dtm_output_model(const dtm_analysis *a, dtm_model_extent *x) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  const dtm_scene *s = dtm_analysis_scene(a);
  const double *vol = dtm_analysis_measure(a);
  size_t i = 0;
  x->ngroups = m->ngroups + 1, x->mass = 0;
  x->group_mass = calloc((size_t)x->ngroups, sizeof *x->group_mass);
  double *rho = malloc(((size_t)s->nmaterials + (size_t)s->nsections + 1) * sizeof *rho), *sf = rho + s->nmaterials;
  if (!x->group_mass || !rho) return free(rho), dtm_output_model_free(x), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  mass_tables(s, rho, sf);
  for (int b = 0; b < m->nblocks; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++, i++) {
      double me = element_mass(m, &m->blocks[b], e, rho, sf, vol ? vol + i : NULL);
      int g = m->blocks[b].group[e];
      x->mass += me, x->group_mass[g >= 0 && g < m->ngroups ? g : m->ngroups] += me;
    }
  free(rho);
  bbox(m, x);
  return DTM_OK;
}

void dtm_output_model_free(dtm_model_extent *x) {
  free(x->group_mass);
  x->group_mass = NULL;
}

double dtm_output_model_size(const dtm_model_extent *x) {
  double d = 0;
  for (int c = 0; c < 3; c++) d = fmax(d, x->hi[c] - x->lo[c]);
  return d;
}

/* Dilatational wave speed of material m in the scene's units (NaN without
 * E and rho; the bar speed without nu). */
static double wave_speed(const dtm_material *m) {
  double E = dtm_material_value(m, "E"), nu = dtm_material_value(m, "nu"), rho = dtm_material_value(m, "rho");
  if (!(E > 0) || !(rho > 0)) return NAN;
  double f = nu > -1 && nu < 0.5 ? (1 - nu) / ((1 + nu) * (1 - 2 * nu)) : 1.0;
  return sqrt(E * f / rho);
}

/* "v unit" in the scene's units, with the SI value beside under mm-t-s. */
static const char *value_text(const dtm_scene *s, double v, double si, dtm_unit what, const char *si_unit, char *buf,
                              size_t len) {
  if (is_mm(s))
    snprintf(buf, len, "%.4g %s (%.4g %s)", v, dtm_unit_label(s, what), si, si_unit);
  else
    snprintf(buf, len, "%.4g %s", v, si_unit);
  return buf;
}

static void material_warnings(const dtm_scene *s, const dtm_material *m, dtm_warnings *w) {
  double L = unit_length(s), M = unit_mass(s), rho = dtm_material_value(m, "rho"), c = wave_speed(m);
  double rho_si = rho * M / (L * L * L), c_si = c * L;
  char v[96];
  const char *hint = is_mm(s) ? "in mm-t-s: E in MPa, rho in t/mm^3" : "in SI: E in Pa, rho in kg/m^3";
  if (rho > 0 && (rho_si < RHO_LO || rho_si > RHO_HI))
    dtm_output_warn(
        w, "material '%s' (line %d): density rho = %s lies outside %g-%g kg/m^3, what solids have: check its unit (%s)",
        m->name, m->line, value_text(s, rho, rho_si, DTM_UNIT_DENSITY, "kg/m^3", v, sizeof v), RHO_LO, RHO_HI, hint);
  if (isfinite(c) && (c_si < C_LO || c_si > C_HI))
    dtm_output_warn(
        w,
        "material '%s' (line %d): dilatational wave speed %s lies outside %g m/s-%g km/s, what solids have: the "
        "step scales with 1/c; check the units of E and rho (%s)",
        m->name, m->line, value_text(s, c, c_si, DTM_UNIT_SPEED, "m/s", v, sizeof v), C_LO, C_HI / 1000, hint);
}

/* Whether the scene's geometry is a .geo, whose numbers are the scene's. */
static int is_geo(const dtm_scene *s) {
  size_t n = s->geometry ? strlen(s->geometry) : 0;
  return n > 4 && !strcmp(s->geometry + n - 4, ".geo");
}

static void size_warning(const dtm_analysis *a, dtm_warnings *w) {
  const dtm_scene *s = dtm_analysis_scene(a);
  dtm_model_extent x = {0};
  bbox(dtm_analysis_mesh(a), &x);
  double d = dtm_output_model_size(&x), d_si = d * unit_length(s);
  char v[96];
  if (!s->mesh && !s->model && s->mesh_size > SIZE_OVER * d && d > 0 && !is_mm(s))
    dtm_output_warn(
        w,
        "<meshing size=\"%g\"> (line %d) is %.3g times the model's extent, %.4g m: sizes are in m, as the model "
        "is; a size meant in mm would be size=\"%g\"",
        s->mesh_size, s->meshing_line, s->mesh_size / d, d, s->mesh_size * 1e-3);
  else if (!s->mesh && !s->model && s->mesh_size > SIZE_OVER * d && d > 0)
    dtm_output_warn(
        w,
        "<meshing size=\"%g\"> (line %d) is %.3g times the model's extent, %.4g mm: a model drawn in metres "
        "is read in mm in this mm-t-s scene unless %s",
        s->mesh_size, s->meshing_line, s->mesh_size / d, d,
        is_geo(s) ? "its .geo is drawn in mm (a .geo has no unit of its own)" : "<geometry unit=\"m\"> says so");
  if (d_si > SIZE_HI || (d_si < SIZE_LO && d_si >= 0))
    dtm_output_warn(w, "the model is %s across, %s than %s: check the unit of the %s (<%s unit=\"...\">)",
                    value_text(s, d, d_si, DTM_UNIT_LENGTH, "m", v, sizeof v), d_si > SIZE_HI ? "larger" : "smaller",
                    d_si > SIZE_HI ? "1 km" : "1 um", s->mesh ? "mesh" : "geometry", s->mesh ? "mesh" : "geometry");
}

void dtm_output_warn_plausibility(const dtm_analysis *a, void *stream) {
  dtm_warnings w = {0, {{0}}};
  dtm_output_plausibility_warnings(a, &w);
  for (int i = 0; i < w.n; i++) fprintf(stream, "dtmap: warning: %s\n", w.text[i]);
}

void dtm_output_plausibility_warnings(const dtm_analysis *a, dtm_warnings *w) {
  const dtm_scene *s = dtm_analysis_scene(a);
  char *used = calloc((size_t)s->nmaterials + 1, 1);
  if (used) dtm_mesh_materials_used(dtm_analysis_mesh(a), s->nmaterials, used);
  for (int i = 0; i < s->nmaterials; i++)
    if (!used || used[i]) material_warnings(s, &s->materials[i].m, w);
  free(used);
  size_warning(a, w);
}

/* Where the file's unit came from, in words: "unit mm found in the file" or
 * "unit mm given by <mesh unit>". */
static void import_text(const dtm_import_units *u, char *buf, size_t len) {
  if (u->given[0] && u->found[0])
    snprintf(buf, len, "unit %s given by the scene (the file declares %s)", u->given, u->found);
  else if (u->given[0])
    snprintf(buf, len, "unit %s given by the scene", u->given);
  else if (u->found[0])
    snprintf(buf, len, "unit %s found in the file", u->found);
  else
    snprintf(buf, len, "no unit in the file: taken as %s", u->system);
}

int dtm_output_import(const dtm_analysis *a, dtm_import_units *u) {
  dtm_gmsh_import_units(u);
  return !dtm_analysis_scene(a)->model && u->active;
}

void dtm_summary_model(const dtm_analysis *a, void *stream) {
  FILE *f = stream;
  const dtm_scene *s = dtm_analysis_scene(a);
  const dtm_mesh *m = dtm_analysis_mesh(a);
  dtm_import_units u;
  char text[160], lbl[64];
  if (is_mm(s)) fprintf(f, "units        mm-t-s: mm, t, s, N, MPa, t/mm^3 (the step in s)\n");
  if (dtm_output_import(a, &u)) {
    import_text(&u, text, sizeof text);
    fprintf(f, "import       %s: coordinates x %.6g into %s\n", text, u.factor, u.system);
  }
  dtm_model_extent x = {0};
  if (dtm_output_model(a, &x)) return;
  const char *L = dtm_unit_label(s, DTM_UNIT_LENGTH), *M = dtm_output_unit(a, DTM_UNIT_MASS);
  fprintf(f, "model        mass %.6g %s%s", x.mass, M, m->dim < 3 && !s->nsections ? " (per unit thickness)" : "");
  for (int g = 0, k = 0; g < x.ngroups && x.ngroups > 2; g++)
    if (x.group_mass[g] > 0)
      fprintf(f, "%s'%s' %.4g %s", k++ ? ", " : " (", dtm_mesh_group_label(m, g < m->ngroups ? g : -1, lbl, sizeof lbl),
              x.group_mass[g], M);
  fprintf(f, "%s; extent %.4g x %.4g x %.4g %s from (%.4g, %.4g, %.4g) %s\n", x.ngroups > 2 ? ")" : "",
          x.hi[0] - x.lo[0], x.hi[1] - x.lo[1], x.hi[2] - x.lo[2], L, x.lo[0], x.lo[1], x.lo[2], L);
  dtm_output_model_free(&x);
}
