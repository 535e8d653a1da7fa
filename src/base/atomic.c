/* Atomic output files: every file dtmap writes (mesh, .opt, report, CSV,
 * plot) goes to a temporary in the target's directory, named
 * .BASE.tmpPID<suffix>, and is renamed over the target only once it is
 * complete; on any failure the temporary is removed and the target, if it
 * existed, is untouched. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/util.h"

static void temp_name(const char *path, const char *suffix, char *out, size_t len) {
  const char *slash = strrchr(path, '/');
  int dirlen = slash ? (int)(slash - path + 1) : 0;
  snprintf(out, len, "%.*s.%s.tmp%ld%s", dirlen, path, slash ? slash + 1 : path, (long)getpid(), suffix);
}

int dtm_atomic_open(dtm_atomic *w, const char *path, const char *suffix, int stream) {
  w->f = NULL;
  w->tmp[0] = '\0';
  if ((size_t)snprintf(w->path, sizeof w->path, "%s", path) >= sizeof w->path)
    return DTM_ERR(DTM_ERR_INPUT, "%s: the path is too long", path);
  temp_name(path, suffix, w->tmp, sizeof w->tmp);
  if (!stream) return DTM_OK;
  w->f = fopen(w->tmp, "w");
  if (!w->f) {
    int e = errno;
    w->tmp[0] = '\0';
    return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", path, strerror(e));
  }
  return DTM_OK;
}

int dtm_atomic_commit(dtm_atomic *w) {
  int e = 0;
  if (w->f) {
    if (ferror(w->f)) e = errno ? errno : EIO;
    if (fclose(w->f) != 0 && !e) e = errno ? errno : EIO;
    w->f = NULL;
  }
  if (!e && rename(w->tmp, w->path)) e = errno;
  if (!e) return w->tmp[0] = '\0', DTM_OK;
  dtm_atomic_abort(w);
  return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", w->path, strerror(e));
}

void dtm_atomic_abort(dtm_atomic *w) {
  if (w->f) fclose(w->f);
  w->f = NULL;
  if (w->tmp[0]) unlink(w->tmp);
  w->tmp[0] = '\0';
}

int dtm_atomic_write_text(const char *path, const char *text, int add_newline) {
  dtm_atomic w;
  DTM_CHECK(dtm_atomic_open(&w, path, "", 1));
  fputs(text, w.f);
  if (add_newline) fputc('\n', w.f);
  return dtm_atomic_commit(&w);
}
