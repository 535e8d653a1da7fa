/* Gmsh's meshing, contained: a crash inside Gmsh's mesher (a SIGSEGV in
 * its surface smoothing has been seen on STL-based models) must not take
 * dtmap down with the rounds it has already paid for.
 *
 * Two ways. Under a supervisor (the dtmap command: src/cli/supervise.c
 * forks one worker that does the whole job and reports its crash, and
 * calls dtm_gmsh_contain(0, log) in it), the first mesh of a scene is
 * made in this process, with nothing to hand back, and Gmsh's messages go
 * to the supervisor's log meanwhile. Otherwise (a script's process, the
 * Python module), and always for a remesh (refine: a crash in Gmsh ends
 * that round, not the run, which keeps its best mesh) and for a probe, the
 * current model is meshed in a forked child, which inherits the whole
 * session (geometry, options, size fields), meshes, saves the mesh as a
 * binary .msh and exits; the parent merges that file into its own model,
 * whose CAD entities the .msh names by tag, so later remeshes still start
 * from the geometry. A probe (what the model does to sizes, causes.c) runs
 * the same way and hands numbers back instead of a mesh, leaving the
 * parent's model as it was.
 *
 * The child dies with its parent (PR_SET_PDEATHSIG, then a check that its
 * parent is still the one that forked it). Its files cannot outlive the
 * processes: its terminal (Gmsh's messages at info level: the parent
 * quotes their end when the child dies by a signal), its error message
 * (an error the child raises comes back with its code and message) and a
 * probe's numbers are unnamed files it inherits; its mesh is an unnamed
 * file in $TMPDIR that Gmsh writes and reads by the name of a link to it
 * (dtm_atomic_open), which a signal handler removes. When the child cannot
 * hand its mesh back (the file cannot be written whole: a full disk, a
 * file size limit), the job runs again in this process, uncontained. The
 * environment variable DTMAP_TEST_GMSH_CRASH makes the job raise SIGSEGV
 * after meshing when it names the stage ("meshing", "remeshing after round 1"),
 * or the stage and the job's number in this process ("meshing#2": a
 * sweep's second size): the tests prove both ways with it. */
#define _GNU_SOURCE /* pread */
#include <errno.h>
#include <gmshc.h>
#include <omp.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "dtmap/gmsh.h"
#include "dtmap/util.h"
#include "gmsh-impl.h"

#define TAIL_LINES 4 /* of Gmsh's log quoted after a crash */
#define HANDBACK 4   /* the child's exit code when it meshed but could not hand the result back */

static int supervised;          /* the caller contains this process: the first mesh is made here */
static int supervisor_log = -1; /* where Gmsh's messages go meanwhile, or -1 */

void dtm_gmsh_contain(int contained, int log_fd) {
  supervised = !contained;
  supervisor_log = contained ? -1 : log_fd;
}

/* The files of one contained job. */
typedef struct {
  dtm_atomic mesh; /* the child's mesh, written and merged by the name mesh.tmp */
  int log;         /* the child's terminal */
  int error;       /* the child's error message */
  int data;        /* a probe's numbers */
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

static void files_close(job_files *f) {
  dtm_atomic_abort(&f->mesh);
  if (f->log >= 0) close(f->log);
  if (f->error >= 0) close(f->error);
  if (f->data >= 0) close(f->data);
  f->log = f->error = f->data = -1;
}

static int files_make(job_files *f, int mesh) {
  f->mesh.fd = -1, f->mesh.tmp[0] = '\0', f->mesh.f = NULL;
  f->log = dtm_scratch_fd(), f->error = dtm_scratch_fd(), f->data = dtm_scratch_fd();
  int r = f->log < 0 || f->error < 0 || f->data < 0
              ? DTM_ERR(DTM_ERR_INTERNAL, "cannot make a scratch file in $TMPDIR: %s", strerror(errno))
              : DTM_OK;
  if (r == DTM_OK && mesh) r = dtm_scratch_named(&f->mesh, "dtmap-mesh", ".msh");
  if (r) files_close(f);
  return r;
}

static void write_text(int fd, const char *text) {
  size_t n = strlen(text);
  if (pwrite(fd, text, n, 0) != (ssize_t)n) return; /* the parent then quotes the log instead */
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
int dtm_gmsh_strip_periodic(const char *path) {
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

static int jobs; /* contained jobs started in this process (a child inherits the count) */

/* The injected crash of the tests: a real SIGSEGV, default action. */
static void maybe_crash(const char *stage) {
  const char *want = getenv("DTMAP_TEST_GMSH_CRASH");
  char numbered[160];
  snprintf(numbered, sizeof numbered, "%s#%d", stage, jobs);
  if (!want || (strcmp(want, stage) && strcmp(want, numbered))) return;
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = SIG_DFL;
  sigaction(SIGSEGV, &sa, NULL);
  raise(SIGSEGV);
}

static int write_data(int fd, const double *v, size_t n) {
  size_t bytes = n * sizeof *v;
  int ok = pwrite(fd, v, bytes, 0) == (ssize_t)bytes;
  return ok ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "cannot write the probe's results: %s", strerror(errno));
}

static int read_data(int fd, double *v, size_t n) {
  size_t bytes = n * sizeof *v;
  int ok = pread(fd, v, bytes, 0) == (ssize_t)bytes;
  return ok ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "cannot read back the probe's results");
}

/* The job runs on a thread of its own: OpenMP's (libgomp's) pool of
 * worker threads belongs to the thread that made it, and a forked child
 * has only the forking thread, whose pool names workers that did not
 * survive the fork; a team started from it waits for them forever. A new
 * thread starts with no pool, so Gmsh's parallel regions make their own.
 * A job made in this process runs on such a thread too, so that it makes
 * the mesh a child would make. */
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
  static job_thread t; /* one job at a time */
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
  DTM_CHECK(dtm_gmsh_save_mesh(f->mesh.tmp));
  if (!complete(f->mesh.tmp)) return DTM_ERR(DTM_ERR_INTERNAL, "%s was cut short", f->mesh.tmp);
  return j->no_periodic ? dtm_gmsh_strip_periodic(f->mesh.tmp) : DTM_OK;
}

/* Curves and surfaces are meshed on the threads asked for, as Gmsh's own
 * `gmsh -nt N` does, only where dtmap reads Gmsh's messages from its
 * terminal (a file: dtm_gmsh_log_terminal): each curve and surface logs
 * "Meshing ..." at info level from its thread, and Gmsh's API logger
 * appends to one vector without a lock, so curves meshed on OpenMP threads
 * corrupt it (ASan: a double free in t312, HXT on 2 threads). That is the
 * dtmap command's first mesh, made in its supervised worker (in_process)
 * unless Gmsh's terminal is shown (dtmap -v). Everywhere else they are
 * meshed one at a time: in a forked child (a remesh, a probe, a library
 * caller's mesh), whose parent may have run OpenMP threads the child does
 * not have (one sanitizer run of the suite failed once in such a child,
 * t322's 2D strip, when its curves were meshed on threads; never
 * reproduced). Volumes keep the threads asked for everywhere. */
static const char *const thread_keys[] = {"Mesh.MaxNumThreads1D", "Mesh.MaxNumThreads2D"};

static void serial_surfaces(double *old) {
  int ierr = 0;
  for (int i = 0; i < 2; i++) {
    if (old) gmshOptionGetNumber(thread_keys[i], &old[i], &ierr);
    gmshOptionSetNumber(thread_keys[i], 1, &ierr);
  }
}

static void restore_surfaces(const double *old) {
  int ierr = 0;
  for (int i = 0; i < 2; i++) gmshOptionSetNumber(thread_keys[i], old[i], &ierr);
}

/* The child: dies with its parent, Gmsh's terminal to the log, the job,
 * its mesh or numbers back. */
static unsigned remesh_limit; /* seconds a remesh may take (0: no limit): dtm_gmsh_remesh_limit */

void dtm_gmsh_remesh_limit(unsigned seconds) { remesh_limit = seconds; }

static void child(pid_t parent, const char *stage, const job_spec *j, const job_files *f) {
  int ierr = 0;
  if (prctl(PR_SET_PDEATHSIG, SIGKILL) || getppid() != parent) _exit(DTM_ERR_INTERNAL);
  if (j->no_periodic && remesh_limit) alarm(remesh_limit); /* a remesh Gmsh does not finish ends by SIGALRM */
  dup2(f->log, STDOUT_FILENO), dup2(f->log, STDERR_FILENO);
  gmshOptionSetNumber("General.Terminal", 1, &ierr);
  gmshOptionSetNumber("General.Verbosity", 4, &ierr); /* errors, warnings and info: the last steps before a crash */
  serial_surfaces(NULL);                              /* a forked child: see above */
  int r = run_job(j);
  fflush(NULL);
  maybe_crash(stage);
  if (r == DTM_OK && hand_back(j, f)) r = HANDBACK;
  if (r) write_text(f->error, dtm_error_message());
  fflush(NULL);
  _exit(r >= 0 && r < 126 ? r : DTM_ERR_INTERNAL); /* no atexit handler: the parent owns the session */
}

/* The last n non-empty lines of the file at fd, "; "-separated, into buf. */
static void tail(int fd, int n, char *buf, size_t len) {
  char lines[TAIL_LINES][400], line[400];
  int count = 0, copy = fd >= 0 ? dup(fd) : -1;
  FILE *in = copy >= 0 ? fdopen(copy, "r") : NULL;
  buf[0] = '\0';
  if (!in) {
    if (copy >= 0) close(copy);
    return;
  }
  rewind(in);
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

void dtm_gmsh_log_tail(int fd, char *buf, size_t len) { tail(fd, TAIL_LINES, buf, len); }

static int read_text(int fd, char *buf, size_t len) {
  ssize_t n = pread(fd, buf, len - 1, 0);
  buf[n > 0 ? n : 0] = '\0';
  return n > 0;
}

/* What the parent makes of the child's end. */
static int judge(const char *stage, int status, const job_files *f) {
  char text[2048];
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM && remesh_limit)
    return DTM_ERR(DTM_ERR_INPUT, "%s: Gmsh did not finish within %u s (the limit of one remesh)", stage, remesh_limit);
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
  dtm_gmsh_source_clear(); /* the model is no longer the file's as read */
  gmshModelMeshClear(NULL, 0, &ierr);
  gmshModelMeshRebuildNodeCache(0, &ierr);       /* no node of the cleared mesh is left to find by tag */
  gmshModelRemovePhysicalGroups(NULL, 0, &ierr); /* the file brings them back; merged, each entity would be in its
                                                    group twice */
  dtm_gmsh_log_reset();
  gmshMerge(f->mesh.tmp, &ierr);
  DTM_GMSH_CHECK_LOG(ierr, DTM_ERR_INTERNAL, "reading back the mesh of the meshing process");
  return DTM_OK;
}

static int run_child(const char *stage, const job_spec *j, const job_files *f) {
  int status = 0;
  pid_t parent = getpid();
  fflush(NULL);
  pid_t pid = fork();
  if (pid < 0) return DTM_ERR(DTM_ERR_INTERNAL, "%s: cannot start the meshing process: %s", stage, strerror(errno));
  if (pid == 0) child(parent, stage, j, f);
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return DTM_ERR(DTM_ERR_INTERNAL, "%s: lost the meshing process: %s", stage, strerror(errno));
  int r = judge(stage, status, f);
  if (r == HANDBACK) return r;
  DTM_CHECK(r);
  return j->job ? merge_back(f) : read_data(f->data, j->out, j->nout);
}

static int contained(const char *stage, const job_spec *j) {
  job_files f;
  DTM_CHECK(files_make(&f, j->job != NULL));
  int r = run_child(stage, j, &f);
  files_close(&f);
  if (r == HANDBACK && j->job)
    r = j->job(j->arg); /* the temporary file cannot be written (a full disk, a file
                           size limit): mesh in this process, uncontained */
  else if (r == HANDBACK)
    r = DTM_ERR(DTM_ERR_INTERNAL, "%s: the probe could not hand its results back", stage);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

/* Gmsh's terminal to the supervisor's log, at info level as the child's
 * (unless the terminal shows Gmsh's messages: dtmap -v). */
typedef struct {
  int out, err;               /* the saved stdout and stderr, or -1: not redirected */
  double terminal, verbosity; /* Gmsh's options before */
} log_redirect;

static log_redirect log_begin(void) {
  log_redirect s = {-1, -1, 0, 0};
  int ierr = 0;
  gmshOptionGetNumber("General.Verbosity", &s.verbosity, &ierr);
  if (supervisor_log < 0 || s.verbosity >= 5) return s;
  gmshOptionGetNumber("General.Terminal", &s.terminal, &ierr);
  fflush(NULL);
  s.out = dup(STDOUT_FILENO), s.err = dup(STDERR_FILENO);
  dup2(supervisor_log, STDOUT_FILENO), dup2(supervisor_log, STDERR_FILENO);
  gmshOptionSetNumber("General.Terminal", 1, &ierr);
  gmshOptionSetNumber("General.Verbosity", 4, &ierr);
  return s;
}

static void log_end(log_redirect s) {
  int ierr = 0;
  if (s.out < 0) return;
  fflush(NULL);
  gmshOptionSetNumber("General.Terminal", s.terminal, &ierr);
  gmshOptionSetNumber("General.Verbosity", s.verbosity, &ierr);
  dup2(s.out, STDOUT_FILENO), close(s.out);
  dup2(s.err, STDERR_FILENO), close(s.err);
}

int dtm_gmsh_logged(dtm_gmsh_job fn, void *arg) {
  log_redirect s = log_begin();
  int r = fn(arg);
  log_end(s);
  return r;
}

/* The job in this process, as the child would run it; the supervisor
 * reports a crash. */
static int in_process(const char *stage, const job_spec *j) {
  double old[2];
  log_redirect s = log_begin();
  if (s.out >= 0)
    dtm_gmsh_log_terminal(supervisor_log); /* curves and surfaces on the threads asked for */
  else
    serial_surfaces(old);
  int r = run_job(j);
  fflush(NULL);
  maybe_crash(stage);
  if (s.out >= 0)
    dtm_gmsh_log_terminal(-1);
  else
    restore_surfaces(old);
  log_end(s);
  return r ? dtm_error_trace(r, __FILE__, __LINE__, __func__) : DTM_OK;
}

int dtm_gmsh_contained(const char *stage, dtm_gmsh_job job, void *arg, int remesh) {
  job_spec j = {job, NULL, arg, NULL, 0, omp_get_max_threads(), remesh};
  jobs++;
  return supervised && !remesh ? in_process(stage, &j) : contained(stage, &j);
}

int dtm_gmsh_contained_probe(const char *stage, dtm_gmsh_probe_job probe, void *arg, double *out, size_t nout) {
  job_spec j = {NULL, probe, arg, out, nout, omp_get_max_threads(), 0};
  return contained(stage, &j);
}
