/* The refine loop behind `dtmap refine`. The size suggestion of the current
 * mesh drives a fresh mesh of the same geometry as its only size source
 * (dtm_gmsh_remesh, with Gmsh's optimisers in 3D), and the new mesh is
 * analysed. The suggestion puts every node at the target, but a fresh mesh
 * has a spread of element shapes, and its worst nodes sit below its typical
 * ones (measured on Gmsh meshes of uniform size: the smallest nodal step is
 * about 0.78 of the median in 3D, 0.8 in 2D). The field is therefore the
 * suggestion times a calibration c: the first round uses that spread, and
 * each later one corrects c by the shortfall it measured,
 * c <- c (target / recommended)^(1/p) x 1.02, p the size exponent of the
 * effect that sets the step. */
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/progress.h"
#include "dtmap/refine.h"
#include "dtmap/util.h"

/* Size exponent of the effect whose step is the recommendation's basis. */
static double basis_exponent(const dtm_analysis *a) {
  int best = -1;
  for (int k = 0; k < dtm_analysis_neffects(a); k++)
    if (dtm_analysis_effect_dt(a, k) &&
        (best < 0 || dtm_analysis_effect_min(a, k)->safe < dtm_analysis_effect_min(a, best)->safe))
      best = k;
  return best >= 0 ? dtm_analysis_effect(a, best)->exponent : 1.0;
}

static double first_calibration(const dtm_analysis *a) {
  int dim = dtm_analysis_mesh(a)->dim;
  double spread = dim == 3 ? 0.78 : dim == 2 ? 0.8 : 1.0;
  return pow(1.0 / spread, 1.0 / basis_exponent(a));
}

static void record(const dtm_analysis *a, double seconds, dtm_refine_round *r) {
  *r =
      (dtm_refine_round){dtm_analysis_nelements(a), dtm_analysis_dt_min(a, NULL), dtm_analysis_recommended(a), seconds};
}

/* One remesh with calibration c and its analysis, replacing rr->analysis. */
static int refine_round(dtm_refine_result *rr, int dim, double c) {
  const dtm_analysis *a = rr->analysis;
  dtm_analysis *next = NULL;
  char stage[64];
  snprintf(stage, sizeof stage, "refine round %d", rr->nrounds);
  dtm_progress_begin(stage);
  int r = dtm_gmsh_remesh(dtm_analysis_mesh(a), dtm_analysis_size_suggestion(a), c, dim, rr->scene.mesh_order);
  if (r == DTM_OK) r = dtm_analysis_current(&rr->scene, dim, &next);
  dtm_progress_end();
  DTM_CHECK(r);
  dtm_analysis_destroy(&rr->analysis);
  rr->analysis = next;
  return DTM_OK;
}

static int refine_loop(dtm_refine_result *rr, int max_rounds) {
  double t0 = dtm_wtime(), target = rr->target;
  int dim;
  DTM_CHECK(dtm_gmsh_load(&rr->scene, &dim));
  DTM_CHECK(dtm_analysis_current(&rr->scene, dim, &rr->analysis));
  record(rr->analysis, dtm_wtime() - t0, &rr->rounds[rr->nrounds++]);
  double c = first_calibration(rr->analysis);
  while (dtm_analysis_recommended(rr->analysis) < target && rr->nrounds <= max_rounds) {
    t0 = dtm_wtime();
    double before = dtm_analysis_recommended(rr->analysis);
    if (rr->nrounds > 1) c *= 1.02 * pow(target / before, 1.0 / basis_exponent(rr->analysis));
    DTM_CHECK(refine_round(rr, dim, c));
    record(rr->analysis, dtm_wtime() - t0, &rr->rounds[rr->nrounds++]);
    if (dtm_analysis_recommended(rr->analysis) < 1.01 * before) break; /* no progress */
  }
  return DTM_OK;
}

int dtm_refine_run(const dtm_scene *s, double target, int max_rounds, dtm_refine_result **out) {
  if (!s->geometry) return DTM_ERR(DTM_ERR_INPUT, "%s: refine needs a <geometry>, not a <mesh>", s->path);
  dtm_refine_result *rr = calloc(1, sizeof *rr);
  if (!rr) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  rr->target = target;
  rr->scene = *s;
  rr->scene.target = target;
  if (max_rounds > DTM_REFINE_MAX_ROUNDS - 1) max_rounds = DTM_REFINE_MAX_ROUNDS - 1;
  int r = refine_loop(rr, max_rounds);
  if (r) {
    dtm_refine_destroy(&rr);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = rr;
  return DTM_OK;
}

void dtm_refine_destroy(dtm_refine_result **pr) {
  if (!*pr) return;
  dtm_analysis_destroy(&(*pr)->analysis);
  free(*pr);
  *pr = NULL;
}
