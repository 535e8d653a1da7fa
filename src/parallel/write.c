/* The outputs of a distributed run, all or nothing. Every rank writes its
 * part's mesh as soon as the part is extracted, into a temporary directory
 * rank 0 makes beside the output, and gives Gmsh's model of the part back
 * (it is not needed again); once the part is analysed and the global
 * figures gathered, it appends the views (they carry the part number, so
 * opening the parts together in Gmsh merges them into one view each; part
 * 1 also gets the .opt, with the whole mesh's figures), rank 0 writes the
 * report, and only when every rank succeeded are the files renamed into
 * place; otherwise every temporary is removed. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "dtmap/util.h"
#include "parallel-impl.h"

char *mkdtemp(char *);

static int same_file(const char *a, const char *b) {
  struct stat sa, sb;
  return a && b && !stat(a, &sa) && !stat(b, &sb) && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* A part's output must not be an input: the scene, its mesh, this part. */
static int check_output(const dtm_par *p, const char *path) {
  const dtm_scene *s = p->scene;
  if (same_file(path, s->path) || same_file(path, p->part_path) ||
      (!s->partitions && same_file(path, s->mesh ? s->mesh : s->geometry)))
    return DTM_ERR(DTM_ERR_INPUT, "%s: refusing to overwrite an input file; choose another output with -o", path);
  return DTM_OK;
}

static int make_dir(dtm_par *p, const char *out) {
  dtm_par_outputs *w = &p->out;
  const char *slash = strrchr(out, '/');
  int r = DTM_OK;
  if (p->rank == 0) {
    snprintf(w->dir, sizeof w->dir, "%.*s.dtmap-out-XXXXXX", slash ? (int)(slash - out + 1) : 0, out);
    if (!mkdtemp(w->dir)) r = DTM_ERR(DTM_ERR_INPUT, "%s: cannot create a directory beside the output", w->dir);
  }
  r = dtm_par_agree(p, r);
  MPI_Bcast(w->dir, (int)sizeof w->dir, MPI_CHAR, 0, p->comm);
  if (r) w->dir[0] = '\0';
  return r;
}

/* This rank's part: its names, and its mesh written (binary above
 * DTM_BINARY_ABOVE elements, as a serial run's). */
static int begin_part(dtm_par *p, const dtm_parallel_opts *o) {
  dtm_par_outputs *w = &p->out;
  DTM_CHECK(dtm_scene_part_path(o->out, p->rank + 1, w->mesh, sizeof w->mesh));
  DTM_CHECK(check_output(p, w->mesh));
  const char *base = strrchr(w->mesh, '/');
  snprintf(w->mesh_tmp, sizeof w->mesh_tmp, "%s/%s", w->dir, base ? base + 1 : w->mesh);
  snprintf(w->opt, sizeof w->opt, "%s.opt", w->mesh);
  snprintf(w->opt_tmp, sizeof w->opt_tmp, "%s.opt", w->mesh_tmp);
  dtm_output_opts oo = {o->format, o->views_only, &p->outpart, 0};
  p->outpart.part = p->rank + 1;
  return dtm_output_begin(&p->part, w->mesh_tmp, &oo, dtm_mesh_nelements(p->mesh), &w->file);
}

int dtm_par_write_begin(dtm_par *p, const dtm_parallel_opts *o) {
  double t0 = dtm_wtime();
  int r = make_dir(p, o->out);
  if (r == DTM_OK) r = dtm_par_agree(p, begin_part(p, o));
  if (r == DTM_OK) dtm_gmsh_release(); /* the part's mesh is extracted and written */
  p->t[PAR_T_OUTPUT] = dtm_wtime() - t0;
  return r;
}

static int write_report(dtm_par *p, const dtm_parallel_opts *o, const dtm_par_figures *f) {
  char *json = NULL;
  int r = p->rank == 0 ? dtm_par_report(p, o, f, &json) : DTM_OK;
  if (r == DTM_OK && json) {
    snprintf(p->out.report_tmp, sizeof p->out.report_tmp, "%s.dtmap-tmp", o->report);
    r = dtm_atomic_write_text(p->out.report_tmp, json, 1);
  }
  free(json);
  return r;
}

static int commit(const dtm_par_outputs *w, const char *report) {
  if (rename(w->mesh_tmp, w->mesh) || (!access(w->opt_tmp, F_OK) && rename(w->opt_tmp, w->opt)))
    return DTM_ERR(DTM_ERR_INPUT, "%s: cannot move the part into place", w->mesh);
  if (w->report_tmp[0] && rename(w->report_tmp, report))
    return DTM_ERR(DTM_ERR_INPUT, "%s: cannot move the report into place", report);
  return DTM_OK;
}

int dtm_par_write_finish(dtm_par *p, const dtm_parallel_opts *o, dtm_par_figures *f) {
  dtm_results res = {p->analysis, p->cost, NULL, o->t_scene, 0.0, o->top, 0, {NULL}, {NULL}, NULL, NULL};
  int r = dtm_par_collect(p, f); /* the views and the .opt take the whole mesh's figures */
  double t0 = dtm_wtime();
  if (r == DTM_OK) r = dtm_par_agree(p, dtm_output_finish(&p->out.file, &res));
  p->t[PAR_T_OUTPUT] += dtm_wtime() - t0;
  if (r == DTM_OK) r = dtm_par_collect_rows(p, f);
  if (r == DTM_OK && o->report) r = dtm_par_agree(p, write_report(p, o, f));
  if (r == DTM_OK) r = dtm_par_agree(p, commit(&p->out, o->report));
  return r;
}

void dtm_par_write_cleanup(dtm_par *p) {
  dtm_par_outputs *w = &p->out;
  dtm_output_abort(&w->file);
  if (w->mesh_tmp[0]) unlink(w->mesh_tmp), unlink(w->opt_tmp);
  if (w->report_tmp[0]) unlink(w->report_tmp);
}

void dtm_par_write_remove_dir(dtm_par *p) {
  if (!p->out.dir[0]) return;
  MPI_Barrier(p->comm); /* every rank has moved or removed its files */
  if (p->rank == 0) rmdir(p->out.dir);
  p->out.dir[0] = '\0';
}
