/* What a run costs, and the two ways around a small step that do not
 * remesh: mass scaling and subcycling. Computed from an analysis and its
 * recommended step, the one basis of every number here; the results are
 * objects of their own, owned by the caller. Arrays over elements follow
 * the analysis's global element order. */
#ifndef DTMAP_COST_H
#define DTMAP_COST_H

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/selective.h"
#include "dtmap/export.h"

/* Mass scaling to reach the target step dt_t (s, compared with the
 * estimates before the safety factor: pass target / safety). Two ways,
 * one per basis:
 *  - element by element (dtm_mass_scaling_compute, the element-bound
 *    basis): as LS-DYNA's DT2MS does it, every element whose own wave step
 *    dt_e (the smallest over the wave-type effects, damping included) is
 *    below dt_t gets m_e ((dt_t/dt_e)^2 - 1), since dt ~ sqrt(m);
 *  - at the nodes (dtm_mass_scaling_nodal, the nodal-bound basis), as
 *    Radioss's nodal time step control does it: the nodal bound
 *    lambda_a = sum_e lambda_e m_ea / m_a keeps its numerator when mass is
 *    added at node a, so node a needs m_a ((dt_t/dt_a)^2 - 1) to bring its
 *    step dt_a to dt_t, and the bound stays rigorous. Non-spectral wave
 *    effects (cohesive) are scaled element by element first. Each node's
 *    mass is attributed to its elements in proportion to their share of it.
 * With damping the factor is taken as unchanged by the added mass (exact
 * for a constant xi, conservative for stiffness-proportional damping).
 * Elements limited only by non-wave effects get none (mass does not change
 * a diffusion limit). */
typedef struct dtm_mass_scaling_s {
  double target;       /* dt_t, s */
  int nodal;           /* 1: added at the nodes, 0: element by element */
  double *added;       /* [nel] added mass, kg (per unit thickness in 2D) */
  double total_mass;   /* mass of the analysed elements, kg */
  double total_added;  /* sum of added, kg */
  size_t scaled;       /* elements that receive mass */
  int ngroups;         /* mesh groups + 1: the last slot is "no group" */
  double *group_mass;  /* [ngroups] */
  double *group_added; /* [ngroups] */
  double *node_added;  /* [nnodes] mass added at each node, kg, indexed like the mesh's
                          nodes (the nodal form; NULL for the element-by-element one) */
  size_t nodes;        /* nodes that receive mass (the nodal form) */
} dtm_mass_scaling;

DTM_EXPORT int dtm_mass_scaling_compute(const dtm_analysis *a, double target, dtm_mass_scaling *ms);
/* At the nodes; only (NULL: every element) restricts it to the elements
 * with only[i] != 0 and their nodes. */
DTM_EXPORT int dtm_mass_scaling_nodal(const dtm_analysis *a, double target, const unsigned char *only,
                                      dtm_mass_scaling *ms);
/* The element shares, group sums and totals of given point masses kg[nnodes]
 * (kg at each node): each node's mass shared out to its elements by their
 * share of its lumped mass; target (s) is only recorded. */
DTM_EXPORT int dtm_mass_scaling_of_nodes(const dtm_analysis *a, const double *kg, double target, dtm_mass_scaling *ms);
DTM_EXPORT void dtm_mass_scaling_free(dtm_mass_scaling *ms);
/* Point masses at the nodes that lift analysis a's recommended step to a
 * target (src/cost/point_masses.c): on the nodal basis the rule of
 * dtm_mass_scaling_nodal; on the global basis (global = 1) the lesser of
 * that rule aimed until the global estimate, run again with the masses,
 * meets the target, and the nodes of the top mode given the mass that
 * lowers its eigenvalue. a keeps them (on top of those it carried) when
 * they meet the target within max_percent % of the mass of its analysed
 * elements; otherwise it is put back as it was. */
#define DTM_MASS_CAP 100.0 /* % of the model's mass past which the search gives up */
typedef struct {
  double target;      /* the recommended step to reach, s */
  int global;         /* 1: on the global estimate, run again with the masses */
  double tol;         /* its relative residual (0: 1e-4) */
  int lanczos_max;    /* its Lanczos steps at most (0: 400) */
  double max_percent; /* the share of the model's mass a may keep, % */
} dtm_mass_aim;
typedef struct {
  int met;           /* masses were found that meet the target */
  int kept;          /* ... within max_percent: a carries them */
  double percent;    /* their share of the model's mass, % (NaN: none found) */
  double added;      /* kg added (kept only) */
  size_t nodes;      /* nodes that got some (kept only) */
  double model_mass; /* the mass of the analysed elements, kg */
} dtm_mass_found;
DTM_EXPORT int dtm_mass_points(dtm_analysis *a, const dtm_mass_aim *aim, dtm_mass_found *out);
/* The lumped mass of each node, kg (per unit thickness in 2D), into
 * m[nnodes]: its elements' shares (rho V times their lumped weights) and
 * the point mass it carries. */
DTM_EXPORT int dtm_mass_lumped(const dtm_analysis *a, double *m);

/* Subcycling levels from the recommended step: element e is on level k
 * when its own safe step (dtm_analysis_local_step, the larger of its
 * element bound and the smallest nodal bound at its nodes, per effect) lies
 * in [b 2^k, b 2^(k+1)), b the basis of dt.recommended (before safety), so
 * level 0 steps at dt.recommended itself; an element below b (possible only
 * when the global estimate is the basis, which holds for the whole mesh)
 * is on level 0. Every level is >= 0, so the ideal speed-up
 * N / sum_k N_k 2^-k is >= 1. */
#define DTM_MAX_LEVELS 64
typedef struct dtm_subcycling_s {
  int *level;                   /* [nel] */
  int nlevels;                  /* highest level + 1 */
  size_t count[DTM_MAX_LEVELS]; /* elements per level */
  double speedup;               /* N / sum_k N_k 2^-k */
  double basis;                 /* the step of level 0: dt.recommended, s */
} dtm_subcycling;

DTM_EXPORT int dtm_subcycling_compute(const dtm_analysis *a, dtm_subcycling *sc);
/* The level rule on its own: own[n] steps against basis b (same units). */
DTM_EXPORT int dtm_subcycling_levels(const double *own, size_t n, double b, dtm_subcycling *sc);
DTM_EXPORT void dtm_subcycling_free(dtm_subcycling *sc);

/* What a run of the scene's duration costs on an analysed mesh, all from
 * one step: dt.recommended. */
struct dtm_measures;
typedef struct dtm_cost {
  double duration;                   /* the scene's <time duration>, s (0: none) */
  double basis;                      /* the step used: dt.recommended, s */
  double steps;                      /* ceil(duration / basis) (NaN: no duration) */
  double element_steps;              /* elements x steps (NaN: no duration) */
  double element_steps_subcycled;    /* element_steps / speedup: never above it */
  dtm_subcycling subcycling;         /* levels from the basis */
  dtm_mass_scaling *mass;            /* to reach the scene's target from the basis, or NULL */
  dtm_mass_scaling *shape_mass;      /* the mass the shape-limited elements' nodes need
                                        to reach the target, or NULL when none */
  dtm_mass_scaling *layer_mass;      /* the same for the thickness-limited ones only (per
                                        group: group_added), or NULL when none */
  double per_element_step;           /* run time of one element-step, s (dtm_cost_per_element_step) */
  char per_element_step_source[320]; /* where that figure came from */
  double hours;                      /* element_steps x per_element_step / 3600 (NaN: no duration) */
  double hours_subcycled;            /* the same with ideal subcycling */
  struct dtm_measures *measures;     /* accuracy at the recommended step (dtm_measures_compute) */
  double seconds;                    /* wall time of dtm_cost_create, s (the measures included) */
  double seconds_measures;           /* of which the accuracy measures, s */
} dtm_cost;

/* The cost of analysis a: subcycling levels always; mass scaling when the
 * scene has a target (every step of the basis brought to target / safety,
 * at the nodes for a nodal or global basis, element by element for the
 * element bound). *out is owned by the caller (dtm_cost_destroy). */
DTM_EXPORT int dtm_cost_create(const dtm_analysis *a, dtm_cost **out);
DTM_EXPORT void dtm_cost_destroy(dtm_cost **c);

/* The run time of one element-step, s, into *seconds and where it comes
 * from into source[len]: the scene's <time cost-per-element-step>, else
 * dtmap's calibration (dtm_cost_calibrated_ns) weighted by the mesh's
 * element types. */
DTM_EXPORT int dtm_cost_per_element_step(const dtm_analysis *a, double *seconds, char *source, size_t len);
/* The same for a mesh of `elements` elements in all, a's types weighted as
 * in a (a distributed run: the whole mesh's count for the calibration's
 * switch, each part's analysis holding a share of it). */
DTM_EXPORT int dtm_cost_per_element_step_of(const dtm_analysis *a, double elements, double *seconds, char *source,
                                            size_t len);
/* dtmap's calibration for one element type in a mesh of `elements`
 * elements (all types), ns per element-step (CalculiX 2.20 explicit, one
 * thread; a type not calibrated takes the nearest). */
DTM_EXPORT double dtm_cost_calibrated_ns(int type, double elements);
/* Time of one element-step of CalculiX's element elem ("C3D4", "S3") in
 * Debian's ccx 2.20, one thread, in a mesh of `elements` elements (all
 * types), measured on dtmap's decks by bench/ccx_cost.py
 * (src/cost/ccx_cost.inc), ns: the figure of a mesh below the table's
 * switch (ccx's per-increment arrays below glibc's mmap threshold) or beyond it; NaN when
 * not measured. */
DTM_EXPORT double dtm_cost_ccx_ns(const char *elem, double elements);
/* The bound of integration points per element that Debian's ccx 2.20
 * sizes its per-element arrays with (6 doubles per point and element,
 * copied several times every increment) for a deck of the n CalculiX
 * elements elems in explicit dynamics: the largest of the elements' own
 * counts, which *DYNAMIC then raises (1 and 8 to 27, 4 to 15, 2 to 9), as
 * its allocation.f does; C3D4 alone gives 27, C3D4 with M3D3 9. */
DTM_EXPORT int dtm_cost_ccx_points(const char *const *elems, int n);
/* dtm_cost_ccx_ns for a deck whose bound is `points` (dtm_cost_ccx_points):
 * the figure measured on elem's deck alone plus the table's cost per point
 * of the bound and element-step (src/cost/ccx_cost.inc) times the
 * difference of the two bounds. */
DTM_EXPORT double dtm_cost_ccx_ns_at(const char *elem, double elements, int points);
/* The CalculiX element whose figure stands for a dtmap type (its own, else
 * the nearest calibrated type's); NULL when the type is not known. */
DTM_EXPORT const char *dtm_cost_calibrated_elem(int type);
/* The table's switch, elements: a mesh of more elements takes the figures
 * measured beyond it (bench/ccx_cost.py, measured on C3D4). */
DTM_EXPORT double dtm_cost_ccx_switch(void);

/* Element-steps to cover the scene's duration (NaN without one): every
 * element takes ceil(duration / recommended) steps. Subcycled: the same
 * divided by the ideal speed-up, (N ceil(duration / recommended)) /
 * speedup, so never above the plain cost. */
DTM_EXPORT double dtm_cost_element_steps(const dtm_analysis *a);
DTM_EXPORT double dtm_cost_element_steps_subcycled(const dtm_analysis *a, const dtm_subcycling *sc);

/* The discrete dispersion of central differences with lumped mass on the
 * regular lattice of an element type (src/cost/dispersion.c: Bloch
 * analysis of the periodic patch; bar, tri3, tri6, quad4, tet4, tet10,
 * hex8). shape: the lattice (dtm_lattice); r = mu / (lam + 2 mu) of the
 * formulation (0 for the bar); kh the wavenumber times the lattice spacing
 * h (the cell edge of a cell of volume h^d); n[3] a unit direction. */
typedef enum {
  DTM_LATTICE_CUBE = 0,    /* the unit square or cube; simplices cut along its main diagonal (right-angled) */
  DTM_LATTICE_REGULAR = 1, /* simplices as regular as a tiling allows (equilateral; body-centred cubic) */
  DTM_LATTICE_OWN = 2,     /* a table from the mesh's own element shapes (dtm_dispersion_table_shapes) */
  DTM_LATTICE_MESH = 3,    /* a structured mesh's own lattice (dtm_dispersion_table_mesh) */
  DTM_LATTICE_MEASURED = 4 /* measured on Gmsh's unstructured meshes (dtm_dispersion_table_measured) */
} dtm_lattice;
/* The name of a model (dtm_lattice) for reports: "cube lattice", "regular
 * lattice", "own shapes", "structured lattice", "measured". */
DTM_EXPORT const char *dtm_dispersion_model_name(int shape);
/* The semi-discrete relative phase-speed errors omega_h / (c k) - 1 of the
 * P branch (err[0]) and the S branch (err[1], the worse of the two in 3D;
 * 0 for the bar) at the wave vector kh n. */
DTM_EXPORT int dtm_dispersion_space(int type, int shape, double r, double kh, const double n[3], double err[2]);
/* The same for the one branch whose Bloch eigenvector overlaps most with
 * the plane wave polarised along the unit vector pol (mode 0: normalised
 * by the P speed, 1: by the S speed), into *err. */
DTM_EXPORT int dtm_dispersion_polarised(int type, int shape, double r, double kh, const double n[3],
                                        const double pol[3], int mode, double *err);
/* 1 when type has a lattice model (bar, tri3, tri6, quad4, tet4, tet10, hex8). */
DTM_EXPORT int dtm_dispersion_has_model(int type);
/* Elements of type per lattice cell: 2 for triangles, 6 for tetrahedra
 * (first or second order), 1 otherwise; the lattice spacing of an element
 * of measure V is (n V)^(1/d). */
DTM_EXPORT int dtm_dispersion_cell_elements(int type);
/* Central differences on top: a semi-discrete error `space` and
 * x = omega_h dt / 2 give the relative phase-speed error of the fully
 * discrete scheme, (1 + space) asin(x) / x - 1 (NaN when x > 1: unstable). */
DTM_EXPORT double dtm_dispersion_time(double space, double x);

#define DTM_DISP_DIRS 48 /* directions of a table (3D; 2D: 24, 1D: 1) */
#define DTM_DISP_KH 16   /* points in k h over (0, pi] */
/* The semi-discrete errors of one element type and r over directions and
 * k h, stored as err / (k h)^2 (smooth in k h), once per type and material. */
typedef struct {
  int type;                                /* element type */
  double r;                                /* mu / (lam + 2 mu) */
  int shape;                               /* dtm_lattice */
  size_t samples;                          /* DTM_LATTICE_OWN, _MESH: the elements it was built from */
  double per_cell;                         /* elements per lattice cell: an element of measure V is at
                                              k h with h = (per_cell V)^(1/d); 0: h its mean edge */
  int ndir;                                /* directions used */
  double dir[DTM_DISP_DIRS][3];            /* unit directions */
  double g[2][DTM_DISP_DIRS][DTM_DISP_KH]; /* [P, S][dir][k h = pi (j + 1) / DTM_DISP_KH] */
} dtm_dispersion;
DTM_EXPORT int dtm_dispersion_table(int type, int shape, double r, dtm_dispersion *t);
/* The fully discrete error of branch mode (0 P, 1 S) of largest magnitude
 * over the table's directions at k h = kh, with x = c k dt / 2 (c that
 * branch's exact speed); NaN when kh > pi (fewer than 2 cells per
 * wavelength: unresolved) or unstable. */
DTM_EXPORT double dtm_dispersion_worst(const dtm_dispersion *t, int mode, double kh, double x);
/* The semi-discrete error of branch mode along the table's direction dir
 * at k h = kh, interpolated (NaN when kh > pi). */
DTM_EXPORT double dtm_dispersion_at(const dtm_dispersion *t, int mode, int dir, double kh);
/* The same as dtm_dispersion_worst, and the index of its direction into *dir (NULL: not wanted). */
DTM_EXPORT double dtm_dispersion_worst_dir(const dtm_dispersion *t, int mode, double kh, double x, int *dir);

/* The measured dispersion of Gmsh's unstructured tetrahedral meshes
 * (src/cost/measured.c; the table bench/tet_dispersion.py measures by
 * simulation): tet4 and tet10, P and S along the axes, the face and the
 * body diagonals, k h with h an element's mean edge, interpolated in r
 * between the Poisson's ratios measured (0.15 to 0.45; clamped outside). */
DTM_EXPORT int dtm_dispersion_has_measured(int type);
DTM_EXPORT int dtm_dispersion_table_measured(int type, double r, dtm_dispersion *t);

/* A structured mesh (src/cost/structured.c): when the elements of type
 * and material mat (no section) of mesh are the translates of at most 12
 * shapes (one of each per cell, at most 8 node classes) by one lattice (a transfinite or extruded mesh of
 * a box), *found = 1 and t is that lattice's exact Bloch table
 * (t->shape = DTM_LATTICE_MESH); else *found = 0 and t is untouched. */
DTM_EXPORT int dtm_dispersion_table_mesh(const dtm_mesh *mesh, int type, int mat, double r, dtm_dispersion *t,
                                         int *found);

/* The dispersion of a mesh's own element shapes (src/cost/shapes.c), for
 * tri3, quad4 and hex8. */
DTM_EXPORT int dtm_dispersion_has_shapes(int type);
/* The table of dtm_dispersion_table from n elements of the mesh, x[n][nn][3]
 * (each scaled to its lattice spacing; the sum of their plane-wave dynamic
 * matrices over the sum of their masses): t->shape = DTM_LATTICE_OWN. */
DTM_EXPORT int dtm_dispersion_table_shapes(int type, double r, const double *x, size_t n, dtm_dispersion *t);
/* One element's plane-wave dynamic matrix D[3][3] (the d x d block used):
 * sum_ab K_ab cos(k.(x_b - x_a)) of its stiffness K for Lame lam, mu at
 * full integration, nodes x[nn][3], wave vector k (1/length). */
DTM_EXPORT int dtm_dispersion_element(int type, const double *x, double lam, double mu, const double k[3], double D[9]);
/* The eigenvalues w[d] of the symmetric D[d][d] (stride 3): first the one
 * whose eigenvector lies most along the unit vector v, then the others
 * (omega^2 of each branch once D is divided by the mass). */
DTM_EXPORT void dtm_dispersion_branches(int d, const double D[9], const double v[3], double w[3]);

/* Accuracy measures of an analysed mesh at its step (src/cost/accuracy.c):
 * one per effect the scene names (cohesive: one per group). */
typedef enum {
  DTM_MEASURE_PHASE = 1,    /* elastic: phase-speed error at the frequency of interest (fraction) */
  DTM_MEASURE_ZONE = 2,     /* cohesive: elements per process zone */
  DTM_MEASURE_DIFFUSION = 3 /* thermal, hydraulic: elements across sqrt(D duration) */
} dtm_measure_kind;
#define DTM_BAND_PHASE 0.01    /* phase-speed error accepted: 1 % */
#define DTM_BAND_DIFFUSION 5.0 /* elements across the diffusion length accepted (dtmap's choice) */

typedef struct {
  int kind;                   /* dtm_measure_kind */
  int effect;                 /* scene index of the effect */
  int group;                  /* cohesive: mesh group index (-1: elements in no group); else -1 */
  double worst;               /* phase: the signed error of largest magnitude (NaN when any element is
                                 unresolved or none applies); counts: the smallest */
  double median;              /* phase: median signed error; counts: median count (NaN: none) */
  size_t worst_element;       /* global element index of the worst */
  double worst_alone;         /* phase: the same with every element at its own spacing, where worst takes the
                                 measured table's elements at the mean over SMOOTH_PASSES (3) rings of
                                 elements around them (src/cost/accuracy.c); equal elsewhere (NaN: unresolved) */
  size_t worst_alone_element; /* phase: global element index of worst_alone */
  int rings;                  /* phase: the rings of elements worst averages over (0: no element is averaged) */
  size_t elements;            /* elements measured */
  size_t unresolved;          /* phase: elements with fewer than 2 lattice cells per wavelength */
  double band_lo;             /* the accepted band: phase [-band_hi, band_hi]; zone [5, 10]; */
  double band_hi;             /* diffusion [DTM_BAND_DIFFUSION, inf) */
  int in_band;                /* 1: worst inside (zone, diffusion: at or above band_lo) */
  double f;                   /* phase: the frequency, Hz */
  int f_default;              /* phase: 1 when the scene names no f-max and f is the mesh's default */
  double per_wavelength;      /* phase: the smallest shear wavelength at f over the element's mean edge
                                 (the elastic effect's "elements per wavelength", also without f-max) */
  int wave;                   /* phase: the branch of the worst, 0 P, 1 S (-1: none) */
  double direction[3];        /* phase: the direction of the worst (unit; the model's direction) */
  int model;                  /* phase: the model of the worst's elements (dtm_lattice; -1: none) */
  char note[640];             /* one line when something is missing or assumed ("" when not) */
} dtm_measure;

typedef struct dtm_measures {
  int n;          /* measures */
  dtm_measure *m; /* [n] in scene effect order (owned) */
} dtm_measures;

/* The step each element takes, for dtm_measures_compute (NULL: the
 * recommended step everywhere). */
typedef struct {
  const int *level;    /* [nel] subcycling levels: recommended x 2^level (NULL: none) */
  double target;       /* > 0: every element steps at it (mass scaling) */
  const double *added; /* [nel] mass added to reach it (dtm_mass_scaling.added) or NULL */
} dtm_measure_step;

/* The measures of analysis a. f > 0: the frequency of the phase error, Hz
 * (else the scene's f-max, else the mesh's default: the smallest over the
 * elements of c_S / (N h), N = elements-per-wavelength, h the lattice
 * spacing: every element has at least N cells per shear wavelength). *out is owned by
 * the caller (dtm_measures_destroy). */
DTM_EXPORT int dtm_measures_compute(const dtm_analysis *a, double f, const dtm_measure_step *st, dtm_measures **out);
DTM_EXPORT void dtm_measures_destroy(dtm_measures **m);
/* Name of a dtm_measure_kind, for tables. */
DTM_EXPORT const char *dtm_measure_name(int kind);

/* The prediction of one wave along one direction (for the simulation
 * check, src/study/wave.c; src/cost/along.c): the fully discrete error of
 * branch mode (0 P, 1 S: the worse transverse branch in 3D) along the unit
 * direction n at frequency f (Hz) and step dt (s), with the measure's
 * models: for tri3, quad4 and hex8 of one material (mat >= 0), and a
 * structured grid, the wave's Rayleigh quotient over their summed
 * plane-wave matrices (dtm_dispersion_element); a structured lattice's
 * Bloch branch; the measured table of unstructured tetrahedra in its
 * direction class nearest n, at the root mean square of the elements' mean
 * edges; the regular lattice of the other types, element by element. The
 * parts are averaged with the element masses as weights (a plane wave's
 * frequency shift is the energy-weighted mean of the local ones to first
 * order; with mat = -1, all materials, every element counts on its own).
 * pol: the polarisation (unit; the branch whose eigenvector overlaps most
 * with it; NULL: n for P, the worse transverse branch for S). */
typedef struct {
  double mean;       /* mass-weighted mean error (fraction; NaN when any element is unresolved) */
  double worst;      /* the signed error of largest magnitude, each element on its own (fraction) */
  size_t elements;   /* elements measured */
  size_t unresolved; /* elements with k h > pi or unstable */
  double speed;      /* the exact speed of the branch in the (last) material measured, m/s */
  int model;         /* the model of the (last) elements measured (dtm_lattice; -1: none) */
} dtm_phase_along;
DTM_EXPORT int dtm_measures_phase_along(const dtm_analysis *a, double f, double dt, const double n[3],
                                        const double pol[3], int mode, int mat, dtm_phase_along *out);

/* The accuracy price of mass scaling in natural frequencies
 * (src/cost/modes_price.c): the lowest n elastic modes of the model (the
 * first elastic effect's operator; dtm_modes_lowest) and, for each modified
 * model (a variant: conventional point masses reaching a target, or any
 * added mass matrix a caller gives, such as selective mass scaling), its
 * modes matched to the model's by MAC and each one's frequency shift
 * (dtm_modes_compare). A variant computes DTM_PRICE_SPARE elastic modes more
 * than the model, so that a mode pushed past the n-th still finds its
 * match. */
#define DTM_PRICE_VARIANTS 4
#define DTM_PRICE_SPARE 4
typedef struct {
  const char *name;      /* "conventional mass", "selective mass", ... (static) */
  int computed;          /* 1: modes computed and compared */
  const char *why;       /* when not: why, in words (static); else NULL */
  double added_mass;     /* mass added, kg (per unit thickness in 2D): its translational inertia added */
  double added_percent;  /* its share of the model's mass, % */
  size_t nodes;          /* nodes that got mass (point masses), else 0 */
  double deformation;    /* selective mass: the trace of its added mass per direction, kg (it all goes into
                            the deformation modes; added_mass, the translational share, is 0); else 0 */
  dtm_modes modes;       /* its modes (owned) */
  dtm_mode_shift *shift; /* [base.nelastic] each model mode's match and shift (owned) */
} dtm_modes_variant;
typedef struct dtm_modes_price {
  int effect;        /* the elastic effect whose operator (index) */
  int n;             /* elastic modes asked */
  double target;     /* the target step of the conventional variant, s (0: none) */
  double model_mass; /* the lumped mass of the model (its analysed elements and point masses), kg */
  dtm_modes base;    /* the model's modes (owned) */
  int nvariants;     /* variants, in the order added */
  dtm_modes_variant variant[DTM_PRICE_VARIANTS];
  dtm_operator *op; /* the model's operator (owned): the unknowns every variant's extra mass is over */
} dtm_modes_price;
/* The model's lowest n elastic modes (and its rigid ones) into p (zeroed
 * first; dtm_modes_price_free also after an error). DTM_ERR_INPUT when no
 * effect is elastic, or for shells and beams. */
DTM_EXPORT int dtm_modes_price_base(const dtm_analysis *a, int n, dtm_modes_price *p);
/* A variant: the model with extra (over p->op's unknowns, dtm_csr), added_mass
 * kg of translational mass (for the report), its modes and shifts. */
DTM_EXPORT int dtm_modes_price_add(dtm_modes_price *p, const char *name, const dtm_csr *extra, double added_mass);
/* The conventional variant: the point masses that lift every nodal bound
 * of a, hence its recommended step, to target (s, safety included), by the
 * rule `deck --target` adds (dtm_mass_scaling_nodal at target / safety),
 * as a diagonal extra mass. A target a already meets adds no mass (shifts
 * 0); without a nodal bound the variant is not computed, with why. */
DTM_EXPORT int dtm_modes_price_conventional(const dtm_analysis *a, double target, dtm_modes_price *p);
/* The selective variant: the added mass of m (dtm_analysis_selective_mass
 * of a, on the same elastic effect as p) as an extra matrix; its target
 * becomes p's when p has none. */
DTM_EXPORT int dtm_modes_price_selective(const dtm_analysis *a, const dtm_selective_mass *m, dtm_modes_price *p);
DTM_EXPORT void dtm_modes_price_free(dtm_modes_price *p);

#endif
