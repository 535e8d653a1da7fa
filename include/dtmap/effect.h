/* The API for effect authors. An effect is a const dtm_effect_class: a
 * versioned table that describes the effect (its scene parameters, the
 * material properties it reads, its time integration scheme, its accuracy
 * indicator) and holds its functions. Built-in effects live in
 * plugins/<name>/ and are registered in plugins/list.h; external ones are
 * shared libraries exporting DTM_EFFECT_ENTRY_SYMBOL. From the description
 * the core validates scenes (an unknown or misspelt attribute, a value out
 * of range or not among the choices is an error at the scene's file:line),
 * generates the scene schema for the built-in effects, checks materials and
 * lists the effect in `dtmap effects`. An effect never calls Gmsh: it sees
 * element blocks as arrays and the materials of the scene. */
#ifndef DTMAP_EFFECT_H
#define DTMAP_EFFECT_H

#include <stddef.h>

#include "dtmap/error.h"
#include "dtmap/export.h"
#include "dtmap/kernel.h"
#include "dtmap/material.h"
#include "dtmap/problem.h"
#include "dtmap/section.h"

/* 2: self-describing classes (params, properties, scheme, indicator).
 * 3: sections: dtm_batch.section, and coefficients() takes the section. */
#define DTM_EFFECT_API_VERSION 3
/* External effects export: const dtm_effect_class *dtm_effect_entry(void); */
#define DTM_EFFECT_ENTRY_SYMBOL "dtm_effect_entry"
/* Groups an effect can tell apart through dtm_batch.gmask. */
#define DTM_EFFECT_MAX_GROUPS 64

/* What an effect does with the step. */
enum {
  DTM_ROLE_LIMITS = 1,        /* produces its own per-element critical step (needs element_dt) */
  DTM_ROLE_MODIFIES_WAVES = 2 /* scales the steps of the central-difference effects (needs wave_factor) */
};

/* The explicit scheme the effect's step is the limit of. */
typedef enum {
  DTM_SCHEME_NONE = 0,               /* limits no integration itself (a modifier such as damping) */
  DTM_SCHEME_CENTRAL_DIFFERENCE = 1, /* second order in time (waves): damping scales it, mass scaling lifts it */
  DTM_SCHEME_FORWARD_EULER = 2       /* first order in time (diffusion) */
} dtm_scheme;

/* Kinds of scene parameter. */
typedef enum {
  DTM_PARAM_NUMBER = 0, /* a finite number within [lo, hi] (open ends as declared) */
  DTM_PARAM_CHOICE = 1, /* one of the words in choices */
  DTM_PARAM_GROUPS = 2, /* physical groups by name or number, separated by spaces */
  DTM_PARAM_TEXT = 3    /* any non-empty text */
} dtm_param_type;

/* One attribute the effect's scene element takes. */
typedef struct {
  const char *name;           /* attribute name, e.g. "xi" */
  dtm_param_type type;        /* DTM_PARAM_* */
  const char *def;            /* default as written in a scene; NULL: none (see required) */
  double lo, hi;              /* numbers: admissible range */
  unsigned open;              /* numbers: DTM_OPEN_LO | DTM_OPEN_HI (material.h) */
  const char *const *choices; /* choices: the words, NULL-terminated */
  int required;               /* 1: the scene must give it */
  const char *unit;           /* SI unit for documentation; "" when none */
  const char *help;           /* one line for `dtmap effects` */
} dtm_param;

/* The accuracy indicator an effect's accuracy() fills. */
typedef struct {
  const char *name; /* stable identifier, e.g. "elements_per_zone" (CSV columns, reports) */
  const char *view; /* view name in the output .msh, e.g. "cohesive zone resolution" */
  const char *help; /* one line: what the value means and what is enough */
} dtm_indicator;

/* The scene element of the effect plus what it may look up at creation. */
typedef struct dtm_effect_args dtm_effect_args;

/* Parameter key (declared by the class) as a number: the scene's value or
 * the declared default; NaN when neither exists. The core has validated
 * the value against the declaration before create() runs. */
DTM_EXPORT int dtm_effect_args_number(const dtm_effect_args *a, const char *key, double *out);
/* Parameter key as text (owned by the scene or the class): the scene's value
 * or the declared default, NULL when neither exists. */
DTM_EXPORT int dtm_effect_args_text(const dtm_effect_args *a, const char *key, const char **out);
/* DTM_PARAM_CHOICE parameter key as the index of its word in choices. */
DTM_EXPORT int dtm_effect_args_choice(const dtm_effect_args *a, const char *key, int *index);
/* Index of a material property in the scene's catalogue (for
 * dtm_material_get in element loops); -1 when no material gives it. */
DTM_EXPORT int dtm_effect_args_property(const dtm_effect_args *a, const char *name);
/* Attribute as a double: *out = def when absent (API 1; prefer
 * dtm_effect_args_number). A value that does not parse as a finite number is
 * DTM_ERR_INPUT naming the scene file and line. */
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
/* Number of physical groups of the analysed dimension. */
DTM_EXPORT int dtm_effect_args_ngroups(const dtm_effect_args *a);
/* Number of elements of the analysed dimension without a <section>: those
 * the effect's own formulation applies to (a section sets its groups'). */
DTM_EXPORT size_t dtm_effect_args_unsectioned(const dtm_effect_args *a);
/* The scene's <time f-max> (Hz, 0 when unset) and its
 * elements-per-wavelength (default DTM_SCENE_PER_WAVELENGTH). */
DTM_EXPORT double dtm_effect_args_fmax(const dtm_effect_args *a);
DTM_EXPORT double dtm_effect_args_per_wavelength(const dtm_effect_args *a);
/* A destroy() for effects whose state is one malloc'ed block: free it and
 * set *state to NULL. */
DTM_EXPORT void dtm_effect_free(void **state);

/* One block of elements of one type, as the effects see it. */
typedef struct {
  int type;                          /* DTM_TET4, ... */
  int dim;                           /* topological dimension */
  int nn;                            /* nodes per element */
  size_t n;                          /* number of elements */
  const double *x;                   /* [n][nn][3] node coordinates, m */
  const size_t *tags;                /* [n] Gmsh element tags */
  const int *group;                  /* [n] physical group index, -1 for none */
  const unsigned long long *gmask;   /* [n] every group of the element (bit g < DTM_EFFECT_MAX_GROUPS),
                                        or NULL: then only `group` is known */
  const dtm_material *const *mat;    /* [n] material of each element */
  const dtm_section *const *section; /* [n] section of each element (NULL where it has none: the
                                        effect's own formulation), or NULL: no element has one */
  const unsigned char *level;        /* [n] each element's converged rule level, as the level search of
                                        second-order elements found it once for the whole analysis (0:
                                        the full rule), for dtm_kernel_elastic_lambda_at; or NULL */
} dtm_batch;

typedef struct dtm_effect_class {
  int api_version;                /* DTM_EFFECT_API_VERSION */
  const char *name;               /* scene element name, e.g. "elastic" */
  const char *summary;            /* one line for `dtmap effects` */
  unsigned role;                  /* DTM_ROLE_* */
  dtm_scheme scheme;              /* the scheme its step limits (DTM_SCHEME_NONE for modifiers) */
  double exponent;                /* dt ~ h^exponent: 1 for waves, 2 for diffusion (size suggestion) */
  const dtm_param *params;        /* its scene attributes, terminated by a NULL name; NULL: none */
  const dtm_property *properties; /* material properties it reads, terminated by a NULL name; NULL: none */
  dtm_indicator indicator;        /* what accuracy() fills (name NULL when it has none) */
  /* Parse the scene element; *state is owned by the effect until destroy.
   * Optional: without it the state is NULL. */
  int (*create)(const dtm_effect_args *args, void **state);
  /* DTM_ROLE_LIMITS: critical step dt[n] (s) and characteristic length
   * len[n] (m) of every element of the block. */
  int (*element_dt)(void *state, const dtm_batch *b, double *dt, double *len);
  /* DTM_ROLE_MODIFIES_WAVES: factor (<= 1) on the step of a
   * central-difference effect for an element of material m whose undamped
   * top frequency is omega (rad/s). */
  int (*wave_factor)(void *state, const dtm_material *m, double omega, double *factor);
  /* Optional accuracy bound: the largest admissible element size hmax[n]
   * (m, +inf where unbounded; compared with the element's mean edge length)
   * and the indicator's value res[n] (NaN where it does not apply). */
  int (*accuracy)(void *state, const dtm_batch *b, double *hmax, double *res);
  /* Optional, DTM_ROLE_LIMITS: the coefficients of the effect's problem for
   * material m in section sec (NULL: none; the elastic formulation follows
   * the section's kind); kind DTM_OP_NONE when the effect is not spectral.
   * Per unit measure: the core multiplies stiffness and mass by the
   * section's thickness or area (dtm_section_factor). */
  int (*coefficients)(void *state, const dtm_material *m, const dtm_section *sec, dtm_operator_coeffs *c);
  /* Optional, DTM_ROLE_MODIFIES_WAVES: equivalent Rayleigh coefficients of
   * material m's damping, C = alpha M + beta K, given the top frequency
   * omega_top (a constant xi becomes beta = 2 xi / omega_top). */
  int (*rayleigh)(void *state, const dtm_material *m, double omega_top, double *alpha, double *beta);
  /* Free the state and set *state to NULL (optional). */
  void (*destroy)(void **state);
} dtm_effect_class;

/* 1 when effect class c is integrated by central differences: its steps are
 * the ones damping scales and mass scaling lifts. */
static inline int dtm_effect_is_wave(const dtm_effect_class *c) { return c->scheme == DTM_SCHEME_CENTRAL_DIFFERENCE; }

#endif
