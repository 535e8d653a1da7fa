/* Checking an output path before any work is done, so that a run that could
 * not write its result fails in a second rather than after meshing and
 * analysing: the path names a file (not a directory or a device), its
 * directory exists and accepts a new file (tried by creating and removing
 * a hidden probe beside the target, which also covers read-only file
 * systems and root, for whom access() says yes), it is none of the
 * scene's inputs, and it has the extension the writer needs. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dtmap/output.h"
#include "dtmap/util.h"

static int same_file(const char *a, const char *b) {
  struct stat sa, sb;
  if (!a || !b || stat(a, &sa) || stat(b, &sb)) return 0;
  return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

static int fail(const char *origin, const char *path, const char *reason, const char *arg) {
  return DTM_ERR(DTM_ERR_INPUT, "%s%s%s: %s%s", origin ? origin : "", origin ? " " : "", path, reason, arg ? arg : "");
}

/* The directory of path into dir ("." when it has none). */
static void dir_of(const char *path, char *dir, size_t len) {
  const char *slash = strrchr(path, '/');
  if (!slash)
    snprintf(dir, len, ".");
  else
    snprintf(dir, len, "%.*s", slash == path ? 1 : (int)(slash - path), path);
}

/* Create and remove a hidden file in dir; 0 or errno. */
static int probe(const char *dir) {
  char p[DTM_PATH_MAX + 64];
  snprintf(p, sizeof p, "%s/.dtmap-probe.tmp%ld", dir, (long)getpid());
  int fd = open(p, O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) return errno;
  close(fd);
  unlink(p);
  return 0;
}

static int check_dir(const char *origin, const char *path) {
  char dir[DTM_PATH_MAX], why[DTM_PATH_MAX + 256];
  struct stat st;
  dir_of(path, dir, sizeof dir);
  if (stat(dir, &st)) {
    snprintf(why, sizeof why, "the directory '%s' %s", dir, errno == ENOENT ? "does not exist" : strerror(errno));
    return fail(origin, path, why, NULL);
  }
  if (!S_ISDIR(st.st_mode)) return fail(origin, path, "not a directory: ", dir);
  int e = probe(dir);
  if (e) {
    snprintf(why, sizeof why, "cannot create a file in the directory '%s': %s", dir, strerror(e));
    return fail(origin, path, why, NULL);
  }
  return DTM_OK;
}

static int has_ext(const char *path, const char *ext) {
  size_t n = strlen(path), k = strlen(ext);
  return n > k && !strcmp(path + n - k, ext);
}

int dtm_output_path_check(const dtm_scene *s, const char *path, const char *ext, const char *origin) {
  struct stat st;
  if (!path || !path[0]) return fail(origin, "''", "names no file", NULL);
  if (strlen(path) >= DTM_PATH_MAX - 64) return fail(origin, path, "the path is too long", NULL);
  if (ext && !has_ext(path, ext)) return fail(origin, path, "the file name must end in ", ext);
  if (!stat(path, &st) && S_ISDIR(st.st_mode)) return fail(origin, path, "is a directory", NULL);
  if (!stat(path, &st) && !S_ISREG(st.st_mode)) return fail(origin, path, "exists and is not a regular file", NULL);
  if (s && (same_file(path, s->path) || same_file(path, s->mesh) || same_file(path, s->geometry)))
    return fail(origin, path, "is an input of the scene: refusing to overwrite it (choose another output)", NULL);
  return check_dir(origin, path);
}
