/* What an element-step costs in time: the scene's own figure (<time
 * cost-per-element-step>, s) or Debian's CalculiX 2.20 explicit dynamics
 * measured on dtmap's own decks, one thread, per CalculiX element
 * (bench/ccx_cost.py writes ccx_cost.inc; docs/accuracy.md), each dtmap
 * type taking its CalculiX element's figure (2D: plane strain);
 * a mesh of several types takes the element-weighted mean. Each figure
 * holds for a mesh of the measured size: the arrays ccx allocates every
 * increment for a mesh beyond the switch (ccx_cost.inc, in elements,
 * measured on C3D4: about 25,000) pass glibc's 32 MiB mmap threshold and
 * are faulted in and zeroed afresh each time, and its element-steps
 * cost about twice as much (the second figure, measured on a mesh beyond
 * it), so the figure is chosen by the mesh's element count. Each figure
 * also holds for the bound of integration points per element its deck
 * gave ccx (27 for C3D4 alone): ccx sizes and copies its per-element
 * arrays by the bound of the whole deck, which its elements together set
 * (C3D4 with M3D3: 9), so a deck of another bound takes the table's cost
 * per point times the difference (dtm_cost_ccx_ns_at). Types not
 * calibrated (bars, prisms, pyramids, serendipity types) take the figure of the
 * calibrated type of the same dimension with the closest node count (said
 * so in the source line). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/kernel.h"

/* ns per element-step of CalculiX's own elements, measured on dtmap's decks
 * (bench/ccx_cost.py writes the table). */
static const struct {
  const char *elem; /* CalculiX's element */
  double ns;        /* time per element-step, one thread, ns: a mesh below the switch */
  double ns_large;  /* ... a mesh beyond it */
  double fit;       /* the switch: a mesh of more elements than this is beyond it */
} ccx_measured[] = {
#include "ccx_cost.inc"
};

/* The integration points per element ccx 2.20 gives each element it
 * reads (its allocation.f, written here from reading it); 0: none (MASS,
 * dashpots) or not known. */
static const struct {
  const char *elem; /* CalculiX's element */
  int points;       /* its own count */
} ccx_points[] = {{"C3D4", 1},   {"C3D10", 4}, {"C3D8", 8}, {"C3D8R", 1}, {"C3D6", 2}, {"C3D15", 9}, {"C3D20", 27},
                  {"C3D20R", 8}, {"CPE3", 2},  {"CPS3", 2}, {"M3D3", 2},  {"S3", 2},   {"CPE4", 8},  {"CPS4", 8},
                  {"M3D4", 8},   {"S4", 8},    {"CPE6", 9}, {"CPS6", 9},  {"S6", 9},   {"CPE8", 27}, {"CPS8", 27},
                  {"S8", 27},    {"B31", 8},   {"T3D2", 8}, {"B31R", 1},  {"B32", 27}, {"B32R", 50}, {"SPRINGA", 1}};

static int own_points(const char *elem) {
  for (size_t i = 0; i < sizeof ccx_points / sizeof *ccx_points; i++)
    if (!strcmp(ccx_points[i].elem, elem)) return ccx_points[i].points;
  return 0;
}

/* *DYNAMIC's change of the bound (allocation.f): 1 and 8 become 27, 4
 * becomes 15, 2 becomes 9, any other stays. */
static int dynamic_points(int points) {
  return points == 1 || points == 8 ? 27 : points == 4 ? 15 : points == 2 ? 9 : points;
}

int dtm_cost_ccx_points(const char *const *elems, int n) {
  int most = 0;
  for (int i = 0; i < n; i++)
    if (own_points(elems[i]) > most) most = own_points(elems[i]);
  return dynamic_points(most);
}

double dtm_cost_ccx_ns_at(const char *elem, double elements, int points) {
  double ns = dtm_cost_ccx_ns(elem, elements);
  int alone = dynamic_points(own_points(elem));
  return points > 0 && alone > 0 ? ns + CCX_POINT_NS * (points - alone) : ns;
}

double dtm_cost_ccx_ns(const char *elem, double elements) {
  for (size_t i = 0; i < sizeof ccx_measured / sizeof *ccx_measured; i++)
    if (!strcmp(ccx_measured[i].elem, elem))
      return elements > ccx_measured[i].fit ? ccx_measured[i].ns_large : ccx_measured[i].ns;
  return NAN;
}

/* The CalculiX element whose measured figure (ccx_cost.inc) stands for
 * each dtmap type: solids as themselves, 2D types as plane strain. */
static const struct {
  int type;         /* element type */
  const char *elem; /* CalculiX's element */
} calibrated[] = {{DTM_TET4, "C3D4"}, {DTM_TET10, "C3D10"}, {DTM_HEX8, "C3D8"},
                  {DTM_TRI3, "CPE3"}, {DTM_TRI6, "CPE6"},   {DTM_QUAD4, "CPE4"}};
#define NCAL (sizeof calibrated / sizeof calibrated[0])

double dtm_cost_ccx_switch(void) { return ccx_measured[0].fit; }

/* The CalculiX element whose figure stands for type: its own, else the
 * calibrated type's of the same dimension with the closest node count
 * (*own 0); NULL for a type not known. */
static const char *standing(int type, int *own) {
  int d, nn, dc, nc;
  *own = 1;
  for (size_t i = 0; i < NCAL; i++)
    if (calibrated[i].type == type) return calibrated[i].elem;
  *own = 0;
  if (dtm_elem_info(type, &d, &nn)) return NULL;
  const char *best = NULL;
  int gap = 1 << 30;
  for (size_t i = 0; i < NCAL; i++) {
    dtm_elem_info(calibrated[i].type, &dc, &nc);
    int g = dc == d ? abs(nc - nn) : 1000 + abs(nc - nn);
    if (g < gap) gap = g, best = calibrated[i].elem;
  }
  return best;
}

const char *dtm_cost_calibrated_elem(int type) {
  int own;
  return standing(type, &own);
}

double dtm_cost_calibrated_ns(int type, double elements) {
  const char *elem = dtm_cost_calibrated_elem(type);
  return elem ? dtm_cost_ccx_ns(elem, elements) : NAN;
}

/* The bound of integration points of the deck of the mesh's types, each as
 * the CalculiX element standing for it (dtm_cost_ccx_points). */
static int mesh_points(const dtm_mesh *m) {
  const char *elems[64];
  int n = 0;
  for (int b = 0; b < m->nblocks && n < 64; b++)
    if (dtm_cost_calibrated_elem(m->blocks[b].type)) elems[n++] = dtm_cost_calibrated_elem(m->blocks[b].type);
  return dtm_cost_ccx_points(elems, n);
}

int dtm_cost_per_element_step(const dtm_analysis *a, double *seconds, char *source, size_t len) {
  return dtm_cost_per_element_step_of(a, (double)dtm_mesh_nelements(dtm_analysis_mesh(a)), seconds, source, len);
}

int dtm_cost_per_element_step_of(const dtm_analysis *a, double all, double *seconds, char *source, size_t len) {
  const dtm_scene *s = dtm_analysis_scene(a);
  if (s->cost_per_element_step > 0) {
    *seconds = s->cost_per_element_step;
    snprintf(source, len, "%s:%d: <time cost-per-element-step>", s->path, s->time_line);
    return DTM_OK;
  }
  const dtm_mesh *m = dtm_analysis_mesh(a);
  double sum = 0;
  size_t n = 0;
  int all_own = 1, own;
  int points = mesh_points(m); /* this mesh's (a distributed run: this part's) */
  for (int b = 0; b < m->nblocks; b++) {
    const char *elem = standing(m->blocks[b].type, &own);
    sum += (elem ? dtm_cost_ccx_ns_at(elem, all, points) : NAN) * (double)m->blocks[b].n;
    n += m->blocks[b].n, all_own &= own;
  }
  *seconds = n ? sum / (double)n * 1e-9 : NAN;
  snprintf(source, len,
           "CalculiX 2.20 explicit, measured on dtmap's decks, one thread (bench/ccx_cost.py), for a mesh of %.0f "
           "elements: %s the switch at %.0f; ccx's bound of %d integration points per element%s",
           all, all > dtm_cost_ccx_switch() ? "beyond" : "below", dtm_cost_ccx_switch(), points,
           all_own ? "" : "; a type it lacks takes its nearest calibrated type");
  return DTM_OK;
}
