/* Which model the ONELAB client works on: the file open in the Gmsh that
 * launched it (asked for as the option General.FileName), the scene beside
 * it (MODEL.xml for MODEL.geo or MODEL.msh) or the one on the command line,
 * and, opened in dtmap's own Gmsh, the dimension to analyse, its physical
 * groups (each gets a material menu in the panel) and the groups of curves
 * and surfaces below that dimension (each gets a section menu: analysed as
 * trusses or membranes, or not at all). */
#define _XOPEN_SOURCE 700 /* realpath */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "onelab-impl.h"

static int model_file(ol_conn *c, char *out, size_t n) {
  ol_param p;
  int found = 0;
  out[0] = '\0';
  DTM_CHECK(dtm_ol_get(c, "General.FileName", 1, &p, &found));
  if (found && p.svalue[0]) {
    char *abs = realpath(p.svalue, NULL);
    snprintf(out, n, "%s", abs ? abs : p.svalue);
    free(abs);
  }
  return DTM_OK;
}

/* MODEL.xml beside MODEL.ext, when it exists. */
static void scene_beside(const char *model, char *out, size_t n) {
  const char *slash = strrchr(model, '/'), *dot = strrchr(model, '.');
  int len = dot && (!slash || dot > slash) ? (int)(dot - model) : (int)strlen(model);
  snprintf(out, n, "%.*s.xml", len, model);
  if (access(out, R_OK)) out[0] = '\0';
}

static int is_msh(const char *path) {
  size_t n = strlen(path);
  return n > 4 && !strcasecmp(path + n - 4, ".msh");
}

static int find_scene(ol_conn *c, const char *scene_arg, ol_model *m) {
  DTM_CHECK(model_file(c, m->model, sizeof m->model));
  if (scene_arg)
    snprintf(m->scene, sizeof m->scene, "%s", scene_arg);
  else if (m->model[0])
    scene_beside(m->model, m->scene, sizeof m->scene);
  if (!m->model[0] && !m->scene[0])
    return DTM_ERR(DTM_ERR_INPUT, "no model is open in Gmsh: open a geometry (.geo, .step, .brep) or a .msh first");
  if (m->scene[0]) DTM_CHECK(dtm_scene_load(m->scene, &m->base));
  return DTM_OK;
}

void dtm_ol_group_ref(const dtm_group *g, char *ref, size_t n) {
  if (g->name && g->name[0])
    snprintf(ref, n, "%s", g->name);
  else
    snprintf(ref, n, "%d", g->tag);
}

/* Whether one of have[n] has the reference (name, or number) of g: a scene
 * could not tell them apart. */
static int ref_taken(const dtm_group *g, const dtm_group *have, int n) {
  char a[128], b[128];
  dtm_ol_group_ref(g, a, sizeof a);
  for (int i = 0; i < n; i++)
    if (dtm_ol_group_ref(&have[i], b, sizeof b), !strcmp(a, b)) return 1;
  return 0;
}

/* The groups of dimension d (below the analysed one) appended to m->lower,
 * but those a scene could not tell from a group listed already. */
static int lower_groups(ol_model *m, int d) {
  dtm_group *g = NULL;
  int n = 0;
  DTM_CHECK(dtm_gmsh_groups(d, &g, &n));
  dtm_group *all = realloc(m->lower, ((size_t)m->nlower + (size_t)n + 1) * sizeof *all);
  if (all) m->lower = all;
  for (int i = 0; i < n; i++) {
    if (all && !ref_taken(&g[i], m->groups, m->ngroups) && !ref_taken(&g[i], m->lower, m->nlower))
      m->lower[m->nlower++] = g[i];
    else
      free(g[i].name);
  }
  free(g);
  return all ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
}

int dtm_ol_model_load(ol_conn *c, const char *scene_arg, ol_model *m) {
  memset(m, 0, sizeof *m);
  DTM_CHECK(find_scene(c, scene_arg, m));
  m->source = m->base ? (m->base->mesh ? m->base->mesh : m->base->geometry) : m->model;
  m->source_is_mesh = is_msh(m->source);
  DTM_CHECK(dtm_gmsh_open(m->source, &m->dim));
  if (m->base && m->base->mesh_dim > 0) m->dim = m->base->mesh_dim;
  DTM_CHECK(dtm_gmsh_groups(m->dim, &m->groups, &m->ngroups));
  for (int d = m->dim - 1; d >= 1; d--) DTM_CHECK(lower_groups(m, d));
  return DTM_OK;
}

static void free_groups(dtm_group **g, int *n) {
  for (int i = 0; *g && i < *n; i++) free((*g)[i].name);
  free(*g);
  *g = NULL;
  *n = 0;
}

void dtm_ol_model_free(ol_model *m) {
  free_groups(&m->groups, &m->ngroups);
  free_groups(&m->lower, &m->nlower);
  dtm_scene_destroy(&m->base);
}
