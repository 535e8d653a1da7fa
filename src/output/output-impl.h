/* Private to src/output/: what the terminal summary and the JSON report
 * both show about the advice (advice.c): warnings, the wording of
 * shape-limited features and remedies, the damping factors, the cohesive
 * zone per material and the smallest steps. Nothing here computes a step:
 * it reads the results bundle. */
#ifndef DTM_OUTPUT_IMPL_H
#define DTM_OUTPUT_IMPL_H

#include <stddef.h>

#include "dtmap/output.h"
#include "dtmap/units.h"

#define DTM_MASS_WARN 5.0 /* percent of added mass above which a warning is given */
#define DTM_WARN_MAX 32
#define DTM_TOP_DEFAULT 10

/* Warnings for the user, one sentence each. */
typedef struct {
  int n;                        /* warnings kept */
  char text[DTM_WARN_MAX][400]; /* their sentences */
} dtm_warnings;

void dtm_output_warnings(const dtm_results *r, dtm_warnings *w);
/* A step capped by a few elements 10x or more below the 1 % quantile of the
 * element steps, naming the worst and its model entities (outlier.c). */
void dtm_output_outlier_warning(const dtm_analysis *a, dtm_warnings *w);
/* Add one warning, printf-style, while there is room (advice.c). */
void dtm_output_warn(dtm_warnings *w, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* The model's mass and extent (plausible.c), in the scene's units. */
typedef struct {
  double mass;         /* rho V of the analysed elements (per unit thickness in 2D without a section) */
  int ngroups;         /* slots of group_mass: the mesh's physical groups, then the elements in none */
  double *group_mass;  /* [ngroups] (malloc'ed; dtm_output_model_free) */
  double lo[3], hi[3]; /* bounding box of the mesh's nodes */
} dtm_model_extent;
int dtm_output_model(const dtm_analysis *a, dtm_model_extent *x);
void dtm_output_model_free(dtm_model_extent *x);
/* The largest extent of the bounding box. */
double dtm_output_model_size(const dtm_model_extent *x);
/* The name of the scene's unit of what (include/dtmap/units.h). */
const char *dtm_unit_label(const dtm_scene *s, dtm_unit what);
/* The name of the unit of what in the analysed scene's system ("mm", "t", ...; docs/units.md); a
 * mass per unit thickness ("kg/m", "t/mm") in 2D without a section. */
const char *dtm_output_unit(const dtm_analysis *a, dtm_unit what);
/* Densities, wave speeds and a model size outside what solids and parts
 * have (plausible.c): each a warning naming the material and the value. */
void dtm_output_plausibility_warnings(const dtm_analysis *a, dtm_warnings *w);
/* The import's unit into u: 1 when the scene's source was a file dtmap
 * imported (STEP, IGES, BREP, a .msh with <mesh unit>), else 0. */
int dtm_output_import(const dtm_analysis *a, dtm_import_units *u);
/* The summary's lines on the units, the import, the mass and the extent
 * (stream is a FILE *). */
void dtm_summary_model(const dtm_analysis *a, void *stream);
/* The report's "model" object (model_report.c). */
struct cJSON *dtm_report_model(const dtm_analysis *a);
/* Its part on sections (section_advice.c): groups left out, rotary-inertia
 * scales above DTM_ROTARY_WARN, a thickness, area or profile larger than the
 * model. */
#define DTM_ROTARY_WARN 100.0 /* rotary-inertia scale above which a warning is given (docs/sections.md) */
void dtm_output_section_warnings(const dtm_analysis *a, dtm_warnings *w);
/* The run time in hours and the accuracy measures of c, for the summary
 * (stream is a FILE *; src/output/measures.c). */
void dtm_summary_measures(const dtm_analysis *a, const dtm_cost *c, void *stream);
/* run --selective-mass's lines (selective.c; nothing when r->selective_mass is NULL). */
void dtm_summary_selective_mass(const dtm_results *r, void *stream);
/* Its parts: the added mass of ms (what: which mass scaling) above
 * DTM_MASS_WARN of the model or a group; a target the accuracy bound
 * forbids at n elements (the bound's view, its size, the step it allows). */
void dtm_output_mass_warnings(const dtm_analysis *a, const dtm_mass_scaling *ms, const char *what, dtm_warnings *w);
void dtm_output_conflict_warning(dtm_warnings *w, const dtm_scene *s, const char *bound, double hmax, double dt_cap,
                                 size_t n);

/* One line on the feature and one on the remedy of a shape-limited element. */
const char *dtm_feature_text(const dtm_analysis *a, const dtm_shape_limited *s, char *buf, size_t len);
const char *dtm_remedy_text(const dtm_results *r, const dtm_shape_limited *s, char *buf, size_t len);
const char *dtm_feature_name(int kind);
const char *dtm_remedy_name(int remedy);
/* Layer k of dtm_analysis_layers: "between model surfaces 3 and 8"; the
 * mass its thickness-limited elements need at their nodes (the cost's
 * layer_mass at the layer's nodes, each once; NAN without it). */
const char *dtm_layer_faces_text(const dtm_layer *l, char *buf, size_t len);
double dtm_layer_added_mass(const dtm_results *r, size_t k);

/* The damping factor of one wave effect on one material: at the undamped
 * top frequency where the effect's basis sits, and its range over the
 * material's elements in the dt map. */
typedef struct {
  int effect;        /* scene index of the wave effect */
  int mat;           /* scene index of the material */
  double omega;      /* rad/s */
  double factor;     /* at omega */
  double emin, emax; /* over the material's elements */
} dtm_damping_row;

/* Rows (malloc'ed, *rows; NULL and 0 without damping). */
int dtm_damping_rows(const dtm_analysis *a, dtm_damping_row **rows, int *n);

/* The cohesive process zone of one material. */
typedef struct {
  int effect;  /* scene index of the cohesive effect */
  int mat;     /* scene index of the material */
  double R;    /* process-zone length, m */
  double hmax; /* R / elements-per-zone, m */
} dtm_zone_row;

int dtm_zone_rows(const dtm_analysis *a, dtm_zone_row **rows, int *n);

/* The elements with the smallest steps, ascending: at most top of them
 * into idx (malloc'ed); returns the count. */
int dtm_worst(const dtm_analysis *a, int top, size_t **idx);
int dtm_results_top(const dtm_results *r);

/* Print the JSON document root (a cJSON tree, freed here) to path
 * atomically; what names it in the error when it cannot be printed. */
struct cJSON;
int dtm_json_write(struct cJSON *root, const char *path, const char *what);

#endif
