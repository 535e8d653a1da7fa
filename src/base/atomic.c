/* Atomic output files: every file dtmap writes (mesh, .opt, report, CSV,
 * plot) goes to a temporary in the target's directory, named
 * .BASE.tmpPID<suffix>, and is renamed over the target only once it is
 * complete; on any failure the temporary is removed and the target, if it
 * existed, is untouched.
 *
 * A process killed while writing (SIGKILL, the OOM killer, a power cut)
 * cannot remove its temporary, so nothing is ever left at the target but
 * the temporary stays. Each writer therefore holds an exclusive flock() on
 * its temporary from creation to rename, and the next writer of the same
 * target removes every temporary of that target that no process holds and
 * whose PID no longer runs (both, so a temporary that is being created is
 * never taken for stale). Temporaries in use are also listed here, so a
 * SIGINT/SIGTERM/SIGHUP handler can remove them (dtm_atomic_cleanup_signal,
 * async-signal-safe).
 *
 * A write that fails names the target (not only its temporary) and the
 * reason. stdio's errno of the first failed write may be overwritten by the
 * time the error is noticed, so the reason is what the system says when the
 * stream is flushed, or written to, again (the temporary is given up
 * anyway). A file a library wrote by name (Gmsh, PLplot: they do not check
 * their writes) counts as failed when the evidence says so: it reached the
 * process's file size limit, or its file system has no space left. */
#define _DEFAULT_SOURCE /* flock() */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/util.h"

#define ACTIVE_MAX 8 /* temporaries of this process a signal can remove */
#include "base.h"

#define CAUSE_UNKNOWN DTM_WRITE_CAUSE_UNKNOWN /* a write failed, but writing again succeeds */

static char active[ACTIVE_MAX][DTM_PATH_MAX + 64]; /* "" when free */

static void track(const char *tmp) {
  for (int i = 0; i < ACTIVE_MAX; i++)
    if (!active[i][0]) {
      snprintf(active[i], sizeof active[i], "%s", tmp);
      return;
    }
}

static void untrack(const char *tmp) {
  for (int i = 0; i < ACTIVE_MAX; i++)
    if (!strcmp(active[i], tmp)) active[i][0] = '\0';
}

void dtm_atomic_cleanup_signal(void) {
  for (int i = 0; i < ACTIVE_MAX; i++)
    if (active[i][0]) unlink(active[i]);
}

static void temp_name(const char *path, const char *suffix, char *out, size_t len) {
  const char *slash = strrchr(path, '/');
  int dirlen = slash ? (int)(slash - path + 1) : 0;
  snprintf(out, len, "%.*s.%s.tmp%ld%s", dirlen, path, slash ? slash + 1 : path, (long)getpid(), suffix);
}

/* The PID in name when it is a temporary of target base (".BASE.tmpPID"
 * and a suffix of ".xxx" or nothing), else 0. */
static long temp_pid(const char *name, const char *base) {
  size_t n = strlen(base);
  if (name[0] != '.' || strncmp(name + 1, base, n) || strncmp(name + 1 + n, ".tmp", 4)) return 0;
  char *end = NULL;
  long pid = strtol(name + n + 5, &end, 10);
  if (end == name + n + 5 || (*end && (*end != '.' || strchr(end + 1, '.') || strchr(end + 1, '/')))) return 0;
  return pid > 0 ? pid : 0;
}

/* Remove file when no process holds its lock and pid does not run. */
static void remove_if_stale(const char *file, long pid) {
  if (pid == (long)getpid() || kill((pid_t)pid, 0) == 0 || errno != ESRCH) return;
  int fd = open(file, O_RDONLY | O_NOFOLLOW);
  if (fd < 0) return;
  if (flock(fd, LOCK_EX | LOCK_NB) == 0) unlink(file);
  close(fd);
}

/* Remove what killed writers of path left beside it. */
static void remove_stale(const char *path) {
  const char *slash = strrchr(path, '/');
  char dir[DTM_PATH_MAX], file[DTM_PATH_MAX + 512];
  snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) + (slash == path) : 1, slash ? path : ".");
  const char *base = slash ? slash + 1 : path;
  DIR *d = opendir(dir);
  if (!d) return;
  for (struct dirent *e; (e = readdir(d));) {
    long pid = temp_pid(e->d_name, base);
    if (!pid) continue;
    snprintf(file, sizeof file, "%s/%s", dir, e->d_name);
    remove_if_stale(file, pid);
  }
  closedir(d);
}

static int open_fail(dtm_atomic *w, const char *path, int e) {
  if (w->fd >= 0) close(w->fd), unlink(w->tmp), untrack(w->tmp);
  w->fd = -1;
  w->tmp[0] = '\0';
  return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", path, strerror(e));
}

int dtm_atomic_open(dtm_atomic *w, const char *path, const char *suffix, int stream) {
  w->f = NULL;
  w->fd = -1;
  w->tmp[0] = '\0';
  if ((size_t)snprintf(w->path, sizeof w->path, "%s", path) >= sizeof w->path)
    return DTM_ERR(DTM_ERR_INPUT, "%s: the path is too long", path);
  remove_stale(path);
  temp_name(path, suffix, w->tmp, sizeof w->tmp);
  w->fd = open(w->tmp, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (w->fd < 0) return open_fail(w, path, errno);
  if (flock(w->fd, LOCK_EX | LOCK_NB)) return open_fail(w, path, errno);
  track(w->tmp);
  if (stream && !(w->f = fopen(w->tmp, "w"))) return open_fail(w, path, errno);
  return DTM_OK;
}

/* The errno of writing to f again, whose writes failed: flushing what it
 * still holds, else writing more; CAUSE_UNKNOWN when both succeed now. */
int dtm_write_errno(FILE *f) {
  static const char pad[1 << 16]; /* more than a block: needs a new one */
  clearerr(f);
  errno = 0;
  if (!fflush(f) && fwrite(pad, 1, sizeof pad, f) == sizeof pad && !fflush(f)) return CAUSE_UNKNOWN;
  return errno ? errno : CAUSE_UNKNOWN;
}

/* Whether a library's writes to the file open at fd failed, from what they
 * left: the file reached this process's size limit (EFBIG), or its file
 * system has no space left for this user (ENOSPC); else 0. */
static int evidence_errno(int fd) {
  struct stat st;
  struct rlimit rl;
  struct statvfs fs;
  if (!fstat(fd, &st) && !getrlimit(RLIMIT_FSIZE, &rl) && rl.rlim_cur != RLIM_INFINITY &&
      (unsigned long long)st.st_size >= (unsigned long long)rl.rlim_cur)
    return EFBIG;
  if (!fstatvfs(fd, &fs) && fs.f_blocks > 0 && (geteuid() ? fs.f_bavail : fs.f_bfree) == 0) return ENOSPC;
  return 0;
}

/* The reason for the message: strerror(e), with the limit behind EFBIG. */
const char *dtm_write_reason(int e, char *buf, size_t len) {
  struct rlimit rl;
  if (e == CAUSE_UNKNOWN)
    snprintf(buf, len, "a write failed, and writing again succeeds: the system gives no reason");
  else if (e == EFBIG && !getrlimit(RLIMIT_FSIZE, &rl) && rl.rlim_cur != RLIM_INFINITY)
    snprintf(buf, len, "%s (this process may write files of at most %llu bytes: ulimit -f)", strerror(e),
             (unsigned long long)rl.rlim_cur);
  else
    snprintf(buf, len, "%s", strerror(e));
  return buf;
}

/* 0 when every write to w's temporary succeeded, else why not; closes w->f. */
static int write_status(dtm_atomic *w) {
  if (!w->f) return w->fd >= 0 ? evidence_errno(w->fd) : 0;
  int e = ferror(w->f) ? dtm_write_errno(w->f) : 0;
  errno = 0;
  if (fclose(w->f) && !e) e = errno ? errno : CAUSE_UNKNOWN;
  w->f = NULL;
  return e;
}

int dtm_atomic_commit(dtm_atomic *w) {
  char why[256];
  int e = write_status(w);
  if (!e && rename(w->tmp, w->path)) e = errno;
  if (e) {
    dtm_write_reason(e, why, sizeof why);
    dtm_atomic_abort(w);
    return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", w->path, why);
  }
  untrack(w->tmp);
  if (w->fd >= 0) close(w->fd);
  w->fd = -1;
  w->tmp[0] = '\0';
  return DTM_OK;
}

void dtm_atomic_abort(dtm_atomic *w) {
  if (w->f) fclose(w->f);
  w->f = NULL;
  if (w->tmp[0]) unlink(w->tmp), untrack(w->tmp);
  if (w->fd >= 0) close(w->fd);
  w->fd = -1;
  w->tmp[0] = '\0';
}

int dtm_atomic_write_text(const char *path, const char *text, int add_newline) {
  dtm_atomic w;
  DTM_CHECK(dtm_atomic_open(&w, path, "", 1));
  fputs(text, w.f);
  if (add_newline) fputc('\n', w.f);
  return dtm_atomic_commit(&w);
}
