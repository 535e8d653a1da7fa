/* The effect registry: the built-in effects (listed once in plugins/list.h)
 * and external effects loaded from shared libraries, checked on
 * registration (API version, name, and that the functions its role needs
 * are there), and the validation of a scene element's attributes against
 * what the class declares. Below the scene reader, which uses it to
 * validate scenes; creating effects for a scene is effect_set.h. */
#ifndef DTMAP_REGISTRY_H
#define DTMAP_REGISTRY_H

#include <stddef.h>

#include "dtmap/effect.h"
#include "dtmap/export.h"

/* The effect API version this libdtmap loads (DTM_EFFECT_API_VERSION of
 * the headers it was built with): an external effect must declare it. */
DTM_EXPORT int dtm_registry_api_version(void);
/* Number of built-in effects and the i-th one, in registration order. */
DTM_EXPORT int dtm_registry_count(void);
DTM_EXPORT const dtm_effect_class *dtm_registry_get(int i);
/* Built-in effect by name; DTM_ERR_INPUT listing the known names if none. */
DTM_EXPORT int dtm_registry_find(const char *name, const dtm_effect_class **out);
/* Load an external effect from a shared library: resolve
 * DTM_EFFECT_ENTRY_SYMBOL, check the API version, the name and the class
 * (dtm_registry_check). *handle is the dlopen handle; the caller closes it
 * with dlclose (dtm_effect_set_destroy does). */
DTM_EXPORT int dtm_registry_load(const char *library, const char *name, const dtm_effect_class **out, void **handle);
/* Check that class c is complete: a name, the functions its role needs
 * (DTM_ROLE_LIMITS: element_dt; DTM_ROLE_MODIFIES_WAVES: wave_factor), an
 * indicator for accuracy(), a scheme for a limiting effect, well-formed
 * parameter and property declarations. DTM_ERR_INPUT "effect X declares Y
 * but has no Z" otherwise. */
DTM_EXPORT int dtm_registry_check(const dtm_effect_class *c);

/* Check the attributes of a scene element of class c: every key is a
 * declared parameter (keys in `skip`, a NULL-terminated list such as
 * {"name", "library", NULL}, are the core's), each value fits its
 * declaration, and every required parameter is given. On failure
 * DTM_ERR_INPUT whose message starts with where (e.g. "scene.xml:7: ") and
 * names the attribute and the known ones. */
DTM_EXPORT int dtm_registry_check_attributes(const dtm_effect_class *c, int n, char *const *keys, char *const *values,
                                             const char *const *skip, const char *where);

/* The material properties the built-in effects declare, without repeats, in
 * registration order (*n of them; the array is static). Two effects that
 * declare the same property must agree on its range (dtm_registry_check_all). */
DTM_EXPORT const dtm_property *const *dtm_registry_properties(int *n);
/* The declaration of property name among the built-in effects and extra
 * (an external effect's class, or NULL), or NULL. */
DTM_EXPORT const dtm_property *dtm_registry_property(const char *name, const dtm_effect_class *extra);
/* Check every built-in class and their property declarations together. */
DTM_EXPORT int dtm_registry_check_all(void);

#endif
