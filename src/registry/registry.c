/* The registry of built-in effects (expanded from plugins/list.h) and the
 * loader of external effects from shared libraries. Every class is checked
 * before it is used (dtm_registry_check): a library whose class is
 * incomplete is refused with a message, never called. */
#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

#include "base.h"
#include "dtmap/registry.h"

#define DTM_EFFECT(sym) extern const dtm_effect_class sym;
#include "list.h"
#undef DTM_EFFECT

static const dtm_effect_class *const builtin[] = {
#define DTM_EFFECT(sym) &sym,
#include "list.h"
#undef DTM_EFFECT
};

int dtm_registry_api_version(void) { return DTM_EFFECT_API_VERSION; }

int dtm_registry_count(void) { return (int)(sizeof builtin / sizeof builtin[0]); }

const dtm_effect_class *dtm_registry_get(int i) { return (i >= 0 && i < dtm_registry_count()) ? builtin[i] : NULL; }

static void known_names(char *buf, size_t len) {
  buf[0] = '\0';
  for (int i = 0; i < dtm_registry_count(); i++) dtm_strlist_add(buf, len, builtin[i]->name, 0);
}

int dtm_registry_find(const char *name, const dtm_effect_class **out) {
  for (int i = 0; i < dtm_registry_count(); i++)
    if (strcmp(builtin[i]->name, name) == 0) {
      *out = builtin[i];
      return DTM_OK;
    }
  char known[1024];
  known_names(known, sizeof known);
  return DTM_ERR(DTM_ERR_INPUT, "unknown effect '%s'; known effects: %s", name, known);
}

/* Why the class c of a library does not fit, or NULL when it does. */
static const char *mismatch(const dtm_effect_class *c, const char *name) {
  if (!c) return "its entry returned NULL";
  if (c->api_version != DTM_EFFECT_API_VERSION) return "API version mismatch";
  if (strcmp(c->name ? c->name : "", name)) return "name mismatch";
  return NULL;
}

static const dtm_effect_class *entry_class(void *sym) {
  const dtm_effect_class *(*entry)(void);
  memcpy(&entry, &sym, sizeof entry); /* object-to-function pointer, POSIX style */
  return entry();
}

int dtm_registry_load(const char *library, const char *name, const dtm_effect_class **out, void **handle) {
  void *h = dlopen(library, RTLD_NOW | RTLD_LOCAL);
  if (!h) return DTM_ERR(DTM_ERR_INPUT, "cannot load effect library: %s", dlerror());
  void *sym = dlsym(h, DTM_EFFECT_ENTRY_SYMBOL);
  if (!sym) {
    dlclose(h);
    return DTM_ERR(DTM_ERR_INPUT, "%s: no symbol '%s': not a dtmap effect library", library, DTM_EFFECT_ENTRY_SYMBOL);
  }
  const dtm_effect_class *c = entry_class(sym);
  const char *why = mismatch(c, name);
  int r = why ? DTM_ERR(DTM_ERR_INPUT, "%s: %s (library: version %d, name '%s'; dtmap: version %d, name '%s')", library,
                        why, c ? c->api_version : -1, c && c->name ? c->name : "", DTM_EFFECT_API_VERSION, name)
              : dtm_registry_check(c);
  if (r) {
    dlclose(h);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = c;
  *handle = h;
  return DTM_OK;
}
