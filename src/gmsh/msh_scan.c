/* What a .msh file says it holds, read from its section headers without
 * Gmsh, so that a mesh too big for the machine, or whose headers promise
 * more than the file can contain (a truncated or corrupt file), is refused
 * before Gmsh allocates for it. Understands MSH 2 and 4 (ASCII and binary:
 * the $MeshFormat line says which) and MSH 1 ($NOD, $ELM). The file is
 * streamed once, 1 MB at a time, looking for the section lines; this costs
 * a small fraction of Gmsh's own reading of it. The scan also checks what
 * Gmsh 4.8 trusts and then crashes or loops on (both found by
 * tests/fuzz/msh.c): a $PhysicalNames entry whose dimension is not 0 to 3
 * (a segmentation fault in GModel::setPhysicalName reading MSH 4), and a
 * block of a binary MSH 2 $Elements section that announces more elements
 * than the section has (Gmsh reads on past the end of the file, logging
 * an error for each of up to 2^31 elements). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "gmsh-impl.h"

#define CHUNK (1 << 20)
#define KEEP 16 /* bytes kept across chunks so a section line is never split */

/* The count a section header gives, from the bytes after its line: MSH 1
 * and 2 write it alone, MSH 4 second (after the number of entity blocks),
 * in ASCII, or as binary size_t (dsize bytes) when the file is binary. */
static size_t header_count(const dtm_msh_head *h, const unsigned char *p, size_t n) {
  if (h->version >= 4 && h->binary) {
    uint64_t v64 = 0;
    uint32_t v32 = 0;
    if (h->dsize == 8 && n >= 16) return memcpy(&v64, p + 8, 8), (size_t)v64;
    if (h->dsize == 4 && n >= 8) return memcpy(&v32, p + 4, 4), (size_t)v32;
    return 0;
  }
  char text[128];
  size_t k = n < sizeof text - 1 ? n : sizeof text - 1;
  memcpy(text, p, k);
  text[k] = '\0';
  char *end = text;
  unsigned long long v = strtoull(text, &end, 10);
  if (h->version >= 4) v = strtoull(end, NULL, 10);
  return (size_t)v;
}

/* Read the header count of the section whose data starts at offset. */
static void read_count(FILE *f, dtm_msh_head *h, long long offset, size_t *count, int *found) {
  unsigned char b[128];
  long long back = ftell(f);
  if (fseek(f, (long)offset, SEEK_SET)) return;
  size_t n = fread(b, 1, sizeof b, f);
  *count = header_count(h, b, n);
  *found = 1;
  fseek(f, (long)back, SEEK_SET);
}

/* Line number (from 1) of file offset off. */
static long long line_of(FILE *f, long long off) {
  char b[1 << 16];
  long long line = 1, done = 0, back = ftell(f);
  rewind(f);
  while (done < off) {
    size_t want = off - done < (long long)sizeof b ? (size_t)(off - done) : sizeof b;
    size_t got = fread(b, 1, want, f);
    if (!got) break;
    for (size_t i = 0; i < got; i++) line += b[i] == '\n';
    done += (long long)got;
  }
  fseek(f, (long)back, SEEK_SET);
  return line;
}

/* The $PhysicalNames section whose data starts at offset: every entry's
 * dimension must be 0 to 3; h->problem says which is not. */
static void check_names(FILE *f, dtm_msh_head *h, long long offset) {
  char line[512];
  long long back = ftell(f);
  if (fseek(f, (long)offset, SEEK_SET) || !fgets(line, sizeof line, f)) return;
  long n = strtol(line, NULL, 10);
  for (long i = 1; i <= n && fgets(line, sizeof line, f) && line[0] != '$'; i++) {
    long dim = strtol(line, NULL, 10);
    if (dim >= 0 && dim <= 3) continue;
    h->problem_line = line_of(f, offset) + i;
    snprintf(h->problem, sizeof h->problem, "$PhysicalNames: a physical group of dimension %ld (need 0 to 3)", dim);
    break;
  }
  fseek(f, (long)back, SEEK_SET);
}

int dtm_msh_type_nodes(int t) {
  static const int nn[] = {0, 2,  3,  4,  4, 8,  6,  5,  3,  6,  9, 10, 27, 18, 14, 1,
                           8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5,  6,  20, 35, 56};
  return t > 0 && t < (int)(sizeof nn / sizeof *nn) ? nn[t] : 0;
}

/* Walk the blocks of a binary MSH 2 $Elements section (data at offset:
 * the ASCII count line, then blocks of int32 type, count, tags and their
 * elements): each must hold at least one and at most the elements left. */
static void check_blocks(FILE *f, dtm_msh_head *h, long long offset) {
  char line[128];
  long long back = ftell(f);
  size_t done = 0;
  if (fseek(f, (long)offset, SEEK_SET) || !fgets(line, sizeof line, f)) return;
  while (done < h->elements) {
    int32_t hd[3];
    long long at = ftell(f);
    if (fread(hd, sizeof hd, 1, f) != 1) break; /* truncated: Gmsh says so */
    if (hd[1] <= 0 || (size_t)hd[1] > h->elements - done || hd[2] < 0 || hd[2] > 1000) {
      snprintf(h->problem, sizeof h->problem,
               "binary $Elements: a block at byte %lld announces %d elements with %d tags, where %zu remain", at,
               (int)hd[1], (int)hd[2], h->elements - done);
      break;
    }
    int nn = dtm_msh_type_nodes(hd[0]);
    if (!nn || fseek(f, (long)hd[1] * (1 + hd[2] + nn) * 4, SEEK_CUR)) break;
    done += (size_t)hd[1];
  }
  fseek(f, (long)back, SEEK_SET);
}

/* A section line "\n$NAME\n" (or "\r\n") at p (p[0] == '\n'), pointing
 * *data past it; 0 when p starts no such line. */
static int section_at(const char *p, const char *end, const char *name, const char **data) {
  size_t n = strlen(name);
  if ((size_t)(end - p) < n + 2 || memcmp(p + 1, name, n)) return 0;
  const char *q = p + 1 + n;
  if (*q == '\r') q++;
  if (q >= end || *q != '\n') return 0;
  *data = q + 1;
  return 1;
}

/* One buffer of the file (buf starts at file offset base): look for the
 * node and element sections. */
static void scan_buffer(FILE *f, dtm_msh_head *h, const char *buf, size_t n, long long base) {
  const char *end = buf + n, *p = buf, *data;
  const char *nodes = h->version < 2 ? "$NOD" : "$Nodes", *elems = h->version < 2 ? "$ELM" : "$Elements";
  while ((p = memchr(p, '\n', (size_t)(end - p))) && p + 1 < end) {
    if (p[1] == '$' && !h->have_nodes && section_at(p, end, nodes, &data))
      read_count(f, h, base + (data - buf), &h->nodes, &h->have_nodes);
    else if (p[1] == '$' && !h->have_elements && section_at(p, end, elems, &data)) {
      read_count(f, h, base + (data - buf), &h->elements, &h->have_elements);
      if (h->version < 3 && h->binary && !h->problem[0]) check_blocks(f, h, base + (data - buf));
    } else if (p[1] == '$' && !h->problem[0] && section_at(p, end, "$PhysicalNames", &data))
      check_names(f, h, base + (data - buf));
    p++;
  }
}

/* The $MeshFormat line (MSH 2 and 4), or MSH 1 when the file starts with
 * $NOD; -1 when the file is not a mesh this scan understands. */
static int read_format(FILE *f, dtm_msh_head *h) {
  char line[256];
  if (!fgets(line, sizeof line, f)) return -1;
  if (!strncmp(line, "$NOD", 4)) return h->version = 1, 0;
  if (strncmp(line, "$MeshFormat", 11) || !fgets(line, sizeof line, f)) return -1;
  if (sscanf(line, "%lf %d %d", &h->version, &h->binary, &h->dsize) != 3) return -1;
  return h->version >= 1 && h->version < 5 ? 0 : -1;
}

static void scan_file(FILE *f, dtm_msh_head *h) {
  char *buf = malloc(CHUNK + KEEP);
  size_t kept = 1, got;
  long long base = -1; /* file offset of buf[0] */
  if (!buf) return;
  buf[0] = '\n'; /* the first line is a line start too */
  rewind(f);
  while ((got = fread(buf + kept, 1, CHUNK, f)) > 0) {
    scan_buffer(f, h, buf, kept + got, base);
    if (h->have_nodes && h->have_elements && h->version >= 4) break; /* names come first in MSH 4 */
    size_t keep = kept + got < KEEP ? kept + got : KEEP;
    memmove(buf, buf + kept + got - keep, keep);
    base += (long long)(kept + got - keep);
    kept = keep;
  }
  free(buf);
}

int dtm_msh_scan(const char *path, dtm_msh_head *h) {
  struct stat st;
  memset(h, 0, sizeof *h);
  FILE *f = fopen(path, "rb");
  if (!f) return -1;
  if (fstat(fileno(f), &st) || read_format(f, h)) return fclose(f), -1;
  h->bytes = (long long)st.st_size;
  scan_file(f, h);
  fclose(f);
  return 0;
}
