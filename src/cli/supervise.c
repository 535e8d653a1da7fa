/* The supervisor: every command that runs Gmsh (run, verify, refine, sweep,
 * snapshot, and the ONELAB client) runs in one worker process forked here,
 * which does the whole job in one address space (mesh, analyse, write), so
 * containing Gmsh costs a fork and nothing is handed back between
 * processes. This process only waits: it draws the worker's progress (the
 * record is shared, progress.c) and relays it (ONELAB progress to Gmsh),
 * passes SIGINT, SIGTERM and SIGHUP on to the worker, and when the worker
 * dies by a signal (a crash in Gmsh's mesher, the OOM killer) reports the
 * stage, the signal and Gmsh's last messages (from a log without a name
 * that the worker's Gmsh writes to while it reads or meshes) and removes
 * the names of the temporaries the worker had open (their list is shared,
 * dtm_atomic_share; their data had no name). Exit 3 then; else the
 * worker's own exit code, or, after a signal passed on, death by that
 * signal.
 *
 * The worker dies with this process: it asks for SIGTERM when its parent
 * dies (PR_SET_PDEATHSIG, then checks that its parent is still the one
 * that forked it), and its SIGTERM handler removes its temporaries' names
 * before the signal ends it; Gmsh's own children (refine's remeshes) die
 * with the worker the same way (src/gmsh/contain.c).
 *
 * Inside the worker, refine's remeshes and probes still run in children of
 * their own (src/gmsh/contain.c), so that a crash of Gmsh in a remesh ends
 * that round, not the run, while the kept mesh waits in a file without a
 * name; a crash anywhere else ends the command, which had nothing to keep.
 * An MPI rank is not supervised: its launcher owns the processes; nor is
 * a command run with DTMAP_SUPERVISE=0 (for a debugger). */
#define _GNU_SOURCE /* strsignal */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli-impl.h"
#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/parallel.h"
#include "dtmap/util.h"

#define NAMES_BYTES (64 * (DTM_PATH_MAX + 64)) /* the worker's temporaries' names (dtm_atomic_share) */

static const int passed[] = {SIGINT, SIGTERM, SIGHUP}; /* the signals passed on to the worker */
#define NPASSED 3

static volatile sig_atomic_t worker;   /* its pid, 0 before the fork */
static volatile sig_atomic_t received; /* the last signal passed on, 0: none */

static void pass_on(int sig) {
  received = sig;
  if (worker > 0) kill((pid_t)worker, sig);
}

/* Interrupted (Ctrl-C, kill, a closed terminal, its parent gone): remove
 * the temporaries being written, then end as the signal would have. */
static void end_worker(int sig) {
  dtm_atomic_cleanup_signal();
  signal(sig, SIG_DFL);
  raise(sig);
}

static void handle(void (*fn)(int)) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = fn;
  sigemptyset(&sa.sa_mask);
  for (int i = 0; i < NPASSED; i++) sigaction(passed[i], &sa, NULL);
}

void dtm_cli_catch_signals(void) { handle(end_worker); }

static void mask(int how) {
  sigset_t set;
  sigemptyset(&set);
  for (int i = 0; i < NPASSED; i++) sigaddset(&set, passed[i]);
  sigprocmask(how, &set, NULL);
}

/* The worker: dies with its parent, then does the whole job. */
static void work(const cli_supervised *s, pid_t parent, int log) {
  handle(end_worker);
  if (prctl(PR_SET_PDEATHSIG, SIGTERM) || getppid() != parent) raise(SIGTERM);
  mask(SIG_UNBLOCK);
  dtm_gmsh_contain(0, log);
  dtm_cli_progress_hook();
  int code = s->job(s->arg);
  exit(code);
}

/* Whether Gmsh runs in the library stage named stage (src/gmsh/session.c,
 * output/mesh.c: Gmsh reads, meshes or writes the mesh). */
static int gmsh_stage(const char *stage) {
  static const char *const names[] = {"reading", "meshing", "writing the mesh"};
  for (size_t i = 0; i < sizeof names / sizeof *names; i++)
    if (!strcmp(stage, names[i])) return 1;
  return 0;
}

/* The worker died by sig: say where and what Gmsh said last. */
static int crashed(const cli_supervised *s, int sig, int log) {
  char stage[128], said[2048], msg[4096];
  int open = dtm_cli_progress_stage(stage, sizeof stage), gmsh = open && gmsh_stage(stage);
  dtm_gmsh_log_tail(log, said, sizeof said);
  snprintf(msg, sizeof msg, "%s%s%s crashed (signal %d, %s); %s last messages: %s", open ? stage : "", open ? ": " : "",
           gmsh ? "Gmsh" : "dtmap", sig, strsignal(sig), gmsh ? "its" : "Gmsh's", said[0] ? said : "(none)");
  fprintf(stderr, "dtmap: error: %s\n", msg);
  if (s->crashed) s->crashed(s->user, msg);
  return DTM_ERR_INTERNAL;
}

/* Wait for the worker and judge its end. */
static int wait_worker(const cli_supervised *s, pid_t pid, int log) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return fprintf(stderr, "dtmap: error: lost the worker: %s\n", strerror(errno)), 3;
  dtm_cli_progress_stop();
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  dtm_atomic_cleanup_signal(); /* what the worker could not remove */
  int sig = WTERMSIG(status);
  if (received) {
    signal(received, SIG_DFL);
    raise(received); /* ended as the signal would have ended it */
  }
  return crashed(s, sig, log);
}

/* An MPI rank, or DTMAP_SUPERVISE=0 (a debugger; the containment
 * benchmark's baseline, which meshes here too, uncontained: in_process):
 * the job in this process, with its progress. */
static int unsupervised(const cli_supervised *s, int in_process) {
  if (in_process) dtm_gmsh_contain(0, -1);
  dtm_cli_progress_start(s->verbosity);
  int code = s->job(s->arg);
  dtm_cli_progress_stop();
  return code;
}

int dtm_cli_supervise(const cli_supervised *s) {
  const char *env = getenv("DTMAP_SUPERVISE");
  int off = env && !strcmp(env, "0");
  if (off || dtm_parallel_launched()) return unsupervised(s, off);
  void *names = mmap(NULL, NAMES_BYTES, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (names != MAP_FAILED) dtm_atomic_share(names, NAMES_BYTES);
  dtm_cli_progress_place();
  int log = dtm_scratch_fd();
  pid_t parent = getpid();
  fflush(NULL);
  mask(SIG_BLOCK); /* no signal between the fork and the handlers of each side */
  pid_t pid = fork();
  if (pid == 0) work(s, parent, log);
  if (pid < 0) {
    mask(SIG_UNBLOCK);
    return fprintf(stderr, "dtmap: error: cannot start the worker: %s\n", strerror(errno)), 3;
  }
  worker = pid;
  handle(pass_on);
  mask(SIG_UNBLOCK);
  dtm_cli_progress_draw(s->verbosity, s->relay, s->user);
  int code = wait_worker(s, pid, log);
  if (log >= 0) close(log);
  return code;
}
