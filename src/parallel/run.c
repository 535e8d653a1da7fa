/* dtm_parallel_run: one rank's whole distributed run. Start MPI, PETSc,
 * SLEPc and Gmsh; read this rank's part (load.c) and write its mesh
 * (write.c; Gmsh's model is then released); find how the parts meet and
 * renumber the part's nodes (layout.c); create the scene's effects and
 * analyse the part with an exchange to the others (the analysis module's
 * distributed interface), the global estimate, and classify the elements
 * below the target on rank 0's whole mesh and model
 * (dtm_analysis_classify_whole), then the cost; write the
 * views, the report and the summary (write.c, summary.c). Every step ends
 * in an agreement, so all ranks stop together; only the rank where an
 * error arose keeps it to print. */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include <mpi.h>

#include "parallel-impl.h"

/* The distributed global estimate holds three unknowns per node: shells
 * and beams (three more, rotations) are not in it yet. A scene-level
 * check: rank 0 raises it (the agreement stops the others) and prints it
 * once. */
static int posterior_supported(const dtm_par *p, const dtm_parallel_opts *o) {
  for (int i = 0; o->posterior && p->rank == 0 && i < p->scene->nsections; i++)
    if (dtm_section_has_rotations(p->scene->sections[i].kind))
      return DTM_ERR(DTM_ERR_INPUT,
                     "%s:%d: --posterior in a distributed run does not take %s sections yet (their nodes carry "
                     "rotations); run without --posterior (the nodal bound covers them), or serially",
                     p->scene->path, p->scene->sections[i].line, dtm_section_kind_name(p->scene->sections[i].kind));
  return DTM_OK;
}

static int analyse(dtm_par *p, const dtm_parallel_opts *o) {
  dtm_effect *e = NULL;
  int ne = 0, r = dtm_par_agree(p, posterior_supported(p, o));
  if (r) return r;
  r = dtm_par_agree(p, dtm_effects_create(&p->part, p->mesh, &e, &ne));
  if (r) return dtm_effects_destroy(&e, ne), r;
  dtm_par_exchange_init(p);
  r = dtm_analysis_compute_shared(&p->part, p->mesh, e, ne, &p->x, &p->analysis);
  if (r) p->mesh = NULL;           /* the analysis took the mesh and the effects, and freed them */
  if (r == DTM_OK && o->posterior) /* first: on the global basis the advice holds the steps to another target */
    r = dtm_analysis_estimate_global(p->analysis, o->tol, o->max_products, DTM_GLOBAL_BASIS);
  if (r == DTM_OK) r = dtm_analysis_classify_whole(p->analysis, &p->whole, &p->whole_geo, &p->advice);
  if (r == DTM_OK) r = dtm_par_agree(p, dtm_cost_create(p->analysis, &p->cost));
  if (r == DTM_OK) r = dtm_analysis_share_advice(p->analysis, p->advice); /* the parts' views mark them */
  if (p->analysis) {
    p->t[PAR_T_EFFECTS] = dtm_analysis_timing(p->analysis, DTM_T_EFFECTS);
    p->t[PAR_T_NODAL] = dtm_analysis_timing(p->analysis, DTM_T_NODAL);
    p->t[PAR_T_GLOBAL] = dtm_analysis_timing(p->analysis, DTM_T_GLOBAL);
  }
  return r;
}

static int run(dtm_par *p, const dtm_parallel_opts *o) {
  dtm_par_figures f = {0};
  int r = dtm_par_agree(p, dtm_gmsh_start(o->verbosity > 1 ? 2 : 0));
  if (r == DTM_OK) r = dtm_par_load(p, o->out);
  if (r == DTM_OK) r = dtm_par_write_begin(p, o);
  double t0 = dtm_wtime();
  if (r == DTM_OK) r = dtm_par_layout(p);
  p->t[PAR_T_LAYOUT] = dtm_wtime() - t0;
  if (r == DTM_OK) r = analyse(p, o);
  if (r == DTM_OK) r = dtm_par_write_finish(p, o, &f);
  if (r == DTM_OK) dtm_par_summary(p, o, &f);
  dtm_par_write_cleanup(p);
  dtm_par_write_remove_dir(p);
  dtm_par_figures_free(&f);
  dtm_gmsh_stop();
  return r;
}

int dtm_parallel_run(const dtm_scene *s, const dtm_parallel_opts *o) {
  dtm_par p;
  memset(&p, 0, sizeof p);
  p.scene = s;
  p.top = o->top;
  p.mesher = (dtm_mesher_info){0, 0, 1}; /* the parts are read from files */
  omp_set_num_threads(o->threads > 0 ? o->threads : 1);
  int r = dtm_par_init(&p);
  if (r == DTM_OK) r = run(&p, o);
  dtm_cost_destroy(&p.cost);
  dtm_analysis_destroy(&p.advice);
  dtm_mesh_destroy(&p.whole);
  dtm_gmsh_geo_destroy(&p.whole_geo);
  if (p.analysis)
    dtm_analysis_destroy(&p.analysis); /* and the mesh it owns */
  else
    dtm_mesh_destroy(&p.mesh);
  dtm_par_layout_destroy(&p);
  if (r && p.quiet) dtm_error_clear(); /* another rank prints it */
  return r;
}

void dtm_parallel_finish(void) {
  int up = 0, done = 0;
  MPI_Initialized(&up);
  MPI_Finalized(&done);
  if (up && !done) MPI_Barrier(MPI_COMM_WORLD);
  dtm_par_finalize();
}
