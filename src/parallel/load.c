/* Each rank's part of the mesh. A scene of partition files
 * (<mesh partitions="P">) gives every rank its own file; a scene of one
 * mesh or geometry is loaded (meshed) by rank 0 alone, partitioned by
 * Gmsh with METIS and written as binary part files into a temporary
 * directory beside the output (visible to every rank wherever the output
 * is), which is removed once the parts are read; rank 0 keeps the whole
 * mesh and where it sits on the model, for the advice on the elements
 * below the target (dtm_analysis_classify_whole). A rank then opens only
 * its part through Gmsh, checks that the file holds that partition of a
 * split into as many parts as there are ranks, and extracts it. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "dtmap/gmsh.h"
#include "parallel-impl.h"

char *mkdtemp(char *);

static int check_count(const dtm_par *p) {
  const dtm_scene *s = p->scene;
  if (!s->partitions || s->partitions == p->size) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT, "%s:%d: the mesh is %d part files, but %d rank%s run: use mpirun -n %d", s->path,
                 s->source_line, s->partitions, p->size, p->size > 1 ? "s" : "", s->partitions);
}

/* Rank 0: load or mesh the scene's source, split it into the ranks' parts. */
static int split_source(dtm_par *p, const char *out) {
  const char *slash = strrchr(out, '/');
  char path[4200];
  int dim;
  snprintf(p->tmpdir, sizeof p->tmpdir, "%.*s.dtmap-parts-XXXXXX", slash ? (int)(slash - out + 1) : 0, out);
  if (!mkdtemp(p->tmpdir)) {
    int r = DTM_ERR(DTM_ERR_INPUT, "%s: cannot create a directory for the parts beside the output", p->tmpdir);
    p->tmpdir[0] = '\0';
    return r;
  }
  DTM_CHECK(dtm_gmsh_load(p->scene, &dim));
  dtm_gmsh_mesher(&p->mesher); /* for the report: how rank 0 got the mesh */
  DTM_CHECK(dtm_analysis_extract_whole(p->scene, dim, &p->whole, &p->whole_geo)); /* for the advice */
  snprintf(path, sizeof path, "%s/part.msh", p->tmpdir);
  return dtm_gmsh_partition_write(p->size, path);
}

/* The other ranks wait for rank 0's split without spinning on the cores
 * it meshes with (oversubscribed runs): a non-blocking broadcast of its
 * status and directory, polled every millisecond. */
static int split_and_wait(dtm_par *p, const char *out) {
  struct {
    int status;
    char dir[sizeof p->tmpdir];
  } msg = {DTM_OK, ""};
  MPI_Request req;
  int done = 0;
  if (p->rank == 0) msg.status = split_source(p, out), memcpy(msg.dir, p->tmpdir, sizeof msg.dir);
  MPI_Ibcast(&msg, (int)sizeof msg, MPI_BYTE, 0, p->comm, &req);
  struct timespec ms = {0, 1000000};
  while (MPI_Test(&req, &done, MPI_STATUS_IGNORE) == MPI_SUCCESS && !done) nanosleep(&ms, NULL);
  if (!done) MPI_Wait(&req, MPI_STATUS_IGNORE);
  memcpy(p->tmpdir, msg.dir, sizeof msg.dir);
  return dtm_par_agree(p, msg.status);
}

/* Where this rank's part is (rank 0 splits a one-mesh scene first). */
static int locate_part(dtm_par *p, const char *out) {
  int r = dtm_par_agree_alike(p, check_count(p));
  if (r == DTM_OK && !p->scene->partitions) r = split_and_wait(p, out);
  if (r) return r;
  if (p->scene->partitions) return dtm_scene_part_path(p->scene->mesh, p->rank + 1, p->part_path, sizeof p->part_path);
  snprintf(p->part_path, sizeof p->part_path, "%s/part_%d.msh", p->tmpdir, p->rank + 1);
  return DTM_OK;
}

/* The file must hold partition rank + 1 of a split into p->size parts. */
static int check_partition(const dtm_par *p, int dim) {
  int part, maxpart;
  DTM_CHECK(dtm_gmsh_partition_info(dim, &part, &maxpart));
  if (part == 0 && p->size == 1) return DTM_OK; /* one part: the whole mesh is it */
  if (part == 0)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s: not a part file (no partition entities); write the parts with Gmsh, e.g. "
                   "gmsh model.msh -part %d -part_split -part_no_topo -save -o model.msh",
                   p->part_path, p->size);
  if (part != p->rank + 1)
    return DTM_ERR(DTM_ERR_INPUT, "%s: holds %s, not partition %d of the mesh", p->part_path,
                   part < 0 ? "several partitions" : "another partition", p->rank + 1);
  if (maxpart > p->size)
    return DTM_ERR(DTM_ERR_INPUT, "%s: is a part of a mesh split into at least %d parts, not %d", p->part_path, maxpart,
                   p->size);
  return DTM_OK;
}

static int open_part(dtm_par *p) {
  const dtm_scene *s = p->scene;
  if (access(p->part_path, R_OK))
    return DTM_ERR(DTM_ERR_INPUT, "mesh part file '%s' not found or not readable (part %d of %d%s%s:%d)", p->part_path,
                   p->rank + 1, p->size, s->partitions ? ", <mesh> of " : ", written from ",
                   s->partitions ? s->path : (s->mesh ? s->mesh : s->geometry), s->partitions ? s->source_line : 0);
  p->part = *s;
  p->part.mesh = p->part_path, p->part.geometry = NULL, p->part.partitions = 0;
  DTM_CHECK(dtm_gmsh_load(&p->part, &p->dim));
  return check_partition(p, p->dim);
}

/* Every part must be of the dimension the others are. */
static int same_dim(dtm_par *p) {
  int lo = 0, hi = 0;
  MPI_Allreduce(&p->dim, &lo, 1, MPI_INT, MPI_MIN, p->comm);
  MPI_Allreduce(&p->dim, &hi, 1, MPI_INT, MPI_MAX, p->comm);
  if (lo == hi) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT, "%s: a %dD mesh, while other parts are %dD", p->part_path, p->dim,
                 p->dim == lo ? hi : lo);
}

int dtm_par_load(dtm_par *p, const char *out) {
  double t0 = dtm_wtime();
  int r = locate_part(p, out);
  if (r == DTM_OK) r = dtm_par_agree(p, open_part(p));
  if (r == DTM_OK) r = dtm_par_agree(p, same_dim(p));
  p->t[PAR_T_READ] = dtm_wtime() - t0;
  if (r == DTM_OK) r = dtm_par_agree(p, dtm_analysis_extract(&p->part, p->dim, &p->mesh, &p->t[PAR_T_EXTRACT]));
  dtm_par_load_cleanup(p);
  return r;
}

void dtm_par_load_cleanup(dtm_par *p) {
  if (!p->tmpdir[0]) return;
  MPI_Barrier(p->comm); /* every rank has read its part */
  for (int k = 1; p->rank == 0 && k <= p->size; k++) {
    char path[4200];
    snprintf(path, sizeof path, "%s/part_%d.msh", p->tmpdir, k);
    unlink(path);
  }
  if (p->rank == 0) rmdir(p->tmpdir);
  p->tmpdir[0] = '\0';
}
