/* The material values no solid has, refused when the scene is read (before
 * any meshing or output): a density rho or a dilatational wave speed
 * c = sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu)) / rho) (sqrt(E/rho) without
 * nu) outside what solids have (rho 1 to 25,000 kg/m^3, aerogels to
 * osmium; c 10 m/s to 20 km/s, soft gels to diamond) is an error (exit 2,
 * the scene's file and the material's line) when
 *  - one of the usual unit slips brings both back inside (E in MPa or GPa
 *    in an SI scene, E in Pa in an mm-t-s one, rho in g/cm^3, a whole
 *    material in the other system): the message names the slip and the
 *    values it means; or
 *  - it lies 1000 times or more outside (rho below 1e-3 or above 2.5e7
 *    kg/m^3, c below 0.01 m/s or above 2e7 m/s), whatever the cause.
 * plausible="no-check" on the <material> (or on <dtmap-scene>, for all)
 * says the values are meant: then only the warnings of
 * src/output/plausible.c remain. Values closer to the bounds that no slip
 * explains stay warnings there (foams and gels are real). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene-impl.h"

#define RHO_LO 1.0     /* kg/m^3 */
#define RHO_HI 25000.0 /* kg/m^3 */
#define C_LO 10.0      /* m/s */
#define C_HI 20000.0   /* m/s */
#define FAR 1000.0     /* this many times outside a range: no solid, whatever the cause */

/* A unit slip: the written E and rho times these give the values meant. */
typedef struct {
  double e, rho;    /* factors on E and on rho */
  const char *what; /* the slip, in words */
} slip;

static const slip si_slips[] =
    {
        {1e6, 1, "E looks like MPa, and this SI scene takes E in Pa:"},
        {1e9, 1, "E looks like GPa, and this SI scene takes E in Pa:"},
        {1, 1e3, "rho looks like g/cm^3, and this SI scene takes rho in kg/m^3:"},
        {1e6, 1e12,
         "E and rho look like mm-t-s values (MPa, t/mm^3): declare the scene's system, <dtmap-scene "
         "units=\"mm-t-s\"> (then lengths, sizes and the model are in mm), or"},
},
                  mm_slips[] = {
                      {1e-6, 1, "E looks like Pa, and this mm-t-s scene takes E in MPa:"},
                      {1e3, 1, "E looks like GPa, and this mm-t-s scene takes E in MPa:"},
                      {1, 1e-12, "rho looks like kg/m^3, and this mm-t-s scene takes rho in t/mm^3:"},
                      {1, 1e-9, "rho looks like g/cm^3, and this mm-t-s scene takes rho in t/mm^3:"},
                      {1e-6, 1e-12,
                       "E and rho look like SI values (Pa, kg/m^3), and this mm-t-s scene takes MPa "
                       "and t/mm^3:"},
};

typedef struct {
  double rho, c; /* SI: kg/m^3, m/s (NaN when the material lacks what it needs) */
} si_values;

/* rho and c of E, nu, rho in the scene's units, in SI. */
static si_values si_of(const dtm_scene *s, double E, double nu, double rho) {
  double L = s->unit_length > 0 ? s->unit_length : 1.0, M = s->unit_mass > 0 ? s->unit_mass : 1.0;
  double f = nu > -1 && nu < 0.5 ? (1 - nu) / ((1 + nu) * (1 - 2 * nu)) : 1.0;
  si_values v = {rho > 0 ? rho * M / (L * L * L) : NAN, E > 0 && rho > 0 ? sqrt(E * f / rho) * L : NAN};
  return v;
}

static int rho_inside(double r, double widen) { return isnan(r) || (r >= RHO_LO / widen && r <= RHO_HI * widen); }
static int c_inside(double c, double widen) { return isnan(c) || (c >= C_LO / widen && c <= C_HI * widen); }

/* What the values say, as "rho = 7850 t/mm^3 (7.85e+15 kg/m^3)" and the wave
 * speed, into buf. */
static void values_text(const dtm_scene *s, double E, double rho, si_values v, char *buf, size_t len) {
  int mm = s->unit_length != 1.0;
  int k = snprintf(buf, len, "rho = %.6g %s", rho, mm ? "t/mm^3" : "kg/m^3");
  if (mm && k > 0 && (size_t)k < len) k += snprintf(buf + k, len - (size_t)k, " (%.4g kg/m^3)", v.rho);
  if (!isnan(v.c) && k > 0 && (size_t)k < len)
    snprintf(buf + k, len - (size_t)k, " and E = %.6g %s give a dilatational wave speed of %.4g m/s", E,
             mm ? "MPa" : "Pa", v.c);
}

/* The error for material m, or DTM_OK. */
static int check_material(const dtm_scene *s, const dtm_scene_material *sm) {
  const dtm_material *m = &sm->m;
  double E = dtm_material_value(m, "E"), nu = dtm_material_value(m, "nu"), rho = dtm_material_value(m, "rho");
  si_values v = si_of(s, E, nu, rho);
  if (rho_inside(v.rho, 1) && c_inside(v.c, 1)) return DTM_OK;
  char said[256];
  values_text(s, E, rho, v, said, sizeof said);
  int mm = s->unit_length != 1.0;
  const slip *t = mm ? mm_slips : si_slips;
  size_t n = mm ? sizeof mm_slips / sizeof *mm_slips : sizeof si_slips / sizeof *si_slips;
  for (size_t i = 0; i < n; i++) {
    si_values w = si_of(s, isnan(E) ? E : E * t[i].e, nu, rho * t[i].rho);
    if (!rho_inside(w.rho, 1) || !c_inside(w.c, 1) || (isnan(E) && t[i].e != 1)) continue;
    char fix[128] = "";
    if (t[i].e != 1 && !isnan(E)) snprintf(fix, sizeof fix, "E=\"%.6g\"", E * t[i].e);
    if (t[i].rho != 1)
      snprintf(fix + strlen(fix), sizeof fix - strlen(fix), "%srho=\"%.6g\"", fix[0] ? " " : "", rho * t[i].rho);
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s:%d: material '%s': %s, which no solid has (rho %g to %g kg/m^3, wave speed %g m/s to %g km/s): "
                   "%s write %s; if the values are meant, add plausible=\"no-check\" to the <material>",
                   s->path, m->line, m->name, said, RHO_LO, RHO_HI, C_LO, C_HI / 1000, t[i].what, fix);
  }
  if (rho_inside(v.rho, FAR) && c_inside(v.c, FAR)) return DTM_OK; /* a warning of the summary */
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s:%d: material '%s': %s, %g times or more outside what solids have (rho %g to %g kg/m^3, wave "
                 "speed %g m/s to %g km/s): check the units of E and rho (%s); if the values are meant, add "
                 "plausible=\"no-check\" to the <material>",
                 s->path, m->line, m->name, said, FAR, RHO_LO, RHO_HI, C_LO, C_HI / 1000,
                 mm ? "mm-t-s: E in MPa, rho in t/mm^3" : "SI: E in Pa, rho in kg/m^3");
}

int dtm_scene_read_plausible(const dtm_scene *s, const xmlNode *n, int *no_check) {
  char *text;
  *no_check = 0;
  DTM_CHECK(dtm_scene_attr(n, "plausible", &text));
  int rc = DTM_OK;
  if (text && !strcmp(text, "no-check"))
    *no_check = 1;
  else if (text && strcmp(text, "check"))
    rc = DTM_SCENE_ERR(s, n, "<%s> plausible=\"%s\" is not check or no-check", (const char *)n->name, text);
  free(text);
  return rc;
}

int dtm_scene_check_plausible(const dtm_scene *s) {
  if (s->no_plausible_check) return DTM_OK;
  for (int i = 0; i < s->nmaterials; i++)
    if (!s->materials[i].no_plausible_check) DTM_CHECK(check_material(s, &s->materials[i]));
  return DTM_OK;
}
