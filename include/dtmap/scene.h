/* The scene file: an XML document validated against schema/dtmap-scene.xsd
 * (embedded in the library at build time) and read into plain structs. Every
 * problem is reported as DTM_ERR_INPUT with "file:line: ..." in the message.
 * Paths inside the scene are resolved relative to the scene file. */
#ifndef DTMAP_SCENE_H
#define DTMAP_SCENE_H

#include <stddef.h>

#include "dtmap/export.h"

#include "dtmap/material.h"
#include "dtmap/section.h"

typedef struct {
  dtm_material m;         /* name, line, properties */
  int is_default;         /* default="true": for elements in no mapped group */
  int no_plausible_check; /* plausible="no-check": its values are meant, not refused (src/scene/plausible.c) */
  int ngroups;            /* number of group references */
  char **groups;          /* [ngroups] physical group names or numbers, as written */
} dtm_scene_material;

typedef struct {
  char *name;    /* element name (<elastic/> -> "elastic"), or name= of <effect> */
  char *library; /* resolved path of <effect library=...>, NULL for built-ins */
  int line;      /* line of the element */
  int nattr;     /* number of attributes */
  char **keys;   /* [nattr] attribute names */
  char **values; /* [nattr] attribute values */
} dtm_scene_effect;

/* Elements per wavelength an accuracy bound asks for when the scene's <time>
 * does not say. */
#define DTM_SCENE_PER_WAVELENGTH 10.0

/* Encodings of an output .msh (<output format>). */
enum { DTM_MSH_AUTO = 0, DTM_MSH_ASCII = 1, DTM_MSH_BINARY = 2 };

typedef struct dtm_scene {
  char *path;           /* scene file as given */
  char *dir;            /* its directory ("." if none) */
  char *geometry;       /* resolved <geometry file>, or NULL */
  char *mesh;           /* resolved <mesh file>, or NULL */
  int partitions;       /* <mesh partitions>: the mesh is that many part files
                           (dtm_scene_part_path); 0: one file */
  int model;            /* 1: <model/>, the current Gmsh model of the program (no file) */
  int source_line;      /* line of <geometry>, <mesh> or <model/> */
  double mesh_size;     /* <meshing size>, m; 0 when unset */
  double mesh_min_size; /* <meshing min-size>, m; 0 when unset */
  int mesh_order;       /* <meshing order>; 1 when unset */
  int mesh_dim;         /* <meshing dim>; 0 when unset (highest dimension) */
  int mesh_algorithm;   /* <meshing algorithm> as Gmsh's Mesh.Algorithm3D code; 0 when unset (the geometry's) */
  int mesh_threads;     /* <meshing threads>; 0 when unset (the geometry's General.NumThreads) */
  int meshing_line;     /* line of <meshing>, 0 when there is none */
  int nmaterials;
  dtm_scene_material *materials; /* [nmaterials] in file order */
  int nsections;
  dtm_section *sections; /* [nsections] <section> elements in file order (none: every
                            element of the analysed dimension, as the effects say) */
  int neffects;
  dtm_scene_effect *effects;      /* [neffects] in file order */
  int effects_line;               /* line of <effects> */
  double safety;                  /* <time safety>; 0.9 when unset */
  double target;                  /* <time target>, s; 0 when unset */
  double duration;                /* <time duration>, s; 0 when unset */
  double f_max;                   /* <time f-max>, Hz; 0 when unset */
  double elements_per_wavelength; /* <time elements-per-wavelength>; 10 when unset */
  double cost_per_element_step;   /* <time cost-per-element-step>, s; 0 when unset (dtmap's calibration) */
  int posterior;                  /* <time posterior>: 1 when the global estimate is the basis (as
                                     --posterior); 0 when unset */
  double max_added_mass;          /* <time max-added-mass>: point masses refine (and deck) may add where
                                     no mesh meets the target, % of the model's mass; NaN when unset */
  int time_line;                  /* line of <time>, 0 when there is none */
  int nprops;                     /* entries in the property catalogue */
  char **prop_names;              /* [nprops] property names: the built-in effects' first, then
                                     the others the materials give (materials' prop is indexed so) */
  int nknown;                     /* the first nknown names are the built-in effects' properties */
  char *out_mesh;                 /* resolved <output mesh>, or NULL */
  char *out_report;               /* resolved <output report>, or NULL */
  int out_format;                 /* <output format>: DTM_MSH_AUTO (unset), _ASCII, _BINARY */
  int out_line;                   /* line of <output>, 0 when there is none */
  double phase_ratio[2];          /* measured / predicted phase-speed error of P [0] and S [1] from
                                     verify --accuracy's reports (--verified; 0: none) */
  int phase_calibrate;            /* 1: the measures multiply each branch's errors by phase_ratio
                                     (--calibrate) */

  /* Units (docs/units.md). */
  const char *units;       /* <dtmap-scene units>: "SI" (unset) or "mm-t-s" (static); every number of
                              the scene and of what dtmap reports is in it, the step in s */
  double unit_length;      /* metres per length unit of units: 1 (SI) or 1e-3 (mm-t-s) */
  double unit_mass;        /* kilograms per mass unit of units: 1 (SI) or 1e3 (mm-t-s, tonnes) */
  const char *source_unit; /* <geometry unit> or <mesh unit> ("mm", "cm", "m", "in"; static), NULL when
                              unset: the file's own unit (STEP, IGES), else the scene's length unit */
  double source_unit_m;    /* metres per unit of source_unit; 0 when unset */
  int no_plausible_check;  /* <dtmap-scene plausible="no-check">: no material's values are refused */
} dtm_scene;

/* Read and validate the scene at path. On success *out owns everything and
 * is freed with dtm_scene_destroy. On failure returns DTM_ERR_INPUT (missing
 * file, malformed XML, schema violation, bad value) with file:line. */
DTM_EXPORT int dtm_scene_load(const char *path, dtm_scene **out);
/* The same for a scene held in memory: len bytes of XML at text (need not
 * be NUL-terminated). name stands for the file in messages ("name:line:
 * ...") and its directory is where relative paths in the scene are
 * resolved ("mem.xml" resolves against the current directory). */
DTM_EXPORT int dtm_scene_load_memory(const char *text, size_t len, const char *name, dtm_scene **out);
DTM_EXPORT void dtm_scene_destroy(dtm_scene **s);
/* Take the current Gmsh model as the scene's source, as <model/> does:
 * forget <geometry> or <mesh>, so that messages name the current model (a
 * program that built or opened the model itself analyses a scene file). */
DTM_EXPORT int dtm_scene_use_model(dtm_scene *s);

/* The scene's system of units (<dtmap-scene units>): "SI" or "mm-t-s" (static; docs/units.md). Its
 * units' names: dtm_units_name (include/dtmap/units.h). */
DTM_EXPORT const char *dtm_scene_units(const dtm_scene *s);
/* The name of the unit of the masses of a mesh of dimension dim analysed with scene s: the mass unit
 * ("kg", "t"), or the mass per unit thickness ("kg/m", "t/mm") in 2D without a section. */
DTM_EXPORT const char *dtm_scene_mass_unit(const dtm_scene *s, int dim);

/* Index of property name in the scene's catalogue (dtm_material_get), or -1. */
DTM_EXPORT int dtm_scene_property_index(const dtm_scene *s, const char *name);
/* DTM_ERR_INPUT, naming the first material that gives it, for a property
 * that neither a built-in effect nor one of extra[nextra] (the properties
 * of the scene's external effects) declares. With extra NULL, a scene that
 * loads external effects passes (they are not known yet). */
DTM_EXPORT int dtm_scene_check_properties(const dtm_scene *s, const dtm_property *const *extra, int nextra);
/* The <meshing algorithm> name of a Gmsh Mesh.Algorithm3D code ("read"
 * for 0, a mesh read from a .msh; "other" for a code without a name). */
DTM_EXPORT const char *dtm_scene_algorithm_name(int code);

/* Path of part `part` (1 ...) of a partitioned file into buf[len]: file
 * with "{part}" replaced by the number, or, as Gmsh names the files it
 * splits, "_<part>" inserted before ".msh" (model.msh -> model_3.msh). For
 * a scene's <mesh partitions="P">, file is s->mesh. DTM_ERR_INPUT when it
 * does not fit. */
DTM_EXPORT int dtm_scene_part_path(const char *file, int part, char *buf, size_t len);

/* Value of attribute key of an effect, or NULL. */
DTM_EXPORT const char *dtm_scene_effect_attr(const dtm_scene_effect *e, const char *key);
/* Set attribute key of an effect to value (a copy), adding it when absent. */
DTM_EXPORT int dtm_scene_effect_set(dtm_scene_effect *e, const char *key, const char *value);

#endif
