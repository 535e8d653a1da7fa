/* The names and SI values of the units of dtmap's two systems (SI and
 * mm-t-s), and a figure printed with its unit: every printed length, mass,
 * density, modulus and stiffness of the model goes through these so that
 * the unit beside a number is the unit it is in (include/dtmap/units.h);
 * the library's own messages about SI figures print them in the system of
 * the last scene loaded. */
#include <stdio.h>
#include <string.h>

#include "dtmap/units.h"

static const char *const si_name[DTM_UNIT_COUNT] = {"m",   "m^2", "m^4", "kg",   "kg/m^3",
                                                    "m/s", "Pa",  "N/m", "kg/m", "m^2/s"};
static const char *const mm_name[DTM_UNIT_COUNT] = {"mm",   "mm^2", "mm^4", "t",    "t/mm^3",
                                                    "mm/s", "MPa",  "N/mm", "t/mm", "mm^2/s"};
/* SI value of one mm-t-s unit: mm, mm^2, mm^4, t, t/mm^3 (1e3 / 1e-9), mm/s, MPa, N/mm, t/mm, mm^2/s. */
static const double mm_si[DTM_UNIT_COUNT] = {1e-3, 1e-6, 1e-12, 1e3, 1e12, 1e-3, 1e6, 1e3, 1e6, 1e-6};

/* The messages' system: a copy, since the scene that set it may be freed
 * (set between analyses, read by their kernels). */
static char messages[8] = "SI";

int dtm_units_mm(const char *system) { return system && !strcmp(system, "mm-t-s"); }

const char *dtm_units_name(const char *system, dtm_unit q) {
  if (q < 0 || q >= DTM_UNIT_COUNT) return "";
  return dtm_units_mm(system) ? mm_name[q] : si_name[q];
}

double dtm_units_si(const char *system, dtm_unit q) {
  if (q < 0 || q >= DTM_UNIT_COUNT) return 1.0;
  return dtm_units_mm(system) ? mm_si[q] : 1.0;
}

const char *dtm_units_text(const char *system, dtm_unit q, double v, int digits, char *buf, size_t len) {
  snprintf(buf, len, "%.*g %s", digits, v, dtm_units_name(system, q));
  return buf;
}

void dtm_units_set_messages(const char *system) {
  snprintf(messages, sizeof messages, "%s", dtm_units_mm(system) ? "mm-t-s" : "SI");
}

const char *dtm_units_messages(void) { return messages; }

const char *dtm_units_si_text(dtm_unit q, double v_si, int digits, char *buf, size_t len) {
  return dtm_units_text(messages, q, v_si / dtm_units_si(messages, q), digits, buf, len);
}
