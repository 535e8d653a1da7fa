/* Private to the scene reader (src/scene*.c): the split between reading and
 * validating the XML (scene_xml.c), turning elements into the dtm_scene
 * struct (scene.c, scene_material.c, scene_effects.c) and the small helpers
 * they share (scene_util.c). Nothing here is installed or exported from
 * libdtmap; every error raised here is "file:line: ..." about the scene. */
#ifndef DTMAP_SCENE_IMPL_H
#define DTMAP_SCENE_IMPL_H

#include <libxml/tree.h>

#include "dtmap/error.h"
#include "dtmap/scene.h"

/* Read, parse and schema-validate the scene at path. On success *doc is
 * owned by the caller (xmlFreeDoc); on failure DTM_ERR_INPUT with
 * "path: cannot read scene file", "path:line: malformed XML: ..." or
 * "path:line: schema: ...". */
int dtm_scene_xml_read(const char *path, xmlDoc **doc);
/* The same on len bytes at buf (not NUL-terminated), reported as name. */
int dtm_scene_xml_parse(const char *name, const char *buf, size_t len, xmlDoc **doc);
/* The order of <dtmap-scene>'s children from the embedded schema, as
 * "(geometry | mesh | model), meshing?, ..." (order.c); -1 if unreadable. */
int dtm_scene_child_order(char *buf, size_t len);

/* Raise DTM_ERR_INPUT with "scene-path:line-of-n: " before the message. */
int dtm_scene_fail(const dtm_scene *s, const xmlNode *n, const char *file, int line, const char *func, const char *fmt,
                   ...) __attribute__((format(printf, 6, 7)));
#define DTM_SCENE_ERR(s, n, ...) dtm_scene_fail((s), (n), __FILE__, __LINE__, __func__, __VA_ARGS__)

/* Line of node n in the scene file (0 if unknown). */
int dtm_scene_line(const xmlNode *n);
/* 1 if n is an element named tag. */
int dtm_scene_is(const xmlNode *n, const char *tag);
/* Number of element children of n. */
int dtm_scene_count_children(const xmlNode *n);
/* *out = malloc'd copy of attribute key of n (caller frees), NULL when
 * absent. DTM_ERR_INTERNAL when out of memory. */
int dtm_scene_attr(const xmlNode *n, const char *key, char **out);
/* Strict number parsing: the whole text (surrounding white space allowed)
 * must be a number; 0 on success, -1 otherwise. NaN and inf do parse. */
int dtm_scene_parse_double(const char *text, double *v);
/* Attribute key of n as a finite number > 0; *out = def when absent. */
int dtm_scene_attr_positive(const dtm_scene *s, const xmlNode *n, const char *key, double def, double *out);
/* Attribute key of n as true/1 or false/0 into *out (unchanged when
 * absent); anything else is an error at n's line. */
int dtm_scene_attr_bool(const dtm_scene *s, const xmlNode *n, const char *key, int *out);
/* Attribute key of n as a percentage, 0 to 100, into *out (unchanged when
 * absent). */
int dtm_scene_attr_percent(const dtm_scene *s, const xmlNode *n, const char *key, double *out);
/* *out = malloc'd path rel resolved against the scene's directory. */
int dtm_scene_resolve(const dtm_scene *s, const char *rel, char **out);
/* Split text at XML white space into *n malloc'd tokens *items. */
int dtm_scene_split(const char *text, int *n, char ***items);
/* Free n strings and the array holding them. */
void dtm_scene_free_strings(int n, char **v);
/* Duplicate s, or DTM_ERR_INTERNAL when out of memory. */
int dtm_scene_strdup(const char *s, char **out);

/* 1 for the <material> attributes that are not properties (name, groups,
 * default, plausible). */
int dtm_scene_material_keyword(const char *attr);
/* s->prop_names: the built-in effects' properties, then the other property
 * attributes of the <material> children of root. */
int dtm_scene_build_catalogue(dtm_scene *s, const xmlNode *root);

/* Read one <material> into s->materials[s->nmaterials++] (preallocated). */
int dtm_scene_read_material(dtm_scene *s, const xmlNode *n);
/* Read one <section> element into s->sections[s->nsections++]. */
int dtm_scene_read_section(dtm_scene *s, const xmlNode *n);
/* Read <effects> and its children into s->effects. */
int dtm_scene_read_effects(dtm_scene *s, const xmlNode *n);
/* The material values no solid has (plausible.c): DTM_ERR_INPUT naming the
 * material's line, the likely unit slip and the remedy. */
int dtm_scene_check_plausible(const dtm_scene *s);
/* A plausible="..." attribute of n: 1 for "no-check", 0 for "check" or
 * none, an error for another word. */
int dtm_scene_read_plausible(const dtm_scene *s, const xmlNode *n, int *no_check);

#endif
