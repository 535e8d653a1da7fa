/* What `verify --accuracy`'s simulation (src/study/wave.c) takes from a
 * periodic sample (src/study/periodic.c). Internal to the study module. */
#ifndef DTM_WAVE_IMPL_H
#define DTM_WAVE_IMPL_H

#include "dtmap/mesh.h"

typedef struct {
  int periodic; /* 1: every pair of opposite faces of the mesh's box carries the same nodes */
  double L[3];  /* the box's sides, m */
  size_t *root; /* [nnodes] the node each node is one unknown with (itself when alone; owned) */
} dtm_wave_periodic;

/* Whether mesh is a periodic sample: p->periodic and its node classes
 * (p->root, freed by dtm_wave_periodic_free), else p->periodic = 0. */
int dtm_wave_periodic_find(const dtm_mesh *mesh, dtm_wave_periodic *p);
void dtm_wave_periodic_free(dtm_wave_periodic *p);
/* The wave vector k (1/m) nearest the given one that fits the box, in
 * place; 0 when it rounds to zero. */
int dtm_wave_periodic_fit(const dtm_wave_periodic *p, int dim, double k[3]);

#endif
