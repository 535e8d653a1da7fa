/* Sections: what kind of structural element the elements of a physical
 * group are, as explicit codes name them (Abaqus *SOLID SECTION, *SHELL
 * SECTION, *MEMBRANE SECTION; LS-DYNA *SECTION_...). A scene's
 * <section groups="rebar" kind="truss" area="3.1e-4"/> says that the line
 * elements of group rebar are trusses of cross-section 3.1e-4 m^2; a
 * section lets a model hold elements of several dimensions (volumes, and
 * surfaces and curves in or on them) coupled through the nodes they share.
 * The kind fixes the element dimension it applies to and the elastic
 * formulation; the thickness or area scales both the stiffness and the
 * lumped mass of the element (so it cancels from the element's own step,
 * but not from the coupling at shared nodes). Pure data and small lookups:
 * no Gmsh, no allocation. */
#ifndef DTMAP_SECTION_H
#define DTMAP_SECTION_H

#include "dtmap/export.h"
#include "dtmap/kernel.h"

typedef enum {
  DTM_SECTION_SOLID = 0,        /* 3D continuum: volume elements */
  DTM_SECTION_PLANE_STRAIN = 1, /* plane strain: plane surface elements (thickness, default 1 m) */
  DTM_SECTION_PLANE_STRESS = 2, /* plane stress: plane surface elements (thickness, default 1 m) */
  DTM_SECTION_MEMBRANE = 3,     /* plane stress in each element's own tangent plane: surface
                                   elements anywhere in 3D (thickness required) */
  DTM_SECTION_TRUSS = 4         /* axial force only: line elements anywhere (area required) */
} dtm_section_kind;

/* Scene names of the kinds, in dtm_section_kind order (initialiser). */
#define DTM_SECTION_NAMES                                                                                              \
  { "solid", "plane-strain", "plane-stress", "membrane", "truss", NULL }

typedef struct dtm_section {
  int kind;         /* dtm_section_kind */
  double thickness; /* m: plane kinds and membrane (1 when a plane kind gives none); 0 otherwise */
  double area;      /* m^2: truss; 0 otherwise */
  int is_default;   /* default="true": for elements of the analysed dimension in no sectioned group */
  int ngroups;      /* number of group references */
  char **groups;    /* [ngroups] physical group names or numbers, as written (owned by the scene) */
  const char *file; /* scene file (not owned) */
  int line;         /* line of its <section> element */
} dtm_section;

/* Scene name of kind k ("unknown" for none). */
DTM_EXPORT const char *dtm_section_kind_name(int k);
/* Topological dimension of the elements kind k applies to: 3, 2 or 1. */
DTM_EXPORT int dtm_section_dim(int k);
/* The elastic formulation of kind k: 3d, plane-strain, plane-stress
 * (membranes too: plane stress in the element's plane) or bar. */
DTM_EXPORT dtm_formulation dtm_section_formulation(int k);
/* The measure factor of section s (NULL: none, 1): the thickness (m) of
 * surface kinds, the area (m^2) of trusses, 1 for solids. An element's
 * stiffness and lumped mass are its per-measure values times this factor. */
DTM_EXPORT double dtm_section_factor(const dtm_section *s);

#endif
