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
  double h;                /* <meshing size> used, in length_unit */
  const char *length_unit; /* the scene's length unit: "m", or "mm" under mm-t-s (static) */
  size_t elements;         /* analysed elements */
  size_t nodes;            /* nodes of the mesh */
  double dt_min;           /* smallest element step, s */
  double recommended;      /* recommended step, s */
  double steps;            /* whole steps of the recommended step to cover the
                              duration, ceil(duration / recommended) (NaN without one) */
  double cost;             /* element-steps: elements x steps */
  double cost_subcycled;   /* element-steps with ideal subcycling, levels of
                              the recommended step x 2^k: cost / speedup */
  double per_zone;         /* smallest value of the indicator "elements_per_zone" (cohesive),
                              NaN without a cohesive effect */
  double per_wavelength;   /* smallest value of the indicator "elements_per_wavelength"
                              (elastic), NaN without <time f-max> */
  double seconds;          /* dtmap's wall time for this size */
  double speedup;          /* ideal subcycling speed-up N / sum_k N_k 2^-k */
  size_t flagged;          /* elements analysed although inverted at a node
                              (dtm_mesh_check; the CLI warns) */
  double per_element_step; /* run time of one element-step, s (dtm_cost_per_element_step) */
  double hours;            /* cost x per_element_step / 3600, h (NaN without a duration) */
  double hours_subcycled;  /* cost_subcycled x per_element_step / 3600, h */
  double hours_mass;       /* with mass scaling to the scene's target instead: elements x
                              ceil(duration / target) x per_element_step / 3600, h (NaN without
                              a duration, or a target above the recommended step to lift it to) */
  double frequency;        /* frequency of the phase error, Hz (NaN: no elastic effect) */
  int frequency_default;   /* 1: the scene names no f-max; the first size's mesh default is
                              used at every size */
  double phase_error;      /* worst phase-speed error at the recommended step, signed fraction
                              (dtm_measures; NaN when unresolved or no elastic effect) */
  int phase_wave;          /* the wave of that worst: 0 P, 1 S (-1: none) */
  double phase_median;     /* median signed phase-speed error at the recommended step */
  size_t unresolved;       /* elements with fewer than 2 lattice cells per wavelength */
  double phase_subcycled;  /* worst with every element at its subcycling level's step */
  double phase_mass;       /* worst at the target step with the mass that reaches it (NaN
                              without a target above the recommended step) */
  double per_diffusion;    /* smallest elements across sqrt(D duration) (NaN: no diffusion) */
  double per_wave_default; /* smallest shear wavelength / mean edge at the frequency used */
  int in_band;             /* 1: every measure inside its band (phase |error| <= 1 %, zone
                              >= 5, diffusion >= DTM_BAND_DIFFUSION) */
  char failed[512];        /* why this size has no figures (Gmsh could not mesh it, or its
                              mesh was refused): "" when it has them; then every figure is
                              NaN or 0 */
} dtm_sweep_row;

/* Analyse scene s (Gmsh started; s->geometry required, not a .msh) at each
 * of the n sizes. rows[n] is filled in the order given. A size that fails
 * (Gmsh cannot mesh it or crashes in it, its mesh would not fit in memory,
 * ...) keeps its row with the reason in failed and the sweep goes on (a
 * crash is contained when Gmsh meshes in a child: dtm_gmsh_contain(1, ...),
 * as `dtmap sweep` asks); DTM_OK when at least one size gave figures, else
 * the first size's error (the rows then say why each failed). */
DTM_EXPORT int dtm_sweep_run(const dtm_scene *s, const double *sizes, int n, dtm_sweep_row *rows);
/* The row of the cheapest size (least hours with one global step, else
 * least element-steps) whose measures are all inside their bands; -1 when
 * none is. */
DTM_EXPORT int dtm_sweep_cheapest(const dtm_sweep_row *rows, int n);
/* Print the table (stream is a FILE *). */
DTM_EXPORT void dtm_sweep_print(const dtm_sweep_row *rows, int n, void *stream);
/* Write one CSV row per size, with a header line, atomically. Columns:
 * h_m, elements, nodes, dt_min_s, dt_recommended_s, steps, element_steps,
 * element_steps_subcycled, subcycling_speedup, elements_per_zone,
 * elements_per_wavelength, time_s, then the accuracy and the run time:
 * frequency_hz, phase_error, phase_error_median, unresolved,
 * phase_error_subcycled, phase_error_mass_scaled, elements_per_diffusion_length,
 * cost_per_element_step_s, run_h, run_subcycled_h, run_mass_scaled_h,
 * in_band, failed (units after the last underscore: _m metres, _s seconds,
 * _h hours, _hz hertz; phase errors are signed fractions; failed is empty,
 * or why that size has no figures, quoted). Counts are whole
 * numbers (the subcycled element-steps rounded up); empty cells for what
 * was not computed (no duration, no target, no such effect, unresolved). */
DTM_EXPORT int dtm_sweep_write_csv(const char *path, const dtm_sweep_row *rows, int n);
#endif
