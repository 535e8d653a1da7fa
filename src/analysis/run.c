/* The whole analysis of a scene: Gmsh load or meshing, physical groups to
 * materials, extraction, creation of only the scene's effects, compute,
 * and where the mesh sits on the model (for shape-limited elements). Also
 * the per-element look-ups (tag, group, centroid) reports and prints use. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "dtmap/gmsh.h"
#include "dtmap/units.h"

/* The dimension below m->dim of a physical group named ref, 0 if none. */
static int lower_dim_of(const dtm_mesh *m, const char *ref) {
  for (int d = m->dim - 1; d >= 1; d--) {
    dtm_mesh low = {.dim = d};
    int found = 0;
    if (dtm_gmsh_groups(d, &low.groups, &low.ngroups)) return dtm_error_clear(), 0;
    found = dtm_mesh_group_find(&low, ref) >= 0;
    for (int j = 0; j < low.ngroups; j++) free(low.groups[j].name);
    free(low.groups);
    if (found) return d;
  }
  return 0;
}

static int missing_group(const dtm_scene *s, const dtm_mesh *m, const dtm_scene_material *sm, const char *ref) {
  char list[2048] = "", lbl[64];
  for (int j = 0; j < m->ngroups; j++)
    if (m->groups[j].dim == m->dim) dtm_strlist_add(list, sizeof list, dtm_mesh_group_label(m, j, lbl, sizeof lbl), 1);
  int low = lower_dim_of(m, ref);
  if (low)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s:%d: material '%s': physical group '%s' holds %s (dimension %d), which a %dD model analyses "
                   "only with a section: add <section groups=\"%s\" kind=\"%s\" %s=\"...\"/>",
                   s->path, sm->m.line, sm->m.name, ref, low == 1 ? "curves" : "surfaces", low, m->dim, ref,
                   low == 1 ? "truss" : "membrane", low == 1 ? "area" : "thickness");
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s:%d: material '%s': physical group '%s' does not exist in dimension %d; "
                 "groups of that dimension: %s",
                 s->path, sm->m.line, sm->m.name, ref, m->dim, list[0] ? list : "(none)");
}

/* Material of every group the scene names, and the default material. */
static int map_one(const dtm_scene *s, const dtm_mesh *m, int i, int *group_mat) {
  const dtm_scene_material *sm = &s->materials[i];
  for (int k = 0; k < sm->ngroups; k++) {
    int g = dtm_mesh_group_find(m, sm->groups[k]);
    if (g < 0) return missing_group(s, m, sm, sm->groups[k]);
    if (group_mat[g] >= 0 && group_mat[g] != i)
      return DTM_ERR(DTM_ERR_INPUT, "%s:%d: material '%s': physical group '%s' already has material '%s'", s->path,
                     sm->m.line, sm->m.name, sm->groups[k], s->materials[group_mat[g]].m.name);
    group_mat[g] = i;
  }
  return DTM_OK;
}

static int map_materials(const dtm_scene *s, const dtm_mesh *m, int **group_mat, int *def) {
  int *gm = malloc(((size_t)m->ngroups + 1) * sizeof *gm);
  if (!gm) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int g = 0; g < m->ngroups; g++) gm[g] = -1;
  *def = -1;
  for (int i = 0; i < s->nmaterials; i++) {
    if (s->materials[i].is_default) *def = i;
    int r = map_one(s, m, i, gm);
    if (r) {
      free(gm);
      return dtm_error_trace(r, __FILE__, __LINE__, __func__);
    }
  }
  *group_mat = gm;
  return DTM_OK;
}

/* whole: m is the whole mesh (not one part of a distributed run, where a
 * sectioned group may well have no element in this part). */
static int extract_mesh(const dtm_scene *s, int dim, int whole, dtm_mesh *m, double *t) {
  double t0 = dtm_wtime();
  int *gm = NULL, *gs = NULL, def = -1, defsec = -1;
  m->dim = dim, m->length_unit = dtm_units_name(s->units, DTM_UNIT_LENGTH);
  DTM_CHECK(dtm_gmsh_groups(dim, &m->groups, &m->ngroups));
  DTM_CHECK(dtm_gmsh_groups_sectioned(dim, s, &m->groups, &m->ngroups));
  DTM_CHECK(map_materials(s, m, &gm, &def));
  int r = dtm_analysis_map_sections(s, m, &gs, &defsec);
  dtm_group_map map = {gm, def, gs, defsec};
  if (r == DTM_OK) r = dtm_gmsh_extract_map(dim, &map, s, m);
  if (r == DTM_OK && whole) r = dtm_analysis_check_sections(s, m, gs);
  if (r == DTM_OK && whole) r = dtm_gmsh_left_out(m);
  free(gm), free(gs);
  if (r == DTM_OK) r = dtm_mesh_reorder(m); /* locality for every loop below; reports stay by tag */
  const char *src = s->mesh ? s->mesh : s->geometry ? s->geometry : "the current Gmsh model";
  if (r == DTM_OK) r = dtm_mesh_check(m, src);
  if (r == DTM_OK) r = dtm_gmsh_node_masses(m, src, dtm_scene_mass_unit(s, m->dim));
  t[DTM_T_EXTRACT] = dtm_wtime() - t0;
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

/* A distributed run sums node masses over the parts that share a node:
 * point masses carried by the mesh would count once per part. */
static int no_point_masses(const dtm_scene *s, const dtm_mesh *m) {
  if (!m->node_mass) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: the mesh carries point masses (view '%s'), which a distributed run does not take yet; run it "
                 "without mpirun",
                 s->mesh ? s->mesh : s->path, DTM_VIEW_NODE_MASS);
}

int dtm_analysis_extract(const dtm_scene *s, int dim, dtm_mesh **out, double *seconds) {
  double t[DTM_T_COUNT] = {0};
  dtm_mesh *m = calloc(1, sizeof *m);
  int r = m ? extract_mesh(s, dim, 0, m, t) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = no_point_masses(s, m);
  if (r) {
    dtm_mesh_destroy(&m);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = m;
  *seconds = t[DTM_T_EXTRACT];
  return DTM_OK;
}

int dtm_analysis_extract_whole(const dtm_scene *s, int dim, dtm_mesh **mesh, dtm_geo **geo) {
  double t[DTM_T_COUNT] = {0};
  dtm_mesh *m = calloc(1, sizeof *m);
  int r = m ? extract_mesh(s, dim, 1, m, t) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) r = no_point_masses(s, m);
  if (r == DTM_OK) r = dtm_gmsh_geo(m, geo);
  if (r) {
    dtm_mesh_destroy(&m);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *mesh = m;
  return DTM_OK;
}

int dtm_analysis_run(const dtm_scene *s, dtm_analysis **out) { return dtm_analysis_run_ex(s, NULL, NULL, out); }

static int current(const dtm_scene *s, int dim, dtm_extracted_fn hook, void *user, dtm_analysis **out);

int dtm_analysis_run_ex(const dtm_scene *s, dtm_extracted_fn hook, void *user, dtm_analysis **out) {
  double t0 = dtm_wtime();
  int dim;
  DTM_CHECK(dtm_gmsh_load(s, &dim));
  double t_mesh = dtm_wtime() - t0;
  DTM_CHECK(current(s, dim, hook, user, out));
  (*out)->timings[DTM_T_MESH] = t_mesh;
  return DTM_OK;
}

int dtm_analysis_current(const dtm_scene *s, int dim, dtm_analysis **out) { return current(s, dim, NULL, NULL, out); }

/* Extract the mesh and read where it sits on the model (timed with the
 * extraction), both before the hook (which may release the model), then
 * create the scene's effects. */
static int prepare(const dtm_scene *s, int dim, dtm_extracted_fn hook, void *user, dtm_mesh *m, dtm_geo **geo,
                   dtm_effect **e, int *ne, double *t) {
  int r = extract_mesh(s, dim, 1, m, t);
  double t0 = dtm_wtime();
  if (r == DTM_OK) r = dtm_gmsh_geo(m, geo);
  t[DTM_T_EXTRACT] += dtm_wtime() - t0;
  if (r == DTM_OK && hook) r = hook(user, dtm_mesh_nelements(m));
  if (r == DTM_OK) r = dtm_effects_create(s, m, e, ne);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

static int current(const dtm_scene *s, int dim, dtm_extracted_fn hook, void *user, dtm_analysis **out) {
  double t[DTM_T_COUNT] = {0};
  dtm_mesh *m = calloc(1, sizeof *m);
  dtm_effect *e = NULL;
  dtm_geo *geo = NULL;
  dtm_mesher_info mi;
  int ne = 0;
  if (!m) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = prepare(s, dim, hook, user, m, &geo, &e, &ne, t);
  dtm_gmsh_mesher(&mi);
  if (r) dtm_mesh_destroy(&m);
  if (r == DTM_OK) r = dtm_analysis_compute(s, m, e, ne, out);
  if (r) {
    dtm_gmsh_geo_destroy(&geo);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  (*out)->timings[DTM_T_EXTRACT] = t[DTM_T_EXTRACT];
  (*out)->mesher = mi;
  (*out)->geo = geo;
  double t0 = dtm_wtime();
  r = dtm_shape_classify(*out); /* again, now with the model's features */
  if (r == DTM_OK) (*out)->timings[DTM_T_ADVICE] += dtm_wtime() - t0;
  if (r) dtm_analysis_destroy(out);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

void dtm_analysis_locate(const dtm_analysis *a, size_t i, int *block, size_t *local) {
  int b = 0;
  while (b + 1 < a->mesh->nblocks && a->offset[b + 1] <= i) b++;
  *block = b;
  *local = i - a->offset[b];
}

size_t dtm_analysis_tag(const dtm_analysis *a, size_t i) {
  int b;
  size_t l;
  dtm_analysis_locate(a, i, &b, &l);
  return a->mesh->blocks[b].tags[l];
}

int dtm_analysis_group(const dtm_analysis *a, size_t i) {
  int b;
  size_t l;
  dtm_analysis_locate(a, i, &b, &l);
  return a->mesh->blocks[b].group[l];
}

void dtm_analysis_centroid(const dtm_analysis *a, size_t i, double c[3]) {
  int b;
  size_t l;
  dtm_analysis_locate(a, i, &b, &l);
  const dtm_block *blk = &a->mesh->blocks[b];
  c[0] = c[1] = c[2] = 0;
  for (int k = 0; k < blk->nn; k++)
    for (int d = 0; d < 3; d++) c[d] += a->mesh->xyz[3 * blk->conn[l * blk->nn + k] + d] / blk->nn;
}
