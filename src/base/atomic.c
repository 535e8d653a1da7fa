/* Atomic output files: every file dtmap writes (mesh, .opt, report, CSV,
 * plot) is written whole before it gets its name. Its data goes to an
 * unnamed file (O_TMPFILE) in the target's directory, which the kernel
 * removes with the last descriptor, so a killed run (SIGKILL, the OOM
 * killer, a power cut) leaves no data behind; it is linked in as
 * .BASE.tmpPID<suffix> only once complete and at once put in place: swapped
 * with the target when that is a regular file (the older file then removed
 * from the temporary's name), else renamed over it. On any failure it is
 * dropped and the target, if it existed, is untouched.
 *
 * Libraries (Gmsh, PLplot) write files by name, so the temporary also has
 * a name while it is open: .BASE.tmpPID<suffix>, a symbolic link to the
 * unnamed file through /proc (a name whose extension tells Gmsh the
 * format), which holds no data. The links in use are listed, so a
 * SIGINT/SIGTERM/SIGHUP handler removes them (dtm_atomic_cleanup_signal,
 * async-signal-safe), and the list can live in memory shared with a
 * supervising parent (dtm_atomic_share), which removes them after a worker
 * died by a signal it could not handle. What a process killed with its
 * parent leaves (a link to nothing) is removed by the next writer of the
 * same target, with the temporaries of killed runs that wrote by name: on
 * a file system without O_TMPFILE the temporary is a plain file as before,
 * held under an exclusive flock() from creation to rename, and removed
 * when no process holds it and its PID no longer runs (both, so a
 * temporary that is being created is never taken for stale).
 *
 * A write that fails names the target (not only its temporary) and the
 * reason. stdio's errno of the first failed write may be overwritten by the
 * time the error is noticed, so the reason is what the system says when the
 * stream is flushed, or written to, again (the temporary is given up
 * anyway). A file a library wrote by name (Gmsh, PLplot: they do not check
 * their writes) counts as failed when the evidence says so: it reached the
 * process's file size limit, or its file system has no space left. */
#define _GNU_SOURCE /* O_TMPFILE, flock() */
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

#include "base.h"

#define CAUSE_UNKNOWN DTM_WRITE_CAUSE_UNKNOWN /* a write failed, but writing again succeeds */
#define SLOT (DTM_PATH_MAX + 64)              /* bytes of one listed name: a flag byte, then the name */
#define OWN_SLOTS 8                           /* names listed in this process's own memory */

static char own_list[OWN_SLOTS][SLOT];
static char (*active)[SLOT] = own_list; /* the names in use: slot[0] = 1, the name from slot + 1 */
static size_t nactive = OWN_SLOTS;

void dtm_atomic_share(void *area, size_t bytes) {
  active = area ? (char(*)[SLOT])area : own_list;
  nactive = area ? bytes / SLOT : OWN_SLOTS;
  for (size_t i = 0; area && i < nactive; i++) active[i][0] = 0;
}

/* The flag is set after the name and cleared before it changes, so a
 * process that reads the list after this one died reads whole names. */
static void track(const char *tmp) {
  for (size_t i = 0; i < nactive; i++)
    if (!active[i][0]) {
      size_t n = strnlen(tmp, SLOT - 2);
      memcpy(active[i] + 1, tmp, n), active[i][n + 1] = '\0';
      __atomic_store_n(&active[i][0], 1, __ATOMIC_RELEASE);
      return;
    }
}

static void untrack(const char *tmp) {
  for (size_t i = 0; i < nactive; i++)
    if (active[i][0] && !strcmp(active[i] + 1, tmp)) __atomic_store_n(&active[i][0], 0, __ATOMIC_RELEASE);
}

void dtm_atomic_cleanup_signal(void) {
  for (size_t i = 0; i < nactive; i++)
    if (__atomic_load_n(&active[i][0], __ATOMIC_ACQUIRE)) unlink(active[i] + 1);
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

/* Remove file when its writer is gone: a link when it leads nowhere (the
 * descriptor it names through /proc is closed: the writer ended, even as
 * a zombie its new parent has not reaped yet, whose PID still answers)
 * and its PID is gone or ours to signal (another user's process may only
 * be hidden from this /proc); a plain file when pid does not run and no
 * process holds its lock. */
static void remove_if_stale(const char *file, long pid) {
  struct stat st, to;
  if (pid == (long)getpid() || lstat(file, &st)) return;
  int mine = kill((pid_t)pid, 0) == 0, gone = !mine && errno == ESRCH;
  if (S_ISLNK(st.st_mode)) {
    if ((gone || mine) && stat(file, &to) && errno == ENOENT) unlink(file);
    return;
  }
  if (!gone) return;
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

/* Close and remove whatever w holds. */
static void drop(dtm_atomic *w) {
  if (w->f) fclose(w->f);
  w->f = NULL;
  if (w->tmp[0]) unlink(w->tmp), untrack(w->tmp);
  if (w->fd >= 0) close(w->fd);
  w->fd = -1;
  w->tmp[0] = '\0';
}

static int open_fail(dtm_atomic *w, const char *path, int e) {
  drop(w);
  return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", path, strerror(e));
}

/* An unnamed file in path's directory, named w->tmp through a link to it:
 * 0, or the errno (EOPNOTSUPP and the like: the file system has none). */
static int open_unnamed(dtm_atomic *w, const char *path) {
  const char *slash = strrchr(path, '/');
  char dir[DTM_PATH_MAX], target[64];
  snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) + (slash == path) : 1, slash ? path : ".");
  w->fd = open(dir, O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
  if (w->fd < 0) return errno;
  snprintf(target, sizeof target, "/proc/%ld/fd/%d", (long)getpid(), w->fd);
  int e = symlink(target, w->tmp) ? errno : 0;
  if (e == EEXIST && !unlink(w->tmp)) /* left by a killed process that had this PID */
    e = symlink(target, w->tmp) ? errno : 0;
  if (!e) return w->unnamed = 1, 0;
  close(w->fd), w->fd = -1;
  return e;
}

/* A plain temporary under its lock (file systems without O_TMPFILE). */
static int open_named(dtm_atomic *w) {
  w->fd = open(w->tmp, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (w->fd < 0) return errno;
  return flock(w->fd, LOCK_EX | LOCK_NB) ? errno : 0;
}

int dtm_atomic_open(dtm_atomic *w, const char *path, const char *suffix, int stream) {
  w->f = NULL;
  w->fd = -1;
  w->tmp[0] = '\0';
  w->unnamed = 0;
  if ((size_t)snprintf(w->path, sizeof w->path, "%s", path) >= sizeof w->path)
    return DTM_ERR(DTM_ERR_INPUT, "%s: the path is too long", path);
  remove_stale(path);
  temp_name(path, suffix, w->tmp, sizeof w->tmp);
  int e = open_unnamed(w, path);
  if (e && (e = open_named(w)) != 0) { /* no O_TMPFILE, or no link: a plain file, or the reason */
    if (w->fd >= 0) close(w->fd), w->fd = -1, unlink(w->tmp);
    w->tmp[0] = '\0';
    return open_fail(w, path, e);
  }
  track(w->tmp);
  int sfd = stream ? dup(w->fd) : -1;
  if (stream && (sfd < 0 || !(w->f = fdopen(sfd, "w")))) {
    e = errno;
    if (sfd >= 0) close(sfd);
    return open_fail(w, path, e);
  }
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

/* Give the unnamed file the name of its link (the link goes first). */
static int link_in(dtm_atomic *w) {
  char self[64];
  snprintf(self, sizeof self, "/proc/self/fd/%d", w->fd);
  if (unlink(w->tmp) && errno != ENOENT) return errno;
  return linkat(AT_FDCWD, self, AT_FDCWD, w->tmp, AT_SYMLINK_FOLLOW) ? errno : 0;
}

/* Put the complete temporary in place of the target. A regular file
 * already there is swapped with it (one atomic exchange: the name always
 * holds the older file or the new one), then the older file, now under the
 * temporary's name, is removed. A plain rename over an existing file makes
 * ext4 allocate the new file's blocks before it returns (its guard for
 * programs that replace files without fsync: 50 ms for a 114 MB mesh, a
 * fifth of everything dtmap adds to Gmsh's meshing of 1e6 tets); Gmsh's own
 * writes, which truncate the file in place, do not pay that. A target that
 * does not exist yet, is not a regular file, or lies on a file system
 * without the exchange is renamed over as before. */
static int put_in_place(const dtm_atomic *w) {
  struct stat st;
  if (!lstat(w->path, &st) && S_ISREG(st.st_mode) && !renameat2(AT_FDCWD, w->tmp, AT_FDCWD, w->path, RENAME_EXCHANGE)) {
    unlink(w->tmp); /* the older file; if this fails, the next writer of the target removes it */
    return 0;
  }
  return rename(w->tmp, w->path) ? errno : 0;
}

int dtm_atomic_commit(dtm_atomic *w) {
  char why[256];
  int e = write_status(w);
  if (!e && w->unnamed) e = link_in(w);
  if (!e) e = put_in_place(w);
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

void dtm_atomic_abort(dtm_atomic *w) { drop(w); }

int dtm_atomic_write_text(const char *path, const char *text, int add_newline) {
  dtm_atomic w;
  DTM_CHECK(dtm_atomic_open(&w, path, "", 1));
  fputs(text, w.f);
  if (add_newline) fputc('\n', w.f);
  return dtm_atomic_commit(&w);
}

int dtm_scratch_fd(void) {
  const char *dir = getenv("TMPDIR");
  char path[DTM_PATH_MAX];
  if (!dir || !dir[0]) dir = "/tmp";
  int fd = open(dir, O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd >= 0) return fd;
  snprintf(path, sizeof path, "%s/dtmap-scratch-XXXXXX", dir);
  fd = mkostemp(path, O_CLOEXEC);
  if (fd >= 0) unlink(path);
  return fd;
}

int dtm_scratch_named(dtm_atomic *w, const char *base, const char *suffix) {
  const char *dir = getenv("TMPDIR");
  char path[DTM_PATH_MAX];
  snprintf(path, sizeof path, "%s/%s", dir && dir[0] ? dir : "/tmp", base);
  return dtm_atomic_open(w, path, suffix, 0);
}
