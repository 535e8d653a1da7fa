/* Private to src/registry/: what its files share. */
#ifndef DTM_REGISTRY_IMPL_H
#define DTM_REGISTRY_IMPL_H

#include "base.h"
#include "dtmap/registry.h"

/* The declaration of parameter key in class c, or NULL. */
const dtm_param *dtm_registry_param(const dtm_effect_class *c, const char *key);

#endif
