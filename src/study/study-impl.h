/* Private to src/study/: the shaping of a size field (grade.c) that the
 * refine loop applies before it remeshes: caps at short model curves and
 * grading. */
#ifndef DTM_STUDY_IMPL_H
#define DTM_STUDY_IMPL_H

#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/mesh.h"

/* Limit size[nnodes] (m, NaN: no value) on mesh m so that no node's size
 * exceeds a neighbour's by more than slope times their distance along mesh
 * edges, then raise it back to floor[nnodes] where it fell below. */
int dtm_grade_sizes(const dtm_mesh *m, double slope, const double *floor, double *size);

/* Cap size at every node on a model curve at the curve's length, and at a
 * model point at its shortest curve's, never below floor. g may be NULL. */
void dtm_cap_at_features(const dtm_geo *g, const double *floor, double *size);

#endif
