/* The report's unit rule (docs/units.md): dtmap computes in the scene's
 * system of units (SI or mm-t-s) and the JSON report is in SI, as its
 * schema says, but for its "model" object, which is the scene's own
 * (an explicit solver's mass summary: mm and tonnes under mm-t-s). The
 * report says so once, in its top-level "units" object. Each report field
 * that carries a length, an area, a second moment of area, a mass or a
 * speed is named in one table here with its quantity, and converted from
 * the scene's unit into SI after the report is built; a field added to the
 * report with a unit is added to this table (tests/t381-units-everywhere.py
 * compares every field of an SI and an mm-t-s report of the same model). */
#include <cJSON.h>
#include <string.h>

#include "output-impl.h"
#include "report.h"

/* The report's fields with a unit of the scene's system (the schema's
 * descriptions give each one's SI unit); mass marks a mass (per unit
 * thickness in 2D without a section). */
static const struct {
  const char *key;
  dtm_unit unit;
} fields[] = {
    {"centroid", DTM_UNIT_LENGTH},
    {"length", DTM_UNIT_LENGTH},
    {"h", DTM_UNIT_LENGTH},
    {"hmax", DTM_UNIT_LENGTH},
    {"binding_hmax", DTM_UNIT_LENGTH},
    {"thickness", DTM_UNIT_LENGTH},
    {"size", DTM_UNIT_LENGTH},
    {"uniform_size", DTM_UNIT_LENGTH},
    {"R", DTM_UNIT_LENGTH},
    {"h_max", DTM_UNIT_LENGTH},
    {"wavelength", DTM_UNIT_LENGTH},
    {"window", DTM_UNIT_LENGTH},
    {"area", DTM_UNIT_AREA},
    {"iy", DTM_UNIT_MOMENT},
    {"iz", DTM_UNIT_MOMENT},
    {"j", DTM_UNIT_MOMENT},
    {"speed", DTM_UNIT_SPEED},
    {"mass", DTM_UNIT_MASS},
    {"added", DTM_UNIT_MASS},
    {"added_mass", DTM_UNIT_MASS},
    {"carried_mass", DTM_UNIT_MASS},
    {"deformation_mass", DTM_UNIT_MASS},
    {"model_mass", DTM_UNIT_MASS},
    {"mass_added", DTM_UNIT_MASS},
    {"total", DTM_UNIT_MASS},
    {"total_added", DTM_UNIT_MASS},
    {"total_mass", DTM_UNIT_MASS},
    {"solver_added_mass", DTM_UNIT_MASS},
    {"translational_mass", DTM_UNIT_MASS},
    {"translational_mass_lumped", DTM_UNIT_MASS},
    {"shell_thickness", DTM_UNIT_LENGTH},
};

/* The SI value of one scene unit of field key (1: not a field with a unit). */
static double factor_of(const char *key, const char *units, dtm_unit mass) {
  for (size_t i = 0; key && i < sizeof fields / sizeof *fields; i++)
    if (!strcmp(key, fields[i].key))
      return dtm_units_si(units, fields[i].unit == DTM_UNIT_MASS ? mass : fields[i].unit);
  return 1.0;
}

/* Multiply the number o, or each number of the array o, by f. */
static void scale(cJSON *o, double f) {
  if (cJSON_IsNumber(o)) cJSON_SetNumberValue(o, o->valuedouble * f);
  if (cJSON_IsArray(o))
    for (cJSON *c = o->child; c; c = c->next)
      if (cJSON_IsNumber(c)) cJSON_SetNumberValue(c, c->valuedouble * f);
}

static void walk(cJSON *o, const char *units, dtm_unit mass) {
  for (cJSON *c = o ? o->child : NULL; c; c = c->next) {
    double f = cJSON_IsObject(o) ? factor_of(c->string, units, mass) : 1.0;
    if (f != 1.0 && (cJSON_IsNumber(c) || (cJSON_IsArray(c) && c->child && cJSON_IsNumber(c->child))))
      scale(c, f);
    else if (cJSON_IsObject(c) || cJSON_IsArray(c))
      walk(c, units, mass);
  }
}

void dtm_report_units(cJSON *root, const dtm_analysis *a, int top) {
  const dtm_scene *s = dtm_analysis_scene(a);
  const char *system = dtm_units_mm(s->units) ? "mm-t-s" : "SI";
  dtm_unit mass = dtm_analysis_mesh(a)->dim < 3 && !s->nsections ? DTM_UNIT_LINE_MASS : DTM_UNIT_MASS;
  if (dtm_units_mm(s->units))
    for (cJSON *c = root->child; c; c = c->next)
      if (!top || !c->string || strcmp(c->string, "model")) {
        double f = factor_of(c->string, s->units, mass);
        if (f != 1.0)
          scale(c, f);
        else
          walk(c, s->units, mass);
      }
  if (!top) return;
  cJSON *u = cJSON_CreateObject();
  cJSON_AddStringToObject(u, "system", system);
  cJSON_AddStringToObject(u, "report", "SI");
  cJSON_AddStringToObject(u, "model", system);
  cJSON_AddItemToObject(root, "units", u);
}
