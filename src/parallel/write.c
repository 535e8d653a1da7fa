/* The outputs of a distributed run, all or nothing: every rank writes its
 * part's mesh with its views (dtm_output_write_part: the views carry the
 * part number, so opening the parts together in Gmsh merges them into one
 * view each) into a temporary directory beside the output, the global
 * figures are gathered (with
 * the output times), rank 0 writes the report likewise, and only when
 * every rank succeeded are they renamed into place; otherwise every
 * temporary is removed. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

/* The temporaries: the part's mesh (+ .opt) under its own name in a
 * directory rank 0 makes beside the output, and rank 0's report. */
typedef struct {
  char dir[4096];                     /* the temporary directory, "" until made */
  char mesh[4096], opt[4200];         /* where the part goes */
  char mesh_tmp[8200], opt_tmp[8300]; /* where it is written first */
  char report_tmp[4200];              /* the report's temporary, "" if none */
} outputs;

static int make_dir(dtm_par *p, const char *out, outputs *w) {
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

static int write_part(dtm_par *p, const dtm_parallel_opts *o, outputs *w) {
  DTM_CHECK(dtm_scene_part_path(o->out, p->rank + 1, w->mesh, sizeof w->mesh));
  DTM_CHECK(check_output(p, w->mesh));
  const char *base = strrchr(w->mesh, '/');
  snprintf(w->mesh_tmp, sizeof w->mesh_tmp, "%s/%s", w->dir, base ? base + 1 : w->mesh);
  snprintf(w->opt, sizeof w->opt, "%s.opt", w->mesh);
  snprintf(w->opt_tmp, sizeof w->opt_tmp, "%s.opt", w->mesh_tmp);
  dtm_results res = {p->analysis, p->cost, NULL, o->t_scene, 0.0};
  return dtm_output_write_part(&res, w->mesh_tmp, p->rank + 1);
}

static int write_report(const dtm_par *p, const dtm_parallel_opts *o, const dtm_par_figures *f, outputs *w) {
  char *json = NULL;
  int r = p->rank == 0 ? dtm_par_report(p, o, f, &json) : DTM_OK;
  if (r == DTM_OK && json) {
    snprintf(w->report_tmp, sizeof w->report_tmp, "%s.dtmap-tmp", o->report);
    r = dtm_atomic_write_text(w->report_tmp, json, 1);
  }
  free(json);
  return r;
}

static int commit(const outputs *w, const char *report) {
  if (rename(w->mesh_tmp, w->mesh) || rename(w->opt_tmp, w->opt))
    return DTM_ERR(DTM_ERR_INPUT, "%s: cannot move the part into place", w->mesh);
  if (w->report_tmp[0] && rename(w->report_tmp, report))
    return DTM_ERR(DTM_ERR_INPUT, "%s: cannot move the report into place", report);
  return DTM_OK;
}

static void discard(const outputs *w) {
  if (w->mesh_tmp[0]) unlink(w->mesh_tmp), unlink(w->opt_tmp);
  if (w->report_tmp[0]) unlink(w->report_tmp);
}

static void remove_dir(dtm_par *p, const outputs *w) {
  if (!w->dir[0]) return;
  MPI_Barrier(p->comm); /* every rank has moved or removed its files */
  if (p->rank == 0) rmdir(w->dir);
}

int dtm_par_write(dtm_par *p, const dtm_parallel_opts *o, dtm_par_figures *f) {
  outputs w;
  memset(&w, 0, sizeof w);
  double t0 = dtm_wtime();
  int r = make_dir(p, o->out, &w);
  if (r == DTM_OK) r = dtm_par_agree(p, write_part(p, o, &w));
  p->t[PAR_T_OUTPUT] = dtm_wtime() - t0;
  if (r == DTM_OK) r = dtm_par_collect(p, f);
  if (r == DTM_OK && o->report) r = dtm_par_agree(p, write_report(p, o, f, &w));
  if (r == DTM_OK) r = dtm_par_agree(p, commit(&w, o->report));
  if (r) discard(&w);
  remove_dir(p, &w);
  return r;
}
