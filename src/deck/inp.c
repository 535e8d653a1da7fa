/* Abaqus-style input, the format CalculiX reads too (Abaqus Keywords
 * Reference; CalculiX's manual, chapter 7): keyword lines starting with
 * '*', parameters after commas, data lines of comma-separated values (at
 * most 16 per line), comments starting with '**'. The pieces the CalculiX
 * and Abaqus writers share: nodes, elements by part (each part one
 * *ELEMENT card whose ELSET its section card names), the sets of the
 * physical groups, materials, section cards, the mass elements of the
 * added mass and the include slots. Numbers are written with 17
 * significant digits, so they read back bit for bit. */
#include <math.h>
#include <string.h>

#include "deck-impl.h"
#include "dtmap/util.h"

#define PER_LINE 16 /* entries of a data line */
#define COLUMNS 20  /* CalculiX reads a real from at most 20 characters */

void deck_inp_reals(deck_ctx *c, int n, const double *v) {
  char b[40];
  for (int i = 0; i < n; i++) fprintf(c->f, "%s%s", deck_number(v[i], COLUMNS, b), i + 1 < n ? ", " : "\n");
}

int deck_inp_nodes(deck_ctx *c) {
  FILE *f = c->f;
  fputs("*NODE\n", f);
  for (size_t v = 0; v < c->m->nnodes; v++) {
    const double *x = c->m->xyz + 3 * v;
    if (!c->used[v]) continue;
    fprintf(f, "%zu, ", c->m->node_tags[v]);
    deck_inp_reals(c, 3, x);
  }
  return DTM_OK;
}

static void part_elements(deck_ctx *c, const deck_part *p) {
  size_t off, tags[DTM_MAX_NODES];
  const dtm_block *b = deck_part_block(c, p, &off);
  int k = (int)(p - c->parts);
  fprintf(c->f, "*ELEMENT, TYPE=%s, ELSET=%s\n", p->elem, p->set);
  for (size_t j = c->first[k]; j < c->first[k + 1]; j++) {
    size_t e = c->order[j] - off;
    int nn = deck_conn(c, b, e, p, tags);
    for (int a = 0; c->twin && p->kind == DTM_SECTION_BEAM && a < nn && a < 2; a++)
      if (c->twin[2 * c->order[j] + (size_t)a]) tags[a] = c->twin[2 * c->order[j] + (size_t)a];
    char line[32 * (DTM_MAX_NODES + 1)], *q = deck_put_uint(line, b->tags[e], 0);
    for (int a = 0; a < nn; a++) *q++ = ',', *q++ = ' ', q = deck_put_uint(q, tags[a], 0);
    *q++ = '\n';
    fwrite(line, 1, (size_t)(q - line), c->f);
  }
}

int deck_inp_elements(deck_ctx *c) {
  for (int k = 0; k < c->nparts; k++) part_elements(c, &c->parts[k]);
  return DTM_OK;
}

/* A list of numbers, PER_LINE a line. */
static void id_lines(FILE *f, const size_t *ids, size_t n) {
  for (size_t i = 0; i < n; i++) fprintf(f, "%zu%s", ids[i], (i + 1) % PER_LINE && i + 1 < n ? ", " : "\n");
}

/* The element set of mesh group g: element by element when listed, else
 * the union of its parts (nothing when its one part's set has its name). */
static void group_elements(deck_ctx *c, const deck_group *g) {
  FILE *f = c->f;
  int n = 0;
  for (int k = 0; k < c->nparts; k++) n += c->parts[k].group == g->mesh_group;
  if (!g->listed && n == 1) return;
  fprintf(f, "*ELSET, ELSET=%s\n", g->name);
  int col = 0;
  for (int k = 0; !g->listed && k < c->nparts; k++)
    if (c->parts[k].group == g->mesh_group) fprintf(f, "%s%s", c->parts[k].set, ++col < n ? ", " : "\n");
  for (int b = 0; g->listed && b < c->m->nblocks; b++) {
    const dtm_block *blk = &c->m->blocks[b];
    for (size_t e = 0; e < blk->n; e++)
      if (blk->group[e] == g->mesh_group ||
          (blk->gmask && g->mesh_group < DTM_MAX_MASK_GROUPS && (blk->gmask[e] >> g->mesh_group & 1)))
        fprintf(f, "%zu%s", blk->tags[e], ++col % PER_LINE ? ", " : "\n");
  }
  if (g->listed && col % PER_LINE) fputs("\n", f);
}

int deck_inp_sets(deck_ctx *c) {
  for (int i = 0; i < c->ngroups; i++) {
    const deck_group *g = &c->groups[i];
    if (g->mesh_group >= 0) group_elements(c, g);
    if (!g->nnodes) continue;
    fprintf(c->f, "*NSET, NSET=%s\n", g->name);
    id_lines(c->f, g->nodes, g->nnodes);
  }
  return DTM_OK;
}

/* Whether material mat is used by a part before part k. */
static int seen(const deck_ctx *c, int k, int mat) {
  for (int j = 0; j < k; j++)
    if (c->parts[j].mat == mat) return 1;
  return 0;
}

/* A material's name in the deck. */
static const char *material_name(const deck_ctx *c, int mat, char *buf) {
  deck_safe_name(c->s->materials[mat].m.name, mat + 1, buf);
  return buf;
}

int deck_inp_materials(deck_ctx *c, int damping) {
  char name[DECK_NAME_MAX];
  for (int k = 0; k < c->nparts; k++) {
    int mat = c->parts[k].mat;
    if (seen(c, k, mat)) continue;
    double E, nu, rho, alpha, beta, xi;
    deck_elastic(c, mat, &E, &nu, &rho);
    fprintf(c->f, "*MATERIAL, NAME=%s\n*ELASTIC\n", material_name(c, mat, name));
    deck_inp_reals(c, 2, (double[]){E, nu});
    fputs("*DENSITY\n", c->f);
    deck_inp_reals(c, 1, &rho);
    deck_damping(c, mat, &alpha, &beta, &xi);
    if (damping && (alpha > 0 || beta > 0)) fprintf(c->f, "*DAMPING, ALPHA=%.14g, BETA=%.14g\n", alpha, beta);
  }
  return DTM_OK;
}

int deck_inp_sections(deck_ctx *c, int (*own)(deck_ctx *c, const deck_part *p, int *done)) {
  static const char *const cards[] = {"SOLID", "SOLID", "SOLID", "MEMBRANE", "SOLID", "SHELL", "BEAM"};
  char name[DECK_NAME_MAX];
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    int done = 0;
    DTM_CHECK(own(c, p, &done));
    if (done) continue;
    fprintf(c->f, "*%s SECTION, ELSET=%s, MATERIAL=%s\n", cards[p->kind], p->set, material_name(c, p->mat, name));
    if (p->kind != DTM_SECTION_SOLID) deck_inp_reals(c, 1, &p->thickness);
  }
  return DTM_OK;
}

int deck_inp_masses(deck_ctx *c, const double *extra) {
  size_t id = c->max_tag;
  for (size_t v = 0; v < c->m->nnodes; v++) {
    double m = deck_node_mass(c, v) + (extra ? extra[v] : 0.0);
    if (!(m > 0)) continue;
    id++;
    fprintf(c->f, "*ELEMENT, TYPE=MASS, ELSET=DTMAP_MASS%zu\n%zu, %zu\n*MASS, ELSET=DTMAP_MASS%zu\n", id, id,
            c->m->node_tags[v], id);
    deck_inp_reals(c, 1, &m);
  }
  return DTM_OK;
}

void deck_inp_slot(deck_ctx *c, const char *what, const char *text) {
  char name[DTM_PATH_MAX];
  fprintf(c->f, "** ---- slot: %s\n** *INCLUDE, INPUT=%s\n", text, deck_slot_name(c, what, name, sizeof name));
}
