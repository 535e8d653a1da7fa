/* What an element-step costs in time: the scene's own figure (<time
 * cost-per-element-step>, s) or Debian's CalculiX 2.20 explicit dynamics
 * measured on dtmap's own decks, one thread, per CalculiX element
 * (bench/ccx_cost.py writes ccx_cost.inc; docs/accuracy.md), each dtmap
 * type taking its CalculiX element's figure (2D: plane strain);
 * a mesh of several types takes the element-weighted mean. Each figure
 * holds for a mesh of the measured size: ccx's arrays of a mesh below the
 * switch (ccx_cost.inc, in elements, measured on C3D4: about 25,000) stay in
 * the processor's cache, a larger mesh's do not, and its element-steps
 * cost about twice as much (the second figure, measured on a mesh beyond
 * it), so the figure is chosen by the mesh's element count. Types not
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

/* The calibrated figure for type (ns) in a mesh of that many elements,
 * and whether it is the type's own. */
static double figure(int type, double elements, int *own) {
  int d, nn, dc, nc;
  *own = 1;
  for (size_t i = 0; i < NCAL; i++)
    if (calibrated[i].type == type) return dtm_cost_ccx_ns(calibrated[i].elem, elements);
  *own = 0;
  if (dtm_elem_info(type, &d, &nn)) return NAN;
  double best = NAN;
  int gap = 1 << 30;
  for (size_t i = 0; i < NCAL; i++) {
    dtm_elem_info(calibrated[i].type, &dc, &nc);
    int g = dc == d ? abs(nc - nn) : 1000 + abs(nc - nn);
    if (g < gap) gap = g, best = dtm_cost_ccx_ns(calibrated[i].elem, elements);
  }
  return best;
}

double dtm_cost_calibrated_ns(int type, double elements) {
  int own;
  return figure(type, elements, &own);
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
  for (int b = 0; b < m->nblocks; b++) {
    sum += figure(m->blocks[b].type, all, &own) * (double)m->blocks[b].n;
    n += m->blocks[b].n, all_own &= own;
  }
  *seconds = n ? sum / (double)n * 1e-9 : NAN;
  snprintf(source, len,
           "CalculiX 2.20 explicit, measured on dtmap's decks, one thread (bench/ccx_cost.py), for a mesh of %.0f "
           "elements: %s the switch at %.0f%s",
           all, all > dtm_cost_ccx_switch() ? "beyond" : "below", dtm_cost_ccx_switch(),
           all_own ? "" : "; a type it lacks takes its nearest calibrated type");
  return DTM_OK;
}
