/* The output's mesh as the bytes of the input .msh it was read from, when
 * Gmsh would write the same mesh: `run` on a .msh changes neither nodes
 * nor elements, so writing them again through Gmsh (its writer builds
 * per-entity arrays of the whole mesh, 650 MB and several seconds of CPU
 * at 1e7 tets, while its model of about 1 GB stays alive) only re-encodes
 * what the file already holds. The copy is taken only where it is the mesh
 * Gmsh would write with dtmap's options (Mesh.SaveAll, MSH 4.1, the
 * output's encoding):
 *  - the model is the file's, unchanged since it was read (no unit
 *    scaling, no remeshing: dtm_gmsh_source_unchanged);
 *  - the file is MSH 4.1 with the output's encoding (and 8-byte sizes when
 *    binary);
 *  - its sections before the first view are mesh sections Gmsh writes back
 *    as it reads them ($MeshFormat, $PhysicalNames, $Entities, $Nodes,
 *    $Elements, $Periodic, and comments); a partitioned or parametrised
 *    mesh ($PartitionedEntities, $GhostElements, $Parametrizations) is left
 *    to Gmsh, and so is a file without $EndElements.
 * What differs from Gmsh's own write: the entities' bounding boxes in
 * $Entities are the file's, where Gmsh recomputes them from the mesh (on
 * the 1e7-tet box every other section, views included, came out byte for
 * byte the same).
 * The views a file may hold (a former dtmap output) are not copied: the
 * copy ends where the first $NodeData, $ElementData, $ElementNodeData or
 * $InterpolationScheme begins, and the new views are appended after it.
 * Section lines are found as msh_scan.c finds them, a line that is exactly
 * "$Name" (binary data would have to hold such a line between two line
 * feeds to be mistaken for one). Two passes: one to find where the mesh
 * ends, then the kernel copies that many bytes (copy_file_range, no pass
 * through this process's memory). */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "gmsh-impl.h"

#define CHUNK (4 << 20)
#define KEEP 32 /* bytes kept across chunks: the longest section line fits */

static const char *const views[] = {"NodeData", "ElementData", "ElementNodeData", "InterpolationScheme"};
static const char *const refused[] = {"PartitionedEntities", "GhostElements", "Parametrizations"};

/* Whether the line starting at p (after its '\n') is "$name" exactly. */
static int line_is(const char *p, const char *end, const char *name) {
  size_t n = strlen(name);
  if ((size_t)(end - p) < n + 2 || p[0] != '$' || memcmp(p + 1, name, n)) return 0;
  const char *q = p + 1 + n;
  if (q < end && *q == '\r') q++;
  return q < end && *q == '\n';
}

static int line_in(const char *p, const char *end, const char *const *names, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (line_is(p, end, names[i])) return 1;
  return 0;
}

/* What the scan found: where the mesh ends (the first view's line, or the
 * end of the file), whether $EndElements came before it, and whether a
 * section Gmsh would not write back as it is came first. */
typedef struct {
  long long end;
  int elements_done, refused;
} extent;

/* One buffer (buf[0] at file offset base); 1 once the mesh's end is found. */
static int scan(const char *buf, size_t n, long long base, extent *x) {
  const char *end = buf + n, *p = buf;
  while ((p = memchr(p, '\n', (size_t)(end - p))) && ++p < end) {
    if (*p != '$') continue;
    if (line_in(p, end, views, sizeof views / sizeof *views)) return x->end = base + (p - buf), 1;
    if (line_in(p, end, refused, sizeof refused / sizeof *refused)) return x->refused = 1;
    if (line_is(p, end, "EndElements")) x->elements_done = 1;
  }
  return 0;
}

/* The mesh's extent in f (after its format lines), or x->refused. */
static void find_extent(FILE *f, long long size, extent *x) {
  char *buf = malloc(CHUNK + KEEP);
  size_t kept = 1, got;
  long long base = -1; /* file offset of buf[0] */
  *x = (extent){size, 0, !buf};
  if (!buf) return;
  buf[0] = '\n';
  rewind(f);
  while (!x->refused && (got = fread(buf + kept, 1, CHUNK, f)) > 0) {
    if (scan(buf, kept + got, base, x)) break;
    size_t keep = kept + got < KEEP ? kept + got : KEEP;
    memmove(buf, buf + kept + got - keep, keep);
    base += (long long)(kept + got - keep);
    kept = keep;
  }
  free(buf);
}

/* Whether f starts "$MeshFormat\n4.1 <binary> <8 when binary>". */
static int format_matches(FILE *f, int binary) {
  char line[256];
  double version;
  int type, dsize;
  if (!fgets(line, sizeof line, f) || strncmp(line, "$MeshFormat", 11) || !fgets(line, sizeof line, f)) return 0;
  if (sscanf(line, "%lf %d %d", &version, &type, &dsize) != 3) return 0;
  return version == 4.1 && type == binary && (!binary || dsize == 8);
}

/* Copy the first n bytes of in to out (both at offset 0). */
static int copy_bytes(int in, int out, long long n) {
  loff_t off_in = 0, off_out = 0;
  while (n > 0) {
    ssize_t c = copy_file_range(in, &off_in, out, &off_out, (size_t)(n < (1LL << 30) ? n : 1LL << 30), 0);
    if (c < 0 && (errno == EXDEV || errno == ENOSYS || errno == EOPNOTSUPP || errno == EINVAL) && off_in == 0)
      return 1; /* not on this file system: the caller copies otherwise */
    if (c <= 0) return -1;
    n -= c;
  }
  return 0;
}

/* The same through a buffer, where copy_file_range cannot. */
static int copy_plain(int in, int out, long long n) {
  char *buf = malloc(CHUNK);
  int r = buf ? 0 : -1;
  if (lseek(in, 0, SEEK_SET) || lseek(out, 0, SEEK_SET) || ftruncate(out, 0)) r = -1;
  while (!r && n > 0) {
    ssize_t c = read(in, buf, (size_t)(n < CHUNK ? n : CHUNK));
    if (c <= 0 || write(out, buf, (size_t)c) != c) r = -1;
    n -= c > 0 ? c : 0;
  }
  free(buf);
  return r;
}

long long dtm_msh_mesh_extent(const char *src, int binary) {
  struct stat st;
  extent x = {0, 0, 1};
  FILE *f = fopen(src, "rb");
  if (!f) return -1; /* Gmsh's writer then */
  if (!fstat(fileno(f), &st) && format_matches(f, binary)) find_extent(f, (long long)st.st_size, &x);
  fclose(f);
  return x.refused || !x.elements_done ? -1 : x.end;
}

int dtm_msh_copy_bytes(const char *src, const char *dst, long long n) {
  int in = open(src, O_RDONLY), out = open(dst, O_WRONLY | O_CREAT | O_TRUNC, 0666), r = -1;
  if (in >= 0 && out >= 0) r = copy_bytes(in, out, n);
  if (r > 0) r = copy_plain(in, out, n);
  int err = errno;
  if (in >= 0) close(in);
  if (out >= 0 && close(out) && !r) r = -1, err = errno;
  if (r) return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write the mesh: %s", dst, strerror(err ? err : EIO));
  return DTM_OK;
}
