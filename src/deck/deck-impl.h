/* Private to src/deck/: the plan of a deck that every solver's writer reads
 * (parts, sets, nodes, the step, the masses), the table of operations one
 * writer fills, and the helpers the writers share (the header, the
 * element connectivity in the solver's node order, the solvers' element
 * rules, Abaqus-style input for CalculiX and Abaqus in inp.c). A writer
 * is one file exporting one table; src/deck/list.h lists them. */
#ifndef DTM_DECK_IMPL_H
#define DTM_DECK_IMPL_H

#include <stdio.h>

#include "dtmap/deck.h"
#include "dtmap/error.h"

#define DECK_NAME_MAX 81 /* set and material names: 80 characters (Abaqus, CalculiX) */

/* The elements of one physical group of one type, material and section:
 * one section card of the deck. */
typedef struct {
  int group;               /* mesh group (-1: elements in no group) */
  int type;                /* dtmap element type (Gmsh code) */
  int mat;                 /* scene material */
  int section;             /* scene section (-1: the effect's formulation) */
  int kind;                /* dtm_section_kind of its elements */
  const char *elem;        /* the solver's element name ("C3D4"; LS-DYNA: "SOLID", "SHELL", "BEAM") */
  int elform;              /* LS-DYNA's ELFORM (0 for the others) */
  const int *perm;         /* the solver's node order: perm[k] = Gmsh local node (NULL: the same) */
  double thickness;        /* plane, membrane and shell kinds: m; truss and beam: area, m^2; else 0 */
  size_t count;            /* its elements */
  char set[DECK_NAME_MAX]; /* its element set's name */
} deck_part;

/* The sets of one physical group. */
typedef struct {
  int dim, tag;             /* Gmsh dimension and tag */
  char name[DECK_NAME_MAX]; /* the set's name (node and element sets share it) */
  int mesh_group;           /* index in the mesh's groups (-1: a group below: node set only) */
  int listed;               /* element set: 1 listed element by element, 0 the union of its parts */
  size_t nnodes;            /* its nodes */
  size_t *nodes;            /* [nnodes] Gmsh node tags, ascending (owned) */
} deck_group;

struct deck_writer;

/* Everything a writer writes from. */
typedef struct deck_ctx {
  const dtm_analysis *a;       /* the analysis */
  const dtm_mesh *m;           /* its mesh */
  const dtm_scene *s;          /* its scene */
  const struct deck_writer *w; /* the writer */
  FILE *f;                     /* the deck's temporary */
  int form;                    /* the elastic formulation of elements without a section */
  int elastic;                 /* the elastic effect's index */
  int nparts;                  /* parts */
  deck_part *parts;            /* [nparts] */
  int *part;                   /* [nel] part of each element, global order */
  size_t *order;               /* [nel] global element indices grouped by part */
  size_t *first;               /* [nparts + 1] where each part starts in order */
  int ngroups;                 /* groups with sets */
  deck_group *groups;          /* [ngroups] the mesh's groups, then the groups below */
  char *used;                  /* [nnodes] 1 for the nodes of written elements */
  const double *added;         /* [nnodes] mass added at each node, kg, or NULL */
  const double *carried;       /* [nnodes] point masses the mesh carries (a refined mesh), kg, or NULL */
  size_t max_tag;              /* largest element tag (mass elements are numbered above it) */
  double *node_data;           /* a writer's data per node, or NULL (CalculiX: shell normals); freed with the plan */
  size_t *twin;                /* [2 nel] the node tag beam element i's node a uses instead of its own (0: its
                                  own) at twin[2 i + a], or NULL (CalculiX: beams on shell nodes); freed with
                                  the plan */
  size_t *twin_node;           /* [ntwins] the mesh node twin tag top_tag + 1 + t stands beside; freed with
                                  the plan */
  size_t ntwins, top_tag;      /* beam nodes of their own; the largest mesh node tag */
  dtm_deck_info *info;         /* what is written */
  char proven[640];            /* the writer's lines on where the step was proven and what holds it ("": none) */
  int probe;                   /* 1 while deck_lacks asks the other writers: raise no error */
  int own_scaling;             /* 1: a target is reached by the solver's own mass scaling (LS-DYNA's DT2MS),
                                  not by masses at the nodes */
} deck_ctx;

/* One solver's format. */
typedef struct deck_writer {
  const char *name;  /* "calculix" (the --solver word) */
  const char *title; /* "CalculiX 2.20" */
  const char *ext;   /* ".inp" */
  const char *rule;  /* the solver's own element-by-element estimate, in words */
  /* The solver's element for part p (its kind, type and section): p->elem,
   * p->elform and p->perm; warnings through deck_warn. DTM_ERR_INPUT
   * naming the kind and the group when the solver lacks it. */
  int (*element)(deck_ctx *c, deck_part *p);
  /* The solver's own step for element e of block b (global index i) in
   * part p, s. */
  double (*own)(const deck_ctx *c, const dtm_block *b, size_t e, size_t i, const deck_part *p);
  /* For elements the solver builds differently from dtmap's kernel
   * (CalculiX's expansion of 2D and 1D elements into solids): the factor
   * on dtmap's step for part p (NULL: 1), and the largest step element e
   * of block b in part p allows before the safety factor (NULL: no cap), s. */
  double (*factor)(deck_ctx *c, const deck_part *p);
  double (*cap)(const deck_ctx *c, const dtm_block *b, size_t e, const deck_part *p);
  /* Change the scene before the analysis (NULL: nothing). */
  int (*adapt)(dtm_scene *s, char *note, size_t len);
  /* Write the whole deck to c->f. */
  int (*write)(deck_ctx *c);
} deck_writer;

/* One row of a writer's element table: the solver's element for dtmap's
 * elements of one kind and type. */
typedef struct {
  int kind;         /* dtm_section_kind */
  int type;         /* dtmap element type */
  const char *elem; /* the solver's element name (LS-DYNA: SOLID, SHELL, BEAM) */
  int elform;       /* LS-DYNA's ELFORM (0 for the others) */
  const int *perm;  /* the solver's node order (NULL: Gmsh's) */
} deck_elem_row;

/* ---- plan.c ---- */
/* The row of rows[n] for part p into p; deck_lacks when there is none. */
int deck_element_from(deck_ctx *c, deck_part *p, const deck_elem_row *rows, size_t n);
/* label made a name for the solvers (letters, digits, '_', a letter first,
 * upper case; "" gives G<tag>) into out[DECK_NAME_MAX]. */
void deck_safe_name(const char *label, int tag, char *out);
/* The block of part p's elements, and the global index of its first element. */
const dtm_block *deck_part_block(const deck_ctx *c, const deck_part *p, size_t *offset);
/* Parts (with the writer's elements), the elements by part, the nodes
 * used and the groups' sets, into c; deck_plan_free frees them. */
int deck_plan(deck_ctx *c);
void deck_plan_free(deck_ctx *c);

/* ---- deck.c: what the writers share ---- */
/* Add a warning (once; at most DTM_DECK_WARN_MAX). */
void deck_warn(deck_ctx *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* "kind type" ("shell tri3") of part p into buf, and its group's label. */
const char *deck_part_label(const deck_ctx *c, const deck_part *p, char *buf, size_t len);
/* Warn about a quad4 part whose solver element elem ("CPE4R", "ELFORM
 * 16") integrates differently: one point with hourglass control (plane),
 * assumed transverse shear strains (shell). */
void deck_warn_quad4(deck_ctx *c, const deck_part *p, const char *elem);
/* DTM_ERR_INPUT: the solver lacks part p's element (why: "" or a reason), naming
 * what would work instead: the solvers that take it, else a first-order
 * mesh when one would be taken, else none. */
int deck_lacks(const deck_ctx *c, const deck_part *p, const char *why);
/* The Gmsh node tags of element e of block b in the solver's node order
 * (part p's perm), plane elements turned counter-clockwise about +z;
 * returns the count. */
int deck_conn(const deck_ctx *c, const dtm_block *b, size_t e, const deck_part *p, size_t *tags);
/* The mass the deck puts at node v (mesh index): what the mesh carries and
 * what the target adds, kg. */
double deck_node_mass(const deck_ctx *c, size_t v);
/* The mass of element e of block b in part p: rho x its measure x the
 * part's thickness (plane, membrane, shell) or area (truss, beam), kg. */
double deck_element_mass(const deck_ctx *c, const dtm_block *b, size_t e, const deck_part *p);
/* E (Pa), nu, rho (kg/m^3) of scene material mat. */
void deck_elastic(const deck_ctx *c, int mat, double *E, double *nu, double *rho);
/* The material's Rayleigh coefficients (alpha 1/s, beta s) and constant
 * damping ratio xi, the scene's where the material gives none (all 0
 * without damping). */
void deck_damping(const deck_ctx *c, int mat, double *alpha, double *beta, double *xi);
/* The orientation of beam x[2][3] of section sec (a vector in its local
 * x-y plane): the scene's vector, else global z (global y for a beam
 * within about 8 degrees of z, as the kernel does), into v[3]. */
void deck_beam_axis(const dtm_section *sec, const double *x, double v[3]);
/* The one orientation of part p's beams (Abaqus-style sections take one):
 * the scene's, else the kernel's rule for most of them, warning when
 * they differ. */
void deck_beam_orientation(deck_ctx *c, const deck_part *p, double v[3]);
/* v in decimal at p, right-aligned in width columns (0: as long as it
 * is); returns the end (no terminator). Element lines are built with it:
 * a million elements' worth of fprintf calls cost more than the rest. */
char *deck_put_uint(char *p, size_t v, int width);
/* v with the most significant digits (at most 17) that fit in width
 * characters, into buf[40]; returns buf. */
const char *deck_number(double v, int width, char *buf);
/* The common header: dtmap's version, the scene, the step, its basis and
 * safety, the solver's own estimate, the added mass, the warnings and what
 * the user must add, each line starting with the comment marker cm. */
void deck_header(const deck_ctx *c, const char *cm);
/* The file names of the include slots: the deck's base name + "_model" or
 * "_step" + ext, into buf. */
const char *deck_slot_name(const deck_ctx *c, const char *what, char *buf, size_t len);

/* ---- rules.c: the solvers' element rules (geometry of the corner nodes x[nn][3]) ---- */
/* Dilatational (3D), plate and bar wave speeds of E, nu, rho, m/s. */
double deck_speed_3d(double E, double nu, double rho);
double deck_speed_plate(double E, double nu, double rho);
double deck_speed_bar(double E, double rho);
/* The shortest altitude of a tetrahedron (corners x[4][3]), m. */
double deck_tet_min_altitude(const double *x);
/* Volume over the largest face of a hexahedron (x[8][3]), m. */
double deck_hex_volume_area(const double *x);
/* LS-DYNA's shell length L_s = (1 + b) A / max(L_1, L_2, L_3, (1 - b) L_4),
 * b = 1 for triangles, 0 for quadrangles (ISDO = 0), of nc = 3 or 4 corners. */
double deck_shell_length(const double *x, int nc);
/* CalculiX 2.20's length (calcstabletimeincvol.f): the smallest over the
 * faces of (volume weight) / (face area) of the solid element it
 * integrates, 2D elements extruded by thickness t and 1D elements by a
 * section of sides a x b; see rules.c. type is the dtmap type. */
double deck_ccx_length(int type, const double *x, double t, double a, double b);
/* The same for a shell or membrane element x of nc = 3 or 4 corners
 * (type tri3 or quad4) whose layer CalculiX builds along the corner
 * normals n[nc][3] (unit): -t/2 and +t/2 from each corner. */
double deck_ccx_layer_length(int type, const double *x, const double *n, double t);
/* CalculiX's factor on that length for its solid of part p's element. */
double deck_ccx_elemfac(const char *elem);

/* ---- lsdyna.c ---- */
/* LS-DYNA's TSSFAC and (c->own_scaling) DT2MS for the step c->info holds,
 * after the solver's own estimate: the step becomes TSSFAC x that estimate,
 * or TSSFAC x |DT2MS| with the mass LS-DYNA adds by its rule predicted
 * (info->solver_added, the model's mass info->model_mass). */
void deck_lsdyna_step(deck_ctx *c);

/* ---- sms.c: decks with selective mass scaling (--selective-mass) ---- */
/* The solver's selective scaling at the step c->info holds (the target):
 * CalculiX's by its rule (calcstabletimeincvol.f: each element whose own
 * step is below the target gets beta_e = (target / own_e)^2 - 1 and a
 * matrix of trace beta_e m_e per direction that leaves its translational
 * mass unchanged), LS-DYNA's the DT2MS prediction it already holds,
 * Abaqus none; into c->info (sms_*). */
void deck_sms_predict(deck_ctx *c);
/* CalculiX: element e of block b (global index i) is one its selective
 * scaling reaches (its own step below the target). */
int deck_sms_scaled(const deck_ctx *c, const dtm_block *b, size_t e, size_t i);
/* The header's lines on the selective scaling, each after cm. */
void deck_sms_header(const deck_ctx *c, const char *cm);
/* CalculiX: *ELSET DTMAP_SMS_SCALED of the elements its scaling reaches. */
void deck_sms_elset(deck_ctx *c);

/* ---- inp.c: Abaqus-style input (CalculiX and Abaqus) ---- */
int deck_inp_nodes(deck_ctx *c);
int deck_inp_elements(deck_ctx *c);
int deck_inp_sets(deck_ctx *c);
/* *MATERIAL cards; damping: 1 writes each material's Rayleigh *DAMPING. */
int deck_inp_materials(deck_ctx *c, int damping);
/* One section card per part; own(c, p, &done) writes the writer's own
 * card for p when it sets done (beams; CalculiX's springs). */
int deck_inp_sections(deck_ctx *c, int (*own)(deck_ctx *c, const deck_part *p, int *done));
/* A MASS element at every node with mass (deck_node_mass) or mass in
 * extra[nnodes] (kg; NULL: none), carrying their sum. */
int deck_inp_masses(deck_ctx *c, const double *extra);
/* A data line of n reals v[n] (each within CalculiX's 20 columns). */
void deck_inp_reals(deck_ctx *c, int n, const double *v);
/* A commented *INCLUDE slot. */
void deck_inp_slot(deck_ctx *c, const char *what, const char *text);

#endif
