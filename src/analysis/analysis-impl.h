/* Private to src/analysis/ (and its white-box tests): the layout of the
 * analysis handle, as PETSc keeps struct _p_PC in a private header, and the
 * stages its files share. Other modules read an analysis through the
 * accessors of include/dtmap/analysis.h. */
#ifndef DTM_ANALYSIS_IMPL_H
#define DTM_ANALYSIS_IMPL_H

#include "base.h"
#include "distributed.h"
#include "dtmap/analysis.h"
#include "dtmap/gmsh.h"
#include "dtmap/section.h"

/* Node parts per thread of the ordered scatters (dtm_mesh_node_parts): a
 * few per thread, taken dynamically, so that a thread slowed by the
 * machine's other work does not hold the others up; 0 gives one part, the
 * serial loop (tests compare the two bit for bit). */
extern int dtm_scatter_parts;

struct dtm_analysis {
  const dtm_scene *scene;       /* not owned */
  dtm_section_stats *sec_stats; /* [nsections] what dtm_analysis_sections returns, computed once */
  unsigned char **level;        /* [nblocks][n] each second-order element's converged rule level,
                                   found once (curvature.c; 0: straight-sided); NULL rows for
                                   linear blocks, NULL without any */
  double **level_rem;           /* [nblocks][n] alongside level: the estimated remaining quadrature
                                   error of each element at its level (dtm_ref_level_elem, 1/m^2) */
  dtm_section_bounds **rot;     /* [nblocks][n] each shell's and beam's bounds, its rotary scale's
                                   eigenproblem solved once (sections.c); nn = 0 where none or refused;
                                   NULL rows for blocks without them, NULL without any */
  dtm_mesh *mesh;               /* owned */
  int neffects;
  dtm_effect *effects;        /* [neffects] owned, scene order */
  size_t nel;                 /* elements analysed */
  size_t *offset;             /* [nblocks + 1] first global index of each block */
  double *dt;                 /* [nel] min over limiting effects, s (before safety) */
  int dt_shared;              /* dt is the one limiting effect's dt_effect row (not freed apart) */
  double *len;                /* [nel] characteristic length of the limiting effect, m */
  int *limiting;              /* [nel] index of the limiting effect, scene order */
  double **dt_effect;         /* [neffects][nel]; NULL rows for non-limiting effects */
  double **dt_bare;           /* [neffects][nel] wave steps before the damping
                                 modifiers; rows only when modifiers exist */
  double *h;                  /* [nel] element size (mean edge length), m */
  double *meas;               /* [nel] element measure (length, area, volume), m^d (NULL: not kept) */
  double *hmax;               /* [nel] accuracy bound on the size, m (+inf: none) */
  int *hmax_by;               /* [nel] effect whose bound hmax is, -1: none */
  double **resolution;        /* [neffects][nel] accuracy view values; NULL rows
                                 for effects without an accuracy bound */
  dtm_accuracy accuracy;      /* under-resolved elements, target conflicts */
  double *size_node;          /* [nnodes] size suggestion, m */
  dtm_effect_min *per_effect; /* [neffects] */
  double dt_min;              /* min of dt, s */
  size_t el_min;              /* its global element index */
  double dt_q1;               /* the 1 % quantile of the finite element steps of dt, s (NaN: none) */
  dtm_node_parts parts;       /* the nodes split for the ordered scatters (nodal bound, size suggestion) */
  double *nodal_node;         /* [nnodes] nodal-bound step per node, min over the
                                 spectral effects, s (+inf: no spectral effect) */
  double **node_dt;           /* [neffects][nnodes] nodal-bound step of each
                                 spectral effect, s; NULL rows otherwise */
  double dt_nodal;            /* min over nodes of nodal_node, s (NaN: none) */
  double dt_global;           /* min over effects of the global estimate, s (NaN) */
  double recommended;         /* safety x the best guaranteed-safe estimate, s */
  double best;                /* that estimate (the basis before safety), s */
  double advice_target;       /* the target the element and nodal steps are held
                                 against (safety included), s: the scene's, or on
                                 the global basis the scene's x the bound basis over
                                 the global one (the nodal-bound step whose mesh has
                                 the target's global step); 0 without a target */
  int global_basis;           /* 1 when a converged global estimate may be the
                                 basis (run --posterior), 0 otherwise */
  int rec_certified;          /* 1 when recommended is the probable bound's step */
  unsigned lanczos_seed;      /* the global estimate's start seed (0: the default) */
  double *local;              /* [nel] each element's own safe step before safety,
                                 s: per limiting effect the larger of its element
                                 step (when a bound) and the smallest nodal bound
                                 at its nodes, then the smallest over effects */
  double **hmax_effect;       /* [neffects][nel] each effect's own accuracy bound,
                                 m; NULL rows for effects without one */
  double *forced;             /* [neffects] elements the accuracy bounds of each
                                 effect add to a mesh at the size suggestion */
  dtm_geo *geo;               /* the mesh on the model's entities, or NULL (owned) */
  size_t below;               /* elements whose safety x local step < target */
  dtm_shape_limited *shape;   /* [nshape] the shape-limited ones among them */
  size_t nshape;
  dtm_layer *layers; /* [nlayers] the groups with thickness-limited elements */
  size_t nlayers;
  const char *basis;           /* what recommended rests on: "element bound",
                                  "nodal bound" or "global estimate" */
  dtm_global_info *global;     /* [neffects], filled by dtm_analysis_estimate_global */
  double timings[DTM_T_COUNT]; /* s */
  int threads;                 /* OpenMP threads used for the element loop */
  dtm_mesher_info mesher;      /* how the mesh was made (dtm_analysis_run and _current) */
  const dtm_exchange *x;       /* the other parts of a distributed run (not owned), or NULL */
  double *curv_ratio;          /* [nel] min det J / max det J of second-order elements,
                                  NaN for the others; NULL without any (curvature.c) */
  double *curv_offset;         /* [nel] their node offset over the edge, NaN for the others */
  dtm_curvature_summary curv;  /* the counts and extremes of curvature.c */
  int planes;                  /* distinct parallel planes of a plane problem's surfaces (planar.c), 0: none */
};

/* The exchange's operations (distributed.h), or, without one, the status
 * unchanged (exchange.c): agree on a status, combine node values, reduce
 * scalars. */
int dtm_x_agree(const dtm_analysis *a, int status);
int dtm_x_nodes(const dtm_analysis *a, int status, double *v, dtm_x_op op);
int dtm_x_reduce(const dtm_analysis *a, int status, double *v, int n, dtm_x_op op);
/* *value, a quantity at this part's own minimum mine, becomes that of the
 * part whose minimum is the global one, min (the smallest value when parts
 * tie). */
int dtm_x_at_min(const dtm_analysis *a, int status, double mine, double min, double *value);

/* Fill a->size_node and a->accuracy from the per-element steps (size.c). */
int dtm_size_suggest(dtm_analysis *a);
/* Nodal bounds of the spectral effects (nodal.c). */
int dtm_nodal_bounds(dtm_analysis *a);
/* Fill per-effect safe steps, dt_nodal, dt_global and recommended
 * (recommend.c). */
void dtm_recommend(dtm_analysis *a);
/* Each element's own safe step (recommend.c), after dtm_recommend. */
int dtm_local_steps(dtm_analysis *a);
/* Elements below the target: how many, and which are shape-limited
 * (shape.c); needs a->local, and a->geo for the features. */
int dtm_shape_classify(dtm_analysis *a);
/* The thickness-limited elements per group, from a->shape (layers.c). */
int dtm_layers_gather(dtm_analysis *a);
/* The same from the n entries sl (thin ones only), flagged at_minimum. */
int dtm_layers_gather_from(dtm_analysis *a, dtm_shape_limited *sl, size_t n, int at_minimum);
/* The step of element i's limiting effects (damping applied, before
 * safety) if its nodes were at x instead, s (shape.c). */
int dtm_analysis_step_at(const dtm_analysis *a, size_t i, int type, const double *x, double *dt);
/* 1 when effect k is integrated by central differences (a wave effect whose
 * step the damping modifiers scale). */
int dtm_analysis_is_wave(const dtm_analysis *a, int k);
/* Section of every group of m (gs[ngroups], -1: none; NULL when the scene
 * has no section) and the default section; DTM_ERR_INPUT at the scene line
 * for a group that does not exist or whose dimension the kind does not suit
 * (src/analysis/sections.c). */
int dtm_analysis_map_sections(const dtm_scene *s, const dtm_mesh *m, int **gs, int *def);
/* After extraction: every sectioned group holds elements of its kind. */
int dtm_analysis_check_sections(const dtm_scene *s, const dtm_mesh *m, const int *gs);
/* Section of element e of block b, NULL when it has none. */
const dtm_section *dtm_analysis_section(const dtm_analysis *a, const dtm_block *b, size_t e);
/* Coefficient slots: one per material and section (none included),
 * slot = mat + nmat (section + 1); dtm_analysis_nslots of them. */
int dtm_analysis_nslots(const dtm_analysis *a);
/* 1 when a scene section is a shell or a beam (nodes with rotations): the
 * same on every part of a distributed run. */
int dtm_analysis_has_rotations(const dtm_analysis *a);
/* Make a->level and a->level_rem for the levelled blocks (before the
 * element map: its measures, the nodal bound's masses and the global
 * operator read them), to be filled a chunk at a time: the kept levels of
 * elements [e0, e0 + n) of block b, with coordinates x[n][nn][3]. */
int dtm_analysis_levels(dtm_analysis *a);
void dtm_analysis_levels_chunk(const dtm_analysis *a, int b, size_t e0, size_t n, const double *x);
/* The largest remaining quadrature error of effect k's operator over this
 * part's curved elements at their kept levels, as a bound on the shift of
 * its top eigenvalue (1/s^2 or 1/s; 0 without curved elements): see
 * curvature.c. Not reduced over parts. */
int dtm_analysis_quadrature_margin(const dtm_analysis *a, int k, double *margin);
/* The kept level of element e of block b, or -1 (search it). */
int dtm_analysis_level(const dtm_analysis *a, int b, size_t e);
/* The first elastic effect whose element step is the element bound (its
 * operator's dt_is_bound), or -1 (curvature.c). */
int dtm_analysis_elastic_bound_effect(const dtm_analysis *a);
/* Compute a->rot (before the nodal bound, which reads the masses there)
 * and a->sec_stats (once, after the nodal bound; it reads a->rot). */
int dtm_analysis_rotary(dtm_analysis *a);
int dtm_analysis_section_stats(dtm_analysis *a);
int dtm_analysis_slot(const dtm_analysis *a, const dtm_block *b, size_t e);
/* A 2D model treated as a plane elastic problem is plane, or its surfaces
 * lie in parallel planes (a->planes counts them; src/analysis/planar.c);
 * DTM_ERR_INPUT naming the distance otherwise. */
int dtm_analysis_check_planar(dtm_analysis *a);
/* The curvature of the second-order elements and the rule dependence of
 * their steps (curvature.c), after the element steps. */
int dtm_analysis_curvature_pass(dtm_analysis *a);
/* Effect k's coefficients for slot i, with the section's factor set. */
int dtm_analysis_coefficients(const dtm_analysis *a, int k, int slot, dtm_operator_coeffs *c);

/* The flops the certificate of a global bound may cost on this analysis
 * (global.c), and the Lanczos start seed it uses. */
double dtm_analysis_cert_budget(const dtm_analysis *a);
unsigned dtm_analysis_seed(const dtm_analysis *a);

#endif
