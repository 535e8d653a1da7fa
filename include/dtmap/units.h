/* The one unit rule for every figure dtmap prints or writes (docs/units.md):
 * a length, mass, density, modulus, stiffness ... of the model is in the
 * scene's system of units (<dtmap-scene units>: SI, or mm-t-s) and is
 * printed with that system's name for its unit; the step is in s in both.
 * These functions name a quantity's unit in a system, give its SI value,
 * and print a figure with its unit. A system is the scene's `units` string:
 * NULL or "SI" for SI, "mm-t-s" for mm, tonne, s (N, MPa, t/mm^3). */
#ifndef DTMAP_UNITS_H
#define DTMAP_UNITS_H

#include <stddef.h>

#include "dtmap/export.h"

/* The quantities dtmap prints with a unit of the scene's system. */
typedef enum {
  DTM_UNIT_LENGTH,      /* m | mm */
  DTM_UNIT_AREA,        /* m^2 | mm^2 */
  DTM_UNIT_MOMENT,      /* second moment of area: m^4 | mm^4 */
  DTM_UNIT_MASS,        /* kg | t */
  DTM_UNIT_DENSITY,     /* kg/m^3 | t/mm^3 */
  DTM_UNIT_SPEED,       /* m/s | mm/s */
  DTM_UNIT_MODULUS,     /* Pa | MPa (also a stress) */
  DTM_UNIT_STIFFNESS,   /* N/m | N/mm */
  DTM_UNIT_LINE_MASS,   /* mass per unit thickness (2D): kg/m | t/mm */
  DTM_UNIT_DIFFUSIVITY, /* m^2/s | mm^2/s */
  DTM_UNIT_COUNT
} dtm_unit;

/* Whether system is mm-t-s (else SI: NULL, "SI"). */
DTM_EXPORT int dtm_units_mm(const char *system);
/* The name of the unit of q in system ("mm", "t", "MPa", ...; static). */
DTM_EXPORT const char *dtm_units_name(const char *system, dtm_unit q);
/* The SI value of one unit of q in system (mm-t-s: 1e-3 for a length, 1e3 for a mass, 1e12 for a
 * density, 1e6 for a modulus, 1e3 for a stiffness; 1 in SI). */
DTM_EXPORT double dtm_units_si(const char *system, dtm_unit q);
/* "v unit" into buf (len bytes; returns buf), v in system's unit of q printed with %.{digits}g. */
DTM_EXPORT const char *dtm_units_text(const char *system, dtm_unit q, double v, int digits, char *buf, size_t len);

/* The system of units of the library's messages about figures it holds in
 * SI (a kernel's or a section's error: a modulus, a density, a thickness):
 * the last scene loaded (dtm_scene_load sets it), SI before any. */
DTM_EXPORT void dtm_units_set_messages(const char *system);
DTM_EXPORT const char *dtm_units_messages(void);
/* "v unit" into buf (len bytes; returns buf): v_si, an SI value of q,
 * converted into the messages' system and printed with %.{digits}g. */
DTM_EXPORT const char *dtm_units_si_text(dtm_unit q, double v_si, int digits, char *buf, size_t len);

#endif
