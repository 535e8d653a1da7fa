/* Accessors effects use at creation time: their attributes (or the
 * defaults their class declares), parsed strictly with errors that name the
 * scene file and line, property indices, and the mesh's groups. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "effect-impl.h"

/* The declaration of parameter key, or NULL (no class: a bare fixture). */
static const dtm_param *declared(const dtm_effect_args *a, const char *key) {
  for (const dtm_param *p = a->cls ? a->cls->params : NULL; p && p->name; p++)
    if (!strcmp(p->name, key)) return p;
  return NULL;
}

int dtm_effect_args_text(const dtm_effect_args *a, const char *key, const char **out) {
  const dtm_param *p = declared(a, key);
  const char *v = dtm_scene_effect_attr(a->se, key);
  *out = v ? v : p ? p->def : NULL;
  return DTM_OK;
}

int dtm_effect_args_number(const dtm_effect_args *a, const char *key, double *out) {
  const char *v;
  DTM_CHECK(dtm_effect_args_text(a, key, &v));
  if (!v) return *out = NAN, DTM_OK;
  char *end = NULL;
  double d = strtod(v, &end);
  if (end == v || *end || !isfinite(d)) return dtm_effect_args_error(a, "%s=\"%s\" is not a finite number", key, v);
  *out = d;
  return DTM_OK;
}

int dtm_effect_args_choice(const dtm_effect_args *a, const char *key, int *index) {
  const dtm_param *p = declared(a, key);
  const char *v;
  DTM_CHECK(dtm_effect_args_text(a, key, &v));
  *index = -1;
  if (!p || p->type != DTM_PARAM_CHOICE) return DTM_ERR(DTM_ERR_INTERNAL, "'%s' is not a declared choice", key);
  for (int i = 0; v && p->choices[i]; i++)
    if (!strcmp(p->choices[i], v)) *index = i;
  if (v && *index < 0) return dtm_effect_args_error(a, "%s=\"%s\" is not one of its choices", key, v);
  return DTM_OK;
}

int dtm_effect_args_property(const dtm_effect_args *a, const char *name) {
  return dtm_scene_property_index(a->scene, name);
}

int dtm_effect_args_double(const dtm_effect_args *a, const char *key, double def, double *out) {
  const char *v = dtm_scene_effect_attr(a->se, key);
  if (!v) {
    *out = def;
    return DTM_OK;
  }
  char *end = NULL;
  double d = strtod(v, &end);
  if (end == v || *end || !isfinite(d)) return dtm_effect_args_error(a, "%s=\"%s\" is not a finite number", key, v);
  *out = d;
  return DTM_OK;
}

int dtm_effect_args_string(const dtm_effect_args *a, const char *key, const char *def, const char **out) {
  const char *v = dtm_scene_effect_attr(a->se, key);
  *out = v ? v : def;
  return DTM_OK;
}

int dtm_effect_args_error(const dtm_effect_args *a, const char *fmt, ...) {
  char msg[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return DTM_ERR(DTM_ERR_INPUT, "%s:%d: <%s>: %s", a->scene->path, a->se->line, a->se->name, msg);
}

int dtm_effect_args_dim(const dtm_effect_args *a) { return a->mesh->dim; }

double dtm_effect_args_fmax(const dtm_effect_args *a) { return a->scene->f_max; }

double dtm_effect_args_per_wavelength(const dtm_effect_args *a) {
  return a->scene->elements_per_wavelength > 0 ? a->scene->elements_per_wavelength : DTM_SCENE_PER_WAVELENGTH;
}

int dtm_effect_args_ngroups(const dtm_effect_args *a) { return a->mesh->ngroups; }

size_t dtm_effect_args_unsectioned(const dtm_effect_args *a) {
  size_t n = 0;
  for (int b = 0; b < a->mesh->nblocks; b++) {
    const dtm_block *bl = &a->mesh->blocks[b];
    for (size_t e = 0; bl->dim == a->mesh->dim && e < bl->n; e++) n += !bl->section || bl->section[e] < 0;
  }
  return n;
}

int dtm_effect_args_group(const dtm_effect_args *a, const char *ref, int *index) {
  *index = dtm_mesh_group_find(a->mesh, ref);
  if (*index >= 0) return DTM_OK;
  char list[2048] = "", lbl[64];
  for (int g = 0; g < a->mesh->ngroups; g++)
    dtm_strlist_add(list, sizeof list, dtm_mesh_group_label(a->mesh, g, lbl, sizeof lbl), 1);
  return dtm_effect_args_error(a, "physical group '%s' does not exist in dimension %d; groups: %s", ref, a->mesh->dim,
                               a->mesh->ngroups ? list : "(none)");
}

void dtm_effect_free(void **state) {
  free(*state);
  *state = NULL;
}
