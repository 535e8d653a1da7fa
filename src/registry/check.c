/* Registration checks: a class is used only when it is complete. Its role
 * needs its functions (a limiting effect its element_dt and a scheme, a
 * wave modifier its wave_factor), accuracy() needs an indicator to show,
 * and its parameter and property declarations must be well formed. The
 * message says what the class declares and what it lacks, so an external
 * effect that is incomplete is refused instead of crashing dtmap. */
#include <math.h>
#include <string.h>

#include "registry-impl.h"

static int lacks(const dtm_effect_class *c, const char *declares, const char *missing) {
  return DTM_ERR(DTM_ERR_INPUT, "effect '%s' declares %s but has no %s", c->name, declares, missing);
}

static int check_role(const dtm_effect_class *c) {
  if (!(c->role & (DTM_ROLE_LIMITS | DTM_ROLE_MODIFIES_WAVES)))
    return DTM_ERR(DTM_ERR_INPUT, "effect '%s' declares no role (DTM_ROLE_LIMITS or DTM_ROLE_MODIFIES_WAVES)", c->name);
  if ((c->role & DTM_ROLE_LIMITS) && !c->element_dt) return lacks(c, "DTM_ROLE_LIMITS", "element_dt");
  if ((c->role & DTM_ROLE_LIMITS) && c->scheme == DTM_SCHEME_NONE)
    return lacks(c, "DTM_ROLE_LIMITS", "time integration scheme (scheme)");
  if ((c->role & DTM_ROLE_LIMITS) && !(c->exponent > 0))
    return lacks(c, "DTM_ROLE_LIMITS", "size exponent (exponent > 0)");
  if ((c->role & DTM_ROLE_MODIFIES_WAVES) && !c->wave_factor) return lacks(c, "DTM_ROLE_MODIFIES_WAVES", "wave_factor");
  if (c->rayleigh && !(c->role & DTM_ROLE_MODIFIES_WAVES)) return lacks(c, "rayleigh", "DTM_ROLE_MODIFIES_WAVES");
  if (c->coefficients && !(c->role & DTM_ROLE_LIMITS)) return lacks(c, "coefficients", "DTM_ROLE_LIMITS");
  return DTM_OK;
}

static int check_param(const dtm_effect_class *c, const dtm_param *p) {
  if (p->type == DTM_PARAM_CHOICE && (!p->choices || !p->choices[0])) return lacks(c, "a choice parameter", "choices");
  if (p->type == DTM_PARAM_NUMBER && (isnan(p->lo) || isnan(p->hi) || p->lo > p->hi))
    return DTM_ERR(DTM_ERR_INPUT, "effect '%s' declares parameter '%s' with an empty range", c->name, p->name);
  if (!strcmp(p->name, "name") || !strcmp(p->name, "library"))
    return DTM_ERR(DTM_ERR_INPUT, "effect '%s' declares parameter '%s', which the core reserves", c->name, p->name);
  return DTM_OK;
}

static int check_declarations(const dtm_effect_class *c) {
  for (const dtm_param *p = c->params; p && p->name; p++) DTM_CHECK(check_param(c, p));
  for (const dtm_property *p = c->properties; p && p->name; p++)
    if (isnan(p->lo) || isnan(p->hi) || p->lo > p->hi)
      return DTM_ERR(DTM_ERR_INPUT, "effect '%s' declares property '%s' with an empty range", c->name, p->name);
  return DTM_OK;
}

int dtm_registry_check(const dtm_effect_class *c) {
  if (!c || !c->name || !c->name[0]) return DTM_ERR(DTM_ERR_INPUT, "an effect class has no name");
  DTM_CHECK(check_role(c));
  if (c->accuracy && !(c->indicator.name && c->indicator.view))
    return lacks(c, "accuracy()", "indicator (name and view)");
  return check_declarations(c);
}

/* Two declarations of one property must agree on what is admissible. */
static int same_range(const dtm_property *a, const dtm_property *b) {
  return a->lo == b->lo && a->hi == b->hi && a->open == b->open;
}

int dtm_registry_check_all(void) {
  for (int i = 0; i < dtm_registry_count(); i++) DTM_CHECK(dtm_registry_check(dtm_registry_get(i)));
  for (int i = 0; i < dtm_registry_count(); i++)
    for (const dtm_property *p = dtm_registry_get(i)->properties; p && p->name; p++) {
      const dtm_property *first = dtm_registry_property(p->name, NULL);
      if (!same_range(first, p))
        return DTM_ERR(DTM_ERR_INPUT, "effect '%s' declares property '%s' with another range than an earlier effect",
                       dtm_registry_get(i)->name, p->name);
    }
  return DTM_OK;
}
