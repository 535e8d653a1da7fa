/* The analysis module's interface to the distributed run (src/parallel/;
 * internal to libdtmap, hidden): an analysis of one part of a partitioned
 * mesh reaches the other parts only through a dtm_exchange, a table of
 * collective operations the caller provides. With it, every per-node
 * result (nodal bound, size suggestion) is the whole mesh's at the part's
 * nodes, and every figure the recommendation rests on is global: the
 * smallest element step, each effect's element, nodal and global minima,
 * hence the recommended step. Element indices (the element and node where
 * a minimum occurs, the accuracy bookkeeping) stay those of the part.
 * Each operation is collective and carries the caller's status: a part
 * that failed still calls it, and every part gets back the same status,
 * so no part waits for one that gave up. */
#ifndef DTMAP_ANALYSIS_DISTRIBUTED_H
#define DTMAP_ANALYSIS_DISTRIBUTED_H

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/gmsh.h"
#include "dtmap/operator.h"

typedef enum { DTM_X_SUM, DTM_X_MIN, DTM_X_MAX } dtm_x_op;

typedef struct dtm_exchange {
  void *ctx; /* the caller's, passed back to every operation */
  /* Agree on status (the first non-zero status of any part, else DTM_OK);
   * when it is DTM_OK, combine v[nnodes] (one value per node of this
   * part's mesh) so that every node shared by several parts gets the sum,
   * min or max over them. Returns the agreed status. */
  int (*nodes)(void *ctx, int status, double *v, dtm_x_op op);
  /* Agree on status; when DTM_OK, v[n] becomes the elementwise sum, min or
   * max over the parts (n = 0: only agree). */
  int (*reduce)(void *ctx, int status, double *v, int n, dtm_x_op op);
  /* Agree on status; when DTM_OK, estimate lambda_max of the whole mesh's
   * M^-1 K from op, this part's operator (its masses are this part's
   * contributions only), from a start drawn from seed: theta, residual (an
   * eigenvalue lies within it), iterations (operator products), converged,
   * seconds; no mode. */
  int (*eigen)(void *ctx, int status, const dtm_operator *op, double tol, int maxit, unsigned seed,
               dtm_lanczos_result *r);
  /* Agree on status; when DTM_OK, part 0 gets in *all (malloc'd, the
   * caller frees; NULL elsewhere) every part's mine[n], in part order, and
   * their total count in *nall. */
  int (*gather)(void *ctx, int status, const double *mine, size_t n, double **all, size_t *nall);
  /* Agree on status; when DTM_OK, every part gets part 0's v[n]: part 0
   * passes *v and *n, the others get a malloc'd copy in *v (the caller
   * frees) and its count in *n. */
  int (*bcast)(void *ctx, int status, double **v, size_t *n);
} dtm_exchange;

/* For the modules above the analysis (the cost module's nodal mass
 * scaling): 1 when a is one part of a distributed run, and v[nnodes] (a
 * value per node of a's mesh) combined over the parts sharing each node,
 * after agreeing on status (without an exchange: status, v unchanged). */
int dtm_analysis_is_distributed(const dtm_analysis *a);
int dtm_analysis_combine_nodes(const dtm_analysis *a, int status, double *v, dtm_x_op op);

/* Extract the current Gmsh model's elements of dimension dim into *out,
 * groups mapped to the scene's materials and sections (as
 * dtm_analysis_current does, except that a sectioned group may hold no
 * element: the model is one part); *seconds receives the time. */
int dtm_analysis_extract(const dtm_scene *s, int dim, dtm_mesh **out, double *seconds);
/* Part 0 of a distributed run, before the split: the whole mesh of the
 * current Gmsh model of dimension dim, extracted as a serial run extracts
 * it (same element order), and where it sits on the model, for
 * dtm_analysis_classify_whole. */
int dtm_analysis_extract_whole(const dtm_scene *s, int dim, dtm_mesh **mesh, dtm_geo **geo);
/* Collective, after dtm_analysis_compute_shared: the advice on elements
 * below the target (or at the smallest steps) of the whole mesh, as a
 * serial run gives it, from every part's element steps and the whole mesh
 * and model that part 0 holds (*whole, *geo: taken, set to NULL; NULL on
 * the other parts, and on part 0 when it has no model: then *out stays
 * NULL everywhere). On part 0, *out is an analysis of the whole mesh that
 * holds the element steps, the shape-limited elements and the layers (read
 * with dtm_analysis_shape_limited, dtm_analysis_layers,
 * dtm_analysis_below_target and the tag, group and centroid accessors). */
int dtm_analysis_classify_whole(const dtm_analysis *part, dtm_mesh **whole, dtm_geo **geo, dtm_analysis **out);
/* Collective: part 0's advice (from dtm_analysis_classify_whole, or NULL)
 * shared with every part, each keeping the shape-limited elements it holds
 * (so its views mark them). Call it after the cost, which then reads none
 * on any part (its masses for them are per part, not the whole mesh's). */
int dtm_analysis_share_advice(dtm_analysis *part, const dtm_analysis *advice);
/* dtm_analysis_compute on one part, with x reaching the others (x must
 * outlive the analysis; NULL: a whole mesh). Collective. */
int dtm_analysis_compute_shared(const dtm_scene *s, dtm_mesh *mesh, dtm_effect *effects, int neffects,
                                const dtm_exchange *x, dtm_analysis **out);

#endif
