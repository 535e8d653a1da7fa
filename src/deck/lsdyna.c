/* The LS-DYNA keyword deck (LS-DYNA Keyword User's Manual, volume I):
 * fixed-column cards (IDs in 8 columns for *NODE and *ELEMENT_*, 10 for
 * the others; reals in 16 columns for coordinates and masses, 10 for the
 * others, each written with the most digits that fit), '$' comments.
 * Elements: *ELEMENT_SOLID (tet4 as the 8-node degenerate form, ELFORM 10,
 * the 1-point tetrahedron; hex8 ELFORM 2, the fully integrated
 * selectively reduced brick, whose one-point volumetric term can only lower
 * the top eigenvalue: dtmap's step is on the safe side), *ELEMENT_SHELL
 * (plane strain ELFORM 13, plane stress 12, membranes 5 (tri3) and 9
 * (quad4), shells 4 (the C0 triangle) and 16 (fully integrated quadrangle)),
 * *ELEMENT_BEAM (trusses ELFORM 3, beams ELFORM 2, the resultant beam with
 * A, I_ss = the section's I_y, I_tt = I_z, J; its s axis along the
 * section's y, given as the orientation vector). One *PART per part.
 * LS-DYNA chooses its own step as TSSFAC x the smallest element step by
 * its rule (rules.c); the deck's TSSFAC is dtmap's step over that smallest
 * step, so that LS-DYNA's estimate is dtmap's step. A 10-node tetrahedron
 * is refused: the manuals do not give the length LS-DYNA's step takes for
 * it, so no TSSFAC could make its estimate dtmap's step. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deck-impl.h"

static const deck_elem_row rows[] = {
    {DTM_SECTION_SOLID, DTM_TET4, "SOLID", 10, NULL},        {DTM_SECTION_SOLID, DTM_HEX8, "SOLID", 2, NULL},
    {DTM_SECTION_PLANE_STRAIN, DTM_TRI3, "SHELL", 13, NULL}, {DTM_SECTION_PLANE_STRAIN, DTM_QUAD4, "SHELL", 13, NULL},
    {DTM_SECTION_PLANE_STRESS, DTM_TRI3, "SHELL", 12, NULL}, {DTM_SECTION_PLANE_STRESS, DTM_QUAD4, "SHELL", 12, NULL},
    {DTM_SECTION_MEMBRANE, DTM_TRI3, "SHELL", 5, NULL},      {DTM_SECTION_MEMBRANE, DTM_QUAD4, "SHELL", 9, NULL},
    {DTM_SECTION_SHELL, DTM_TRI3, "SHELL", 4, NULL},         {DTM_SECTION_SHELL, DTM_QUAD4, "SHELL", 16, NULL},
    {DTM_SECTION_TRUSS, DTM_LINE2, "BEAM", 3, NULL},         {DTM_SECTION_BEAM, DTM_LINE2, "BEAM", 2, NULL}};

#define ID_MAX 99999999 /* the largest ID in 8 columns */

/* v in w columns, right-aligned, with the most digits that fit (LS-DYNA
 * reads a field by its columns: it may touch the one before). */
static void real(FILE *f, int w, double v) {
  char b[40];
  fprintf(f, "%*s", w, deck_number(v, w, b));
}

static int element(deck_ctx *c, deck_part *p) {
  if (p->type == DTM_TET10)
    return deck_lacks(c, p,
                      "its manuals do not give the length its step takes for 10-node tetrahedra, so no TSSFAC "
                      "could make its estimate dtmap's step");
  DTM_CHECK(deck_element_from(c, p, rows, sizeof rows / sizeof *rows));
  char form[16];
  snprintf(form, sizeof form, "ELFORM %d", p->elform);
  deck_warn_quad4(c, p, form);
  return DTM_OK;
}

/* LS-DYNA's own step of one element (rules.c). */
static double own(const deck_ctx *c, const dtm_block *b, size_t e, size_t i, const deck_part *p) {
  double x[3 * DTM_MAX_NODES], E, nu, rho;
  dtm_mesh_gather_one(c->m, b, e, x);
  deck_elastic(c, p->mat, &E, &nu, &rho);
  (void)i;
  switch (p->kind) {
  case DTM_SECTION_SOLID:
    return (b->type == DTM_TET4 ? deck_tet_min_altitude(x) : deck_hex_volume_area(x)) / deck_speed_3d(E, nu, rho);
  case DTM_SECTION_TRUSS:
  case DTM_SECTION_BEAM:
    return sqrt((x[3] - x[0]) * (x[3] - x[0]) + (x[4] - x[1]) * (x[4] - x[1]) + (x[5] - x[2]) * (x[5] - x[2])) /
           deck_speed_bar(E, rho);
  default:
    return deck_shell_length(x, b->type == DTM_TRI3 ? 3 : 4) /
           (p->kind == DTM_SECTION_PLANE_STRAIN ? deck_speed_3d(E, nu, rho) : deck_speed_plate(E, nu, rho));
  }
}

/* ---- cards ---- */

static void control(deck_ctx *c) {
  dtm_deck_info *in = c->info;
  fprintf(c->f, "*TITLE\ndtmap deck of %.70s\n*CONTROL_TERMINATION\n$#  endtim\n", c->s->path);
  real(c->f, 10, in->duration);
  fprintf(c->f,
          "\n*CONTROL_TIMESTEP\n$#  dtinit    tssfac      isdo    tslimt     dt2ms      lctm     erode     ms1st\n"
          "       0.0");
  real(c->f, 10, in->tssfac);
  fprintf(c->f, "         0       0.0       0.0         0         0         0\n");
}

static void materials(deck_ctx *c) {
  char name[DECK_NAME_MAX];
  for (int mat = 0; mat < c->s->nmaterials; mat++) {
    int used = 0;
    for (int k = 0; k < c->nparts; k++) used |= c->parts[k].mat == mat;
    if (!used) continue;
    double E, nu, rho;
    deck_elastic(c, mat, &E, &nu, &rho);
    deck_safe_name(c->s->materials[mat].m.name, mat + 1, name);
    fprintf(c->f, "*MAT_ELASTIC_TITLE\n%s\n$#     mid        ro         e        pr\n%10d", name, mat + 1);
    real(c->f, 10, rho), real(c->f, 10, E), real(c->f, 10, nu);
    fputc('\n', c->f);
  }
}

static void section_beam(deck_ctx *c, const deck_part *p) {
  const dtm_section *s = p->section >= 0 ? &c->s->sections[p->section] : NULL;
  fprintf(c->f, "*SECTION_BEAM_TITLE\n%s\n$#   secid    elform      shrf\n%10d%10d", p->set, (int)(p - c->parts) + 1,
          p->elform);
  if (p->kind == DTM_SECTION_TRUSS) {
    fprintf(c->f, "       1.0\n$#       a\n");
    real(c->f, 10, p->thickness);
  } else {
    double k = s->shear > 0 ? s->shear : 5.0 / 6.0;
    real(c->f, 10, k);
    fprintf(c->f, "\n$#       a       iss       itt         j        sa\n");
    real(c->f, 10, s->area), real(c->f, 10, s->iy), real(c->f, 10, s->iz), real(c->f, 10, s->jt);
    real(c->f, 10, k * s->area);
  }
  fputc('\n', c->f);
}

static void sections(deck_ctx *c) {
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    if (!strcmp(p->elem, "BEAM")) {
      section_beam(c, p);
    } else if (!strcmp(p->elem, "SOLID")) {
      fprintf(c->f, "*SECTION_SOLID_TITLE\n%s\n$#   secid    elform\n%10d%10d\n", p->set, k + 1, p->elform);
    } else {
      fprintf(c->f,
              "*SECTION_SHELL_TITLE\n%s\n$#   secid    elform      shrf       nip\n%10d%10d       1.0       2.0\n"
              "$#      t1        t2        t3        t4\n",
              p->set, k + 1, p->elform);
      for (int j = 0; j < 4; j++) real(c->f, 10, p->thickness);
      fputc('\n', c->f);
    }
    fprintf(c->f, "*PART\n%s\n$#     pid     secid       mid\n%10d%10d%10d\n", p->set, k + 1, k + 1, p->mat + 1);
  }
}

static int nodes(deck_ctx *c) {
  fputs("*NODE\n$#   nid               x               y               z\n", c->f);
  for (size_t v = 0; v < c->m->nnodes; v++) {
    if (!c->used[v]) continue;
    if (c->m->node_tags[v] > ID_MAX)
      return DTM_ERR(DTM_ERR_INPUT, "%s: node tag %zu does not fit LS-DYNA's 8 columns (at most %d)", c->s->path,
                     c->m->node_tags[v], ID_MAX);
    fprintf(c->f, "%8zu", c->m->node_tags[v]);
    for (int k = 0; k < 3; k++) real(c->f, 16, c->m->xyz[3 * v + k]);
    fputc('\n', c->f);
  }
  return DTM_OK;
}

/* The card(s) of element e of block b in part p, nodes n[nn]: the
 * degenerate forms of LS-DYNA (a tet repeats its last node to 8, a
 * triangle its third to 4); beams add their orientation vector. */
static void element_card(deck_ctx *c, const deck_part *p, const dtm_block *b, size_t e, const size_t *n, int nn) {
  int slots = !strcmp(p->elem, "SOLID") ? 8 : !strcmp(p->elem, "SHELL") ? 4 : 2;
  char line[32 * 10], *q = deck_put_uint(deck_put_uint(line, b->tags[e], 8), (size_t)(p - c->parts) + 1, 8);
  for (int a = 0; a < slots; a++) q = deck_put_uint(q, n[a < nn ? a : nn - 1], 8);
  *q++ = '\n';
  fwrite(line, 1, (size_t)(q - line), c->f);
  if (p->kind != DTM_SECTION_BEAM) return;
  double v[3], x[6];
  dtm_mesh_gather_one(c->m, b, e, x);
  deck_beam_axis(&c->s->sections[p->section], x, v);
  for (int k = 0; k < 3; k++) real(c->f, 16, v[k]);
  fputc('\n', c->f);
}

static int elements(deck_ctx *c) {
  size_t off, tags[DTM_MAX_NODES];
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    const dtm_block *b = deck_part_block(c, p, &off);
    fprintf(c->f, "*ELEMENT_%s%s\n", p->elem, p->kind == DTM_SECTION_BEAM ? "_ORIENTATION" : "");
    for (size_t j = c->first[k]; j < c->first[k + 1]; j++) {
      size_t e = c->order[j] - off;
      if (b->tags[e] > ID_MAX)
        return DTM_ERR(DTM_ERR_INPUT, "%s: element tag %zu does not fit LS-DYNA's 8 columns", c->s->path, b->tags[e]);
      element_card(c, p, b, e, tags, deck_conn(c, b, e, p, tags));
    }
  }
  return DTM_OK;
}

static int masses(deck_ctx *c) {
  size_t id = c->max_tag;
  if (c->added || c->carried) fputs("*ELEMENT_MASS\n$#   eid     nid            mass\n", c->f);
  for (size_t v = 0; (c->added || c->carried) && v < c->m->nnodes; v++) {
    double m = deck_node_mass(c, v);
    if (!(m > 0)) continue;
    if (++id > ID_MAX)
      return DTM_ERR(DTM_ERR_INPUT, "%s: mass element %zu exceeds LS-DYNA's 8 columns", c->s->path, id);
    fprintf(c->f, "%8zu%8zu", id, c->m->node_tags[v]);
    real(c->f, 16, m);
    fputc('\n', c->f);
  }
  return DTM_OK;
}

/* IDs, 8 to a line of 10 columns. */
static void id_lines(FILE *f, const size_t *ids, size_t n) {
  for (size_t i = 0; i < n; i++) fprintf(f, "%10zu%s", ids[i], (i + 1) % 8 && i + 1 < n ? "" : "\n");
}

/* IDs written as they come, 8 to a line. */
typedef struct {
  FILE *f;      /* the deck */
  size_t id[8]; /* the line being filled */
  int n;        /* IDs in it */
} id_line;

static void id_flush(id_line *l) {
  id_lines(l->f, l->id, (size_t)l->n);
  l->n = 0;
}

static void id_put(id_line *l, size_t id) {
  l->id[l->n++] = id;
  if (l->n == 8) id_flush(l);
}

static int in_group(const dtm_block *b, size_t e, int g) {
  return b->group[e] == g || (b->gmask && g < DTM_MAX_MASK_GROUPS && (b->gmask[e] >> g & 1));
}

/* Block b's elements of mesh group g as one set of its LS-DYNA family. */
static void block_set(deck_ctx *c, const dtm_block *b, const deck_group *g, int sid) {
  id_line l = {c->f, {0}, 0};
  size_t e = 0;
  while (e < b->n && !in_group(b, e, g->mesh_group)) e++;
  if (e == b->n) return;
  fprintf(c->f, "*SET_%s_TITLE\n%s\n%10d\n", b->dim == 3 ? "SOLID" : b->dim == 2 ? "SHELL_LIST" : "BEAM", g->name, sid);
  for (; e < b->n; e++)
    if (in_group(b, e, g->mesh_group)) id_put(&l, b->tags[e]);
  id_flush(&l);
}

/* Element set of mesh group g: its parts, or (listed) its elements. */
static void group_elements(deck_ctx *c, const deck_group *g, int sid) {
  id_line l = {c->f, {0}, 0};
  if (g->listed) {
    for (int b = 0; b < c->m->nblocks; b++) block_set(c, &c->m->blocks[b], g, sid);
    return;
  }
  fprintf(c->f, "*SET_PART_LIST_TITLE\n%s\n%10d\n", g->name, sid);
  for (int k = 0; k < c->nparts; k++)
    if (c->parts[k].group == g->mesh_group) id_put(&l, (size_t)k + 1);
  id_flush(&l);
}

static void sets(deck_ctx *c) {
  for (int i = 0; i < c->ngroups; i++) {
    const deck_group *g = &c->groups[i];
    if (g->mesh_group >= 0) group_elements(c, g, i + 1);
    if (!g->nnodes) continue;
    fprintf(c->f, "*SET_NODE_LIST_TITLE\n%s\n$#     sid\n%10d\n", g->name, i + 1);
    id_lines(c->f, g->nodes, g->nnodes);
  }
}

static void slot(deck_ctx *c, const char *what, const char *text) {
  char name[4200];
  fprintf(c->f, "$ ---- slot: %s\n$*INCLUDE\n$%s\n", text, deck_slot_name(c, what, name, sizeof name));
}

/* TSSFAC: dtmap's step over LS-DYNA's estimate, rounded down to what its
 * 10 columns hold, so that LS-DYNA's step, TSSFAC x its estimate, is the
 * deck's step and never above dtmap's. */
static void tssfac(dtm_deck_info *in) {
  double t = in->step / in->own, v = t;
  char b[40];
  for (int d = 8; d > 0; d--) {
    v = floor(t * pow(10, d)) / pow(10, d);
    if (snprintf(b, sizeof b, "%.*f", d, v) <= 10) break;
  }
  in->tssfac = strtod(b, NULL), in->step = in->tssfac * in->own;
}

static int write(deck_ctx *c) {
  tssfac(c->info);
  fputs("*KEYWORD\n", c->f);
  deck_header(c, "$");
  control(c);
  materials(c);
  sections(c);
  DTM_CHECK(nodes(c));
  DTM_CHECK(elements(c));
  DTM_CHECK(masses(c));
  sets(c);
  slot(c, "model", "boundary and initial conditions, contact, loads");
  slot(c, "step", "output requests (*DATABASE_...)");
  fputs("*END\n", c->f);
  return DTM_OK;
}

const deck_writer dtm_deck_lsdyna = {"lsdyna",
                                     "LS-DYNA",
                                     ".k",
                                     "tetrahedra: shortest altitude / c_d; hexahedra: V / A_max / c_d; shells and "
                                     "2D solids: L_s / c; beams and trusses: L / sqrt(E/rho)",
                                     element,
                                     own,
                                     NULL,
                                     NULL,
                                     NULL,
                                     write};
