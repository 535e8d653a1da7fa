/* Gmsh's meshing, contained: a crash inside Gmsh's mesher (a SIGSEGV in
 * its surface smoothing has been seen on STL-based models) must not take
 * dtmap down with the rounds it has already paid for. The current model is
 * meshed in a forked child, which inherits the whole session (geometry,
 * options, size fields), meshes, saves the mesh to a temporary binary .msh
 * and exits; the parent merges that file into its own model, whose CAD
 * entities the .msh names by tag, so later remeshes still start from the
 * geometry. The child's terminal output (Gmsh's messages at info level) goes
 * to a log file, whose last lines the parent quotes when the child dies by a
 * signal; an error the child raises (Gmsh refused the model) comes back with
 * its code and message. When the child cannot hand its mesh back (the
 * temporary file cannot be written whole: a full disk, a file size limit),
 * the job runs again in this process, uncontained. A probe (what the model does to sizes, causes.c)
 * runs the same way and hands numbers back instead of a mesh, leaving the
 * parent's model as it was. The environment variable DTMAP_TEST_GMSH_CRASH,
 * read only in the child, makes it raise SIGSEGV after meshing when it
 * names the stage ("meshing", "remeshing round 2"): the tests prove the
 * path with it. */
#include <errno.h>
#include <gmshc.h>
#include <omp.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

#define TAIL_LINES 4 /* of Gmsh's log quoted after a crash */
#define HANDBACK 4   /* the child's exit code when it meshed but could not hand the result back */

/* The temporary files of one contained job. */
typedef struct {
  char dir[256];   /* the temporary directory */
  char mesh[300];  /* dir/mesh.msh: the child's mesh */
  char log[300];   /* dir/gmsh.log: the child's terminal */
  char error[300]; /* dir/error.txt: the child's error message */
  char data[300];  /* dir/data.bin: a probe's numbers */
} job_files;

/* What the child runs and what it hands back. */
typedef struct {
  dtm_gmsh_job job;         /* a meshing job (its mesh is merged back), or NULL */
  dtm_gmsh_probe_job probe; /* a probe (its numbers are read back), or NULL */
  void *arg;                /* the job's argument */
  double *out;              /* [nout] the probe's numbers */
  size_t nout;              /* how many */
  int threads;              /* OpenMP threads of the forking thread (Gmsh's General.NumThreads) */
  int no_periodic;          /* leave the $Periodic section out of the mesh handed back */
} job_spec;

static int files_make(job_files *f) {
  const char *tmp = getenv("TMPDIR");
  snprintf(f->dir, sizeof f->dir, "%s/dtmap-mesh-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
  if (!mkdtemp(f->dir)) return DTM_ERR(DTM_ERR_INTERNAL, "cannot make a temporary directory in %s", f->dir);
  snprintf(f->mesh, sizeof f->mesh, "%s/mesh.msh", f->dir);
  snprintf(f->log, sizeof f->log, "%s/gmsh.log", f->dir);
  snprintf(f->error, sizeof f->error, "%s/error.txt", f->dir);
  snprintf(f->data, sizeof f->data, "%s/data.bin", f->dir);
  return DTM_OK;
}

static void files_remove(const job_files *f) {
  unlink(f->mesh), unlink(f->log), unlink(f->error), unlink(f->data);
  rmdir(f->dir);
}

static void write_text(const char *path, const char *text) {
  FILE *o = fopen(path, "w");
  if (o) fputs(text, o), fclose(o);
}

/* Offset of the first pat at or after from in f, or -1 (chunked, so that
 * a .msh of any size is scanned in little memory). */
static long find_text(FILE *f, long from, const char *pat) {
  char buf[65536 + 64];
  size_t plen = strlen(pat), keep = 0;
  long base = from;
  if (fseek(f, from, SEEK_SET)) return -1;
  for (;;) {
    size_t n = fread(buf + keep, 1, sizeof buf - 1 - keep, f) + keep;
    if (n < plen) return -1;
    for (size_t i = 0; i + plen <= n; i++)
      if (buf[i] == pat[0] && !memcmp(buf + i, pat, plen)) return base + (long)i;
    if (n < sizeof buf - 1) return -1;
    keep = plen - 1;
    memmove(buf, buf + n - keep, keep);
    base += (long)(n - keep);
  }
}

/* Cut the $Periodic section out of a .msh the child wrote after a remesh:
 * Gmsh 4.8 keeps the periodic node pairs of a cleared mesh, so the section
 * names nodes that no longer exist, and reading it back crashes Gmsh in the
 * parent (seen on a periodic square). The parent's model keeps its own
 * periodic entities; only the node pairs of the handed-back mesh are lost. */
static int strip_periodic(const char *path) {
  FILE *f = fopen(path, "r+b");
  if (!f) return DTM_ERR(DTM_ERR_INTERNAL, "cannot open %s", path);
  long start = find_text(f, 0, "$Periodic\n"), end = start < 0 ? -1 : find_text(f, start, "$EndPeriodic\n");
  int ok = 1;
  if (end >= 0) {
    char buf[65536];
    long rd = end + (long)strlen("$EndPeriodic\n"), wr = start;
    size_t n;
    while (ok && !fseek(f, rd, SEEK_SET) && (n = fread(buf, 1, sizeof buf, f)) > 0) {
      ok = !fseek(f, wr, SEEK_SET) && fwrite(buf, 1, n, f) == n;
      rd += (long)n, wr += (long)n;
    }
    ok = ok && !fflush(f) && !ftruncate(fileno(f), wr);
  }
  if (fclose(f)) ok = 0;
  return ok ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "cannot rewrite %s", path);
}

/* The injected crash of the tests: a real SIGSEGV, default action. */
static void maybe_crash(const char *stage) {
  const char *want = getenv("DTMAP_TEST_GMSH_CRASH");
  if (!want || strcmp(want, stage)) return;
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = SIG_DFL;
  sigaction(SIGSEGV, &sa, NULL);
  raise(SIGSEGV);
}

static int write_data(const char *path, const double *v, size_t n) {
  FILE *o = fopen(path, "wb");
  int ok = o && fwrite(v, sizeof *v, n, o) == n;
  if (o && fclose(o)) ok = 0;
  return ok ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "cannot write %s", path);
}

static int read_data(const char *path, double *v, size_t n) {
  FILE *in = fopen(path, "rb");
  int ok = in && fread(v, sizeof *v, n, in) == n;
  if (in) fclose(in);
  return ok ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "cannot read back the probe's results (%s)", path);
}

/* The job runs on a thread of its own: OpenMP's (libgomp's) pool of
 * worker threads belongs to the thread that made it, and a forked child
 * has only the forking thread, whose pool names workers that did not
 * survive the fork; a team started from it waits for them forever. A new
 * thread starts with no pool, so Gmsh's parallel regions make their own. */
typedef struct {
  const job_spec *j; /* the job */
  int r;             /* its result */
  char msg[2048];    /* its error message (errors are recorded per thread) */
} job_thread;

static void *job_main(void *arg) {
  job_thread *t = arg;
  const job_spec *j = t->j;
  omp_set_num_threads(j->threads); /* a new thread starts from OpenMP's default, all cores */
  t->r = j->job ? j->job(j->arg) : j->probe(j->arg, j->out, j->nout);
  snprintf(t->msg, sizeof t->msg, "%s", t->r ? dtm_error_message() : "");
  return NULL;
}

#define JOB_STACK ((size_t)256 << 20) /* reserved, not committed: Gmsh's recursions have room */

static int run_job(const job_spec *j) {
  static job_thread t; /* the child's only job */
  t.j = j, t.r = DTM_ERR_INTERNAL;
  pthread_attr_t attr;
  pthread_t th;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, JOB_STACK);
  int started = pthread_create(&th, &attr, job_main, &t) == 0;
  pthread_attr_destroy(&attr);
  if (!started) return DTM_ERR(DTM_ERR_INTERNAL, "cannot start the meshing thread");
  pthread_join(th, NULL);
  if (t.r) return dtm_error_raise(t.r, __FILE__, __LINE__, __func__, "%s", t.msg);
  return DTM_OK;
}

/* Whether the .msh at path ends with a section's end line: Gmsh's writer
 * does not check its writes, so a file cut by a full disk or a file size
 * limit is found here. */
static int complete(const char *path) {
  char buf[65];
  FILE *in = fopen(path, "rb");
  long size = in && !fseek(in, 0, SEEK_END) ? ftell(in) : -1;
  size_t n = size > 0 && !fseek(in, size > 64 ? size - 64 : 0, SEEK_SET) ? fread(buf, 1, 64, in) : 0;
  if (in) fclose(in);
  if (!n || buf[n - 1] != '\n') return 0;
  size_t start = n - 1; /* the last line's first byte: the bytes before it are binary (NULs included) */
  while (start > 0 && buf[start - 1] != '\n') start--;
  return n - 1 - start >= 4 && !memcmp(buf + start, "$End", 4);
}

/* Hand the job's result back: the mesh (complete, without the stale
 * periodic pairs of a remesh) or the probe's numbers. */
static int hand_back(const job_spec *j, const job_files *f) {
  if (!j->job) return write_data(f->data, j->out, j->nout);
  DTM_CHECK(dtm_gmsh_save_mesh(f->mesh));
  if (!complete(f->mesh)) return DTM_ERR(DTM_ERR_INTERNAL, "%s was cut short", f->mesh);
  return j->no_periodic ? strip_periodic(f->mesh) : DTM_OK;
}

/* The child: Gmsh's terminal to the log, the job, its mesh or numbers to a
 * file. */
static void child(const char *stage, const job_spec *j, const job_files *f) {
  int ierr = 0, fd = -1;
  FILE *log = fopen(f->log, "w");
  if (log) fd = fileno(log);
  if (fd >= 0) dup2(fd, STDOUT_FILENO), dup2(fd, STDERR_FILENO);
  gmshOptionSetNumber("General.Terminal", 1, &ierr);
  gmshOptionSetNumber("General.Verbosity", 4, &ierr); /* errors, warnings and info: the last steps before a crash */
  /* Curves and surfaces one at a time: each logs "Meshing ..." at info
   * level, and Gmsh's API logger (which dtmap reads for errors) appends to
   * one vector without a lock, so curves meshed on OpenMP threads corrupt
   * it (ASan: a double free in t312, HXT on 2 threads). Volumes keep the
   * threads asked for. */
  gmshOptionSetNumber("Mesh.MaxNumThreads1D", 1, &ierr);
  gmshOptionSetNumber("Mesh.MaxNumThreads2D", 1, &ierr);
  int r = run_job(j);
  fflush(NULL);
  maybe_crash(stage);
  if (r == DTM_OK && hand_back(j, f)) r = HANDBACK;
  if (r) write_text(f->error, dtm_error_message());
  fflush(NULL);
  _exit(r >= 0 && r < 126 ? r : DTM_ERR_INTERNAL); /* no atexit handler: the parent owns the session */
}

/* The last n non-empty lines of path, "; "-separated, into buf. */
static void tail(const char *path, int n, char *buf, size_t len) {
  char lines[TAIL_LINES][400], line[400];
  int count = 0;
  FILE *in = fopen(path, "r");
  buf[0] = '\0';
  if (!in) return;
  while (fgets(line, sizeof line, in)) {
    line[strcspn(line, "\r\n")] = '\0';
    if (line[0] && (!count || strcmp(line, lines[(count - 1) % TAIL_LINES]))) /* a repeated line once */
      snprintf(lines[count++ % TAIL_LINES], sizeof lines[0], "%s", line);
  }
  fclose(in);
  for (int i = count > n ? count - n : 0; i < count; i++) {
    size_t used = strlen(buf);
    snprintf(buf + used, len - used, "%s%s", used ? "; " : "", lines[i % TAIL_LINES]);
  }
}

static int read_text(const char *path, char *buf, size_t len) {
  FILE *in = fopen(path, "r");
  size_t n = in ? fread(buf, 1, len - 1, in) : 0;
  if (in) fclose(in);
  buf[n] = '\0';
  return n > 0;
}

/* What the parent makes of the child's end. */
static int judge(const char *stage, int status, const job_files *f) {
  char text[2048];
  if (WIFSIGNALED(status)) {
    int sig = WTERMSIG(status);
    tail(f->log, TAIL_LINES, text, sizeof text);
    return DTM_ERR(DTM_ERR_INTERNAL, "%s: Gmsh crashed (signal %d, %s); its last messages: %s", stage, sig,
                   strsignal(sig), text[0] ? text : "(none)");
  }
  int code = WIFEXITED(status) ? WEXITSTATUS(status) : DTM_ERR_INTERNAL;
  if (code == DTM_OK || code == HANDBACK) return code;
  if (!read_text(f->error, text, sizeof text)) tail(f->log, TAIL_LINES, text, sizeof text);
  return DTM_ERR(code == DTM_ERR_INPUT ? DTM_ERR_INPUT : DTM_ERR_INTERNAL, "%s", text[0] ? text : "Gmsh failed");
}

/* Replace the current model's mesh by the child's. */
static int merge_back(const job_files *f) {
  int ierr = 0;
  gmshModelMeshClear(NULL, 0, &ierr);
  gmshModelMeshRebuildNodeCache(0, &ierr);       /* no node of the cleared mesh is left to find by tag */
  gmshModelRemovePhysicalGroups(NULL, 0, &ierr); /* the file brings them back; merged, each entity would be in its
                                                    group twice */
  dtm_gmsh_log_reset();
  gmshMerge(f->mesh, &ierr);
  DTM_GMSH_CHECK_LOG(ierr, DTM_ERR_INTERNAL, "reading back the mesh of the meshing process");
  return DTM_OK;
}

static int run_child(const char *stage, const job_spec *j, const job_files *f) {
  int status = 0;
  fflush(NULL);
  pid_t pid = fork();
  if (pid < 0) return DTM_ERR(DTM_ERR_INTERNAL, "%s: cannot start the meshing process: %s", stage, strerror(errno));
  if (pid == 0) child(stage, j, f);
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return DTM_ERR(DTM_ERR_INTERNAL, "%s: lost the meshing process: %s", stage, strerror(errno));
  int r = judge(stage, status, f);
  if (r == HANDBACK) return r;
  DTM_CHECK(r);
  return j->job ? merge_back(f) : read_data(f->data, j->out, j->nout);
}

static int contained(const char *stage, const job_spec *j) {
  job_files f;
  DTM_CHECK(files_make(&f));
  int r = run_child(stage, j, &f);
  files_remove(&f);
  if (r == HANDBACK && j->job)
    r = j->job(j->arg); /* the temporary file cannot be written (a full disk, a file
                           size limit): mesh in this process, uncontained */
  else if (r == HANDBACK)
    r = DTM_ERR(DTM_ERR_INTERNAL, "%s: the probe could not hand its results back", stage);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_gmsh_contained(const char *stage, dtm_gmsh_job job, void *arg, int remesh) {
  job_spec j = {job, NULL, arg, NULL, 0, omp_get_max_threads(), remesh};
  return contained(stage, &j);
}

int dtm_gmsh_contained_probe(const char *stage, dtm_gmsh_probe_job probe, void *arg, double *out, size_t nout) {
  job_spec j = {NULL, probe, arg, out, nout, omp_get_max_threads(), 0};
  return contained(stage, &j);
}
