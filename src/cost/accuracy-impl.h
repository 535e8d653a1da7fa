/* What the accuracy measures (src/cost/accuracy.c) and the prediction of
 * one wave (src/cost/along.c) share: the elastic formulation and moduli of
 * a scene's materials and the choice of dispersion model for the elements
 * of one type and material. Internal to the cost module. */
#ifndef DTM_ACCURACY_IMPL_H
#define DTM_ACCURACY_IMPL_H

#include "dtmap/cost.h"
#include "dtmap/kernel.h"

/* The elastic formulation effect k uses (its attribute, else the default). */
dtm_formulation dtm_acc_formulation(const dtm_analysis *a, int k);
/* Moduli of material index mat for formulation f; -1 when it lacks E, nu or rho. */
int dtm_acc_moduli(const dtm_analysis *a, int mat, dtm_formulation f, dtm_elastic_moduli *m);
/* The table of the elements of type and material mat (r their mu / M):
 * the mesh's own shapes (tri3, quad4, hex8), else the lattice of a
 * structured mesh, else the measured table (tet4, tet10), else the regular
 * lattice (bar, tri6); *have = 0 when none applies (t untouched). */
int dtm_acc_table(const dtm_mesh *mesh, int type, int mat, double r, dtm_dispersion *t, int *have);
/* The spacing h at which an element of measure meas (m^d) and mean edge
 * edge (m) enters table t: (per_cell meas)^(1/d), or its mean edge. */
double dtm_acc_spacing(const dtm_dispersion *t, int d, double meas, double edge);

#endif
