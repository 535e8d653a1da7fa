/* One dtmap analysis: scene + mesh + effects -> per-element steps, the
 * limiting effect, characteristic lengths, the nodal bound, the size
 * suggestion and the recommended step. The analysis is an opaque handle
 * (its layout is private to src/analysis/); everything it computed is read
 * through the accessors below. Arrays over elements follow the mesh's block
 * order (block 0's elements, then block 1's, ...) and are indexed by the
 * "global element index" i; arrays over nodes follow the mesh's node order.
 * Returned arrays and strings are owned by the analysis and live as long
 * as it does. Steps are in s, lengths in m. */
#ifndef DTMAP_ANALYSIS_H
#define DTMAP_ANALYSIS_H

#include <stddef.h>

#include "dtmap/export.h"
#include "dtmap/gmsh.h"
#include "dtmap/mesh.h"
#include "dtmap/operator.h"
#include "dtmap/effect_set.h"
#include "dtmap/registry.h"
#include "dtmap/scene.h"

typedef struct dtm_analysis dtm_analysis;

/* The minima of one effect. */
typedef struct {
  double min;           /* smallest element step of this effect, s (NaN if it does not limit) */
  size_t element;       /* global element index where it occurs */
  int element_rigorous; /* 0 when the element steps come from a length rule
                           (length=min-edge, ...) that is not a bound: then
                           only the nodal and global estimates vouch */
  double nodal;         /* its nodal bound, s (NaN if not spectral) */
  size_t node;          /* node index where the nodal bound occurs */
  double global;        /* its global (Lanczos) estimate, s (NaN if not computed) */
  double certified;     /* the step of the probable bound (dtm_global_info.dt_certified) when the global
                           estimate is the basis without a deterministic proof, s; NaN otherwise */
  double safe;          /* the step dtmap vouches for, s: global (safe side of the
                           bracket) if converged and allowed as the basis, else
                           nodal, else element */
  double omega;         /* waves: undamped top angular frequency where the
                           basis of this effect sits (its nodal-bound node, or
                           its smallest element), rad/s; NaN otherwise */
} dtm_effect_min;

/* The global (Lanczos) estimate of one spectral effect. */
typedef struct {
  int done;                 /* 1 when computed */
  double theta;             /* largest Ritz value of M^-1 K */
  double residual;          /* an eigenvalue lies in theta +- residual */
  int iterations;           /* Lanczos steps */
  int converged;            /* invariant subspace, or residual <= tol theta */
  double seconds;           /* wall time */
  double dt_low;            /* step from theta + residual + quad_err: the safe side, s */
  double dt_high;           /* step from theta: never safe to exceed, s */
  double omega_top;         /* sqrt(theta + residual) (waves), for damping */
  double *mode;             /* [ndof] top Ritz vector (u^T M u = 1), or NULL; owned by the analysis */
  int certified;            /* DTM_CERT_* (dtmap/operator.h): DTM_CERT_PROVEN when theta + residual was shown to
                               bound every eigenvalue by the factorisation of (theta + residual) I - A;
                               DTM_CERT_PROBABLE when the Kuczynski-Wozniakowski bound holds instead */
  int deterministic;        /* DTM_CERT_* of the factorisation alone (why no proof, when probable) */
  double eps;               /* probable: the bound's relative gap eps_k after iterations steps; NaN otherwise */
  double failure;           /* probable: its failure probability (1e-12); NaN otherwise */
  double nbound;            /* probable: the order n of the bound (dofs with mass) */
  unsigned seed;            /* the start vector's seed */
  double dt_certified;      /* probable: the step of theta / (1 - eps) (rounding allowance included), s; at
                               most the exact step but with probability failure; NaN otherwise */
  double cert_predicted[2]; /* the factorisation's predicted flops and bytes (NaN: not predicted) */
  double cert_budget;       /* the flops it was allowed (the run's own cost, src/analysis/global.c) */
  double cert_seconds;      /* wall time of the certificate: analysis, assembly, factorisations */
  double quad_err;          /* the most the top eigenvalue of the converged integration can lie above this
                               model's, from the curved elements' remaining quadrature error (0 without
                               any): dt_low is the step from theta + residual + quad_err, dt_certified
                               from the probable bound + quad_err */
} dtm_global_info;

/* Accuracy bookkeeping: accuracy bounds (cohesive R/N, wavelength/N)
 * against the element sizes and against the target step. */
typedef struct {
  size_t under_resolved; /* elements with h > hmax */
  size_t conflicts;      /* elements whose size for the target exceeds hmax */
  double dt_cap;         /* smallest recommended step allowed at h = hmax among
                            the conflicting elements, s (NaN: none) */
  size_t cap_element;    /* global index of that element */
  double forced;         /* elements the accuracy bounds add to a mesh at the
                            size suggestion (the clamp's share, estimated as
                            sum_e (h_e/h_clamped)^d - (h_e/h_free)^d) */
  int forced_by;         /* effect whose bound adds most of them (-1: none) */
} dtm_accuracy;

/* What makes an element below the target keep a small step at any size
 * the geometry allows there (src/analysis/shape.c). */
typedef enum {
  DTM_FEATURE_FLAT_ANGLE = 1,  /* a near-flat angle (>= 150 deg) between model curves
                                  (2D) or surfaces (3D) held by this one element */
  DTM_FEATURE_SMALL_ANGLE = 2, /* a small angle (< 30 deg) between model curves or surfaces */
  DTM_FEATURE_SHORT_CURVE = 3, /* a model curve shorter than the size the target needs */
  DTM_FEATURE_THIN = 4         /* two boundaries that do not touch, closer than that size */
} dtm_feature_kind;

/* The cheapest remedy of a shape-limited element. */
typedef enum {
  DTM_REMEDY_SPLIT = 1,    /* local refinement that splits the angle */
  DTM_REMEDY_OPTIMISE = 2, /* an optimiser pass (edge/face swaps) */
  DTM_REMEDY_MASS = 3      /* mass scaling of its nodes (dtm_cost: shape_mass) */
} dtm_remedy;

typedef struct {
  size_t element; /* global element index */
  int feature;    /* dtm_feature_kind */
  double angle;   /* the model's angle there, degrees (NaN for short and thin) */
  int entity_dim; /* the model entity of the feature: 0 point, 1 curve */
  int entity_tag; /* its Gmsh tag (thin: one of the two boundaries) */
  double size;    /* the largest element size the feature allows, m */
  double quality; /* element step / step of the well-shaped element of its size */
  double reach;   /* the largest own safe step it can reach at that size, s
                     (safety included): below the target */
  int remedy;     /* dtm_remedy */
  double split;   /* DTM_REMEDY_SPLIT: local size at the feature that splits the
                     angle into well-shaped elements meeting the target, m */
  int other_dim;  /* thin: the other of the two boundaries (its dimension, -1 otherwise) */
  int other_tag;  /* thin: its Gmsh tag (-1 otherwise) */
  int layer;      /* thin: its layer's index in dtm_analysis_layers (-1 otherwise) */
} dtm_shape_limited;

/* Elements limited by the thickness of the part they are in (shape-limited
 * with the thin feature: two boundaries closer than the size the target
 * needs), gathered per layer: per physical group, the pair of model
 * boundaries the elements' thickness spans, joined with the pairs of its
 * group of the same thickness (within 10 % of the thinnest). No mesh of
 * that layer reaches the target there (src/analysis/layers.c). */
typedef struct {
  int group;         /* mesh group index (-1: in no group) */
  int faces[2][2];   /* two model boundaries it spans, {dim, tag} each, the smaller first
                        (of its thinnest pair when it joins several) */
  size_t elements;   /* its thickness-limited elements */
  double thickness;  /* the smallest local thickness among them (the gap between the two
                        boundaries at their corners), m */
  double reach;      /* the best own safe step any mesh of the layer reaches there: the
                        smallest reach of its elements (safety included), s */
  size_t worst;      /* global index of its element with the smallest step */
  double size;       /* mean size of those elements (mean edge), m */
  double shell_step; /* LS-DYNA's shell (or, in 2D, beam) rule at that size, size / c_p
                        with c_p = sqrt(E/(rho(1 - nu^2))) of the group's material, s;
                        NaN without E, nu, rho */
  int at_minimum;    /* 1: the scene has no target, and these are elements whose own step
                        is within 10 % of the smallest (at most 64 examined): the layer
                        caps the smallest steps; reach may lie above them */
} dtm_layer;

/* Stages the analysis times, s. */
enum { DTM_T_MESH, DTM_T_EXTRACT, DTM_T_EFFECTS, DTM_T_NODAL, DTM_T_GLOBAL, DTM_T_ADVICE, DTM_T_COUNT };

/* Run everything up to the views on scene s (which must outlive the
 * analysis): load/mesh through Gmsh, map groups to materials, create only
 * the scene's effects, compute. Gmsh must be started. */
DTM_EXPORT int dtm_analysis_run(const dtm_scene *s, dtm_analysis **out);
/* Called by dtm_analysis_run_ex once the mesh is extracted and before the
 * effects compute: the current Gmsh model (nelements analysed elements)
 * is no longer needed by the analysis, so the hook may write it
 * (dtm_output_begin) and release it (dtm_gmsh_release). A non-zero return
 * (a DTM_ERR_* code, with the error recorded) stops the run. */
typedef int (*dtm_extracted_fn)(void *user, size_t nelements);
/* dtm_analysis_run with that hook (NULL: none). */
DTM_EXPORT int dtm_analysis_run_ex(const dtm_scene *s, dtm_extracted_fn hook, void *user, dtm_analysis **out);
/* The same on the current Gmsh model, already meshed, in dimension dim. */
DTM_EXPORT int dtm_analysis_current(const dtm_scene *s, int dim, dtm_analysis **out);
/* Compute steps on an already extracted mesh with created effects (used by
 * dtm_analysis_run and by tests on hand-built blocks). Takes ownership of
 * mesh and effects. */
DTM_EXPORT int dtm_analysis_compute(const dtm_scene *s, dtm_mesh *mesh, dtm_effect *effects, int neffects,
                                    dtm_analysis **out);
DTM_EXPORT void dtm_analysis_destroy(dtm_analysis **a);

/* The global estimate of every spectral effect: Lanczos on the
 * lumped-mass generalized problem to relative residual tol, at most maxit
 * products. With DTM_GLOBAL_BASIS (run --posterior) a converged estimate
 * enters the recommendation on its safe side (theta + residual, then the
 * safety factor); without it, and for an unconverged one, the estimate is
 * reported and the recommendation keeps its basis (verify without
 * --posterior checks exactly the step run reports). DTM_GLOBAL_MODES: also
 * build each top Ritz vector (for dtm_verify; twice the products), with the
 * true residual; otherwise the residual is Paige's estimate. */
#define DTM_GLOBAL_MODES 1u
#define DTM_GLOBAL_BASIS 2u
DTM_EXPORT int dtm_analysis_estimate_global(dtm_analysis *a, double tol, int maxit, unsigned flags);

/* Point masses at the nodes, kg per node in the mesh's node order (per
 * unit thickness in a plane model), added to every wave effect's lumped
 * mass (src/analysis/point_mass.c): the mesh keeps a copy (kg NULL removes
 * them), and the nodal bound, the recommendation, each element's own step
 * and the advice are computed again; a global estimate made before is
 * dropped. The element steps do not change. Not in a distributed run. */
DTM_EXPORT int dtm_analysis_set_point_masses(dtm_analysis *a, const double *kg);
/* The point masses the analysed mesh carries (read with its .msh, view
 * DTM_VIEW_NODE_MASS, or set), kg per node, or NULL. */
DTM_EXPORT const double *dtm_analysis_point_masses(const dtm_analysis *a);

/* What was analysed. */
DTM_EXPORT const dtm_scene *dtm_analysis_scene(const dtm_analysis *a);
DTM_EXPORT const dtm_mesh *dtm_analysis_mesh(const dtm_analysis *a);
DTM_EXPORT size_t dtm_analysis_nelements(const dtm_analysis *a);

/* Curvature of the second-order elements (src/analysis/curvature.c). */
#define DTM_CURVED_STRONG 0.5 /* min det J / max det J below which an element is strongly curved */
typedef struct {
  size_t second_order;       /* second-order elements */
  size_t curved;             /* of which curved: a node off its straight place by more than 1e-9 of the edge */
  size_t strong;             /* of which strongly curved (jacobian ratio below DTM_CURVED_STRONG) */
  size_t sensitive;          /* of which rule sensitive: the elastic element step differs by more than 1e-3
                                between the full rules and the converged integration */
  double worst_ratio;        /* smallest min det J / max det J over the curved elements (1: none) */
  size_t worst_element;      /* its global element index ((size_t)-1: none, or in another part) */
  double max_offset;         /* largest node offset over the edge */
  double max_dependence;     /* largest relative step change between the two models */
  size_t dependence_element; /* its global element index ((size_t)-1: none) */
  int model;                 /* DTM_INTEGRATION_* the element steps are for */
} dtm_curvature_summary;
DTM_EXPORT const dtm_curvature_summary *dtm_analysis_curvature(const dtm_analysis *a);
/* [nel] min det J / max det J of each element (NaN for linear ones), or
 * NULL when the mesh has no second-order element. */
DTM_EXPORT const double *dtm_analysis_curvature_ratio(const dtm_analysis *a);
DTM_EXPORT int dtm_analysis_neffects(const dtm_analysis *a);
/* Nodes of the analysed mesh, and their Gmsh tags [nnodes] (the order of
 * the per-node arrays). */
DTM_EXPORT size_t dtm_analysis_nnodes(const dtm_analysis *a);
DTM_EXPORT const size_t *dtm_analysis_node_tags(const dtm_analysis *a);
/* The Gmsh tag of every element, in global element order, into the
 * caller's tags[nelements]. */
DTM_EXPORT void dtm_analysis_tags(const dtm_analysis *a, size_t *tags);
/* Class of effect k (scene order). */
DTM_EXPORT const dtm_effect_class *dtm_analysis_effect(const dtm_analysis *a, int k);

/* Where global element i is: block and index in it, Gmsh tag, centroid
 * (m), and the index of its physical group (-1: none). */
DTM_EXPORT void dtm_analysis_locate(const dtm_analysis *a, size_t i, int *block, size_t *local);
DTM_EXPORT size_t dtm_analysis_tag(const dtm_analysis *a, size_t i);
DTM_EXPORT void dtm_analysis_centroid(const dtm_analysis *a, size_t i, double c[3]);
DTM_EXPORT int dtm_analysis_group(const dtm_analysis *a, size_t i);

/* Per element [nelements]: the step (min over the limiting effects, before
 * the safety factor), the characteristic length of the limiting effect,
 * the index of the limiting effect, the element size (mean edge length),
 * the accuracy bound on the size (+inf: none) and the effect whose bound it
 * is (-1: none). */
DTM_EXPORT const double *dtm_analysis_dt(const dtm_analysis *a);
DTM_EXPORT const double *dtm_analysis_length(const dtm_analysis *a);
DTM_EXPORT const int *dtm_analysis_limiting(const dtm_analysis *a);
DTM_EXPORT const double *dtm_analysis_size(const dtm_analysis *a);
/* Per element: its measure (length, area or volume, m^d, as
 * dtm_elem_measure, unsigned), or NULL when the analysis does not keep it
 * (rank 0's whole-mesh advice in a distributed run). */
DTM_EXPORT const double *dtm_analysis_measure(const dtm_analysis *a);
DTM_EXPORT const double *dtm_analysis_hmax(const dtm_analysis *a);
DTM_EXPORT const int *dtm_analysis_hmax_by(const dtm_analysis *a);
/* Per element [nelements] for effect k: its own step (NULL when k limits
 * nothing; +inf where it does not apply), and its accuracy view's values
 * (NULL when k has none that applies; NaN where it does not apply). */
DTM_EXPORT const double *dtm_analysis_effect_dt(const dtm_analysis *a, int k);
/* The same before the damping factors (the row above where no damping
 * applies; NULL when k limits nothing). */
DTM_EXPORT const double *dtm_analysis_effect_dt_undamped(const dtm_analysis *a, int k);
DTM_EXPORT const double *dtm_analysis_resolution(const dtm_analysis *a, int k);

/* Per element [nelements]: its own safe step before the safety factor, s:
 * for each limiting effect the larger of its element step (when that is a
 * bound) and the smallest nodal bound at its nodes (spectral effects),
 * then the smallest over the effects; +inf where no effect limits it. The
 * subcycling levels and "below the target" use it. Per element for effect
 * k: its own accuracy bound on the size, m (NULL when k has none; +inf
 * where it does not apply). */
DTM_EXPORT const double *dtm_analysis_local_step(const dtm_analysis *a);
DTM_EXPORT const double *dtm_analysis_effect_hmax(const dtm_analysis *a, int k);

/* Per node [nnodes]: the size suggestion (NaN at nodes of no analysed
 * element), the nodal-bound step (min over the spectral effects; +inf
 * where none), and that of spectral effect k (NULL otherwise). */
DTM_EXPORT const double *dtm_analysis_size_suggestion(const dtm_analysis *a);
/* The size suggestion with a calibration c on the size that reaches the
 * target: at node a min(max(h_a, c need_a), hcap_a) (h_a the current size,
 * need_a the size at which the node meets the target, hcap_a the accuracy
 * bound). c = 1 gives dtm_analysis_size_suggestion, c = 0 the current
 * size (clamped). size has nnodes entries (NaN at nodes of no analysed
 * element). */
DTM_EXPORT int dtm_analysis_size_field(const dtm_analysis *a, double c, double *size);
DTM_EXPORT const double *dtm_analysis_nodal(const dtm_analysis *a);
DTM_EXPORT const double *dtm_analysis_effect_nodal(const dtm_analysis *a, int k);

/* The steps: the smallest element step (the element bound, the map's own
 * minimum) and its global element index (element may be NULL); the nodal
 * and global minima (NaN when not computed); the recommended step,
 * safety x the best estimate that is guaranteed safe, and what it rests on
 * ("element bound", "nodal bound" or "global estimate"). */
DTM_EXPORT double dtm_analysis_dt_min(const dtm_analysis *a, size_t *element);
/* The 1 % quantile of the element steps: the k-th smallest finite step of
 * the dt map, k = (n - 1) / 100 over its n finite steps (this part's in a
 * distributed run), s; NaN when none is finite. */
DTM_EXPORT double dtm_analysis_dt_quantile(const dtm_analysis *a);
/* The analysed mesh's nodes split into parts for scatters in parallel that
 * add in the serial order (dtm_mesh_node_parts). */
DTM_EXPORT const dtm_node_parts *dtm_analysis_node_parts(const dtm_analysis *a);
DTM_EXPORT double dtm_analysis_dt_nodal(const dtm_analysis *a);
DTM_EXPORT double dtm_analysis_dt_global(const dtm_analysis *a);
DTM_EXPORT double dtm_analysis_recommended(const dtm_analysis *a);
DTM_EXPORT const char *dtm_analysis_basis(const dtm_analysis *a);
/* The basis estimate itself (recommended / safety), s. */
DTM_EXPORT double dtm_analysis_basis_step(const dtm_analysis *a);
/* 1 when the recommended step is the probable bound's certified step
 * (below safety x the basis step: dtm_recommend), 0 otherwise. */
DTM_EXPORT int dtm_analysis_recommended_certified(const dtm_analysis *a);
/* The Lanczos start vector's seed of the global estimate (0: dtmap's
 * default, 20261121): any seed chosen without looking at the mesh keeps the
 * probable bound's failure probability. */
DTM_EXPORT void dtm_analysis_set_lanczos_seed(dtm_analysis *a, unsigned seed);
/* The factor the scene's damping applies to a wave step of material mat
 * (scene index) at undamped angular frequency omega (rad/s): the product
 * over the damping effects, 1 without any. */
DTM_EXPORT int dtm_analysis_wave_factor(const dtm_analysis *a, int mat, double omega, double *factor);
/* The target the advice holds the elements' own safe steps (safety
 * included) against, s: the scene's target, or on the global basis that
 * target times the bound basis over the global estimate (src/analysis/
 * recommend.c); 0 without a target. */
DTM_EXPORT double dtm_analysis_advice_target(const dtm_analysis *a);
/* With a target: the elements whose safety x own safe step is below the
 * advice target, and the shape-limited ones among them (*n entries, NULL
 * when none; owned by the analysis). Features need the Gmsh model (dtm_analysis_run
 * or _current); an analysis of hand-built blocks lists none. */
DTM_EXPORT size_t dtm_analysis_below_target(const dtm_analysis *a);
/* Where the mesh sits on the model (NULL for hand-built blocks). */
DTM_EXPORT const dtm_geo *dtm_analysis_geo(const dtm_analysis *a);
/* The spread of a fresh Gmsh mesh of dimension dim: its smallest nodal
 * step over its median one at a uniform size (measured: 0.78 in 3D, 0.8
 * in 2D; 1 in 1D). */
DTM_EXPORT double dtm_analysis_mesh_spread(int dim);
DTM_EXPORT const dtm_shape_limited *dtm_analysis_shape_limited(const dtm_analysis *a, size_t *n);
/* The groups with thickness-limited elements, *n of them (without a
 * target: the layers the smallest steps lie across, at_minimum). */
DTM_EXPORT const dtm_layer *dtm_analysis_layers(const dtm_analysis *a, size_t *n);
/* The minima of effect k. */
DTM_EXPORT const dtm_effect_min *dtm_analysis_effect_min(const dtm_analysis *a, int k);
/* The global estimate of effect k, or NULL when it was not computed. */
DTM_EXPORT const dtm_global_info *dtm_analysis_global(const dtm_analysis *a, int k);
DTM_EXPORT void dtm_analysis_accuracy(const dtm_analysis *a, dtm_accuracy *out);

/* How the analysed mesh was made: Gmsh's 3D algorithm and threads, and
 * whether its numbering is reproducible (all zero with reproducible = 1
 * for a hand-built mesh given to dtm_analysis_compute). */
DTM_EXPORT const dtm_mesher_info *dtm_analysis_mesher(const dtm_analysis *a);

/* What the elements of one scene section come to (dtm_analysis_sections). */
typedef struct {
  size_t elements;    /* elements with the section */
  double dt_min;      /* smallest element step among them (the dt map), s; NaN when none */
  size_t element;     /* Gmsh tag of that element */
  double anchor_min;  /* smallest step by the rule explicit codes use for the kind (truss:
                         L/sqrt(E/rho); membrane: LS-DYNA's shell step L_s/c_p, L_s = 2A/longest
                         side on triangles, A/max(sides, diagonals) on quadrangles,
                         c_p = sqrt(E/(rho(1 - nu^2)))), s; NaN for the other kinds or
                         without E, nu, rho */
  const char *anchor; /* that rule, in words ("" when none) */
  /* Shells and beams (NaN for the other kinds): */
  double dt_physical_min;  /* smallest element step with physical rotary inertia, s */
  size_t physical_element; /* Gmsh tag of that element */
  double scale_max;        /* largest rotary-inertia scale of the scaled convention (1: physical) */
} dtm_section_stats;
/* Stats of every scene section, out[nsections] (caller-owned). */
DTM_EXPORT void dtm_analysis_sections(const dtm_analysis *a, dtm_section_stats *out);
/* Wall time of stage t (DTM_T_*), s, and the OpenMP threads of the element
 * loop. */
DTM_EXPORT double dtm_analysis_timing(const dtm_analysis *a, int t);
DTM_EXPORT int dtm_analysis_threads(const dtm_analysis *a);
/* The dimension of the space the mesh's nodes span (dtm_mesh_space_dim). */
DTM_EXPORT int dtm_analysis_space_dim(const dtm_analysis *a);
/* The distinct parallel planes the surfaces of a plane problem (plane strain
 * or plane stress) lie in, each analysed in its own plane; 0 when the model
 * is no plane problem. */
DTM_EXPORT int dtm_analysis_planes(const dtm_analysis *a);

/* The operator of spectral effect k (with the scene's damping as Rayleigh
 * coefficients at omega_top, 0 for none). Caller destroys. */
DTM_EXPORT int dtm_analysis_operator(const dtm_analysis *a, int k, double omega_top, dtm_operator **op);

#endif
