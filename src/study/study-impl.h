/* Private to src/study/: the shaping of a size field (grade.c) that the
 * refine loop applies before it remeshes: caps at short model curves and
 * grading; and the parts of the refine loop in files of their own: its
 * causes (refine_causes.c), its mass round (refine_mass.c) and its
 * selective mass way (refine_selective.c). */
#ifndef DTM_STUDY_IMPL_H
#define DTM_STUDY_IMPL_H

#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/mesh.h"
#include "dtmap/refine.h"

/* Limit size[nnodes] (m, NaN: no value) on mesh m so that no node's size
 * exceeds a neighbour's by more than slope times their distance along mesh
 * edges, then raise it back to floor[nnodes] where it fell below. */
int dtm_grade_sizes(const dtm_mesh *m, double slope, const double *floor, double *size);

/* Cap size at every node on a model curve at the curve's length, and at a
 * model point at its shortest curve's, never below floor. g may be NULL. */
void dtm_cap_at_features(const dtm_geo *g, const double *floor, double *size);

/* Whether a remesh ends as a failed mesh (its strategy ends, the refine
 * goes on, a cause says why) rather than ending the refine: Gmsh refused or
 * crashed in it (remeshed, the remesh's code, is not DTM_OK), or the mesh
 * Gmsh made cannot be analysed (analysed, its analysis's code, is
 * DTM_ERR_INPUT: flat or inverted elements, say). The scene and the input
 * mesh went through the same analysis before any remesh, so an input error
 * there is the remesh's, not the user's; any other code (DTM_ERR_INTERNAL:
 * out of memory, interrupted) ends the refine. */
int dtm_refine_remesh_failed(int remeshed, int analysed);

/* A new cause of kind (cleared) in rr, or NULL when the list is full. */
dtm_cause *dtm_refine_new_cause(dtm_refine_result *rr, const char *kind);
/* The mesh round of strategy name with the largest step (-1: none; refine_causes.c). */
int dtm_refine_best_of(const dtm_refine_result *rr, const char *name);
/* The causes of a target the kept mesh does not meet, from the way the loop
 * stopped, the kept analysis and the nmodel causes the model holds (found
 * on the input mesh), then the size options refine lifted. */
void dtm_refine_collect_causes(dtm_refine_result *rr, const dtm_cause *model, int nmodel);
/* A target met (by the mesh or with point masses): only the size options
 * refine lifted stay among the causes, and the stop is DTM_REFINE_MET. */
void dtm_refine_met_causes(dtm_refine_result *rr);
/* The cause "mass-limit": rr->mass_needed % of the mass would meet the
 * target, more than the options allow. */
void dtm_refine_mass_cause(dtm_refine_result *rr);
/* Point masses on the kept mesh (rr->analysis) that lift its basis to the
 * target, when the options allow them and the mesh alone fell short
 * (dtm_mass_points). Within the limit the analysis keeps the masses and a
 * DTM_ROUND_MASS round is recorded and kept; beyond it, rr->mass_needed
 * says how much was needed and the analysis is left as it was. */
int dtm_refine_mass_round(dtm_refine_result *rr);
/* The way mesh + selective mass (refine_selective.c): with
 * options.selective_mass, where the kept mesh (rr->analysis, no point
 * masses yet) falls short, rr->selective from it; run before the mass
 * round. */
int dtm_refine_selective_way(dtm_refine_result *rr);
/* Free what rr->selective owns. */
void dtm_refine_selective_free(dtm_refine_result *rr);

#endif
