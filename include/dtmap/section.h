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
  DTM_SECTION_TRUSS = 4,        /* axial force only: line elements anywhere (area required) */
  DTM_SECTION_SHELL = 5,        /* Reissner-Mindlin shell: tri3/quad4 surface elements anywhere in 3D
                                   (thickness required); 3 rotations per node */
  DTM_SECTION_BEAM = 6          /* Timoshenko beam: line2 elements anywhere in 3D (area and second
                                   moments, or a circular or rectangular profile); 3 rotations per node */
} dtm_section_kind;

/* Scene names of the kinds, in dtm_section_kind order (initialiser). */
#define DTM_SECTION_NAMES                                                                                              \
  { "solid", "plane-strain", "plane-stress", "membrane", "truss", "shell", "beam", NULL }

typedef struct dtm_section {
  int kind;         /* dtm_section_kind */
  double thickness; /* m: plane kinds and membrane (1 when a plane kind gives none); 0 otherwise */
  double area;      /* m^2: truss and beam; 0 otherwise */
  double iy, iz;    /* beam: second moments of area about the section's y and z axes, m^4 */
  double jt;        /* beam: torsion constant, m^4 */
  double orient[3]; /* beam: a vector in the section's local x-y plane (y: its part normal to the
                       axis); all zero: global z, or global y for a beam within ~8 degrees of z */
  double shear;     /* shell and beam: transverse shear correction k (0: 5/6) */
  int rotary;       /* shell and beam: DTM_ROTARY_SCALED_INERTIA (the default) or
                       DTM_ROTARY_PHYSICAL_INERTIA, see dtm_section_bounds */
  int is_default;   /* default="true": for elements of the analysed dimension in no sectioned group */
  int ngroups;      /* number of group references */
  char **groups;    /* [ngroups] physical group names or numbers, as written (owned by the scene) */
  const char *file; /* scene file (not owned) */
  int line;         /* line of its <section> element */
} dtm_section;

/* Rotary inertia conventions of shell and beam sections (the scene's
 * rotary="scaled" | "physical"). */
enum { DTM_ROTARY_SCALED_INERTIA = 0, DTM_ROTARY_PHYSICAL_INERTIA = 1 };

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

/* 1 for the kinds whose nodes carry rotations (shell, beam). */
DTM_EXPORT int dtm_section_has_rotations(int k);

/* One shell or beam element's eigenvalue bounds (1/s^2) and lumped masses.
 * The critical step is 2/sqrt(lambda). With physical rotary inertia a
 * shell's thickness-shear mode (12 k G/(rho t^2)) or a beam's shear-rotation
 * mode (k G A/(rho I)) governs whatever the element size; explicit codes
 * therefore scale the rotary inertia so that the membrane (shell) or axial
 * (beam) mode governs. rotary = DTM_ROTARY_SCALED_INERTIA multiplies every
 * rotary inertia of the element by the smallest scale s >= 1 that brings
 * lambda down to lambda_reference (exact, not bisected); physical keeps
 * s = 1. Rotary inertia is the same about every axis of a node, so the
 * lumped mass is diagonal in any frame: a shell's J_a = t^2/12 m_a (m_a its
 * translational mass), a beam's rho L/2 min(I_y, I_z) (the smaller
 * principal inertia: the conservative isotropic choice; the torsional
 * inertia rho L/2 (I_y + I_z) is larger). */
typedef struct {
  double lambda;           /* under the section's convention: what the element's step uses */
  double lambda_physical;  /* physical rotary inertia (s = 1) */
  double lambda_reference; /* membrane alone (shell) or axial alone, 4 E/(rho L^2) (beam) */
  double scale;            /* s of the convention (1: physical) */
  int nn;                  /* nodes */
  double mt[4];            /* translational lumped mass of each node, kg (the same on x, y, z) */
  double mr[4];            /* rotary inertia of each node about every axis, kg m^2, under the convention */
} dtm_section_bounds;

/* Bounds of the element of type (DTM_TRI3 or DTM_QUAD4 for a shell, DTM_LINE2
 * for a beam) with nodes x[nn][3] (m), material E (Pa), nu, rho (kg/m^3),
 * section s (its thickness or area included in the masses). DTM_ERR_INPUT
 * (with a message) for another kind or type, bad values, a degenerate
 * element, or a scaled convention that no finite scale satisfies. */
DTM_EXPORT int dtm_section_element(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                                   dtm_section_bounds *out);
/* The same, except that under the scaled convention lambda_physical is NaN
 * (not computed) when one Cholesky factorisation proves it below screen
 * (> 0; 0: always computed): what a section's smallest physical step
 * needs, once screen is the largest lambda_physical found so far. */
DTM_EXPORT int dtm_section_element_screened(const dtm_section *s, int type, double E, double nu, double rho,
                                            const double *x, double screen, dtm_section_bounds *out);
/* The same for an element whose lambda under the physical convention is
 * known (the element map's, 4/dt^2): the masses alone are computed, with
 * the kernel's checks; lambda_reference is NaN. Under the scaled
 * convention, dtm_section_element. */
DTM_EXPORT int dtm_section_element_known(const dtm_section *s, int type, double E, double nu, double rho,
                                         const double *x, double lambda, dtm_section_bounds *out);
/* The same without lambda_physical (NaN) under the scaled convention: the
 * step, the scale and the masses from two small eigenproblems (the
 * reference block and the rotary scale's Schur complement) instead of four,
 * since lambda = lambda_reference whenever the scale is finite. What the
 * element map, the nodal bound and the operator use; with the physical
 * convention it is dtm_section_element. */
DTM_EXPORT int dtm_section_element_step(const dtm_section *s, int type, double E, double nu, double rho,
                                        const double *x, dtm_section_bounds *out);
/* The element's lambda under its section's convention, alone: for a shell
 * under the scaled convention with a shear factor <= 1 (its scale is then
 * finite) the membrane eigenvalue of the element, from the plane-stress
 * kernel directly; else as dtm_section_element_step. */
DTM_EXPORT int dtm_section_element_lambda(const dtm_section *s, int type, double E, double nu, double rho,
                                          const double *x, double *lambda);

#endif
