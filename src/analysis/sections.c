/* The scene's sections on the mesh's physical groups: which group has which
 * section, and the checks that need the mesh. A section names groups that
 * exist, of the dimension its kind applies to (solid: volumes; plane-strain
 * and plane-stress: the surfaces of a 2D model; membrane: surfaces, in 2D
 * or 3D; truss: curves); after extraction each sectioned group holds
 * elements. Every error names the scene file and line of the section. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* ref NULL: the default section, which applies to the model's elements. */
static int wrong_dim(const dtm_scene *s, const dtm_section *sec, const char *ref, int gd, int dim) {
  const char *kind = dtm_section_kind_name(sec->kind);
  char where[128];
  snprintf(where, sizeof where, ref ? "on group '%s'" : "(the default)", ref);
  if (gd == 2 && dtm_section_dim(sec->kind) == 2)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s:%d: section (%s) %s: a %s section is for a 2D model; the model is analysed in "
                   "%dD, where surfaces are membranes (kind=\"membrane\" thickness=\"...\")",
                   s->path, sec->line, kind, where, kind, dim);
  return DTM_ERR(DTM_ERR_INPUT, "%s:%d: section (%s) %s: %s %s (dimension %d), a %s section needs %s (dimension %d)",
                 s->path, sec->line, kind, where, ref ? "the group holds" : "the model is analysed on its",
                 dim_noun(gd), gd, kind, dim_noun(dtm_section_dim(sec->kind)), dtm_section_dim(sec->kind));
}

static int map_one(const dtm_scene *s, const dtm_mesh *m, int i, int *gs, int *def) {
  const dtm_section *sec = &s->sections[i];
  if (sec->is_default && !suits(sec->kind, m->dim, m->dim)) return wrong_dim(s, sec, NULL, m->dim, m->dim);
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

int dtm_analysis_has_rotations(const dtm_analysis *a) {
  for (int i = 0; i < a->scene->nsections; i++)
    if (dtm_section_has_rotations(a->scene->sections[i].kind)) return 1;
  return 0;
}

int dtm_analysis_coefficients(const dtm_analysis *a, int k, int slot, dtm_operator_coeffs *c) {
  const dtm_effect *ef = &a->effects[k];
  int nm = a->scene->nmaterials, sec = slot / nm - 1;
  const dtm_section *s = sec >= 0 ? &a->scene->sections[sec] : NULL;
  DTM_CHECK(ef->cls->coefficients(ef->state, &a->scene->materials[slot % nm].m, s, c));
  c->section_factor = dtm_section_factor(s);
  c->section = s;
  return DTM_OK;
}

/* Largest distance between two of the first nc nodes of x (sides and,
 * on quadrangles, diagonals). */
static double longest_chord(const double *x, int nc) {
  double mx = 0;
  for (int i = 0; i < nc; i++)
    for (int j = i + 1; j < nc; j++) {
      double d2 = 0;
      for (int k = 0; k < 3; k++) d2 += (x[3 * i + k] - x[3 * j + k]) * (x[3 * i + k] - x[3 * j + k]);
      mx = fmax(mx, sqrt(d2));
    }
  return mx;
}

/* The anchor rule's step of element e of block b (material m), NaN when
 * the kind has none. */
static double anchor_step(const dtm_analysis *a, const dtm_block *b, size_t e, const dtm_section *sec) {
  const dtm_material *m = &a->scene->materials[b->mat[e]].m;
  double E = dtm_material_value(m, "E"), nu = dtm_material_value(m, "nu"), rho = dtm_material_value(m, "rho");
  double x[3 * DTM_MAX_NODES];
  dtm_mesh_gather_one(a->mesh, b, e, x);
  if (sec->kind == DTM_SECTION_TRUSS || sec->kind == DTM_SECTION_BEAM) return longest_chord(x, 2) / sqrt(E / rho);
  if (sec->kind != DTM_SECTION_MEMBRANE && sec->kind != DTM_SECTION_SHELL) return NAN;
  int tri = b->type == DTM_TRI3 || b->type == DTM_TRI6, nc = tri ? 3 : 4;
  double area = fabs(dtm_elem_measure(b->type, x));
  return (tri ? 2 : 1) * area / longest_chord(x, nc) / sqrt(E / (rho * (1 - nu * nu)));
}

#define ROTARY_SEED 64 /* every 64th element is solved whole first: the screen of its section */

/* The element map's undamped steps of the first elastic effect whose
 * element step is the element bound, or NULL. */
static const double *elastic_steps(const dtm_analysis *a) {
  int k = dtm_analysis_elastic_bound_effect(a);
  if (k < 0) return NULL;
  return a->dt_bare && a->dt_bare[k] ? a->dt_bare[k] : a->dt_effect[k];
}

/* The bounds of element e of block b under its section's convention
 * (dtm_section_element_screened, the screen of its section from
 * screen[]; NULL: none). Under the physical convention the element map
 * has solved the element's eigenproblem already: its step dt (from dt[],
 * NULL: none) gives lambda = 4/dt^2 and only the masses are computed. An
 * element the kernel refuses keeps nn = 0 (the nodal bound then raises
 * the kernel's error for it). */
static void rotary_one(const dtm_analysis *a, const dtm_block *b, size_t e, const double *screen, const double *dt,
                       dtm_section_bounds *out) {
  const dtm_section *sec = dtm_analysis_section(a, b, e);
  const dtm_material *m = &a->scene->materials[b->mat[e]].m;
  double x[3 * DTM_MAX_NODES], E = dtm_material_value(m, "E"), nu = dtm_material_value(m, "nu");
  double rho = dtm_material_value(m, "rho");
  out->nn = 0;
  if (!sec || !dtm_section_has_rotations(sec->kind)) return;
  dtm_mesh_gather_one(a->mesh, b, e, x);
  double lam = dt ? 4.0 / (dt[e] * dt[e]) : NAN;
  int r = sec->rotary == DTM_ROTARY_PHYSICAL_INERTIA && lam > 0 && isfinite(lam)
              ? dtm_section_element_known(sec, b->type, E, nu, rho, x, lam, out)
              : dtm_section_element_screened(sec, b->type, E, nu, rho, x, screen ? screen[sec - a->scene->sections] : 0,
                                             out);
  if (r) out->nn = 0, dtm_error_clear();
}

/* The bounds of every shell and beam element of block b, the rotary
 * scale's eigenproblem solved once (for the nodal bound and the report;
 * dt: the block's element steps of the elastic effect, or NULL). The
 * report wants only each section's largest lambda_physical: the seed
 * elements (every ROTARY_SEED-th) are solved whole first and their
 * largest per section, screen[], spares the others' physical eigenproblem
 * wherever a factorisation proves it below (lambda_physical NaN there;
 * the largest is still found exactly). */
static void block_rotary(const dtm_analysis *a, const dtm_block *b, const double *dt, double *screen,
                         dtm_section_bounds *out) {
  size_t nseed = (b->n + ROTARY_SEED - 1) / ROTARY_SEED;
#pragma omp parallel for schedule(dynamic, 16)
  for (size_t k = 0; k < nseed; k++) rotary_one(a, b, k * ROTARY_SEED, NULL, dt, &out[k * ROTARY_SEED]);
  for (size_t k = 0; k < nseed; k++) {
    const dtm_section_bounds *sb = &out[k * ROTARY_SEED];
    int i = sb->nn ? (int)(dtm_analysis_section(a, b, k * ROTARY_SEED) - a->scene->sections) : -1;
    if (i >= 0 && sb->lambda_physical > screen[i]) screen[i] = sb->lambda_physical;
  }
#pragma omp parallel for schedule(dynamic, 256)
  for (size_t e = 0; e < b->n; e++)
    if (e % ROTARY_SEED) rotary_one(a, b, e, screen, dt, &out[e]);
}

static int has_rotary(const dtm_analysis *a, const dtm_block *b) {
  for (size_t e = 0; e < b->n; e++) {
    const dtm_section *sec = dtm_analysis_section(a, b, e);
    if (sec && dtm_section_has_rotations(sec->kind)) return 1;
  }
  return 0;
}

int dtm_analysis_rotary(dtm_analysis *a) {
  if (!dtm_analysis_has_rotations(a)) return DTM_OK;
  a->rot = calloc((size_t)a->mesh->nblocks + 1, sizeof *a->rot);
  double *screen = calloc((size_t)a->scene->nsections + 1, sizeof *screen);
  const double *steps = elastic_steps(a);
  if (!a->rot || !screen) return free(screen), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int b = 0; b < a->mesh->nblocks; b++) {
    const dtm_block *blk = &a->mesh->blocks[b];
    if (!has_rotary(a, blk)) continue;
    a->rot[b] = malloc(blk->n * sizeof **a->rot);
    if (!a->rot[b]) return free(screen), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    block_rotary(a, blk, steps ? steps + a->offset[b] : NULL, screen, a->rot[b]);
  }
  free(screen);
  return DTM_OK;
}

/* A shell or beam element's step with physical rotary inertia and the
 * scale of the scaled convention, into st (from a->rot). */
static void rotary_stats(const dtm_analysis *a, int b, size_t e, dtm_section_stats *st) {
  const dtm_section_bounds *sb = &a->rot[b][e];
  if (!sb->nn) return;
  if (!(sb->scale <= st->scale_max)) st->scale_max = sb->scale;
  if (isnan(sb->lambda_physical)) return; /* proved below the section's largest (block_rotary) */
  double dt = 2.0 / sqrt(sb->lambda_physical);
  if (!(dt >= st->dt_physical_min))
    st->dt_physical_min = dt, st->physical_element = a->mesh->blocks[b].tags ? a->mesh->blocks[b].tags[e] : e;
}

static const char *anchor_rule(int k) {
  if (k == DTM_SECTION_TRUSS || k == DTM_SECTION_BEAM) return "L/c, c = sqrt(E/rho)";
  return k == DTM_SECTION_MEMBRANE || k == DTM_SECTION_SHELL ? "LS-DYNA shell step L_s/c_p" : "";
}

static void section_stats(const dtm_analysis *a, dtm_section_stats *out) {
  const double *dt = dtm_analysis_dt(a);
  for (int i = 0; i < a->scene->nsections; i++)
    out[i] = (dtm_section_stats){0, NAN, 0, NAN, anchor_rule(a->scene->sections[i].kind), NAN, 0, NAN};
  size_t g = 0;
  for (int b = 0; b < a->mesh->nblocks; b++)
    for (size_t e = 0; e < a->mesh->blocks[b].n; e++, g++) {
      const dtm_block *blk = &a->mesh->blocks[b];
      const dtm_section *sec = dtm_analysis_section(a, blk, e);
      if (!sec) continue;
      dtm_section_stats *st = &out[sec - a->scene->sections];
      st->elements++;
      if (!(dt[g] >= st->dt_min)) st->dt_min = dt[g], st->element = blk->tags[e];
      double an = anchor_step(a, blk, e, sec);
      if (isfinite(an) && !(an >= st->anchor_min)) st->anchor_min = an;
      if (dtm_section_has_rotations(sec->kind)) rotary_stats(a, b, e, st);
    }
}

int dtm_analysis_section_stats(dtm_analysis *a) {
  if (!a->scene->nsections) return DTM_OK;
  a->sec_stats = malloc((size_t)a->scene->nsections * sizeof *a->sec_stats);
  if (!a->sec_stats) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  section_stats(a, a->sec_stats);
  return DTM_OK;
}

void dtm_analysis_sections(const dtm_analysis *a, dtm_section_stats *out) {
  if (a->sec_stats)
    memcpy(out, a->sec_stats, (size_t)a->scene->nsections * sizeof *out);
  else
    section_stats(a, out);
}
