/* The LS-DYNA keyword deck (LS-DYNA Keyword User's Manual, volume I):
 * cards in LS-DYNA's free format, fields separated by commas, so that a
 * person can read and edit them; each field keeps at most the characters
 * of its fixed columns (IDs 8 for *NODE and *ELEMENT_*, 10 for the others;
 * reals 16 for coordinates and masses, 20 for curve points, 10 for the
 * others, each with the most digits that fit), so it carries the digits
 * the fixed columns would; a card of one field stays in its columns. '$'
 * comments.
 * Elements: *ELEMENT_SOLID (tet4 as the 8-node degenerate form, ELFORM 10,
 * the 1-point tetrahedron; hex8 ELFORM 2, the fully integrated
 * selectively reduced brick, whose one-point volumetric term can only lower
 * the top eigenvalue: dtmap's step is on the safe side), *ELEMENT_SHELL
 * (plane strain ELFORM 13, plane stress 12, membranes 5 (tri3) and 9
 * (quad4), shells 4 (the C0 triangle) and 16 (fully integrated quadrangle),
 * with the transverse shear factor dtmap's shell takes, 5/6 unless the
 * section gives one), *ELEMENT_BEAM (trusses ELFORM 3, beams ELFORM 2, the
 * resultant beam with A, I_ss = the section's I_y, I_tt = I_z, J; its s
 * axis along the section's y, given as the orientation vector). One *PART
 * per part.
 * The step: LS-DYNA takes TSSFAC x the smallest element step by its rule
 * (rules.c), recomputed every cycle. By default TSSFAC is at most 0.9 (its
 * users' convention): where dtmap's step is below 0.9 x that smallest step,
 * TSSFAC is their ratio; above it, TSSFAC is 0.9 and DT2MS = -step / 0.9,
 * LS-DYNA's conventional mass scaling, whose added mass the deck predicts
 * by LS-DYNA's rule (dt2ms_mass). With --lsdyna-step proven (and before
 * issue 43 always) the deck's TSSFAC is dtmap's step over
 * that smallest step, so that LS-DYNA's first step is dtmap's. LCTM
 * names a *DEFINE_CURVE flat at dtmap's step, the largest step LS-DYNA may
 * take, for the whole run: once the mesh deforms and TSSFAC scales another
 * estimate, the step still never exceeds the one proven (for the
 * undeformed mesh). A 10-node tetrahedron is refused: the manuals do not
 * give the length LS-DYNA's step takes for it, so no TSSFAC could make its
 * estimate dtmap's step. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deck-impl.h"
#include "dtmap/kernel.h"

static const deck_elem_row rows[] = {
    {DTM_SECTION_SOLID, DTM_TET4, "SOLID", 10, NULL},        {DTM_SECTION_SOLID, DTM_HEX8, "SOLID", 2, NULL},
    {DTM_SECTION_PLANE_STRAIN, DTM_TRI3, "SHELL", 13, NULL}, {DTM_SECTION_PLANE_STRAIN, DTM_QUAD4, "SHELL", 13, NULL},
    {DTM_SECTION_PLANE_STRESS, DTM_TRI3, "SHELL", 12, NULL}, {DTM_SECTION_PLANE_STRESS, DTM_QUAD4, "SHELL", 12, NULL},
    {DTM_SECTION_MEMBRANE, DTM_TRI3, "SHELL", 5, NULL},      {DTM_SECTION_MEMBRANE, DTM_QUAD4, "SHELL", 9, NULL},
    {DTM_SECTION_SHELL, DTM_TRI3, "SHELL", 4, NULL},         {DTM_SECTION_SHELL, DTM_QUAD4, "SHELL", 16, NULL},
    {DTM_SECTION_TRUSS, DTM_LINE2, "BEAM", 3, NULL},         {DTM_SECTION_BEAM, DTM_LINE2, "BEAM", 2, NULL}};

#define ID_MAX 99999999 /* the largest ID in 8 columns */
#define CARD_MAX 256    /* a card's characters: 10 fields of 20 and their commas */
#define LCTM 1          /* the ID of the curve that caps the step */
#define LCTM_SPAN 1000  /* the curve runs flat to this many times ENDTIM */
#define TSSFAC_MAX 0.9  /* the largest TSSFAC written unless --lsdyna-step proven: LS-DYNA's default */

/* One card being built: fields separated by commas (LS-DYNA's free
 * format), each at most as long as its fixed columns. */
typedef struct {
  char s[CARD_MAX];
  int n; /* characters so far */
} card;

static void put_text(card *l, const char *t) {
  size_t k = strlen(t);
  if (l->n) l->s[l->n++] = ',';
  memcpy(l->s + l->n, t, k);
  l->n += (int)k;
}

/* v with the most digits its w columns hold. */
static void put_real(card *l, int w, double v) {
  char b[40];
  put_text(l, deck_number(v, w, b));
}

/* v >= 0 with the most digits its w columns hold, rounded down, into
 * b[40]: the cap written is never above the step it caps. */
static const char *number_down(double v, int w, char *b) {
  double x = v, d = v * DBL_EPSILON;
  while (strtod(deck_number(x, w, b), NULL) > v) x = v - d, d *= 2;
  return b;
}

static void put_real_down(card *l, int w, double v) {
  char b[40];
  put_text(l, number_down(v, w, b));
}

static void put_id(card *l, size_t v) {
  if (l->n) l->s[l->n++] = ',';
  l->n = (int)(deck_put_uint(l->s + l->n, v, 0) - l->s);
}

static void card_end(card *l, FILE *f) {
  l->s[l->n++] = '\n';
  fwrite(l->s, 1, (size_t)l->n, f);
  l->n = 0;
}

/* A card of one field, v in its w columns (fixed format: no comma to
 * separate it from anything). */
static void real_alone(FILE *f, int w, double v) {
  char b[40];
  fprintf(f, "%*s\n", w, deck_number(v, w, b));
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

/* The ID of the part set of selective mass scaling: after the groups'. */
static int sms_set(const deck_ctx *c) { return c->ngroups + 1; }

/* *CONTROL_TIMESTEP: TSSFAC makes LS-DYNA's first step the deck's; LCTM
 * names the curve that caps every later one. */
static void control(deck_ctx *c) {
  dtm_deck_info *in = c->info;
  card l = {.n = 0};
  fprintf(c->f, "*TITLE\ndtmap deck of %.70s\n*CONTROL_TERMINATION\n$#  endtim\n", c->s->path);
  real_alone(c->f, 10, in->duration);
  fputs("*CONTROL_TIMESTEP\n$# dtinit,tssfac,isdo,tslimt,dt2ms,lctm,erode,ms1st\n", c->f);
  put_text(&l, "0.0"), put_real(&l, 10, in->tssfac), put_text(&l, "0"), put_text(&l, "0.0");
  if (isfinite(in->dt2ms))
    put_real(&l, 10, in->dt2ms);
  else
    put_text(&l, "0.0");
  put_id(&l, LCTM), put_text(&l, "0"), put_text(&l, "0");
  card_end(&l, c->f);
  if (!in->selective || !isfinite(in->dt2ms)) return;
  /* the second card: DT2MSF, DT2MSLC, IMSCL (minus the part set), two unused, RMSCL */
  fputs("$# dt2msf,dt2mslc,imscl,unused,unused,rmscl\n", c->f);
  char imscl[16];
  snprintf(imscl, sizeof imscl, "%d", -sms_set(c));
  put_text(&l, "0.0"), put_text(&l, "0"), put_text(&l, imscl), put_text(&l, "0"), put_text(&l, "0");
  put_text(&l, "0.0");
  card_end(&l, c->f);
}

/* The curve LCTM names: the deck's step from time 0 to LCTM_SPAN x ENDTIM
 * (a longer run keeps the cap). */
static void step_curve(deck_ctx *c) {
  const dtm_deck_info *in = c->info;
  card l = {.n = 0};
  fprintf(c->f,
          "*DEFINE_CURVE_TITLE\nDTMAP_LARGEST_STEP\n$ the largest step LS-DYNA may take (LCTM of *CONTROL_TIMESTEP): "
          "the deck's step, flat to %d x ENDTIM\n$# lcid,sidr,sfa,sfo,offa,offo,dattyp\n",
          LCTM_SPAN);
  put_id(&l, LCTM), put_text(&l, "0"), put_text(&l, "1.0"), put_text(&l, "1.0"), put_text(&l, "0.0");
  put_text(&l, "0.0"), put_text(&l, "0");
  card_end(&l, c->f);
  fputs("$# a1 (time, s),o1 (largest step, s)\n", c->f);
  put_text(&l, "0.0"), put_real_down(&l, 20, in->step);
  card_end(&l, c->f);
  put_real(&l, 20, LCTM_SPAN * in->duration), put_real_down(&l, 20, in->step);
  card_end(&l, c->f);
}

static void materials(deck_ctx *c) {
  char name[DECK_NAME_MAX];
  for (int mat = 0; mat < c->s->nmaterials; mat++) {
    int used = 0;
    for (int k = 0; k < c->nparts; k++) used |= c->parts[k].mat == mat;
    if (!used) continue;
    double E, nu, rho;
    card l = {.n = 0};
    deck_elastic(c, mat, &E, &nu, &rho);
    deck_safe_name(c->s->materials[mat].m.name, mat + 1, name);
    fprintf(c->f, "*MAT_ELASTIC_TITLE\n%s\n$# mid,ro,e,pr\n", name);
    put_id(&l, (size_t)mat + 1), put_real(&l, 10, rho), put_real(&l, 10, E), put_real(&l, 10, nu);
    card_end(&l, c->f);
  }
}

/* The transverse shear factor of part p's shells and beams: the section's,
 * else 5/6, as dtmap's kernels take it. */
static double shear_factor(const deck_ctx *c, const deck_part *p) {
  double k = p->section >= 0 ? c->s->sections[p->section].shear : 0.0;
  return k > 0 ? k : 5.0 / 6.0;
}

static void section_beam(deck_ctx *c, const deck_part *p) {
  const dtm_section *s = p->section >= 0 ? &c->s->sections[p->section] : NULL;
  card l = {.n = 0};
  fprintf(c->f, "*SECTION_BEAM_TITLE\n%s\n$# secid,elform,shrf\n", p->set);
  put_id(&l, (size_t)(p - c->parts) + 1), put_id(&l, (size_t)p->elform);
  if (p->kind == DTM_SECTION_TRUSS) {
    put_text(&l, "1.0");
    card_end(&l, c->f);
    fputs("$#       a\n", c->f);
    real_alone(c->f, 10, p->thickness);
    return;
  }
  double k = shear_factor(c, p);
  put_real(&l, 10, k);
  card_end(&l, c->f);
  fputs("$# a,iss,itt,j,sa\n", c->f);
  put_real(&l, 10, s->area), put_real(&l, 10, s->iy), put_real(&l, 10, s->iz), put_real(&l, 10, s->jt);
  put_real(&l, 10, k * s->area);
  card_end(&l, c->f);
}

/* *SECTION_SHELL: SHRF is the shear factor dtmap's shell takes (plane and
 * membrane elements have no transverse shear: it is written alike). */
static void section_shell(deck_ctx *c, const deck_part *p) {
  card l = {.n = 0};
  fprintf(c->f, "*SECTION_SHELL_TITLE\n%s\n$# secid,elform,shrf,nip\n", p->set);
  put_id(&l, (size_t)(p - c->parts) + 1), put_id(&l, (size_t)p->elform), put_real(&l, 10, shear_factor(c, p));
  put_text(&l, "2.0");
  card_end(&l, c->f);
  fputs("$# t1,t2,t3,t4\n", c->f);
  for (int j = 0; j < 4; j++) put_real(&l, 10, p->thickness);
  card_end(&l, c->f);
}

static void sections(deck_ctx *c) {
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    card l = {.n = 0};
    if (!strcmp(p->elem, "BEAM")) {
      section_beam(c, p);
    } else if (!strcmp(p->elem, "SOLID")) {
      fprintf(c->f, "*SECTION_SOLID_TITLE\n%s\n$# secid,elform\n", p->set);
      put_id(&l, (size_t)k + 1), put_id(&l, (size_t)p->elform);
      card_end(&l, c->f);
    } else {
      section_shell(c, p);
    }
    fprintf(c->f, "*PART\n%s\n$# pid,secid,mid\n", p->set);
    put_id(&l, (size_t)k + 1), put_id(&l, (size_t)k + 1), put_id(&l, (size_t)p->mat + 1);
    card_end(&l, c->f);
  }
}

static int nodes(deck_ctx *c) {
  card l = {.n = 0};
  fputs("*NODE\n$# nid,x,y,z\n", c->f);
  for (size_t v = 0; v < c->m->nnodes; v++) {
    if (!c->used[v]) continue;
    if (c->m->node_tags[v] > ID_MAX)
      return DTM_ERR(DTM_ERR_INPUT, "%s: node tag %zu does not fit LS-DYNA's 8 columns (at most %d)", c->s->path,
                     c->m->node_tags[v], ID_MAX);
    put_id(&l, c->m->node_tags[v]);
    for (int k = 0; k < 3; k++) put_real(&l, 16, c->m->xyz[3 * v + k]);
    card_end(&l, c->f);
  }
  return DTM_OK;
}

/* The card(s) of element e of block b in part p, nodes n[nn]: the
 * degenerate forms of LS-DYNA (a tet repeats its last node to 8, a
 * triangle its third to 4); beams add their orientation vector. */
static void element_card(deck_ctx *c, const deck_part *p, const dtm_block *b, size_t e, const size_t *n, int nn) {
  int slots = !strcmp(p->elem, "SOLID") ? 8 : !strcmp(p->elem, "SHELL") ? 4 : 2;
  card l = {.n = 0};
  put_id(&l, b->tags[e]), put_id(&l, (size_t)(p - c->parts) + 1);
  for (int a = 0; a < slots; a++) put_id(&l, n[a < nn ? a : nn - 1]);
  card_end(&l, c->f);
  if (p->kind != DTM_SECTION_BEAM) return;
  double v[3], x[6];
  dtm_mesh_gather_one(c->m, b, e, x);
  deck_beam_axis(&c->s->sections[p->section], x, v);
  for (int k = 0; k < 3; k++) put_real(&l, 16, v[k]);
  card_end(&l, c->f);
}

static int elements(deck_ctx *c) {
  size_t off, tags[DTM_MAX_NODES];
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    const dtm_block *b = deck_part_block(c, p, &off);
    fprintf(c->f, "*ELEMENT_%s%s\n", p->elem, p->kind == DTM_SECTION_BEAM ? "_ORIENTATION" : "");
    fprintf(c->f, "$# eid,pid,n1,...%s\n", p->kind == DTM_SECTION_BEAM ? "\n$# vx,vy,vz (orientation)" : "");
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
  card l = {.n = 0};
  if (c->added || c->carried) fputs("*ELEMENT_MASS\n$# eid,nid,mass\n", c->f);
  for (size_t v = 0; (c->added || c->carried) && v < c->m->nnodes; v++) {
    double m = deck_node_mass(c, v);
    if (!(m > 0)) continue;
    if (++id > ID_MAX)
      return DTM_ERR(DTM_ERR_INPUT, "%s: mass element %zu exceeds LS-DYNA's 8 columns", c->s->path, id);
    put_id(&l, id), put_id(&l, c->m->node_tags[v]), put_real(&l, 16, m);
    card_end(&l, c->f);
  }
  return DTM_OK;
}

/* IDs, 8 to a card (a lone ID in its 10 columns). */
static void id_lines(FILE *f, const size_t *ids, size_t n) {
  card l = {.n = 0};
  for (size_t i = 0; i < n; i++) {
    if (i + 1 == n && i % 8 == 0) {
      fprintf(f, "%10zu\n", ids[i]);
      break;
    }
    put_id(&l, ids[i]);
    if ((i + 1) % 8 == 0 || i + 1 == n) card_end(&l, f);
  }
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

/* The part set IMSCL names: every part (--selective-mass with DT2MS). */
static void sms_parts(deck_ctx *c) {
  id_line l = {c->f, {0}, 0};
  if (!c->info->selective || !isfinite(c->info->dt2ms)) return;
  fprintf(c->f, "*SET_PART_LIST_TITLE\nDTMAP_SMS_PARTS\n%10d\n", sms_set(c));
  for (int k = 0; k < c->nparts; k++) id_put(&l, (size_t)k + 1);
  id_flush(&l);
}

static void sets(deck_ctx *c) {
  sms_parts(c);
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

/* A ratio t > 0 rounded down to what TSSFAC's 10 columns hold. */
static double ratio_down(double t) {
  double v = t;
  char b[40];
  for (int d = 8; d > 0; d--) {
    v = floor(t * pow(10, d)) / pow(10, d);
    if (snprintf(b, sizeof b, "%.*f", d, v) <= 10) break;
  }
  return strtod(b, NULL);
}

/* TSSFAC: dtmap's step over LS-DYNA's estimate, rounded down to what its
 * 10 columns hold, so that LS-DYNA's step, TSSFAC x its estimate, is the
 * deck's step and never above dtmap's. */
static void tssfac(dtm_deck_info *in) { in->tssfac = ratio_down(in->step / in->own), in->step = in->tssfac * in->own; }

/* The mass LS-DYNA adds at its start with DT2MS = -dt (its conventional
 * mass scaling, docs/deck.md): an element whose step by its rule, dt_e,
 * is below dt gets its density scaled so that its step is dt. Every rule
 * is a length over a wave speed proportional to 1/sqrt(rho), so the
 * element's mass m_e becomes m_e (dt / dt_e)^2: it adds m_e ((dt / dt_e)^2
 * - 1). Also the model's mass when the target added none at the nodes. */
static void dt2ms_mass(deck_ctx *c, double dt) {
  dtm_deck_info *in = c->info;
  double model = 0.0;
  size_t i = 0;
  in->solver_added = 0.0, in->solver_added_elements = 0;
  for (int k = 0; k < c->m->nblocks; k++)
    for (size_t e = 0; e < c->m->blocks[k].n; e++, i++) {
      const dtm_block *b = &c->m->blocks[k];
      const deck_part *p = &c->parts[c->part[i]];
      double m = deck_element_mass(c, b, e, p), t = own(c, b, e, i, p);
      model += m;
      if (t < dt) in->solver_added += m * ((dt / t) * (dt / t) - 1.0), in->solver_added_elements++;
    }
  if (isnan(in->model_mass)) in->model_mass = model;
}

void deck_lsdyna_step(deck_ctx *c) {
  dtm_deck_info *in = c->info;
  char b[40];
  if (!c->own_scaling || in->step <= TSSFAC_MAX * in->own) {
    tssfac(in);
    return;
  }
  /* |DT2MS| = step / 0.9 rounded up to what its 10 columns hold with the
   * minus sign, then TSSFAC = step / |DT2MS| (at most 0.9) rounded down:
   * their product is dtmap's step to TSSFAC's 8 digits, never above it */
  double v = in->step / TSSFAC_MAX, x = v, dx = v * DBL_EPSILON, d;
  while ((d = -strtod(deck_number(-x, 10, b), NULL)) < v) x = v + dx, dx *= 2;
  in->dt2ms = -d, in->tssfac = ratio_down(in->step / d);
  in->step = in->tssfac * fmax(d, in->own);
  dt2ms_mass(c, d);
}

/* The header's lines on what the step rests on and what holds LS-DYNA to it. */
static void proven(deck_ctx *c) {
  const dtm_deck_info *in = c->info;
  char cap[200];
  snprintf(cap, sizeof cap, "LCTM (*DEFINE_CURVE %d) caps its step at %.10g s for the whole run", LCTM, in->step);
  if (!c->own_scaling)
    snprintf(c->proven, sizeof c->proven,
             "The step was proven for the undeformed mesh. LS-DYNA recomputes its estimate every cycle and\n"
             "multiplies it by TSSFAC; %s,\n"
             "so it never exceeds the proven step; once the mesh deforms, only LS-DYNA's own estimate\n"
             "shortens it.%s",
             cap,
             in->tssfac > TSSFAC_MAX ? "\nWARNING: TSSFAC is above the 0.9 LS-DYNA's users keep to (--lsdyna-step "
                                       "proven):\nthe deck rests on dtmap's proof alone."
                                     : "");
  else if (!isfinite(in->dt2ms))
    snprintf(c->proven, sizeof c->proven,
             "The step was proven for the undeformed mesh. TSSFAC is at most 0.9, LS-DYNA's convention;\n"
             "LS-DYNA recomputes its estimate every cycle and multiplies it by TSSFAC; %s.",
             cap);
  else if (strncmp(in->basis, "the target", 10))
    snprintf(c->proven, sizeof c->proven,
             "The step was proven for the undeformed mesh. It holds with the mass LS-DYNA adds: added mass\n"
             "can only lower the highest frequency. TSSFAC is at most 0.9, LS-DYNA's convention, and its\n"
             "DT2MS mass scaling (above) lifts its estimate to the step over TSSFAC; %s.",
             cap);
  else
    snprintf(c->proven, sizeof c->proven,
             "The step is the target, reached by LS-DYNA's own DT2MS mass scaling, TSSFAC at most 0.9 (its\n"
             "convention): dtmap proved %.10g s for the undeformed mesh without that mass, not the target\n"
             "with the mass LS-DYNA adds (--lsdyna-step proven writes dtmap's nodal masses, proven, with\n"
             "TSSFAC above 1); %s.",
             in->recommended, cap);
}

static int write(deck_ctx *c) {
  proven(c);
  fputs("*KEYWORD\n", c->f);
  deck_header(c, "$");
  control(c);
  step_curve(c);
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
