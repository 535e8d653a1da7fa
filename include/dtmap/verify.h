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

#include "dtmap/cost.h"

/* The plane wave of dtm_verify_wave (src/study/wave.c). */
typedef struct {
  double f;       /* frequency, Hz: k = 2 pi f / c of the branch in the host material */
  double dir[3];  /* unit direction of k */
  int mode;       /* 0 P (polarised along dir), 1 S (across it) */
  double periods; /* 0: a packet under a Gaussian window, run until it meets the boundary (a
                     periodic sample: the whole wave for 12 periods); else the whole plane wave
                     for this many periods of the exact wave (>= 2) */
  int raise;      /* 1: f may be raised until a packet fits the mesh (f is a default, not asked for) */
} dtm_wave_spec;

typedef struct {
  int material;              /* the host: the scene material of the largest volume */
  double f;                  /* the frequency run, Hz: the spec's, raised to fit a packet or moved to fit
                                a periodic sample */
  double dir[3];             /* the direction run (unit): the spec's, or the nearest that fits a
                                periodic sample */
  int periodic;              /* 1: the mesh is a periodic sample (opposite faces joined) */
  double speed;              /* its exact speed of the branch, m/s */
  double pol[3];             /* the polarisation: dir (P); in 2D dir turned by 90 degrees, in 3D e_x x dir
                                (e_y x dir when dir is near e_x) normalised (S), dir the one run */
  double k;                  /* wave number 2 pi f / speed, 1/m */
  double omega;              /* measured discrete angular frequency, rad/s: the coherent wave's peak */
  double measured;           /* measured phase-speed error omega / (speed k) - 1 (fraction) */
  dtm_phase_along predicted; /* the measures' prediction over the host's elements, at f and dir */
  double agreement;          /* (measured - predicted.mean) / |predicted.mean| (fraction) */
  double omega_crossings;    /* the same from a line through the zero crossings (NaN: fewer than 4) */
  int crossings;             /* zero crossings fitted */
  double sigma;              /* the packet's window width, m (0: none, the whole wave) */
  double duration;           /* time integrated, s */
  int steps;                 /* time steps run */
  double seconds;            /* wall time of the integration, s */
  dtm_measure mesh;          /* the mesh's phase-speed measure as `run` gives it (dtm_measures_compute at
                                the recommended step and the scene's frequency: its worst averaged over
                                the element's neighbourhood and alone); kind 0 when there is none */
} dtm_wave_result;

/* Run the plane wave w at step dt (s) through the mesh of analysis a (its
 * elastic effect, undamped; src/study/wave.c) for several periods and
 * compare the measured phase-speed error with the predicted one.
 * DTM_ERR_INPUT without an elastic effect, with a bad spec, or when a
 * packet at the frequency given cannot run 3 periods in the mesh. */
DTM_EXPORT int dtm_verify_wave(const dtm_analysis *a, double dt, const dtm_wave_spec *w, dtm_wave_result *r);

#endif
