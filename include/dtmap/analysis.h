/* One dtmap analysis: scene + mesh + effects -> per-element steps, the
 * limiting effect, characteristic lengths, the size suggestion and the
 * summary the report and the terminal print. Arrays over elements follow the
 * mesh's block order (block 0's elements, then block 1's, ...). */
#ifndef DTMAP_ANALYSIS_H
#define DTMAP_ANALYSIS_H

#include <stddef.h>

#include "dtmap/mesh.h"
#include "dtmap/registry.h"
#include "dtmap/scene.h"

typedef struct {
  double min;           /* smallest element step of this effect, s (NaN if it does not limit) */
  size_t element;       /* global element index where it occurs */
  int element_rigorous; /* 0 when the element steps come from a length rule
                           (length=min-edge, ...) that is not a bound: then
                           only the nodal and global estimates vouch */
  double nodal;         /* its nodal bound, s (NaN if not spectral) */
  size_t node;          /* node index where the nodal bound occurs */
  double global;        /* its global (Lanczos) estimate, s (NaN if not computed) */
  double safe;          /* the step dtmap vouches for, s: global (safe side of the
                           bracket) if converged, else nodal, else element */
} dtm_effect_min;

/* The global (Lanczos) estimate of one spectral effect. */
typedef struct {
  int done;        /* 1 when computed */
  double theta;    /* largest Ritz value of M^-1 K */
  double residual; /* an eigenvalue lies in theta +- residual */
  int iterations;  /* Lanczos steps */
  int converged;   /* invariant subspace, or residual <= tol theta */
  double seconds;
  double dt_low;    /* step from theta + residual: the safe side, s */
  double dt_high;   /* step from theta: never safe to exceed, s */
  double omega_top; /* sqrt(theta + residual) (waves), for damping */
  double *mode;     /* [ndof] top Ritz vector (u^T M u = 1), owned */
} dtm_global_info;

/* Named stage timings, s. */
enum { DTM_T_SCENE, DTM_T_MESH, DTM_T_EXTRACT, DTM_T_EFFECTS, DTM_T_NODAL, DTM_T_GLOBAL, DTM_T_OUTPUT, DTM_T_COUNT };

typedef struct dtm_analysis {
  const dtm_scene *scene; /* not owned */
  dtm_mesh *mesh;         /* owned */
  int neffects;
  dtm_effect *effects;                            /* [neffects] owned, scene order */
  size_t nel;                                     /* elements analysed */
  size_t *offset;                                 /* [nblocks + 1] first global index of each block */
  double *dt;                                     /* [nel] min over limiting effects, s (before safety) */
  double *len;                                    /* [nel] characteristic length of the limiting effect, m */
  int *limiting;                                  /* [nel] index of the limiting effect, scene order */
  double **dt_effect;                             /* [neffects][nel]; NULL rows for non-limiting effects */
  double **dt_bare;                               /* [neffects][nel] wave steps before the damping
                                                     modifiers; rows only when modifiers exist */
  double *h;                                      /* [nel] element size (mean edge length), m */
  double *hmax;                                   /* [nel] accuracy bound on the size, m (+inf: none) */
  int *hmax_by;                                   /* [nel] effect whose bound hmax is, -1: none */
  double **resolution;                            /* [neffects][nel] accuracy view values; NULL rows
                                                     for effects without an accuracy bound */
  size_t under_resolved;                          /* elements with h > hmax */
  size_t conflicts;                               /* elements whose target size exceeds hmax */
  double dt_accuracy_cap;                         /* smallest recommended step allowed at h = hmax
                                                     among the conflicting elements, s (NaN: none) */
  size_t cap_element;                             /* global index of that element */
  double *size_node;                              /* [nnodes] size suggestion, m */
  dtm_effect_min *per_effect;                     /* [neffects] */
  double dt_min;                                  /* min of dt, s */
  size_t el_min;                                  /* its global element index */
  double *nodal_node;                             /* [nnodes] nodal-bound step per node, min over the
                                                     spectral effects, s (+inf: no spectral effect) */
  double **node_dt;                               /* [neffects][nnodes] nodal-bound step of each
                                                     spectral effect, s; NULL rows otherwise */
  double dt_nodal;                                /* min over nodes of nodal_node, s (NaN: none) */
  double dt_global;                               /* min over effects of the global estimate, s (NaN) */
  double recommended;                             /* safety x the best guaranteed-safe estimate, s */
  const char *basis;                              /* what recommended rests on: "element bound",
                                                     "nodal bound" or "global estimate" */
  dtm_global_info *global;                        /* [neffects], filled by dtm_global_estimate */
  struct dtm_subcycling_s *subcycling;            /* levels of a->dt (owned; cost.h) */
  struct dtm_mass_scaling_s *mass_scaling;        /* to reach the target, when the scene
                                      has one: mass so that safety x the element step
                                      reaches it (owned; cost.h), else NULL */
  const struct dtm_refine_round_s *refine_rounds; /* set by `refine` for the report (not owned) */
  int nrefine;                                    /* number of refine rounds, 0 otherwise */
  double timings[DTM_T_COUNT];
  int threads; /* OpenMP threads used for the element loop */
} dtm_analysis;

/* Run everything up to the views on scene s (which must outlive the
 * analysis): load/mesh through Gmsh, map groups to materials, create only
 * the scene's effects, compute. Gmsh must be started. */
int dtm_analysis_run(const dtm_scene *s, dtm_analysis **out);
/* The same on the current Gmsh model, already meshed, in dimension dim. */
int dtm_analysis_current(const dtm_scene *s, int dim, dtm_analysis **out);
/* Compute steps on an already extracted mesh with created effects (used by
 * dtm_analysis_run and by tests on hand-built blocks). Takes ownership of
 * mesh and effects. */
int dtm_analysis_compute(const dtm_scene *s, dtm_mesh *mesh, dtm_effect *effects, int neffects, dtm_analysis **out);
void dtm_analysis_destroy(dtm_analysis **a);

/* Block and local index of global element index i. */
void dtm_analysis_locate(const dtm_analysis *a, size_t i, int *block, size_t *local);
/* Gmsh tag, centroid (m) and group of global element i. */
size_t dtm_analysis_tag(const dtm_analysis *a, size_t i);
void dtm_analysis_centroid(const dtm_analysis *a, size_t i, double c[3]);
int dtm_analysis_group(const dtm_analysis *a, size_t i);

/* The global estimate (--posterior) of every spectral effect: Lanczos on
 * the lumped-mass generalized problem to relative residual tol, at most
 * maxit products. A converged estimate enters the recommendation on its
 * safe side (theta + residual, then the safety factor); an unconverged one
 * is reported and the nodal bound stays the basis. want_modes: also build
 * each top Ritz vector (for dtm_verify; twice the products), with the true
 * residual; otherwise the residual is Paige's estimate. */
int dtm_global_estimate(dtm_analysis *a, double tol, int maxit, int want_modes);

/* The operator of spectral effect k (with the scene's damping as Rayleigh
 * coefficients at omega_top, 0 for none). Caller destroys. */
struct dtm_operator;
int dtm_analysis_operator(const dtm_analysis *a, int k, double omega_top, struct dtm_operator **op);

/* `dtmap verify`: simulate every spectral effect of the analysis (its
 * global estimate must have run) for steps steps of dt from its top Ritz
 * mode plus a seeded random part (10% in the M-norm): central differences
 * with the damping force on the lagged velocity for waves, forward Euler
 * for diffusion. out[k] gets the result of effect k (steps = 0 when the
 * effect was not simulated). */
typedef struct {
  int simulated; /* 1 if effect k was simulated */
  double growth; /* energy-norm growth (see dtm_verify_result) */
  int unstable;
  double seconds;
} dtm_verify_effect;
int dtm_verify(const dtm_analysis *a, double dt, int steps, dtm_verify_effect *out);

/* Write the mesh with its views to path atomically, plus path.opt.
 * Refuses to overwrite the scene's input mesh. */
int dtm_output_write(const dtm_analysis *a, const char *path);
/* Write the JSON report to path atomically. */
int dtm_report_write(const dtm_analysis *a, const char *path);
/* Print the terminal summary (counts, min dt and where, recommendation,
 * the 10 smallest, a histogram by decade). */
void dtm_summary_print(const dtm_analysis *a, void *stream);

/* Monotonic wall clock, s. */
double dtm_wtime(void);

#endif
