/* Solver decks: the table of writers (one line each in list.h), the choice
 * by name, and the one flow every deck follows: plan the parts and sets
 * (plan.c), choose the step (dtmap's recommended step, capped where the
 * solver builds an element differently, or the target with mass added at
 * the nodes), the solver's own estimate by its documented rule, then the
 * writer writes the deck to a temporary renamed into place only when
 * complete. Also the helpers every writer shares: the connectivity in the
 * solver's node order, material values, damping, beam orientation,
 * warnings and the deck's header. */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "deck-impl.h"
#include "dtmap/cost.h"
#include "dtmap/kernel.h"
#include "dtmap/units.h"
#include "dtmap/util.h"
#include "dtmap/version.h"

#define DECK_WRITER(t) extern const deck_writer t;
#include "list.h"
#undef DECK_WRITER
static const deck_writer *const writers[] = {
#define DECK_WRITER(t) &t,
#include "list.h"
#undef DECK_WRITER
    NULL};

#define DECK_STEPS_DEFAULT 1000 /* steps of a deck whose scene gives no duration */

const char *dtm_deck_solvers(void) {
  static char list[256];
  list[0] = '\0';
  for (int i = 0; writers[i]; i++) dtm_strlist_add(list, sizeof list, writers[i]->name, 0);
  return list;
}

static const deck_writer *find(const char *name) {
  for (int i = 0; name && writers[i]; i++)
    if (!strcmp(name, writers[i]->name)) return writers[i];
  return NULL;
}

/* name's letters and digits, lower case ("LS-Dyna" -> "lsdyna"). */
static void letters(const char *name, char *buf, size_t len) {
  size_t k = 0;
  for (const char *p = name; *p && k + 1 < len; p++)
    if ((*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9'))
      buf[k++] = *p;
    else if (*p >= 'A' && *p <= 'Z')
      buf[k++] = (char)(*p - 'A' + 'a');
  buf[k] = '\0';
}

/* The writer likely meant: the same letters and digits in any case
 * ("ls-dyna", "CalculiX"), else one that starts alike (at least 4 letters in
 * common: "abaqus-explicit"; "ccx" none). */
const char *dtm_deck_solver_near(const char *name) {
  char a[64], b[64];
  letters(name, a, sizeof a);
  for (int i = 0; writers[i]; i++)
    if (letters(writers[i]->name, b, sizeof b), !strcmp(a, b)) return writers[i]->name;
  for (int i = 0; writers[i]; i++) {
    letters(writers[i]->name, b, sizeof b);
    size_t n = strlen(a) < strlen(b) ? strlen(a) : strlen(b);
    if (n >= 4 && !strncmp(a, b, n)) return writers[i]->name;
  }
  return NULL;
}

int dtm_deck_solver(const char *name, const char **ext) {
  const deck_writer *w = find(name);
  const char *near = w || !name ? NULL : dtm_deck_solver_near(name);
  if (near)
    return DTM_ERR(DTM_ERR_INPUT, "unknown solver '%s': did you mean %s? (the solvers are: %s)", name, near,
                   dtm_deck_solvers());
  if (!w)
    return DTM_ERR(DTM_ERR_INPUT, "unknown solver '%s'; the solvers are: %s", name ? name : "", dtm_deck_solvers());
  if (ext) *ext = w->ext;
  return DTM_OK;
}

int dtm_deck_adapt(dtm_scene *s, const char *solver, char *note, size_t len) {
  const deck_writer *w = find(solver);
  if (len) note[0] = '\0';
  if (!w) return dtm_deck_solver(solver, NULL);
  return w->adapt ? w->adapt(s, note, len) : DTM_OK;
}

/* ---- helpers the writers share ---- */

void deck_warn(deck_ctx *c, const char *fmt, ...) {
  dtm_deck_info *in = c->info;
  char text[sizeof in->warnings[0]];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(text, sizeof text, fmt, ap);
  va_end(ap);
  for (int i = 0; i < in->nwarnings; i++)
    if (!strcmp(in->warnings[i], text)) return;
  if (in->nwarnings < DTM_DECK_WARN_MAX) memcpy(in->warnings[in->nwarnings++], text, sizeof text);
}

const char *deck_part_label(const deck_ctx *c, const deck_part *p, char *buf, size_t len) {
  char g[64];
  snprintf(buf, len, "%s %s elements of group '%s'", dtm_section_kind_name(p->kind), dtm_elem_name(p->type),
           p->group >= 0 ? dtm_mesh_group_label(c->m, p->group, g, sizeof g) : "(none)");
  return buf;
}

void deck_warn_quad4(deck_ctx *c, const deck_part *p, const char *elem) {
  char lbl[160];
  if (p->type != DTM_QUAD4) return;
  deck_part_label(c, p, lbl, sizeof lbl);
  if (p->kind == DTM_SECTION_PLANE_STRAIN || p->kind == DTM_SECTION_PLANE_STRESS)
    deck_warn(c,
              "%s: %s integrates at one point with hourglass control; its step was not measured against dtmap's "
              "fully integrated element",
              lbl, elem);
  if (p->kind == DTM_SECTION_SHELL)
    deck_warn(c,
              "%s: %s takes assumed transverse shear strains, dtmap's quad4 shell one point at the centre; a "
              "textbook MITC4 gives an element step 9.0 %% (t = 0.01 m) to 2.0 %% (0.05 m) shorter and a global step "
              "0.1 %% to 3.0 %% shorter",
              lbl, elem);
}

/* The writers (but skip) that have an element for part p's kind as type:
 * their names into list[len]. Each is asked as it would be asked for the
 * part (its element operation), on a copy that raises no error and keeps
 * its warnings apart. */
static void takers(const deck_ctx *c, const deck_part *p, int type, const deck_writer *skip, char *list, size_t len) {
  dtm_deck_info *scratch = malloc(sizeof *scratch);
  list[0] = '\0';
  for (int i = 0; scratch && writers[i]; i++) {
    deck_ctx t = *c;
    deck_part q = *p;
    if (writers[i] == skip) continue;
    memset(scratch, 0, sizeof *scratch);
    t.w = writers[i], t.info = scratch, t.probe = 1, q.type = type;
    if (writers[i]->element(&t, &q) == DTM_OK) dtm_strlist_add(list, len, writers[i]->name, 0);
  }
  free(scratch);
}

/* What would work instead of part p with c's writer, into buf: the
 * solvers that take its elements, else a first-order mesh when one would
 * be taken, else none. */
static const char *instead(const deck_ctx *c, const deck_part *p, char *buf, size_t len) {
  char list[256];
  int parent = dtm_elem_parent(p->type);
  takers(c, p, p->type, c->w, list, sizeof list);
  if (list[0]) {
    snprintf(buf, len, "choose another solver: %s", list);
    return buf;
  }
  if (parent && parent != p->type) takers(c, p, parent, NULL, list, sizeof list);
  if (parent && parent != p->type && list[0])
    snprintf(buf, len, "no solver here takes them; a first-order mesh would%s: %s take%s its %s elements",
             c->s->mesh ? "" : " (<meshing order=\"1\"> in the scene)", list, strchr(list, ',') ? "" : "s",
             dtm_elem_name(parent));
  else
    snprintf(buf, len, "no solver here takes them");
  return buf;
}

int deck_lacks(const deck_ctx *c, const deck_part *p, const char *why) {
  char lbl[160], alt[512];
  if (c->probe) return DTM_ERR_INPUT;
  deck_part_label(c, p, lbl, sizeof lbl);
  return DTM_ERR(DTM_ERR_INPUT, "%s: %s has no element for the %s%s%s (%s)", c->s->path, c->w->title, lbl,
                 why[0] ? ": " : "", why, instead(c, p, alt, sizeof alt));
}

/* Gmsh local nodes of a plane element turned over (counter-clockwise). */
static const int *flip_of(int type) {
  static const int tri3[] = {0, 2, 1}, quad4[] = {0, 3, 2, 1}, tri6[] = {0, 2, 1, 5, 4, 3},
                   quad8[] = {0, 3, 2, 1, 7, 6, 5, 4};
  return type == DTM_TRI3 ? tri3 : type == DTM_QUAD4 ? quad4 : type == DTM_TRI6 ? tri6 : quad8;
}

/* Whether plane element e of block b turns clockwise about +z: the
 * cross product of its first two sides (triangles) or of its diagonals
 * (quadrangles) points down. */
static int clockwise(const dtm_mesh *m, const dtm_block *b, size_t e) {
  const size_t *n = b->conn + e * b->nn;
  int quad = dtm_elem_parent(b->type) == DTM_QUAD4;
  const double *p0 = m->xyz + 3 * n[0], *p1 = m->xyz + 3 * n[1], *p2 = m->xyz + 3 * n[2];
  const double *u1 = quad ? p2 : p1, *v0 = quad ? p1 : p0, *v1 = quad ? m->xyz + 3 * n[3] : p2;
  double u[2] = {u1[0] - p0[0], u1[1] - p0[1]}, v[2] = {v1[0] - v0[0], v1[1] - v0[1]};
  return u[0] * v[1] - u[1] * v[0] < 0;
}

int deck_conn(const deck_ctx *c, const dtm_block *b, size_t e, const deck_part *p, size_t *tags) {
  const size_t *conn = b->conn + e * b->nn;
  int plane = p->kind == DTM_SECTION_PLANE_STRAIN || p->kind == DTM_SECTION_PLANE_STRESS;
  const int *fl = plane && clockwise(c->m, b, e) ? flip_of(b->type) : NULL;
  for (int k = 0; k < b->nn; k++) {
    int a = p->perm ? p->perm[k] : k;
    tags[k] = c->m->node_tags[conn[fl ? fl[a] : a]];
  }
  return b->nn;
}

double deck_node_mass(const deck_ctx *c, size_t v) {
  return (c->added ? c->added[v] : 0.0) + (c->carried ? c->carried[v] : 0.0);
}

double deck_element_mass(const deck_ctx *c, const dtm_block *b, size_t e, const deck_part *p) {
  double x[3 * DTM_MAX_NODES], E, nu, rho;
  dtm_mesh_gather_one(c->m, b, e, x);
  deck_elastic(c, p->mat, &E, &nu, &rho);
  return rho * dtm_elem_measure(b->type, x) * (p->kind == DTM_SECTION_SOLID ? 1.0 : p->thickness);
}

void deck_elastic(const deck_ctx *c, int mat, double *E, double *nu, double *rho) {
  const dtm_material *m = &c->s->materials[mat].m;
  *E = dtm_material_value(m, "E"), *nu = dtm_material_value(m, "nu"), *rho = dtm_material_value(m, "rho");
  if (isnan(*nu)) *nu = 0.0; /* a bar's material needs none */
}

/* The scene's damping effect, or NULL. */
static const dtm_scene_effect *damping_effect(const dtm_scene *s) {
  for (int k = 0; k < s->neffects; k++)
    if (!strcmp(s->effects[k].name, "damping")) return &s->effects[k];
  return NULL;
}

/* The material's value of key, else the effect's, else 0. */
static double damping_value(const dtm_material *m, const dtm_scene_effect *d, const char *key) {
  double v = dtm_material_value(m, key);
  const char *t = isnan(v) ? dtm_scene_effect_attr(d, key) : NULL;
  return !isnan(v) ? v : t ? strtod(t, NULL) : 0.0;
}

void deck_damping(const deck_ctx *c, int mat, double *alpha, double *beta, double *xi) {
  const dtm_scene_effect *d = damping_effect(c->s);
  const dtm_material *m = &c->s->materials[mat].m;
  *alpha = *beta = *xi = 0.0;
  if (!d) return;
  *alpha = damping_value(m, d, "alpha"), *beta = damping_value(m, d, "beta"), *xi = damping_value(m, d, "xi");
}

/* Whether the beam x[2][3] runs within about 8 degrees of z (the kernel
 * then orients it by global y). */
static int along_z(const double *x) {
  double d[3], len = 0;
  for (int k = 0; k < 3; k++) d[k] = x[3 + k] - x[k], len += d[k] * d[k];
  return fabs(d[2]) > 0.99 * sqrt(len);
}

void deck_beam_axis(const dtm_section *sec, const double *x, double v[3]) {
  memcpy(v, sec->orient, 3 * sizeof *v);
  if (v[0] != 0 || v[1] != 0 || v[2] != 0) return;
  v[along_z(x) ? 1 : 2] = 1.0;
}

void deck_beam_orientation(deck_ctx *c, const deck_part *p, double v[3]) {
  const dtm_section *sec = &c->s->sections[p->section];
  size_t off, k = (size_t)(p - c->parts), near_z = 0;
  const dtm_block *b = deck_part_block(c, p, &off);
  double x[6];
  for (size_t j = c->first[k]; j < c->first[k + 1]; j++) {
    dtm_mesh_gather_one(c->m, b, c->order[j] - off, x);
    near_z += along_z(x);
  }
  memcpy(v, sec->orient, 3 * sizeof *v);
  if (v[0] != 0 || v[1] != 0 || v[2] != 0) return;
  v[2 * near_z > p->count ? 1 : 2] = 1.0;
  if (near_z && near_z < p->count)
    deck_warn(c,
              "section at %s:%d gives no orientation and its beams run both along z and across it: the deck "
              "orients them all by global %s; give orientation=\"x y z\"",
              c->s->path, sec->line, 2 * near_z > p->count ? "y" : "z");
}

char *deck_put_uint(char *p, size_t v, int width) {
  char d[24];
  int n = 0;
  do d[n++] = (char)('0' + v % 10), v /= 10;
  while (v);
  for (; width > n; width--) *p++ = ' ';
  while (n) *p++ = d[--n];
  return p;
}

const char *deck_number(double v, int width, char *buf) {
  int p = 17, n = snprintf(buf, 40, "%.*g", p, v);
  if (n > width) p -= n - width, n = snprintf(buf, 40, "%.*g", p > 1 ? p : 1, v); /* one digit a character */
  while (n > width && --p > 0) n = snprintf(buf, 40, "%.*g", p, v);               /* the exponent form took over */
  return buf;
}

const char *deck_slot_name(const deck_ctx *c, const char *what, char *buf, size_t len) {
  const char *path = c->info->path, *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
  const char *dot = strrchr(base, '.');
  snprintf(buf, len, "%.*s_%s%s", dot ? (int)(dot - base) : (int)strlen(base), base, what, c->w->ext);
  return buf;
}

/* The deck's system of units, stated once: the scene's, in which the
 * nodes, materials, sections and masses are written (docs/units.md). */
static void deck_units_line(const deck_ctx *c, const char *cm) {
  const char *u = dtm_scene_units(c->s);
  int dim = dtm_analysis_mesh(c->a)->dim;
  fprintf(c->f, "%s units: %s (lengths %s, masses %s, densities %s, moduli and stresses %s, time s)\n", cm,
          dtm_units_mm(u) ? "mm-t-s" : "SI", dtm_units_name(u, DTM_UNIT_LENGTH), dtm_scene_mass_unit(c->s, dim),
          dtm_units_name(u, DTM_UNIT_DENSITY), dtm_units_name(u, DTM_UNIT_MODULUS));
}

void deck_header(const deck_ctx *c, const char *cm) {
  const dtm_deck_info *in = c->info;
  FILE *f = c->f;
  const char *M = dtm_scene_mass_unit(c->s, dtm_analysis_mesh(c->a)->dim);
  fprintf(f, "%s dtmap %s: %s input deck\n%s scene: %s\n", cm, dtm_version(), in->title, cm, c->s->path);
  fprintf(f, "%s %zu nodes, %zu elements, %d element sets and %d node sets (one per physical group)\n", cm, in->nodes,
          in->elements, in->element_sets, in->node_sets);
  deck_units_line(c, cm);
  if (dtm_analysis_recommended_certified(c->a))
    fprintf(f,
            "%s step: %.10g s, %s (dtmap's recommended step %.10g s: the probable bound's certified step, below "
            "safety %g x the %s)\n",
            cm, in->step, in->basis, in->recommended, c->s->safety, dtm_analysis_basis(c->a));
  else
    fprintf(f, "%s step: %.10g s, %s (dtmap's recommended step %.10g s: safety %g x the %s)\n", cm, in->step, in->basis,
            in->recommended, c->s->safety, dtm_analysis_basis(c->a));
  if (isnan(in->own))
    fprintf(f, "%s %s's own estimate (%s) covers none of these elements\n", cm, in->title, in->own_rule);
  else
    fprintf(f, "%s %s's own estimate for this mesh: %.10g s (element %zu; %s): the step is %.4fx it\n", cm, in->title,
            in->own, in->own_element, in->own_rule, in->step / in->own);
  if (in->carried > 0)
    fprintf(f, "%s point masses the mesh carries: %.10g %s at %zu nodes (mass elements below)\n", cm, in->carried, M,
            in->carried_nodes);
  if (in->added > 0)
    fprintf(f, "%s added mass: %.10g %s at %zu nodes, %.4g %% of the model's %.10g %s (mass elements below)\n", cm,
            in->added, M, in->added_nodes, 100 * in->added / in->model_mass, in->model_mass, M);
  if (isfinite(in->tssfac) && isfinite(in->dt2ms))
    fprintf(f,
            "%s TSSFAC %.10g and DT2MS %.10g s: the step is TSSFAC x |DT2MS|; %s adds mass at its start to\n"
            "%s each element whose own step is below |DT2MS|, bringing it to |DT2MS|: by its rule %.10g %s at\n"
            "%s %zu elements, %.4g %% of the model's %.10g %s\n",
            cm, in->tssfac, in->dt2ms, in->title, cm, in->solver_added, M, cm, in->solver_added_elements,
            100 * in->solver_added / in->model_mass, in->model_mass, M);
  else if (isfinite(in->tssfac))
    fprintf(f, "%s TSSFAC %.10g: the step over %s's own estimate, so that its first step is the deck's\n", cm,
            in->tssfac, in->title);
  if (in->selective) deck_sms_header(c, cm);
  for (const char *l = c->proven; *l;) {
    size_t n = strcspn(l, "\n");
    fprintf(f, "%s %.*s\n", cm, (int)n, l);
    l += n + (l[n] == '\n');
  }
  fprintf(f, "%s duration: %.10g s%s\n", cm, in->duration,
          c->s->duration > 0 ? " (<time duration>)" : " (the scene gives no <time duration>: 1000 steps)");
  for (int i = 0; i < in->nwarnings; i++) fprintf(f, "%s warning: %s\n", cm, in->warnings[i]);
  fprintf(f,
          "%s Not in this deck, since the scene does not describe it: loads, boundary conditions, initial\n"
          "%s conditions, contact and output requests. Add them in the files of the two include slots\n"
          "%s below and uncomment the slots.\n",
          cm, cm, cm);
}

/* ---- the flow ---- */

/* The scene's elastic effect (its index into *k), required. */
static int elastic_of(const dtm_analysis *a, int *k) {
  for (*k = 0; *k < dtm_analysis_neffects(a); (*k)++)
    if (!strcmp(dtm_analysis_effect(a, *k)->name, "elastic")) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: a deck needs the elastic effect (<elastic/> under <effects>): the solver's "
                 "materials and step are elastic",
                 dtm_analysis_scene(a)->path);
}

/* The elastic effect's formulation (its attribute, else the dimension's). */
static int formulation(const dtm_analysis *a, int k) {
  const char *names[] = DTM_FORMULATION_NAMES;
  const char *v = dtm_scene_effect_attr(&dtm_analysis_scene(a)->effects[k], "formulation");
  for (int i = 0; v && names[i]; i++)
    if (!strcmp(v, names[i])) return i;
  return dtm_formulation_default(dtm_analysis_mesh(a)->dim);
}

/* The solver's own estimate: the smallest element step by its rule. */
static void own_estimate(deck_ctx *c) {
  dtm_deck_info *in = c->info;
  size_t i = 0;
  in->own = INFINITY;
  for (int b = 0; b < c->m->nblocks; b++)
    for (size_t e = 0; e < c->m->blocks[b].n; e++, i++) {
      double t = c->w->own(c, &c->m->blocks[b], e, i, &c->parts[c->part[i]]);
      if (t < in->own) in->own = t, in->own_element = c->m->blocks[b].tags[e];
    }
  snprintf(in->own_rule, sizeof in->own_rule, "%s", c->w->rule);
  if (!isfinite(in->own)) in->own = NAN; /* its rule covers none of the elements (CalculiX's springs) */
}

/* The step the solver's own elements allow, as a factor on dtmap's step
 * (*factor) and as a cap before the safety factor (returned, s). */
static double solver_limits(deck_ctx *c, double *factor) {
  double cap = INFINITY;
  size_t i = 0;
  *factor = 1.0;
  for (int k = 0; k < c->nparts && c->w->factor; k++) *factor = fmin(*factor, c->w->factor(c, &c->parts[k]));
  for (int b = 0; b < c->m->nblocks && c->w->cap; b++)
    for (size_t e = 0; e < c->m->blocks[b].n; e++, i++)
      cap = fmin(cap, c->w->cap(c, &c->m->blocks[b], e, &c->parts[c->part[i]]));
  return cap;
}

/* The mass the target needs at the nodes: the one call that decides it
 * (the nodal form, each node's nodal-bound step brought to dt_t / safety). */
static int target_mass(const dtm_analysis *a, double dt_t, dtm_mass_scaling *ms) {
  return dtm_mass_scaling_nodal(a, dt_t / dtm_analysis_scene(a)->safety, NULL, ms);
}

static int mass_check(const deck_ctx *c, const dtm_deck_opts *o) {
  const dtm_deck_info *in = c->info;
  const char *M = dtm_scene_mass_unit(c->s, dtm_analysis_mesh(c->a)->dim);
  double added = in->added + in->solver_added, pc = 100 * added / in->model_mass;
  if (!(pc > o->max_added)) return DTM_OK;
  return DTM_ERR(DTM_ERR_TARGET,
                 "%s: the target %.4e s needs %.6g %s added at %zu %s, %.4g %% of the model's %.6g %s: above "
                 "--max-added-mass %g %%; nothing written",
                 c->s->path, o->target, added, M, in->added > 0 ? in->added_nodes : in->solver_added_elements,
                 in->added > 0 ? "nodes" : "elements (LS-DYNA's DT2MS rule)", pc, in->model_mass, M, o->max_added);
}

/* The step and its basis; the masses when the target needs them. */
static int choose_step(deck_ctx *c, const dtm_deck_opts *o, dtm_mass_scaling *ms) {
  dtm_deck_info *in = c->info;
  double factor, cap = c->s->safety * solver_limits(c, &factor);
  in->recommended = dtm_analysis_recommended(c->a);
  in->step = fmin(in->recommended * factor, cap);
  snprintf(in->basis, sizeof in->basis, "%s",
           in->step < in->recommended ? "capped by the solver's elements" : "the recommended step");
  if (!(o->target > in->step)) return DTM_OK;
  if (c->own_scaling) {                        /* the solver's mass scaling reaches it; checked once predicted */
    int ccx = !strcmp(c->w->name, "calculix"); /* ccx runs at its minimum increment, the target */
    in->step = ccx ? o->target : fmin(o->target, cap);
    snprintf(in->basis, sizeof in->basis, "%s",
             o->selective_mass ? "the target, by selective mass scaling"
                               : "the target, with the solver's mass scaling");
    if (ccx && cap < o->target)
      deck_warn(c,
                "dtmap caps CalculiX's layers (shells, membranes, beams, plane stress) at %.4e s, below the target "
                "%.4e s; ccx's selective scaling lowers their thickness modes too, by its rule, not measured here",
                cap, o->target);
    return DTM_OK;
  }
  DTM_CHECK(target_mass(c->a, o->target / factor, ms));
  in->added = ms->total_added, in->model_mass = ms->total_mass, in->added_nodes = ms->nodes;
  c->added = ms->node_added;
  in->step = fmin(o->target, cap);
  snprintf(in->basis, sizeof in->basis, "the target, with added mass");
  if (cap < o->target)
    deck_warn(c,
              "%s's own elements cap the step at %.4e s, below the target %.4e s: the mass added does not lift "
              "that cap",
              in->title, cap, o->target);
  return mass_check(c, o);
}

/* ccx's bound of integration points per element for the deck's elements
 * (dtm_cost_ccx_points: it scales ccx's per-element arrays). */
static int deck_points(const deck_ctx *c) {
  const char *elems[64];
  int n = 0;
  for (int k = 0; k < c->nparts && n < 64; k++) elems[n++] = c->parts[k].elem;
  return dtm_cost_ccx_points(elems, n);
}

/* The cost per element-step of the solver's elements, s, and its source:
 * the scene's <time cost-per-element-step>; else for CalculiX its
 * elements' measured figures (ccx_cost.inc, at the deck's element count)
 * weighted by their counts, an
 * element not measured taking dtmap's figure for its type; else not
 * known (NaN). */
static double solver_cost(const deck_ctx *c, char *src, size_t len) {
  if (c->s->cost_per_element_step > 0)
    return snprintf(src, len, "%s:%d: <time cost-per-element-step>", c->s->path, c->s->time_line),
           c->s->cost_per_element_step;
  if (strcmp(c->w->name, "calculix"))
    return snprintf(src, len, "not known: no %s here to measure, and the scene gives no <time cost-per-element-step>",
                    c->w->title),
           NAN;
  double sum = 0.0, n = 0.0, all = 0.0;
  char lacks[64] = "";
  int points = deck_points(c);
  for (int k = 0; k < c->nparts; k++) all += (double)c->parts[k].count;
  for (int k = 0; k < c->nparts; k++) {
    const deck_part *p = &c->parts[k];
    double ns = dtm_cost_ccx_ns_at(p->elem, all, points);
    if (isnan(ns) && !strstr(lacks, p->elem) && strlen(lacks) + strlen(p->elem) + 3 < sizeof lacks)
      strcat(strcat(lacks, lacks[0] ? ", " : ""), p->elem);
    const char *stand = dtm_cost_calibrated_elem(p->type);
    if (isnan(ns)) ns = stand ? dtm_cost_ccx_ns_at(stand, all, points) : NAN;
    sum += ns * (double)p->count, n += (double)p->count;
  }
  snprintf(src, len,
           "Debian's ccx 2.20, one thread, measured on dtmap's decks (bench/ccx_cost.py), for a deck of %.0f "
           "elements: %s the switch at %.0f; ccx's bound of %d integration points per element%s%s%s",
           all, all > dtm_cost_ccx_switch() ? "beyond" : "below", dtm_cost_ccx_switch(), points, lacks[0] ? "; " : "",
           lacks, lacks[0] ? " not measured: their dtmap type's figure" : "");
  return n > 0 ? sum / n * 1e-9 : NAN;
}

/* The step the solver takes with the deck c->info describes (after its
 * own estimate) and the hours the scene's duration then takes. */
static void solver_run(const deck_ctx *c, dtm_solver_run *r) {
  const dtm_deck_info *in = c->info;
  r->step = in->step;
  if (!strcmp(c->w->name, "calculix") && in->selective)
    snprintf(r->basis, sizeof r->basis, "the deck's minimum increment, with ccx's selective mass scaling");
  else if (!strcmp(c->w->name, "calculix") && in->own < in->step)
    r->step = in->own,
    snprintf(r->basis, sizeof r->basis, "ccx's own estimate: it takes the smaller of it and the deck's increment");
  else if (!strcmp(c->w->name, "calculix"))
    snprintf(r->basis, sizeof r->basis, "the deck's increment, below ccx's own estimate");
  else if (isfinite(in->dt2ms))
    snprintf(r->basis, sizeof r->basis, "TSSFAC x |DT2MS|, after LS-DYNA's mass scaling");
  else if (isfinite(in->tssfac))
    snprintf(r->basis, sizeof r->basis, "TSSFAC x LS-DYNA's own estimate");
  else
    snprintf(r->basis, sizeof r->basis, "the deck's increment (DIRECT USER CONTROL)");
  double d = c->s->duration;
  r->element_steps = d > 0 ? (double)dtm_mesh_nelements(c->m) * ceil(d / r->step) : NAN;
  r->cost = solver_cost(c, r->cost_source, sizeof r->cost_source);
  r->hours = r->element_steps * r->cost / 3600;
}

/* A constant damping ratio has no solver equivalent: say so. */
static void damping_ratio(deck_ctx *c) {
  double alpha, beta, xi;
  for (int k = 0; k < c->nparts; k++) {
    deck_damping(c, c->parts[k].mat, &alpha, &beta, &xi);
    if (xi > 0)
      deck_warn(c,
                "the scene's damping ratio xi = %g (material '%s') has no equivalent in %s's input: add the "
                "damping you mean; the step already includes its factor",
                xi, c->s->materials[c->parts[k].mat].m.name, c->w->title);
  }
}

static void count(deck_ctx *c) {
  dtm_deck_info *in = c->info;
  for (size_t v = 0; v < c->m->nnodes; v++) {
    in->nodes += c->used[v];
    in->carried += c->carried ? c->carried[v] : 0.0, in->carried_nodes += c->carried && c->carried[v] > 0;
  }
  in->elements = dtm_mesh_nelements(c->m);
  for (int g = 0; g < c->ngroups; g++) in->element_sets += c->groups[g].mesh_group >= 0;
  in->node_sets = c->ngroups;
}

static int write_file(deck_ctx *c, const char *path) {
  dtm_atomic w;
  DTM_CHECK(dtm_atomic_open(&w, path, "", 1));
  c->f = w.f;
  int r = c->w->write(c);
  if (r) {
    dtm_atomic_abort(&w);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  return dtm_atomic_commit(&w);
}

/* --selective-mass needs a target and the solver's own scaling. */
static int selective_usage(const dtm_deck_opts *o) {
  if (!o->selective_mass) return DTM_OK;
  if (!(o->target > 0))
    return DTM_ERR(DTM_ERR_INPUT, "--selective-mass scales the mass to reach a step: give --target DT");
  if (o->lsdyna_proven)
    return DTM_ERR(DTM_ERR_INPUT,
                   "--selective-mass takes LS-DYNA's own scaling (DT2MS < 0 with IMSCL); --lsdyna-step proven "
                   "writes dtmap's masses at the nodes instead: choose one");
  return DTM_OK;
}

static void info_init(const deck_ctx *c, const dtm_deck_opts *o, dtm_deck_info *in) {
  memset(in, 0, sizeof *in);
  in->selective = o->selective_mass;
  in->sms_added = in->sms_beta_max = NAN;
  snprintf(in->solver, sizeof in->solver, "%s", c->w->name);
  snprintf(in->title, sizeof in->title, "%s", c->w->title);
  snprintf(in->path, sizeof in->path, "%s", o->path);
  in->tssfac = in->model_mass = in->dt2ms = NAN;
}

int dtm_deck_write(const dtm_analysis *a, const dtm_deck_opts *o, dtm_deck_info *info) {
  double t0 = dtm_wtime();
  int k;
  deck_ctx c = {.a = a,
                .m = dtm_analysis_mesh(a),
                .s = dtm_analysis_scene(a),
                .w = find(o->solver),
                .carried = dtm_analysis_point_masses(a),
                .info = info};
  if (!c.w) return dtm_deck_solver(o->solver, NULL);
  DTM_CHECK(selective_usage(o));
  info_init(&c, o, info);
  DTM_CHECK(elastic_of(a, &k));
  c.form = formulation(a, k), c.elastic = k;
  dtm_mass_scaling ms = {0};
  int r = deck_plan(&c);
  c.own_scaling =
      (!strcmp(c.w->name, "lsdyna") && !o->lsdyna_proven) || (!strcmp(c.w->name, "calculix") && o->selective_mass);
  info->lsdyna_proven = !strcmp(c.w->name, "lsdyna") && o->lsdyna_proven;
  if (r == DTM_OK) r = choose_step(&c, o, &ms);
  if (r == DTM_OK) own_estimate(&c);
  if (r == DTM_OK && !strcmp(c.w->name, "lsdyna")) deck_lsdyna_step(&c);
  if (r == DTM_OK && o->selective_mass) deck_sms_predict(&c);
  /* selective scaling leaves the translational mass unchanged: the limit is for mass at the nodes */
  if (r == DTM_OK && c.own_scaling && o->target > 0 && !o->selective_mass) r = mass_check(&c, o);
  if (r == DTM_OK) {
    solver_run(&c, &info->run);
    damping_ratio(&c);
    count(&c);
    info->duration = c.s->duration > 0 ? c.s->duration : DECK_STEPS_DEFAULT * info->step;
    r = write_file(&c, o->path);
  }
  dtm_mass_scaling_free(&ms);
  deck_plan_free(&c);
  info->seconds = dtm_wtime() - t0;
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

/* ---- the solver's own steps as a map (run --solver-rule) ---- */

/* Centroid of element e of block b: the mean of its corner nodes. */
static void corner_centroid(const dtm_mesh *m, const dtm_block *b, size_t e, double c[3]) {
  int nc = dtm_elem_is_simplex(b->type) ? b->dim + 1 : 1 << b->dim;
  if (nc > b->nn) nc = b->nn;
  c[0] = c[1] = c[2] = 0;
  for (int k = 0; k < nc; k++)
    for (int d = 0; d < 3; d++) c[d] += m->xyz[3 * b->conn[e * (size_t)b->nn + k] + d] / nc;
}

int dtm_deck_own_steps(const dtm_analysis *a, const char *solver, dtm_deck_steps *out) {
  dtm_deck_info *info = calloc(1, sizeof *info);
  deck_ctx c = {.a = a, .m = dtm_analysis_mesh(a), .s = dtm_analysis_scene(a), .w = find(solver), .info = info};
  size_t nel = dtm_analysis_nelements(a), i = 0;
  int k, r = info ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  memset(out, 0, sizeof *out);
  if (r == DTM_OK && !c.w) r = dtm_deck_solver(solver, NULL);
  if (r == DTM_OK) r = elastic_of(a, &k);
  if (r == DTM_OK) c.form = formulation(a, k), c.elastic = k, r = deck_plan(&c);
  out->dt = r ? NULL : malloc((nel + 1) * sizeof *out->dt);
  if (r == DTM_OK && !out->dt) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  out->min = NAN;
  for (int b = 0; r == DTM_OK && b < c.m->nblocks; b++)
    for (size_t e = 0; e < c.m->blocks[b].n; e++, i++) {
      double t = c.w->own(&c, &c.m->blocks[b], e, i, &c.parts[c.part[i]]);
      out->dt[i] = isfinite(t) ? t : NAN; /* a rule that covers no such element (CalculiX's springs) */
      if (t < out->min || (isnan(out->min) && isfinite(t))) {
        out->min = t, out->element = c.m->blocks[b].tags[e];
        corner_centroid(c.m, &c.m->blocks[b], e, out->centroid);
      }
    }
  dtm_mass_scaling ms = {0};
  dtm_deck_opts none = {.path = ""};
  if (r == DTM_OK) info_init(&c, &none, info), c.own_scaling = !strcmp(c.w->name, "lsdyna");
  if (r == DTM_OK) r = choose_step(&c, &none, &ms);
  if (r == DTM_OK) {
    own_estimate(&c);
    if (!strcmp(c.w->name, "lsdyna")) deck_lsdyna_step(&c);
    solver_run(&c, &out->run);
  }
  dtm_mass_scaling_free(&ms);
  if (r == DTM_OK) {
    snprintf(out->solver, sizeof out->solver, "%s", c.w->name);
    snprintf(out->title, sizeof out->title, "%s", c.w->title);
    snprintf(out->rule, sizeof out->rule, "%s", c.w->rule);
  }
  deck_plan_free(&c);
  free(info);
  if (r) dtm_deck_steps_free(out);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

void dtm_deck_steps_free(dtm_deck_steps *s) {
  free(s->dt);
  s->dt = NULL;
}
