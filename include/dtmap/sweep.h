/* `dtmap sweep`: what accuracy costs in run time. The scene is meshed at
 * each requested size and analysed; each row gives the mesh, the steps, the
 * number of steps and the cost of the scene's duration with and without
 * subcycling, the accuracy indicators, and dtmap's own time. */
#ifndef DTMAP_SWEEP_H
#define DTMAP_SWEEP_H

#include "dtmap/export.h"

#include <stddef.h>

#include "dtmap/scene.h"

typedef struct {
  double h;              /* <meshing size> used, m */
  size_t elements;       /* analysed elements */
  size_t nodes;          /* nodes of the mesh */
  double dt_min;         /* smallest element step, s */
  double recommended;    /* recommended step, s */
  double steps;          /* whole steps of the recommended step to cover the
                            duration, ceil(duration / recommended) (NaN without one) */
  double cost;           /* element-steps: elements x steps */
  double cost_subcycled; /* element-steps with ideal subcycling, levels of
                            the recommended step x 2^k: cost / speedup */
  double per_zone;       /* smallest value of the indicator "elements_per_zone" (cohesive),
                            NaN without a cohesive effect */
  double per_wavelength; /* smallest value of the indicator "elements_per_wavelength"
                            (elastic), NaN without <time f-max> */
  double seconds;        /* dtmap's wall time for this size */
  double speedup;        /* ideal subcycling speed-up N / sum_k N_k 2^-k */
  size_t flagged;        /* elements analysed although inverted at a node
                            (dtm_mesh_check; the CLI warns) */
} dtm_sweep_row;

/* Analyse scene s (Gmsh started; s->geometry required, not a .msh) at each
 * of the n sizes. rows[n] is filled in the order given. */
DTM_EXPORT int dtm_sweep_run(const dtm_scene *s, const double *sizes, int n, dtm_sweep_row *rows);
/* Print the table (stream is a FILE *). */
DTM_EXPORT void dtm_sweep_print(const dtm_sweep_row *rows, int n, void *stream);
/* Write one CSV row per size, with a header line, atomically. Columns:
 * h_m, elements, nodes, dt_min_s, dt_recommended_s, steps, element_steps,
 * element_steps_subcycled, subcycling_speedup, elements_per_zone,
 * elements_per_wavelength, time_s (units after the last underscore: _m
 * metres, _s seconds). Counts (elements, nodes, steps, element-steps) are
 * whole numbers (the subcycled element-steps rounded up); empty cells for
 * what was not computed (no duration, no cohesive effect, no f-max). */
DTM_EXPORT int dtm_sweep_write_csv(const char *path, const dtm_sweep_row *rows, int n);
#endif
