/* Material properties: look-up in a scene's catalogue by name or index,
 * the admissibility check of a value against the range its declaring
 * effect gives (finite, within [lo, hi] with open ends as declared), and
 * the check that a material gives what an effect needs. Messages name the
 * scene file and line of the material when it has them. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "dtmap/material.h"

int dtm_material_index(const dtm_material *m, const char *name) {
  for (int i = 0; m && name && i < m->nprops; i++)
    if (!strcmp(m->prop_names[i], name)) return i;
  return -1;
}

int dtm_material_has(const dtm_material *m, int i) { return m && i >= 0 && i < m->nprops && !isnan(m->prop[i]); }

double dtm_material_get(const dtm_material *m, int i) { return dtm_material_has(m, i) ? m->prop[i] : NAN; }

double dtm_material_value(const dtm_material *m, const char *name) {
  return dtm_material_get(m, dtm_material_index(m, name));
}

static int admissible(const dtm_property *p, double v) {
  if (!isfinite(v)) return 0;
  int lo_ok = (p->open & DTM_OPEN_LO) ? v > p->lo : v >= p->lo;
  int hi_ok = (p->open & DTM_OPEN_HI) ? v < p->hi : v <= p->hi;
  return lo_ok && hi_ok;
}

/* "need -1 < nu < 0.5", "need E > 0", "need xi >= 0", ... */
static void requirement(const dtm_property *p, double v, char *buf, size_t n) {
  const char *lt_lo = (p->open & DTM_OPEN_LO) ? "<" : "<=", *lt_hi = (p->open & DTM_OPEN_HI) ? "<" : "<=";
  const char *gt_lo = (p->open & DTM_OPEN_LO) ? ">" : ">=";
  if (!isfinite(v))
    snprintf(buf, n, "need a finite number");
  else if (isfinite(p->lo) && isfinite(p->hi))
    snprintf(buf, n, "need %g %s %s %s %g", p->lo, lt_lo, p->name, lt_hi, p->hi);
  else if (isfinite(p->lo))
    snprintf(buf, n, "need %s %s %g", p->name, gt_lo, p->lo);
  else
    snprintf(buf, n, "need %s %s %g", p->name, lt_hi, p->hi);
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

int dtm_property_check(const dtm_property *p, const dtm_material *m, double v) {
  char at[1024], value[32], need[96];
  if (!p || !p->name) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_property_check: no property");
  if (admissible(p, v)) return DTM_OK;
  where(m, at, sizeof at);
  if (m && m->name) snprintf(at + strlen(at), sizeof at - strlen(at), "material '%s': ", m->name);
  format_value(v, value, sizeof value);
  requirement(p, v, need, sizeof need);
  return DTM_ERR(DTM_ERR_INPUT, "%s%s = %s is not admissible (%s)", at, p->name, value, need);
}

static int missing_error(const dtm_material *m, const char *missing, const char *who) {
  char at[1024];
  where(m, at, sizeof at);
  return DTM_ERR(DTM_ERR_INPUT, "%smaterial '%s' has no %s, needed by effect '%s'", at, m->name ? m->name : "?",
                 missing, who ? who : "?");
}

int dtm_material_require(const dtm_material *m, const dtm_property *props, const char *who) {
  char missing[512] = "";
  if (!m) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_material_require: no material");
  for (const dtm_property *p = props; p && p->name; p++)
    if (p->required && isnan(dtm_material_value(m, p->name))) dtm_strlist_add(missing, sizeof missing, p->name, 1);
  return missing[0] ? missing_error(m, missing, who) : DTM_OK;
}

int dtm_material_require_one(const dtm_material *m, const char *name, const char *who) {
  char missing[256] = "";
  if (!isnan(dtm_material_value(m, name))) return DTM_OK;
  dtm_strlist_add(missing, sizeof missing, name, 1);
  return missing_error(m, missing, who);
}
