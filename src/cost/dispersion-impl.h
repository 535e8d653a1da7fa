/* Parts of the lattice dispersion (src/cost/dispersion.c) that the other
 * models use too: the dispersion of a mesh's own element shapes
 * (src/cost/shapes.c), of a structured mesh's own lattice
 * (src/cost/structured.c) and the measured table (src/cost/measured.c):
 * an element's stiffness at full integration, the cyclic Jacobi
 * eigensolver, the periodic patch and its Bloch analysis, the table's
 * directions. Internal to libdtmap. */
#ifndef DTM_DISPERSION_IMPL_H
#define DTM_DISPERSION_IMPL_H

#include "dtmap/cost.h"

#define DTM_DISP_MAX_EL 12 /* elements per cell (a structured mesh's cell: up to 12) */
#define DTM_DISP_MAX_CLS 8 /* node classes per cell (tet10 of the cube: a vertex and seven edges) */
#define DTM_DISP_ELDOF 30  /* unknowns of one element (tet10) */
#define DTM_DISP_MAX_NN 10 /* nodes of one element */

/* A periodic patch: the elements of one cell of a lattice, their node
 * classes (a node and its translates by the lattice vectors are one
 * unknown) and the cell's vectors. Node coordinates in space, scaled to a
 * cell of volume 1; class positions and shifts in cell units. */
typedef struct {
  int type, d, nel, nn, ncls;                     /* element type, dimension, elements, nodes each, classes */
  double x[DTM_DISP_MAX_EL][DTM_DISP_ELDOF];      /* node coordinates [nel][nn][3] */
  int cls[DTM_DISP_MAX_EL][DTM_DISP_MAX_NN];      /* node class of each element node */
  int shift[DTM_DISP_MAX_EL][DTM_DISP_MAX_NN][3]; /* the cell each node lies in */
  double pos[DTM_DISP_MAX_CLS][3];                /* class position in the cell (cell units) */
  double cell[3][3];                              /* physical = cell x fractional (columns: the vectors) */
  double mass[DTM_DISP_MAX_CLS];                  /* lumped mass per class (density 1) */
  double klam[DTM_DISP_MAX_EL][DTM_DISP_ELDOF * DTM_DISP_ELDOF]; /* element stiffness from lam = 1, mu = 0 */
  double kmu[DTM_DISP_MAX_EL][DTM_DISP_ELDOF * DTM_DISP_ELDOF];  /* from lam = 0, mu = 1 */
} dtm_disp_lattice;

/* Element stiffness of isotropic elasticity (lam, mu) at full integration,
 * K[nn d][nn d], of the element with nodes x[nn][3] in d dimensions. */
void dtm_disp_stiffness(int type, int d, int nn, const double *x, double lam, double mu, double *K);
/* Eigenvalues (diagonal of A) and eigenvectors (columns of V) of the
 * symmetric A[n][n], by cyclic Jacobi to round-off. */
void dtm_disp_jacobi(int n, double *A, double *V);
/* The unit directions of a table in d dimensions into n; returns how many. */
int dtm_disp_directions(int d, double n[DTM_DISP_DIRS][3]);

/* Start a patch of elements of type in a cell whose vectors are the
 * columns of cell (volume 1). */
int dtm_disp_lattice_begin(dtm_disp_lattice *L, int type, const double cell[3][3]);
/* Add one element with nodes f[nn][3] in cell units (fractional
 * coordinates: a node's class is its position modulo the cell). */
int dtm_disp_lattice_add(dtm_disp_lattice *L, const double *f);
/* The table of the patch for r = mu / (lam + 2 mu) (t->shape left to the caller). */
int dtm_disp_lattice_table(const dtm_disp_lattice *L, double r, dtm_dispersion *t);
/* The semi-discrete errors of P (err[0]) and of the worse S branch (err[1]) at kh n. */
int dtm_disp_lattice_space(const dtm_disp_lattice *L, double r, double kh, const double n[3], double err[2]);
/* The semi-discrete error of the branch whose Bloch eigenvector overlaps
 * most with polarisation pol at kh n (mode 0: over the P speed, 1: S). */
int dtm_disp_lattice_polarised(const dtm_disp_lattice *L, double r, double kh, const double n[3], const double pol[3],
                               int mode, double *err);
/* The plane-wave table (src/cost/shapes.c) of n elements x[n][nn][3] of a
 * type whose nodes are all corners, element e counted w[e] times (NULL:
 * once each): the Rayleigh quotient of the summed dynamic matrices over
 * the summed masses (t->shape = DTM_LATTICE_OWN). */
int dtm_disp_table_weighted(int type, double r, const double *x, const double *w, size_t n, dtm_dispersion *t);

#define DTM_DISP_MAX_SHAPES 24 /* element shapes of a structured mesh */

/* What a structured mesh is (src/cost/structured.c). */
typedef struct {
  dtm_disp_lattice *lattice;                          /* a lattice: its patch (owned), else NULL */
  int nshapes;                                        /* a grid of one node class: its shapes, else 0 */
  double x[DTM_DISP_MAX_SHAPES][3 * DTM_DISP_MAX_NN]; /* one element of each shape, m */
  double count[DTM_DISP_MAX_SHAPES];                  /* elements of each shape */
} dtm_disp_structure;

/* Whether the elements of type and material mat of mesh are structured:
 * translates of one cell (a lattice, s->lattice), or of types whose nodes
 * are all corners with every node on one lattice (s->nshapes: their plane
 * wave is a Bloch mode of each cell, and of their mixture very nearly).
 * Neither: s->lattice NULL and s->nshapes 0. dtm_disp_structure_free
 * releases it. */
int dtm_disp_structure_find(const dtm_mesh *mesh, int type, int mat, dtm_disp_structure *s);
void dtm_disp_structure_free(dtm_disp_structure *s);
/* The class of the measured table (src/cost/measured.c) nearest to the
 * unit direction n: 0 an axis, 1 a face diagonal, 2 a body diagonal. */
int dtm_disp_measured_class(const double n[3]);

#endif
