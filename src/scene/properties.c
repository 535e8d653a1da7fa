/* Material properties: their XML attribute names, the physical admissibility
 * of each value (moduli, densities, conductivities and the like strictly
 * positive, Poisson's ratio in (-1, 0.5), damping coefficients non-negative,
 * always finite) and the check that a material has what an effect needs.
 * Errors name the scene file and line of the material when it has them. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/material.h"

enum { RULE_POSITIVE, RULE_POISSON, RULE_NON_NEGATIVE };

static const struct {
  const char *name; /* XML attribute name */
  int rule;         /* RULE_*: which values are admissible */
} props[DTM_PROP_COUNT] = {
    [DTM_PROP_E] = {"E", RULE_POSITIVE},
    [DTM_PROP_NU] = {"nu", RULE_POISSON},
    [DTM_PROP_RHO] = {"rho", RULE_POSITIVE},
    [DTM_PROP_CONDUCTIVITY] = {"conductivity", RULE_POSITIVE},
    [DTM_PROP_HEAT_CAPACITY] = {"heat-capacity", RULE_POSITIVE},
    [DTM_PROP_PERMEABILITY] = {"permeability", RULE_POSITIVE},
    [DTM_PROP_VISCOSITY] = {"viscosity", RULE_POSITIVE},
    [DTM_PROP_STORAGE] = {"storage", RULE_POSITIVE},
    [DTM_PROP_FRACTURE_ENERGY] = {"fracture-energy", RULE_POSITIVE},
    [DTM_PROP_STRENGTH] = {"strength", RULE_POSITIVE},
    [DTM_PROP_XI] = {"xi", RULE_NON_NEGATIVE},
    [DTM_PROP_ALPHA] = {"alpha", RULE_NON_NEGATIVE},
    [DTM_PROP_BETA] = {"beta", RULE_NON_NEGATIVE},
};

const char *dtm_prop_name(int p) { return p >= 0 && p < DTM_PROP_COUNT ? props[p].name : NULL; }

int dtm_prop_find(const char *attr) {
  for (int p = 0; attr && p < DTM_PROP_COUNT; p++)
    if (!strcmp(props[p].name, attr)) return p;
  return -1;
}

static int admissible(int p, double v) {
  if (!isfinite(v)) return 0;
  switch (props[p].rule) {
  case RULE_POSITIVE: return v > 0;
  case RULE_POISSON: return v > -1 && v < 0.5;
  default: return v >= 0;
  }
}

static void requirement(int p, double v, char *buf, size_t n) {
  const char *name = props[p].name;
  if (!isfinite(v))
    snprintf(buf, n, "need a finite number");
  else if (props[p].rule == RULE_POSITIVE)
    snprintf(buf, n, "need %s > 0", name);
  else if (props[p].rule == RULE_POISSON)
    snprintf(buf, n, "need -1 < %s < 0.5", name);
  else
    snprintf(buf, n, "need %s >= 0", name);
}

/* Shortest "%g" text that reads back as v, so 0.49999999 never shows as 0.5. */
static void format_value(double v, char *buf, size_t n) {
  for (int digits = 1; digits <= 17; digits++) {
    snprintf(buf, n, "%.*g", digits, v);
    if (strtod(buf, NULL) == v) return;
  }
}

/* "file:line: " when the material knows where it came from, else "". */
static void where(const dtm_material *m, char *buf, size_t n) {
  if (m && m->file)
    snprintf(buf, n, "%s:%d: ", m->file, m->line);
  else
    buf[0] = '\0';
}

/* "file:line: material 'name': " with the parts that are known. */
static void subject(const dtm_material *m, char *buf, size_t n) {
  size_t used;
  where(m, buf, n);
  used = strlen(buf);
  if (m && m->name) snprintf(buf + used, n - used, "material '%s': ", m->name);
}

int dtm_prop_check(const dtm_material *m, int p, double v) {
  char at[1024], value[32], need[64];
  if (p < 0 || p >= DTM_PROP_COUNT) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_prop_check: no material property %d", p);
  if (admissible(p, v)) return DTM_OK;
  subject(m, at, sizeof at);
  format_value(v, value, sizeof value);
  requirement(p, v, need, sizeof need);
  return DTM_ERR(DTM_ERR_INPUT, "%s%s = %s is not admissible (%s)", at, props[p].name, value, need);
}

/* "'a', 'b'" for the properties in mask. */
static void list_props(unsigned mask, char *buf, size_t n) {
  size_t used = 0;
  buf[0] = '\0';
  for (int p = 0; p < DTM_PROP_COUNT && used < n; p++) {
    if (!(mask & DTM_PROP_BIT(p))) continue;
    int w = snprintf(buf + used, n - used, "%s'%s'", used ? ", " : "", props[p].name);
    used += w > 0 ? (size_t)w : 0;
  }
}

int dtm_material_require(const dtm_material *m, unsigned needs, const char *who) {
  char at[1024], missing[256];
  if (!m) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_material_require: no material");
  unsigned lack = needs & ~m->have & (DTM_PROP_BIT(DTM_PROP_COUNT) - 1u);
  if (!lack) return DTM_OK;
  where(m, at, sizeof at);
  list_props(lack, missing, sizeof missing);
  return DTM_ERR(DTM_ERR_INPUT, "%smaterial '%s' has no %s, needed by effect '%s'", at, m->name ? m->name : "?",
                 missing, who ? who : "?");
}
