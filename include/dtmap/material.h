/* Materials and their properties. The property set is open: an effect
 * declares the properties it reads (dtm_property: name, unit, admissible
 * range, whether every material in use must have it), the registry collects
 * the declarations of all effects, and a scene's materials carry a value for
 * each property of its catalogue (the declared names plus any other the
 * scene's materials give, for external effects). Effects look a property up
 * once by name (dtm_material_index) and then read it by index in their
 * element loops. Errors name the scene file and line of the material, the
 * property and the effect. */
#ifndef DTMAP_MATERIAL_H
#define DTMAP_MATERIAL_H

#include "dtmap/export.h"

/* Open ends of an admissible range (dtm_property.open). */
#define DTM_OPEN_LO 1u /* the value must be > lo (else >= lo) */
#define DTM_OPEN_HI 2u /* the value must be < hi (else <= hi) */

/* One material property as an effect declares it. */
typedef struct {
  const char *name; /* attribute of <material>, e.g. "heat-capacity" */
  const char *unit; /* SI unit for documentation, e.g. "J/(kg K)"; "" when none */
  double lo, hi;    /* admissible range (use -HUGE_VAL / HUGE_VAL for none) */
  unsigned open;    /* DTM_OPEN_LO | DTM_OPEN_HI: which ends are excluded */
  int required;     /* 1: every material some element uses must give it */
  const char *help; /* one line for `dtmap effects` */
} dtm_property;

typedef struct dtm_material {
  char *name;              /* material name (owned by the scene) */
  const char *file;        /* scene file it came from (not owned) */
  int line;                /* line of its <material> element */
  int nprops;              /* size of the scene's property catalogue */
  char *const *prop_names; /* [nprops] the catalogue's names (owned by the scene) */
  double *prop;            /* [nprops] values; NaN where the material gives none */
} dtm_material;

/* Index of the property named name in m's catalogue, or -1. Every material
 * of one scene shares the catalogue, so an index found on one is valid for
 * all of them. */
DTM_EXPORT int dtm_material_index(const dtm_material *m, const char *name);
/* 1 when m gives property i (an index from dtm_material_index; -1 gives 0). */
DTM_EXPORT int dtm_material_has(const dtm_material *m, int i);
/* Value of property i, NaN when m gives none (or i is -1). */
DTM_EXPORT double dtm_material_get(const dtm_material *m, int i);
/* Value of the property named name, NaN when m gives none. */
DTM_EXPORT double dtm_material_value(const dtm_material *m, const char *name);

/* Check that v is admissible for property p (finite, within its range);
 * DTM_ERR_INPUT otherwise, with "file:line: material 'name': " when m is
 * given, e.g. "nu = 0.5 is not admissible (need -1 < nu < 0.5)". */
DTM_EXPORT int dtm_property_check(const dtm_property *p, const dtm_material *m, double v);
/* Raise DTM_ERR_INPUT unless m gives every required property of the list
 * props (terminated by a NULL name; NULL: none); the message names file:line,
 * the material, all missing properties and `who` (the effect). */
DTM_EXPORT int dtm_material_require(const dtm_material *m, const dtm_property *props, const char *who);
/* The same for one property by name, whether declared required or not. */
DTM_EXPORT int dtm_material_require_one(const dtm_material *m, const char *name, const char *who);

#endif
