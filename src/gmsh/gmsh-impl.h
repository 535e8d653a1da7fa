/* Private to src/gmsh/ (white-box tests may include it; nothing here is
 * exported): turning a non-zero ierr of the Gmsh C API into a dtmap error
 * that carries Gmsh's own last message (or the errors Gmsh only logged:
 * many input problems, a .geo syntax error or a .msh cut inside $Elements,
 * are logged as "Error: ..." with ierr = 0, so every call that reads user
 * input is bracketed by dtm_gmsh_log_reset() and DTM_GMSH_CHECK_LOG),
 * counting models, and the writers of the .msh view sections (msh_data.c). */
#ifndef DTM_GMSH_UTIL_H
#define DTM_GMSH_UTIL_H

#include <stddef.h>
#include <stdio.h>

#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/scene.h"

/* Raise DTM_ERR_INPUT or code with "<what>: <Gmsh's last error>". */
int dtm_gmsh_fail(int code, const char *file, int line, const char *func, const char *what);
#define DTM_GMSH_CHECK(ierr, code, what)                                                                               \
  do {                                                                                                                 \
    if (ierr) return dtm_gmsh_fail((code), __FILE__, __LINE__, __func__, (what));                                      \
  } while (0)

/* Number of models in the session: at least one once Gmsh is initialised,
 * none (silently) before gmshInitialize. */
int dtm_gmsh_model_count(void);
/* Cut the $Periodic section out of the .msh at path (src/gmsh/contain.c):
 * after a remesh Gmsh 4.8 writes periodic node pairs of a cleared mesh,
 * which crash it when the file is read back. */
int dtm_gmsh_strip_periodic(const char *path);
/* The .msh 4.1 format header ($MeshFormat ... $EndMeshFormat) of a file
 * that holds only views; 0, or -1 on a write error. */
int dtm_msh_header(FILE *f, int binary);
/* The records a view writes (the finite values only with finite_only). */
size_t dtm_msh_view_records(const dtm_view *v);
/* Append one view as $ElementData or $NodeData (msh_data.c), with the part
 * number of a partitioned result (0: none). */
int dtm_msh_write_view(FILE *f, const dtm_view *v, int binary, int partition);
/* Forget that the current model is a .msh as read (session.c): every
 * function that changes the model calls it first. */
void dtm_gmsh_source_clear(void);
/* The path of the .msh the current model was read from (dtm_gmsh_open),
 * while nothing has changed the model since; NULL else. */
const char *dtm_gmsh_source_unchanged(void);
/* The length of the mesh sections of the MSH 4.1 file src (up to its
 * first view) when they are the mesh Gmsh would write with dtmap's options
 * in the encoding binary (msh_copy.c says when); -1 else. */
long long dtm_msh_mesh_extent(const char *src, int binary);
/* The first n bytes of src into dst (created or emptied); a failed write
 * raises DTM_ERR_INPUT naming dst. */
int dtm_msh_copy_bytes(const char *src, const char *dst, long long n);
/* What a .msh file's headers say (msh_scan.c). */
typedef struct {
  double version;         /* $MeshFormat version (1 for MSH 1) */
  int binary;             /* file-type: 1 binary, 0 ASCII */
  int dsize;              /* data-size (sizeof size_t in MSH 4 binary files) */
  long long bytes;        /* size of the file */
  size_t nodes;           /* node count of $Nodes ($NOD) */
  size_t elements;        /* element count of $Elements ($ELM), all dimensions */
  int have_nodes;         /* the $Nodes header was found */
  int have_elements;      /* the $Elements header was found */
  char problem[160];      /* what Gmsh would crash on, "" when nothing */
  long long problem_line; /* its line */
} dtm_msh_head;
/* Scan path's headers into h: 0, or -1 when it cannot be read or is not a
 * .msh the scan understands (then Gmsh alone judges it). */
int dtm_msh_scan(const char *path, dtm_msh_head *h);

/* Nodes of MSH element type t (Gmsh's numbering, 1 to 31), 0 when not
 * listed (msh_scan.c). */
int dtm_msh_type_nodes(int t);

/* One $Elements block of an MSH 4.1 file (msh_read.c). */
typedef struct {
  int dim, tag, type; /* its entity and MSH element type */
  size_t n;           /* elements */
  size_t *tags;       /* [n] element tags (NULL once extraction took them) */
  size_t *conn;       /* [n nodes] node tags */
} dtm_msh_eblock;
/* The nodes and elements of an MSH 4.1 file, in the order Gmsh's C API
 * lists them (msh_read.c). */
typedef struct {
  size_t nnodes;
  size_t *node_tags; /* [nnodes] (NULL once taken) */
  double *xyz;       /* [3 nnodes] */
  int nblocks;
  dtm_msh_eblock *blocks; /* sorted by dtm_msh_block_order */
  size_t family[8];       /* elements of each family: point, line, triangle, quadrangle, tet, hex, prism, pyramid */
} dtm_msh_parsed;
/* Read path into *p: 0, or -1 (p empty) when the file is not an MSH 4.1
 * this reader takes on (or cannot be read): then Gmsh's listing is used. */
int dtm_msh_parse(const char *path, dtm_msh_parsed *p);
void dtm_msh_parsed_free(dtm_msh_parsed *p);
/* qsort/bsearch order of blocks: entity dimension, entity tag, type. */
int dtm_msh_block_order(const void *a, const void *b);
/* Reading path beside Gmsh (msh_beside.c): start a thread reading it
 * (dropping what an earlier reading kept), then join it once Gmsh has read
 * the file, keeping what it read when keep is set; drop forgets it. */
void dtm_msh_beside_start(const char *path);
void dtm_msh_beside_finish(int keep);
void dtm_msh_beside_drop(void);
/* The nodes and elements of the .msh the current model was read from, read
 * by dtmap beside Gmsh (session.c), when the model is still the file's and
 * its node and element counts agree with them: the caller owns *p (free it
 * with dtm_msh_parsed_free) and takes what it wants; 0 when there is none
 * (then list the model through Gmsh). */
int dtm_gmsh_parsed_take(dtm_msh_parsed *p);
/* Turn that reading beside Gmsh off (0) or on (1, the default); for tests
 * that compare it with Gmsh's listing. Returns how many readings were
 * taken so far. */
int dtm_gmsh_parsed_enable(int on);

/* The kill switches (budget.c): refuse, before Gmsh allocates, a .msh
 * whose headers promise more than the file holds or than the machine's
 * memory can take, and a geometry whose <meshing size> would give more
 * elements than the memory can take. DTM_ERR_INPUT naming the file (and
 * the scene line of <meshing>) with the figures. */
int dtm_gmsh_check_msh(const char *path);
int dtm_gmsh_check_meshing(const dtm_scene *s, int dim);
/* Refuse tags (of nodes or elements: what) going up to max_tag when the
 * views dtmap writes would need more memory than the machine has. */
int dtm_gmsh_check_tags(const char *src, const char *what, size_t max_tag, size_t count);

/* Forget what Gmsh has logged so far. */
void dtm_gmsh_log_reset(void);
/* fd >= 0: read Gmsh's messages from its terminal, the file at fd (where
 * its stdout and stderr go), from its present end, with the API logger
 * stopped, so that Gmsh may log from several threads; -1: from the API
 * logger again (restarted). */
void dtm_gmsh_log_terminal(int fd);
/* Raise code with "<what>: <the errors Gmsh logged since the last reset>"
 * (at most three, "; "-separated; Gmsh's last error, or ierr's, when none
 * was logged) when ierr is set or Gmsh logged an error; else DTM_OK. */
int dtm_gmsh_check_log(int ierr, int code, const char *file, int line, const char *func, const char *what);
#define DTM_GMSH_CHECK_LOG(ierr, code, what)                                                                           \
  do {                                                                                                                 \
    int dtm_glog_ = dtm_gmsh_check_log((ierr), (code), __FILE__, __LINE__, __func__, (what));                          \
    if (dtm_glog_) return dtm_glog_;                                                                                   \
  } while (0)

/* A meshing job on the current model, run in the child process of
 * dtm_gmsh_contained: a dtmap code (its error message is carried back). */
typedef int (*dtm_gmsh_job)(void *arg);
/* Run job in a forked child (contain.c) and give the current model the
 * mesh it made. stage names it in messages ("meshing", "remeshing after
 * round 1"). A crash of the child is DTM_ERR_INTERNAL "<stage>: Gmsh crashed
 * (signal N, name); its last messages: ..."; an error the job raised comes
 * back with its message, DTM_ERR_INPUT or DTM_ERR_INTERNAL. remesh: the
 * model had a mesh before (its periodic node pairs are not handed back).
 * The first mesh (remesh 0) of a supervised process is made in this
 * process instead (dtm_gmsh_contain), its crash the supervisor's to report. */
int dtm_gmsh_contained(const char *stage, dtm_gmsh_job job, void *arg, int remesh);
/* Run fn(arg) in this process with Gmsh's messages in the supervisor's
 * log (dtm_gmsh_contain), at info level; just fn(arg) without one. */
int dtm_gmsh_logged(dtm_gmsh_job fn, void *arg);
/* A probe of the current model run in a child: it fills out[nout], which
 * comes back to the caller; the caller's model is left as it was. */
typedef int (*dtm_gmsh_probe_job)(void *arg, double *out, size_t nout);
int dtm_gmsh_contained_probe(const char *stage, dtm_gmsh_probe_job probe, void *arg, double *out, size_t nout);

/* Whether view index's name is name (snapshot.c). */
int dtm_gmsh_view_is(int index, const char *name);
/* A partitioned model's elements back in their parent entities, its
 * user's physical groups kept (src/gmsh/unpartition.c); no-op otherwise. */
int dtm_gmsh_unpartition(void);
/* The camera of a snapshot of the model just opened, for a drawing area of
 * width x height pixels: an oblique view facing the worst elements for a
 * model that spans 3D, and the whole model framed between dtmap's text and
 * the colour scales (frame.c). Set through Gmsh's options, before its
 * window is created. */
void dtm_gmsh_snapshot_camera(int width, int height);
/* For a flat model, frame the worst elements instead (frame.c); 0 (the
 * camera unchanged) for a model that spans 3D or has no worst elements. */
int dtm_gmsh_snapshot_camera_worst(int width, int height);
/* Mark the worst element (the smallest value of the dt view) in the
 * current camera: a red ring around it and a tag with its element tag and
 * step, in a list-based view "worst element"; 1 when drawn. */
int dtm_gmsh_snapshot_mark_worst(int width, int height);

/* views.c: whether run's background writer has the model (dtm_gmsh_model_given); read under
 * dtm_gmsh_lock. */
int dtm_gmsh_model_is_given(void);

#endif
