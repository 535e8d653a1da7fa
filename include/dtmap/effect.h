/* The API for effect authors. An effect is a const dtm_effect_class: a
 * versioned table of function pointers with a name. Built-in effects live in
 * plugins/<name>/ and are registered in plugins/list.h; external ones are
 * shared libraries exporting DTM_EFFECT_ENTRY_SYMBOL. An effect never calls
 * Gmsh: it sees element blocks as arrays and the materials of the scene. */
#ifndef DTMAP_EFFECT_H
#define DTMAP_EFFECT_H

#include "dtmap/export.h"

#include <stddef.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/material.h"
#include "dtmap/problem.h"

#define DTM_EFFECT_API_VERSION 1
/* External effects export: const dtm_effect_class *dtm_effect_entry(void); */
#define DTM_EFFECT_ENTRY_SYMBOL "dtm_effect_entry"

/* What an effect does with the step. */
enum {
  DTM_ROLE_LIMITS = 1,        /* produces its own per-element critical step */
  DTM_ROLE_MODIFIES_WAVES = 2 /* scales the steps of wave-type (exponent 1) effects */
};

/* The scene element of the effect plus what it may look up at creation. */
typedef struct dtm_effect_args dtm_effect_args;

/* Attribute as a double: *out = def when absent. A value that does not parse
 * as a finite number is DTM_ERR_INPUT naming the scene file and line. */
DTM_EXPORT int dtm_effect_args_double(const dtm_effect_args *a, const char *key, double def, double *out);
/* Attribute as a string (owned by the scene): *out = def when absent. */
DTM_EXPORT int dtm_effect_args_string(const dtm_effect_args *a, const char *key, const char *def, const char **out);
/* Raise DTM_ERR_INPUT with "scene:line: <effect>: " before the message. */
DTM_EXPORT int dtm_effect_args_error(const dtm_effect_args *a, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Spatial dimension of the elements being analysed (1, 2 or 3). */
DTM_EXPORT int dtm_effect_args_dim(const dtm_effect_args *a);
/* Index of the physical group named (or numbered) ref among the mesh's
 * groups of the analysed dimension; DTM_ERR_INPUT listing the groups that
 * exist when there is none. */
DTM_EXPORT int dtm_effect_args_group(const dtm_effect_args *a, const char *ref, int *index);
/* The scene's <time f-max> (Hz, 0 when unset) and its
 * elements-per-wavelength (default 10). */
DTM_EXPORT double dtm_effect_args_fmax(const dtm_effect_args *a);
DTM_EXPORT double dtm_effect_args_per_wavelength(const dtm_effect_args *a);
/* A destroy() for effects whose state is one malloc'ed block: free it and
 * set *state to NULL. */
DTM_EXPORT void dtm_effect_free(void **state);
/* Number of physical groups of the analysed dimension. */
DTM_EXPORT int dtm_effect_args_ngroups(const dtm_effect_args *a);

/* One block of elements of one type, as the effects see it. */
typedef struct {
  int type;                        /* DTM_TET4, ... */
  int dim;                         /* topological dimension */
  int nn;                          /* nodes per element */
  size_t n;                        /* number of elements */
  const double *x;                 /* [n][nn][3] node coordinates, m */
  const size_t *tags;              /* [n] Gmsh element tags */
  const int *group;                /* [n] physical group index, -1 for none */
  const unsigned long long *gmask; /* [n] every group of the element (bit g),
                                      or NULL: then only `group` is known */
  const dtm_material *const *mat;  /* [n] material of each element */
} dtm_batch;

typedef struct dtm_effect_class {
  int api_version;     /* DTM_EFFECT_API_VERSION */
  const char *name;    /* scene element name, e.g. "elastic" */
  const char *summary; /* one line for `dtmap effects` */
  unsigned role;       /* DTM_ROLE_* */
  unsigned needs;      /* DTM_PROP_BIT mask every material in use must have */
  double exponent;     /* dt ~ h^exponent: 1 for waves, 2 for diffusion */
  /* Parse the scene element; *state is owned by the effect until destroy.
   * Optional: without it the state is NULL. */
  int (*create)(const dtm_effect_args *args, void **state);
  /* DTM_ROLE_LIMITS: critical step dt[n] (s) and characteristic length
   * len[n] (m) of every element of the block. */
  int (*element_dt)(void *state, const dtm_batch *b, double *dt, double *len);
  /* DTM_ROLE_MODIFIES_WAVES: factor (<= 1) on the step of a wave-type effect
   * for an element of material m whose undamped top frequency is omega
   * (rad/s). */
  int (*wave_factor)(void *state, const dtm_material *m, double omega, double *factor);
  /* Optional accuracy bound: the largest admissible element size hmax[n]
   * (m, +inf where unbounded; compared with the element's mean edge length)
   * and a resolution value res[n] for the view named accuracy_view (NaN
   * where it does not apply). */
  int (*accuracy)(void *state, const dtm_batch *b, double *hmax, double *res);
  const char *accuracy_view; /* view name for res, e.g. "cohesive zone resolution" */
  /* Optional, DTM_ROLE_LIMITS: the coefficients of the effect's problem for
   * material m; kind DTM_OP_NONE when the effect is not spectral. */
  int (*coefficients)(void *state, const dtm_material *m, dtm_operator_coeffs *c);
  /* Optional, DTM_ROLE_MODIFIES_WAVES: equivalent Rayleigh coefficients of
   * material m's damping, C = alpha M + beta K, given the top frequency
   * omega_top (a constant xi becomes beta = 2 xi / omega_top). */
  int (*rayleigh)(void *state, const dtm_material *m, double omega_top, double *alpha, double *beta);
  /* Free the state and set *state to NULL (optional). */
  void (*destroy)(void **state);
} dtm_effect_class;

/* 1 when effect class c is a wave effect integrated by central differences,
 * whose steps the DTM_ROLE_MODIFIES_WAVES effects (damping) scale and which
 * mass scaling can lift. */
static inline int dtm_effect_is_wave(const dtm_effect_class *c) { return c->exponent == 1.0; }

#endif
