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

#define DTM_HIDDEN __attribute__((visibility("hidden")))

/* Read, parse and schema-validate the scene at path. On success *doc is
 * owned by the caller (xmlFreeDoc); on failure DTM_ERR_INPUT with
 * "path: cannot read scene file", "path:line: malformed XML: ..." or
 * "path:line: schema: ...". */
DTM_HIDDEN int dtm_scene_xml_read(const char *path, xmlDoc **doc);

/* Raise DTM_ERR_INPUT with "scene-path:line-of-n: " before the message. */
DTM_HIDDEN int dtm_scene_fail(const dtm_scene *s, const xmlNode *n, const char *file, int line, const char *func,
                              const char *fmt, ...) __attribute__((format(printf, 6, 7)));
#define DTM_SCENE_ERR(s, n, ...) dtm_scene_fail((s), (n), __FILE__, __LINE__, __func__, __VA_ARGS__)

/* Line of node n in the scene file (0 if unknown). */
DTM_HIDDEN int dtm_scene_line(const xmlNode *n);
/* 1 if n is an element named tag. */
DTM_HIDDEN int dtm_scene_is(const xmlNode *n, const char *tag);
/* Number of element children of n. */
DTM_HIDDEN int dtm_scene_count_children(const xmlNode *n);
/* *out = malloc'd copy of attribute key of n (caller frees), NULL when
 * absent. DTM_ERR_INTERNAL when out of memory. */
DTM_HIDDEN int dtm_scene_attr(const xmlNode *n, const char *key, char **out);
/* Strict number parsing: the whole text (surrounding white space allowed)
 * must be a number; 0 on success, -1 otherwise. NaN and inf do parse. */
DTM_HIDDEN int dtm_scene_parse_double(const char *text, double *v);
/* Attribute key of n as a finite number > 0; *out = def when absent. */
DTM_HIDDEN int dtm_scene_attr_positive(const dtm_scene *s, const xmlNode *n, const char *key, double def, double *out);
/* *out = malloc'd path rel resolved against the scene's directory. */
DTM_HIDDEN int dtm_scene_resolve(const dtm_scene *s, const char *rel, char **out);
/* Split text at XML white space into *n malloc'd tokens *items. */
DTM_HIDDEN int dtm_scene_split(const char *text, int *n, char ***items);
/* Free n strings and the array holding them. */
DTM_HIDDEN void dtm_scene_free_strings(int n, char **v);
/* Duplicate s, or DTM_ERR_INTERNAL when out of memory. */
DTM_HIDDEN int dtm_scene_strdup(const char *s, char **out);

/* Read one <material> into s->materials[s->nmaterials++] (preallocated). */
DTM_HIDDEN int dtm_scene_read_material(dtm_scene *s, const xmlNode *n);
/* Read <effects> and its children into s->effects. */
DTM_HIDDEN int dtm_scene_read_effects(dtm_scene *s, const xmlNode *n);

#endif
