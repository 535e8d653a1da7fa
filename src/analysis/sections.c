/* The scene's sections on the mesh's physical groups: which group has which
 * section, and the checks that need the mesh. A section names groups that
 * exist, of the dimension its kind applies to (solid: volumes; plane-strain
 * and plane-stress: the surfaces of a 2D model; membrane: surfaces, in 2D
 * or 3D; truss: curves); after extraction each sectioned group holds
 * elements. Every error names the scene file and line of the section. */
#include <stdio.h>
#include <stdlib.h>

#include "analysis-impl.h"

static const char *dim_noun(int d) { return d == 3 ? "volumes" : d == 2 ? "surfaces" : "curves"; }

static int missing_group(const dtm_scene *s, const dtm_mesh *m, const dtm_section *sec, const char *ref) {
  char list[2048] = "", lbl[64];
  for (int j = 0; j < m->ngroups; j++)
    dtm_strlist_add(list, sizeof list, dtm_mesh_group_label(m, j, lbl, sizeof lbl), 1);
  return DTM_ERR(DTM_ERR_INPUT, "%s:%d: section (%s): physical group '%s' does not exist; groups: %s", s->path,
                 sec->line, dtm_section_kind_name(sec->kind), ref, m->ngroups ? list : "(none)");
}

/* Whether kind k suits a group of dimension gd in a model analysed in dim. */
static int suits(int k, int gd, int dim) {
  if (gd != dtm_section_dim(k)) return 0;
  return !(k == DTM_SECTION_PLANE_STRAIN || k == DTM_SECTION_PLANE_STRESS) || dim == 2;
}

static int wrong_dim(const dtm_scene *s, const dtm_section *sec, const char *ref, int gd, int dim) {
  const char *kind = dtm_section_kind_name(sec->kind);
  if (gd == 2 && dtm_section_dim(sec->kind) == 2)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s:%d: section (%s) on group '%s': a %s section is for a 2D model; the model is analysed in "
                   "%dD, where surfaces are membranes (kind=\"membrane\" thickness=\"...\")",
                   s->path, sec->line, kind, ref, kind, dim);
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s:%d: section (%s) on group '%s': the group holds %s (dimension %d), a %s section needs %s "
                 "(dimension %d)",
                 s->path, sec->line, kind, ref, dim_noun(gd), gd, kind, dim_noun(dtm_section_dim(sec->kind)),
                 dtm_section_dim(sec->kind));
}

static int map_one(const dtm_scene *s, const dtm_mesh *m, int i, int *gs, int *def) {
  const dtm_section *sec = &s->sections[i];
  if (sec->is_default && !suits(sec->kind, m->dim, m->dim)) return wrong_dim(s, sec, "(default)", m->dim, m->dim);
  if (sec->is_default) *def = i;
  for (int k = 0; k < sec->ngroups; k++) {
    int g = dtm_mesh_group_find(m, sec->groups[k]);
    if (g < 0) return missing_group(s, m, sec, sec->groups[k]);
    if (!suits(sec->kind, m->groups[g].dim, m->dim)) return wrong_dim(s, sec, sec->groups[k], m->groups[g].dim, m->dim);
    gs[g] = i;
  }
  return DTM_OK;
}

int dtm_analysis_map_sections(const dtm_scene *s, const dtm_mesh *m, int **gs, int *def) {
  *gs = NULL, *def = -1;
  if (!s->nsections) return DTM_OK;
  int *t = malloc(((size_t)m->ngroups + 1) * sizeof *t);
  if (!t) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int g = 0; g < m->ngroups; g++) t[g] = -1;
  for (int i = 0; i < s->nsections; i++) {
    int r = map_one(s, m, i, t, def);
    if (r) return free(t), dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *gs = t;
  return DTM_OK;
}

int dtm_analysis_check_sections(const dtm_scene *s, const dtm_mesh *m, const int *gs) {
  if (!gs) return DTM_OK;
  size_t *count = calloc((size_t)m->ngroups + 1, sizeof *count);
  if (!count) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int b = 0; b < m->nblocks; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++) {
      const dtm_block *blk = &m->blocks[b];
      if (blk->group[e] >= 0) count[blk->group[e]]++;
      for (int g = 0; blk->gmask && g < m->ngroups && g < DTM_MAX_MASK_GROUPS; g++) count[g] += blk->gmask[e] >> g & 1;
    }
  int r = DTM_OK;
  for (int g = 0; g < m->ngroups && r == DTM_OK; g++) {
    if (gs[g] < 0 || count[g]) continue;
    char lbl[64];
    const dtm_section *sec = &s->sections[gs[g]];
    r = DTM_ERR(DTM_ERR_INPUT, "%s:%d: section (%s) on group '%s': the group holds no mesh element of dimension %d",
                s->path, sec->line, dtm_section_kind_name(sec->kind), dtm_mesh_group_label(m, g, lbl, sizeof lbl),
                m->groups[g].dim);
  }
  free(count);
  return r;
}

const dtm_section *dtm_analysis_section(const dtm_analysis *a, const dtm_block *b, size_t e) {
  return b->section && b->section[e] >= 0 ? &a->scene->sections[b->section[e]] : NULL;
}

int dtm_analysis_nslots(const dtm_analysis *a) { return a->scene->nmaterials * (a->scene->nsections + 1); }

int dtm_analysis_slot(const dtm_analysis *a, const dtm_block *b, size_t e) {
  return b->mat[e] + (b->section ? a->scene->nmaterials * (b->section[e] + 1) : 0);
}

int dtm_analysis_coefficients(const dtm_analysis *a, int k, int slot, dtm_operator_coeffs *c) {
  const dtm_effect *ef = &a->effects[k];
  int nm = a->scene->nmaterials, sec = slot / nm - 1;
  const dtm_section *s = sec >= 0 ? &a->scene->sections[sec] : NULL;
  DTM_CHECK(ef->cls->coefficients(ef->state, &a->scene->materials[slot % nm].m, s, c));
  c->section_factor = dtm_section_factor(s);
  return DTM_OK;
}
