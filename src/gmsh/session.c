/* Gmsh session: start/stop or attach to a session a script opened, error
 * translation (ierr and the errors Gmsh only logs), the versions, and
 * loading the scene's geometry (meshed here with the scene's <meshing>
 * options) or .msh. */
#include <gmshc.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dtmap/gmsh.h"
#include "dtmap/progress.h"
#include "gmsh-impl.h"

int dtm_gmsh_fail(int code, const char *file, int line, const char *func, const char *what) {
  char *msg = NULL;
  int ierr = 0;
  gmshLoggerGetLastError(&msg, &ierr);
  int r = dtm_error_raise(code, file, line, func, "%s: %s", what, (msg && msg[0]) ? msg : "Gmsh reported an error");
  if (msg) gmshFree(msg);
  return r;
}

/* Where Gmsh's messages are read: its API logger, or (terminal >= 0) its
 * terminal, the file at that descriptor, from byte `from` on. The API
 * logger appends to one vector without a lock, so messages logged from
 * OpenMP threads (curves and surfaces meshed in parallel) corrupt it; its
 * terminal is written a whole line at a time under stdio's lock. */
static int terminal = -1;
static off_t terminal_from;

static off_t terminal_end(void) {
  struct stat st;
  fflush(NULL);
  return fstat(terminal, &st) ? 0 : st.st_size;
}

void dtm_gmsh_log_terminal(int fd) {
  int ierr = 0;
  if (fd >= 0 && terminal < 0) gmshLoggerStop(&ierr);
  if (fd < 0 && terminal >= 0) gmshLoggerStart(&ierr);
  terminal = fd;
  if (fd >= 0) terminal_from = terminal_end();
}

void dtm_gmsh_log_reset(void) {
  int ierr = 0;
  if (terminal >= 0) {
    terminal_from = terminal_end();
    return;
  }
  gmshLoggerStop(&ierr);
  gmshLoggerStart(&ierr);
}

/* Add error text to buf[len] ("; "-separated), the first three. */
static void add_error(char *buf, size_t len, int *count, const char *text) {
  size_t used = strlen(buf);
  if ((*count)++ < 3) snprintf(buf + used, len - used, "%s%s", used ? "; " : "", text);
}

/* The "Error   : " lines Gmsh wrote to its terminal since the reset,
 * without its summary of the counts (a block between two lines of dashes,
 * which Gmsh writes to its terminal only, not to its logger). */
static int terminal_errors(char *buf, size_t len) {
  static const char prefix[] = "Error   : ";
  char line[1024];
  int count = 0, summary = 0, copy = dup(terminal);
  FILE *in = copy >= 0 ? fdopen(copy, "r") : NULL;
  if (!in) {
    if (copy >= 0) close(copy);
    return 0;
  }
  fflush(NULL);
  fseeko(in, terminal_from, SEEK_SET);
  while (fgets(line, sizeof line, in)) {
    char *text = line + sizeof prefix - 1;
    if (strncmp(line, prefix, sizeof prefix - 1)) continue;
    text[strcspn(text, "\r\n")] = '\0';
    if (text[0] == '-' && !text[strspn(text, "-")])
      summary = !summary;
    else if (!summary)
      add_error(buf, len, &count, text);
  }
  fclose(in);
  return count;
}

/* Up to three "Error: " lines of the log, without the prefix, into buf;
 * returns how many the log holds. */
static int logged_errors(char *buf, size_t len) {
  char **log = NULL;
  size_t n = 0;
  int ierr = 0, count = 0;
  static const char prefix[] = "Error: ";
  buf[0] = '\0';
  if (terminal >= 0) return terminal_errors(buf, len);
  gmshLoggerGet(&log, &n, &ierr);
  for (size_t i = 0; i < n; i++) {
    if (!strncmp(log[i], prefix, sizeof prefix - 1)) add_error(buf, len, &count, log[i] + sizeof prefix - 1);
    gmshFree(log[i]);
  }
  gmshFree(log);
  return count;
}

int dtm_gmsh_check_log(int ierr, int code, const char *file, int line, const char *func, const char *what) {
  char errors[2048];
  int n = logged_errors(errors, sizeof errors);
  if (!n && !ierr) return DTM_OK;
  if (!n) return dtm_gmsh_fail(code, file, line, func, what);
  return dtm_error_raise(code, file, line, func, "%s: %s%s", what, errors, n > 3 ? " (and more)" : "");
}

/* Gmsh sets OpenMP's thread count from General.NumThreads (1 by default)
 * when it starts and when it meshes. Gmsh meshes with the threads the scene
 * or the geometry file asks for (mesher.c; one unless they say otherwise,
 * so that the same scene gives the same numbering); dtmap's own loops get
 * back the caller's count (all cores, or -j). */
static int dtm_threads = 1;

void dtm_gmsh_restore_threads(void) { omp_set_num_threads(dtm_threads); }

void dtm_gmsh_serial(void) {
  int ierr = 0;
  gmshOptionSetNumber("General.NumThreads", 1, &ierr);
  omp_set_num_threads(1);
}

int dtm_gmsh_start(int verbosity) {
  int ierr = 0;
  dtm_threads = omp_get_max_threads();
  gmshInitialize(0, NULL, 0, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot initialise Gmsh");
  gmshOptionSetNumber("General.AbortOnError", 0, &ierr);
  gmshOptionSetNumber("General.Terminal", verbosity > 0 ? 1 : 0, &ierr);
  gmshOptionSetNumber("General.Verbosity", verbosity > 1 ? 5 : verbosity > 0 ? 2 : 1, &ierr);
  dtm_gmsh_restore_threads();
  gmshLoggerStart(&ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot configure Gmsh");
  return DTM_OK;
}

void dtm_gmsh_stop(void) {
  int ierr = 0;
  gmshFinalize(&ierr);
}

int dtm_gmsh_model_count(void) {
  char **names = NULL;
  size_t n = 0;
  int ierr = 0;
  gmshModelList(&names, &n, &ierr);
  for (size_t i = 0; i < n; i++) gmshFree(names[i]);
  gmshFree(names);
  return ierr ? 0 : (int)n;
}

/* Gmsh 4.8 has no query for it, but an initialised Gmsh always has a model. */
static int is_initialized(void) { return dtm_gmsh_model_count() > 0; }

int dtm_gmsh_attach(int threads) {
  if (!is_initialized())
    return DTM_ERR(DTM_ERR_INPUT, "Gmsh is not initialised: call gmsh.initialize() and build or open a model first");
  dtm_threads = threads > 0 ? threads : omp_get_num_procs();
  dtm_gmsh_restore_threads();
  return DTM_OK;
}

int dtm_gmsh_version(char *buf, size_t len, const char **api) {
  int ierr = 0, own = !is_initialized();
  char *v = NULL;
  if (own) gmshInitialize(0, NULL, 0, &ierr);
  DTM_GMSH_CHECK(ierr, DTM_ERR_INTERNAL, "cannot initialise Gmsh");
  gmshOptionGetString("General.Version", &v, &ierr);
  snprintf(buf, len, "%s", !ierr && v ? v : "unknown");
  gmshFree(v);
  if (own) gmshFinalize(&ierr);
  if (api) *api = GMSH_API_VERSION;
  return DTM_OK;
}

/* What the meshing job does (contain.c): mesh, then raise the order. */
typedef struct {
  const dtm_scene *s; /* the scene */
  int dim;            /* dimension to mesh */
} geometry_job;

static int mesh_job(void *arg) {
  const geometry_job *j = arg;
  int ierr = 0;
  char what[4200];
  snprintf(what, sizeof what, "%s: Gmsh cannot mesh it", j->s->geometry);
  dtm_gmsh_log_reset();
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshModelMeshGenerate(j->dim, &ierr);
  DTM_GMSH_CHECK_LOG(ierr, DTM_ERR_INPUT, what);
  if (j->s->mesh_order > 1) {
    gmshModelMeshSetOrder(j->s->mesh_order, &ierr);
    DTM_GMSH_CHECK_LOG(ierr, DTM_ERR_INPUT, what);
  }
  return DTM_OK;
}

/* Mesh the geometry contained (a child process, or this one when a
 * supervisor contains it: contain.c), so that a crash inside Gmsh is an
 * error with its signal and Gmsh's last messages, not dtmap's end. */
static int mesh_geometry(const dtm_scene *s, int dim) {
  int ierr = 0;
  geometry_job j = {s, dim};
  if (s->mesh_size > 0) gmshOptionSetNumber("Mesh.MeshSizeMax", s->mesh_size, &ierr);
  if (s->mesh_min_size > 0) gmshOptionSetNumber("Mesh.MeshSizeMin", s->mesh_min_size, &ierr);
  dtm_gmsh_mesher_apply(s); /* the scene's algorithm and threads, else the geometry file's */
  dtm_progress_begin("meshing");
  int r = dtm_gmsh_contained("meshing", mesh_job, &j, 0);
  dtm_progress_end();
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_gmsh_load(const dtm_scene *s, int *dim) {
  if (s->model)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s:%d: <model/> stands for the current Gmsh model of a program that builds it (the Python "
                   "module's dtmap.analyse); the command line needs <geometry file=...> or <mesh file=...>",
                   s->path, s->source_line);
  const char *src = s->mesh ? s->mesh : s->geometry;
  int d;
  DTM_CHECK(dtm_gmsh_units_before(s, src));
  int r = dtm_gmsh_open(src, &d), ru = dtm_gmsh_units_after(src);
  DTM_CHECK(r ? r : ru);
  if (s->mesh_dim > 0) d = s->mesh_dim;
  if (s->mesh) dtm_gmsh_mesher_read();
  if (!s->mesh) DTM_CHECK(dtm_gmsh_check_meshing(s, d));
  if (!s->mesh) DTM_CHECK(mesh_geometry(s, d));
  dtm_gmsh_restore_threads();
  *dim = d;
  return DTM_OK;
}

/* Gmsh reads the file (in the supervisor's log: dtm_gmsh_logged). */
typedef struct {
  const char *path; /* the file */
  int ierr;         /* Gmsh's error code */
} open_job;

static int open_file(void *arg) {
  open_job *j = arg;
  gmshOpen(j->path, &j->ierr);
  return DTM_OK;
}

/* The .msh the current model was read from, while it is unchanged
 * (dtm_gmsh_source_clear); "" else. */
static char source[4096];

void dtm_gmsh_source_clear(void) {
  source[0] = '\0';
  dtm_msh_beside_drop();
}

const char *dtm_gmsh_source_unchanged(void) { return source[0] ? source : NULL; }

static int is_msh_path(const char *p) {
  size_t n = strlen(p);
  return n > 4 && !strcasecmp(p + n - 4, ".msh");
}

int dtm_gmsh_open(const char *path, int *dim) {
  int ierr = 0;
  open_job j = {path, 0};
  char what[4200];
  snprintf(what, sizeof what, "%s: Gmsh cannot read it", path);
  dtm_gmsh_source_clear();
  DTM_CHECK(dtm_gmsh_check_msh(path)); /* only .msh files are scanned */
  gmshClear(&ierr);
  dtm_gmsh_mesher_defaults();
  dtm_gmsh_log_reset();
  dtm_progress_begin("reading");
  if (is_msh_path(path)) dtm_msh_beside_start(path); /* its nodes and elements, on a thread of dtmap's */
  dtm_gmsh_logged(open_file, &j);
  dtm_progress_end();
  int r = dtm_gmsh_check_log(j.ierr, DTM_ERR_INPUT, __FILE__, __LINE__, __func__, what);
  dtm_msh_beside_finish(r == DTM_OK);
  DTM_CHECK(r);
  if (is_msh_path(path) && strlen(path) < sizeof source) snprintf(source, sizeof source, "%s", path);
  *dim = gmshModelGetDimension(&ierr);
  if (*dim < 1 || *dim > 3) return DTM_ERR(DTM_ERR_INPUT, "%s: the model has no curve, surface or volume", path);
  return DTM_OK;
}
