/* `dtmap verify`: prove a step by simulation. Every spectral effect of an
 * analysis (whose global estimate must have run with its modes) is
 * integrated on the whole mesh for a number of steps from its top Ritz mode
 * plus a seeded random part (10% in the M-norm): central differences with
 * the damping force on the lagged velocity for waves, forward Euler for
 * diffusion; a growing energy means the step is unstable. */
#ifndef DTMAP_VERIFY_H
#define DTMAP_VERIFY_H

#include "dtmap/analysis.h"
#include "dtmap/export.h"

typedef struct {
  int simulated; /* 1 if effect k was simulated */
  double growth; /* energy-norm growth (see dtm_verify_result) */
  int unstable;  /* 1 when the energy grew past the limit */
  double seconds;
} dtm_verify_effect;

/* out[k] (neffects entries) gets the result of effect k (simulated = 0
 * when the effect was not simulated). */
DTM_EXPORT int dtm_verify(const dtm_analysis *a, double dt, int steps, dtm_verify_effect *out);

#endif
