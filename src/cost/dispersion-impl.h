/* Parts of the lattice dispersion (src/cost/dispersion.c) that the
 * dispersion of a mesh's own element shapes (src/cost/shapes.c) uses too:
 * an element's stiffness at full integration, the cyclic Jacobi
 * eigensolver and the table's directions. Internal to libdtmap. */
#ifndef DTM_DISPERSION_IMPL_H
#define DTM_DISPERSION_IMPL_H

#include "dtmap/cost.h"

/* Element stiffness of isotropic elasticity (lam, mu) at full integration,
 * K[nn d][nn d], of the element with nodes x[nn][3] in d dimensions. */
void dtm_disp_stiffness(int type, int d, int nn, const double *x, double lam, double mu, double *K);
/* Eigenvalues (diagonal of A) and eigenvectors (columns of V) of the
 * symmetric A[n][n], by cyclic Jacobi to round-off. */
void dtm_disp_jacobi(int n, double *A, double *V);
/* The unit directions of a table in d dimensions into n; returns how many. */
int dtm_disp_directions(int d, double n[DTM_DISP_DIRS][3]);

#endif
