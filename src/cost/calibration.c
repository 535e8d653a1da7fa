/* What an element-step costs in time: the scene's own figure (<time
 * cost-per-element-step>, s) or dtmap's calibration against CalculiX 2.20
 * explicit dynamics on this project's bundled geometries, one thread
 * (bench/ccx_calibrate.py, table in docs/accuracy.md), per element type;
 * a mesh of several types takes the element-weighted mean. Types not
 * calibrated (bars, prisms, pyramids, serendipity types) take the figure of the
 * calibrated type of the same dimension with the closest node count (said
 * so in the source line). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/cost.h"
#include "dtmap/kernel.h"

/* ns per element-step, CalculiX 2.20, one thread (docs/accuracy.md). */
static const struct {
  int type;  /* element type */
  double ns; /* ns per element-step */
} calibrated[] = {{DTM_TET4, 1181}, {DTM_TET10, 3674}, {DTM_HEX8, 5577},
                  {DTM_TRI3, 3125}, {DTM_TRI6, 10519}, {DTM_QUAD4, 7180}};
#define NCAL (sizeof calibrated / sizeof calibrated[0])

/* The calibrated figure for type (ns), and whether it is the type's own. */
static double figure(int type, int *own) {
  int d, nn, dc, nc;
  *own = 1;
  for (size_t i = 0; i < NCAL; i++)
    if (calibrated[i].type == type) return calibrated[i].ns;
  *own = 0;
  if (dtm_elem_info(type, &d, &nn)) return NAN;
  double best = NAN;
  int gap = 1 << 30;
  for (size_t i = 0; i < NCAL; i++) {
    dtm_elem_info(calibrated[i].type, &dc, &nc);
    int g = dc == d ? abs(nc - nn) : 1000 + abs(nc - nn);
    if (g < gap) gap = g, best = calibrated[i].ns;
  }
  return best;
}

double dtm_cost_calibrated_ns(int type) {
  int own;
  return figure(type, &own);
}

int dtm_cost_per_element_step(const dtm_analysis *a, double *seconds, char *source, size_t len) {
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
    sum += figure(m->blocks[b].type, &own) * (double)m->blocks[b].n;
    n += m->blocks[b].n, all_own &= own;
  }
  *seconds = n ? sum / (double)n * 1e-9 : NAN;
  snprintf(source, len, "dtmap's CalculiX 2.20 explicit calibration, one thread (docs/accuracy.md)%s",
           all_own ? "" : "; a type it lacks takes its nearest calibrated type");
  return DTM_OK;
}
