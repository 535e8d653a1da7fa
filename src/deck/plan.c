/* The plan of a deck, whatever the solver: the parts (the elements of one
 * physical group of one type, material and section, each one section card,
 * with the writer's element for it), the elements grouped by part, the
 * nodes the elements use, and the sets of every physical group (the mesh's
 * groups with their elements and nodes, then the groups below the analysed
 * dimension with their nodes, read from the Gmsh model). Set names are the
 * groups' names made safe for the solvers (letters, digits and '_', at most
 * 80 characters, starting with a letter; an unnamed group is G<tag>), made
 * unique. */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "deck-impl.h"
#include "dtmap/gmsh.h"

/* The kind of element e of block b: its section's, else the formulation's. */
static int elem_kind(const deck_ctx *c, const dtm_block *b, size_t e) {
  static const int of_form[] = {DTM_SECTION_SOLID, DTM_SECTION_PLANE_STRAIN, DTM_SECTION_PLANE_STRESS,
                                DTM_SECTION_TRUSS};
  if (b->section && b->section[e] >= 0) return c->s->sections[b->section[e]].kind;
  return of_form[c->form];
}

/* The part's thickness (plane, membrane, shell) or area (truss, beam). */
static double part_measure(const deck_ctx *c, const deck_part *p) {
  if (p->kind == DTM_SECTION_SOLID) return 0.0;
  return p->section >= 0 ? dtm_section_factor(&c->s->sections[p->section]) : 1.0;
}

static int same_part(const deck_part *p, int g, int type, int mat, int sec) {
  return p->group == g && p->type == type && p->mat == mat && p->section == sec;
}

/* Index of the part of element e of block b, adding it when new. */
static int part_of(deck_ctx *c, const dtm_block *b, size_t e, int hint) {
  int g = b->group[e], sec = b->section ? b->section[e] : -1;
  if (hint >= 0 && same_part(&c->parts[hint], g, b->type, b->mat[e], sec)) return hint;
  for (int k = 0; k < c->nparts; k++)
    if (same_part(&c->parts[k], g, b->type, b->mat[e], sec)) return k;
  deck_part *np = realloc(c->parts, ((size_t)c->nparts + 1) * sizeof *np);
  if (!np) return -1;
  c->parts = np;
  np[c->nparts] = (deck_part){g, b->type, b->mat[e], sec, elem_kind(c, b, e), "", 0, NULL, 0.0, 0, ""};
  np[c->nparts].thickness = part_measure(c, &np[c->nparts]);
  return c->nparts++;
}

/* Every element's part, the elements grouped by part, the nodes used. */
static int assign_parts(deck_ctx *c) {
  size_t nel = dtm_mesh_nelements(c->m), i = 0;
  c->part = malloc((nel + 1) * sizeof *c->part);
  c->used = calloc(c->m->nnodes + 1, 1);
  if (!c->part || !c->used) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the deck's %zu elements", nel);
  int k = -1;
  for (int b = 0; b < c->m->nblocks; b++) {
    const dtm_block *blk = &c->m->blocks[b];
    for (size_t e = 0; e < blk->n; e++, i++) {
      if ((k = part_of(c, blk, e, k)) < 0) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
      c->part[i] = k, c->parts[k].count++;
      for (int a = 0; a < blk->nn; a++) c->used[blk->conn[e * blk->nn + a]] = 1;
      if (blk->tags[e] > c->max_tag) c->max_tag = blk->tags[e];
    }
  }
  return DTM_OK;
}

/* order[]: the global element indices by part (a counting sort). */
static int sort_by_part(deck_ctx *c) {
  size_t nel = dtm_mesh_nelements(c->m);
  c->order = malloc((nel + 1) * sizeof *c->order);
  c->first = calloc((size_t)c->nparts + 1, sizeof *c->first);
  if (!c->order || !c->first) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int k = 0; k < c->nparts; k++) c->first[k + 1] = c->first[k] + c->parts[k].count;
  size_t *at = malloc(((size_t)c->nparts + 1) * sizeof *at);
  if (!at) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  memcpy(at, c->first, (size_t)c->nparts * sizeof *at);
  for (size_t i = 0; i < nel; i++) c->order[at[c->part[i]]++] = i;
  free(at);
  return DTM_OK;
}

/* ---- names ---- */

void deck_safe_name(const char *label, int tag, char *out) {
  size_t n = 0;
  if (!label[0]) {
    snprintf(out, DECK_NAME_MAX, "G%d", tag);
    return;
  }
  if (!isalpha((unsigned char)label[0])) out[n++] = 'G';
  for (const char *p = label; *p && n + 1 < DECK_NAME_MAX - 8; p++)
    out[n++] = isalnum((unsigned char)*p) ? (char)toupper((unsigned char)*p) : '_';
  out[n] = '\0';
}

/* Whether name is already used by a group or a part (before index upto of
 * each list). */
static int taken(const deck_ctx *c, const char *name, int groups, int parts) {
  for (int g = 0; g < groups; g++)
    if (!strcmp(c->groups[g].name, name)) return 1;
  for (int k = 0; k < parts; k++)
    if (!strcmp(c->parts[k].set, name)) return 1;
  return 0;
}

/* base, else base_2, base_3, ... the first that is free. */
static void unique_name(const deck_ctx *c, const char *base, int groups, int parts, char *out) {
  snprintf(out, DECK_NAME_MAX, "%s", base);
  for (int i = 2; i < 1000000 && taken(c, out, groups, parts); i++) snprintf(out, DECK_NAME_MAX, "%.70s_%d", base, i);
}

/* Parts of mesh group g. */
static int parts_in(const deck_ctx *c, int g) {
  int n = 0;
  for (int k = 0; k < c->nparts; k++) n += c->parts[k].group == g;
  return n;
}

/* A part's set: its group's name when it is the group's only part, else
 * the group's name and the element's. */
static void name_parts(deck_ctx *c) {
  char base[DECK_NAME_MAX];
  for (int k = 0; k < c->nparts; k++) {
    deck_part *p = &c->parts[k];
    const char *group = p->group >= 0 ? c->groups[p->group].name : "NOGROUP";
    if (p->group >= 0 && parts_in(c, p->group) == 1 && !c->groups[p->group].listed)
      snprintf(base, sizeof base, "%s", group);
    else
      snprintf(base, sizeof base, "%.60s_%.18s", group, p->elem[0] ? p->elem : dtm_elem_name(p->type));
    unique_name(c, base, p->group >= 0 && !strcmp(base, group) ? 0 : c->ngroups, k, p->set);
  }
}

/* ---- sets ---- */

/* Whether element e of block b is in mesh group g. */
static int in_group(const dtm_block *b, size_t e, int g) {
  if (b->group[e] == g) return 1;
  return b->gmask && g < DTM_MAX_MASK_GROUPS && (b->gmask[e] >> g & 1);
}

static int by_size(const void *x, const void *y) {
  size_t a = *(const size_t *)x, b = *(const size_t *)y;
  return a < b ? -1 : a > b;
}

/* The nodes of mesh group g (tags, ascending) and whether its element set
 * must be listed (an element of another group's part is in it). */
static int mesh_group_nodes(deck_ctx *c, deck_group *dg, int g, char *mark) {
  size_t n = 0;
  memset(mark, 0, c->m->nnodes);
  for (int b = 0; b < c->m->nblocks; b++) {
    const dtm_block *blk = &c->m->blocks[b];
    for (size_t e = 0; e < blk->n; e++) {
      if (!in_group(blk, e, g)) continue;
      dg->listed |= blk->group[e] != g;
      for (int a = 0; a < blk->nn; a++) mark[blk->conn[e * blk->nn + a]] = 1;
    }
  }
  for (size_t v = 0; v < c->m->nnodes; v++) n += mark[v];
  dg->nodes = malloc((n + 1) * sizeof *dg->nodes);
  if (!dg->nodes) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < c->m->nnodes; v++)
    if (mark[v]) dg->nodes[dg->nnodes++] = c->m->node_tags[v];
  qsort(dg->nodes, dg->nnodes, sizeof *dg->nodes, by_size);
  dg->listed |= !parts_in(c, g);
  return DTM_OK;
}

static int add_group(deck_ctx *c, int dim, int tag, const char *label, int mesh_group) {
  deck_group *ng = realloc(c->groups, ((size_t)c->ngroups + 1) * sizeof *ng);
  if (!ng) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  c->groups = ng;
  deck_group *g = &ng[c->ngroups];
  char base[DECK_NAME_MAX];
  *g = (deck_group){dim, tag, "", mesh_group, 0, 0, NULL};
  deck_safe_name(label, tag, base);
  unique_name(c, base, c->ngroups, 0, g->name);
  c->ngroups++;
  return DTM_OK;
}

/* Keep only the written nodes among a group below's Gmsh nodes. */
static size_t keep_written(const deck_ctx *c, const char *written, size_t maxtag, size_t *tags, size_t n) {
  size_t k = 0;
  for (size_t j = 0; j < n; j++)
    if (tags[j] <= maxtag && written[tags[j]]) tags[k++] = tags[j];
  qsort(tags, k, sizeof *tags, by_size);
  (void)c;
  return k;
}

/* Whether (dim, tag) is one of the mesh's groups. */
static int is_mesh_group(const dtm_mesh *m, int dim, int tag) {
  for (int g = 0; g < m->ngroups; g++)
    if (m->groups[g].dim == dim && m->groups[g].tag == tag) return 1;
  return 0;
}

/* The groups of dimension d below the analysed one: node sets. */
static int groups_below(deck_ctx *c, int d, const char *written, size_t maxtag) {
  dtm_group *gs = NULL;
  int n = 0, r = dtm_gmsh_groups(d, &gs, &n);
  for (int i = 0; i < n; i++) {
    if (r == DTM_OK && !is_mesh_group(c->m, gs[i].dim, gs[i].tag)) {
      r = add_group(c, gs[i].dim, gs[i].tag, gs[i].name, -1);
      deck_group *g = &c->groups[c->ngroups - 1];
      if (r == DTM_OK) r = dtm_gmsh_group_nodes(d, gs[i].tag, &g->nodes, &g->nnodes);
      if (r == DTM_OK) g->nnodes = keep_written(c, written, maxtag, g->nodes, g->nnodes);
    }
    free(gs[i].name);
  }
  free(gs);
  return r;
}

/* written[tag] = 1 for the nodes of written elements (by Gmsh tag). */
static char *written_tags(const deck_ctx *c, size_t *maxtag) {
  *maxtag = 0;
  for (size_t v = 0; v < c->m->nnodes; v++)
    if (c->m->node_tags[v] > *maxtag) *maxtag = c->m->node_tags[v];
  char *w = calloc(*maxtag + 1, 1);
  for (size_t v = 0; w && v < c->m->nnodes; v++) w[c->m->node_tags[v]] = c->used[v];
  return w;
}

static int make_groups(deck_ctx *c) {
  char *mark = malloc(c->m->nnodes + 1), lbl[64];
  size_t maxtag;
  char *written = written_tags(c, &maxtag);
  int r = mark && written ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int g = 0; g < c->m->ngroups && r == DTM_OK; g++) {
    const dtm_group *mg = &c->m->groups[g];
    r = add_group(c, mg->dim, mg->tag, dtm_mesh_group_label(c->m, g, lbl, sizeof lbl), g);
    if (r == DTM_OK) r = mesh_group_nodes(c, &c->groups[c->ngroups - 1], g, mark);
  }
  for (int d = 0; d < c->m->dim && r == DTM_OK; d++) r = groups_below(c, d, written, maxtag);
  free(mark), free(written);
  return r;
}

int deck_element_from(deck_ctx *c, deck_part *p, const deck_elem_row *rows, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (rows[i].kind == p->kind && rows[i].type == p->type) {
      p->elem = rows[i].elem, p->elform = rows[i].elform, p->perm = rows[i].perm;
      return DTM_OK;
    }
  return deck_lacks(c, p, "");
}

const dtm_block *deck_part_block(const deck_ctx *c, const deck_part *p, size_t *offset) {
  *offset = 0;
  for (int b = 0; b < c->m->nblocks; *offset += c->m->blocks[b].n, b++)
    if (c->m->blocks[b].type == p->type) return &c->m->blocks[b];
  return NULL;
}

int deck_plan(deck_ctx *c) {
  DTM_CHECK(assign_parts(c));
  for (int k = 0; k < c->nparts; k++) DTM_CHECK(c->w->element(c, &c->parts[k]));
  DTM_CHECK(make_groups(c));
  name_parts(c);
  return sort_by_part(c);
}

void deck_plan_free(deck_ctx *c) {
  for (int g = 0; g < c->ngroups; g++) free(c->groups[g].nodes);
  free(c->groups), free(c->parts), free(c->part), free(c->order), free(c->first), free(c->used);
  free(c->node_data), free(c->twin), free(c->twin_node);
}
