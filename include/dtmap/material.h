/* Materials as the scene gives them: a name, the scene line, and the
 * properties that were set. Shared by the scene reader, the mesh mapping and
 * the effects; an effect declares which properties it needs as a mask of
 * DTM_PROP_* bits, and a material that lacks one is an error naming both. */
#ifndef DTMAP_MATERIAL_H
#define DTMAP_MATERIAL_H

#include "dtmap/export.h"

enum dtm_prop {
  DTM_PROP_E = 0,           /* Young's modulus, Pa */
  DTM_PROP_NU,              /* Poisson's ratio */
  DTM_PROP_RHO,             /* density, kg/m^3 */
  DTM_PROP_CONDUCTIVITY,    /* thermal conductivity, W/(m K) */
  DTM_PROP_HEAT_CAPACITY,   /* specific heat capacity, J/(kg K) */
  DTM_PROP_PERMEABILITY,    /* intrinsic permeability, m^2 */
  DTM_PROP_VISCOSITY,       /* fluid dynamic viscosity, Pa s */
  DTM_PROP_STORAGE,         /* specific storage, 1/Pa */
  DTM_PROP_FRACTURE_ENERGY, /* G_c, J/m^2 */
  DTM_PROP_STRENGTH,        /* cohesive strength sigma_max, Pa */
  DTM_PROP_XI,              /* damping ratio at the top frequency */
  DTM_PROP_ALPHA,           /* Rayleigh mass-proportional coefficient, 1/s */
  DTM_PROP_BETA,            /* Rayleigh stiffness-proportional coefficient, s */
  DTM_PROP_COUNT
};
#define DTM_PROP_BIT(p) (1u << (p))

typedef struct dtm_material {
  char *name;                  /* material name (owned) */
  const char *file;            /* scene file it came from (not owned) */
  int line;                    /* line of its <material> element */
  double prop[DTM_PROP_COUNT]; /* values; meaningful only where `have` says */
  unsigned have;               /* DTM_PROP_BIT(p) set when p was given */
} dtm_material;

/* XML attribute name of a property ("heat-capacity"). */
DTM_EXPORT const char *dtm_prop_name(int p);
/* Index of the property with that attribute name, or -1. */
DTM_EXPORT int dtm_prop_find(const char *attr);
/* Check value v of property p is physically admissible; DTM_ERR_INPUT with a
 * message naming file:line, material and property otherwise. */
DTM_EXPORT int dtm_prop_check(const dtm_material *m, int p, double v);
/* Raise DTM_ERR_INPUT unless m has every property in `needs`; the message
 * names file:line, the material, the missing property and `who` (the effect). */
DTM_EXPORT int dtm_material_require(const dtm_material *m, unsigned needs, const char *who);

#endif
