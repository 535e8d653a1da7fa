/* A views-only copy of a result .msh, for merging into a Gmsh session that
 * already holds the same mesh: the $MeshFormat section and every data
 * section ($NodeData, $ElementData, $ElementNodeData) are kept, the mesh
 * sections dropped, so Gmsh attaches the views to the elements and nodes it
 * has (same tags) instead of loading a second model. Sections are found by
 * their "$Name" and "$EndName" lines, which also delimit binary data. The
 * .opt beside the result is copied beside the copy. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/util.h"
#include "onelab-impl.h"

static int read_file(const char *path, char **buf, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return DTM_ERR(DTM_ERR_INPUT, "%s: cannot read it", path);
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  *buf = malloc((size_t)(n > 0 ? n : 0) + 1);
  size_t got = *buf ? fread(*buf, 1, (size_t)(n > 0 ? n : 0), f) : 0;
  fclose(f);
  if (!*buf || n < 0 || got != (size_t)n)
    return free(*buf), *buf = NULL, DTM_ERR(DTM_ERR_INPUT, "%s: cannot read it", path);
  (*buf)[n] = '\0';
  *len = (size_t)n;
  return DTM_OK;
}

/* First occurrence of pat (m bytes) in s (n bytes), or NULL. */
static const char *find(const char *s, size_t n, const char *pat, size_t m) {
  for (const char *p = s; m <= n && p <= s + n - m; p++) {
    p = memchr(p, pat[0], (size_t)(s + n - m - p) + 1);
    if (!p) return NULL;
    if (!memcmp(p, pat, m)) return p;
  }
  return NULL;
}

static int keep(const char *name, size_t n) {
  static const char *const kept[] = {"MeshFormat", "NodeData", "ElementData", "ElementNodeData"};
  for (size_t i = 0; i < sizeof kept / sizeof *kept; i++)
    if (strlen(kept[i]) == n && !strncmp(kept[i], name, n)) return 1;
  return 0;
}

/* Copy the kept sections of buf[0..len) to f. */
static int filter(const char *path, const char *buf, size_t len, FILE *f) {
  size_t at = 0;
  while (at < len && buf[at] == '$') {
    const char *name = buf + at + 1;
    size_t n = strcspn(name, "\r\n");
    char end[96];
    snprintf(end, sizeof end, "\n$End%.*s", (int)(n < 80 ? n : 80), name);
    const char *stop = find(name, len - at - 1, end, strlen(end));
    if (!stop) return DTM_ERR(DTM_ERR_INPUT, "%s: section $%.*s has no end", path, (int)n, name);
    size_t next = (size_t)(stop - buf) + strlen(end);
    while (next < len && (buf[next] == '\r' || buf[next] == '\n')) next++;
    if (keep(name, n)) fwrite(buf + at, 1, next - at, f);
    at = next;
  }
  return DTM_OK;
}

static int copy_opt(const char *msh, const char *out) {
  char src[DTM_PATH_MAX + 8], dst[DTM_PATH_MAX + 8], *text = NULL;
  size_t len;
  snprintf(src, sizeof src, "%s.opt", msh);
  snprintf(dst, sizeof dst, "%s.opt", out);
  DTM_CHECK(read_file(src, &text, &len));
  int r = dtm_atomic_write_text(dst, text, 0);
  free(text);
  return r;
}

int dtm_ol_views_only(const char *msh, const char *out) {
  char *buf = NULL;
  size_t len = 0;
  dtm_atomic w;
  DTM_CHECK(read_file(msh, &buf, &len));
  int r = dtm_atomic_open(&w, out, ".msh", 1);
  if (r == DTM_OK) {
    r = filter(msh, buf, len, w.f);
    r = r ? (dtm_atomic_abort(&w), r) : dtm_atomic_commit(&w);
  }
  free(buf);
  return r ? r : copy_opt(msh, out);
}
