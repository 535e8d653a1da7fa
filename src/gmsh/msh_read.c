/* The nodes and elements of an MSH 4.1 file read by dtmap itself, on a
 * thread of its own while Gmsh reads the same file (session.c), so that
 * extraction takes them from here instead of listing Gmsh's model through
 * its C API: that listing is serial, grows its vectors by copying, and is
 * copied once more into the C arrays (at 1e7 tets 0.7-1.2 s, most of the
 * extraction, while the second core waited for Gmsh's read).
 *
 * Only what extraction would get from Gmsh is kept, in Gmsh's order:
 * - nodes: every $Nodes block, which must come in Gmsh's entity order
 *   (dimension, then tag, each entity once), as gmsh/model/mesh/getNodes
 *   lists them; the parametric coordinates are skipped;
 * - elements: one array of tags and one of node tags per $Elements block,
 *   the blocks sorted by entity and type for extraction's look-up
 *   ((entity, type) at most once per family: Gmsh keeps one list of each
 *   family per entity and would list a mixed-order entity as one type).
 * Anything else this reader does not take on is left to Gmsh's listing:
 * another version or data size, a partitioned or parametrised mesh, a
 * type it does not know, a block out of order, a malformed number. Gmsh
 * still reads the file and judges it: the reading here never raises an
 * error, it only succeeds or not; session.c then checks its counts against
 * Gmsh's model (dtm_gmsh_parsed_take) before extraction trusts it.
 *
 * Numbers: binary data is copied as it is (little-endian, 8-byte sizes:
 * the $MeshFormat's check integer says so); ASCII coordinates go through
 * strtod, as Gmsh's fscanf("%lf") does, so both give the same doubles. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "gmsh-impl.h"

_Static_assert(sizeof(size_t) == 8, "binary sizes are copied into size_t");

#define CHUNK (4 << 20) /* bytes read at a time */
#define TOKEN 128       /* longest ASCII number taken */

/* The family of MSH element type t (0 point, 1 line, 2 triangle, 3
 * quadrangle, 4 tetrahedron, 5 hexahedron, 6 prism, 7 pyramid), -1 when
 * this reader does not know t. */
static int family_of(int t) {
  static const signed char fam[] = {-1, 1, 2, 3, 4, 5, 6, 7, 1, 2, 3, 4, 5, 6, 7, 0,
                                    3,  5, 6, 7, 2, 2, 2, 2, 2, 2, 1, 1, 1, 4, 4, 4};
  return t > 0 && t < (int)sizeof fam ? fam[t] : -1;
}

/* A file read through a buffer; buf[len] is always '\0'. */
typedef struct {
  FILE *f;
  char *buf;
  size_t len, pos;
  int eof;
  int binary;
} reader;

/* At least want bytes from pos (fewer at the end of the file): 1 if so. */
static int fill(reader *r, size_t want) {
  if (r->len - r->pos >= want) return 1;
  memmove(r->buf, r->buf + r->pos, r->len - r->pos);
  r->len -= r->pos, r->pos = 0;
  while (r->len < CHUNK && !r->eof) {
    size_t got = fread(r->buf + r->len, 1, CHUNK - r->len, r->f);
    if (!got) r->eof = 1;
    r->len += got;
  }
  r->buf[r->len] = '\0';
  return r->len - r->pos >= want;
}

/* n bytes into dst (binary data). */
static int take_bytes(reader *r, void *dst, size_t n) {
  size_t have = r->len - r->pos < n ? r->len - r->pos : n;
  memcpy(dst, r->buf + r->pos, have);
  r->pos += have;
  if (have == n) return 0;
  return fread((char *)dst + have, 1, n - have, r->f) == n - have ? 0 : -1;
}

/* The next line (without its "\r\n"), *len its length; NULL at the end.
 * A line longer than the buffer is passed over in pieces (binary data
 * can hold such stretches; none of them is a line looked for). */
static const char *next_line(reader *r, size_t *len) {
  for (;;) {
    char *s = r->buf + r->pos, *nl = r->pos < r->len ? memchr(s, '\n', r->len - r->pos) : NULL;
    if (nl) {
      r->pos = (size_t)(nl - r->buf) + 1;
      *len = (size_t)(nl - s) - (nl > s && nl[-1] == '\r');
      return s;
    }
    if (r->eof) { /* the last line, without its line feed */
      *len = r->len - r->pos, r->pos = r->len;
      return *len ? s : NULL;
    }
    if (r->pos == 0 && r->len == CHUNK) r->pos = r->len;
    fill(r, CHUNK);
  }
}

static int line_is(const char *s, size_t n, const char *what) { return n == strlen(what) && !memcmp(s, what, n); }

static int is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

/* Past white space, with the next TOKEN bytes in the buffer. */
static void skip_space(reader *r) {
  for (;;) {
    fill(r, TOKEN);
    while (r->pos < r->len && is_space(r->buf[r->pos])) r->pos++;
    if (r->pos < r->len || r->eof) {
      fill(r, TOKEN);
      return;
    }
  }
}

static int ends_token(char c) { return is_space(c) || c == '\0'; }

/* An unsigned decimal integer (ASCII). */
static int ascii_size(reader *r, size_t *v) {
  skip_space(r);
  const char *p = r->buf + r->pos;
  uint64_t x = 0;
  int digits = 0;
  for (; *p >= '0' && *p <= '9' && digits < 19; p++, digits++) x = x * 10 + (uint64_t)(*p - '0');
  if (!digits || !ends_token(*p)) return -1;
  r->pos = (size_t)(p - r->buf);
  *v = (size_t)x;
  return 0;
}

/* A signed int (ASCII), for dimensions, entity tags and types. */
static int ascii_int(reader *r, int *v) {
  skip_space(r);
  int neg = r->buf[r->pos] == '-';
  size_t x;
  r->pos += (size_t)neg;
  if (ascii_size(r, &x) || x > INT32_MAX) return -1;
  *v = neg ? -(int)x : (int)x;
  return 0;
}

/* A number as strtod reads it; one of TOKEN characters or more may run
 * past the buffer, so it is not taken (Gmsh writes at most 25). */
static int ascii_double(reader *r, double *v) {
  skip_space(r);
  char *end;
  *v = strtod(r->buf + r->pos, &end);
  if (end == r->buf + r->pos || end - (r->buf + r->pos) >= TOKEN || !ends_token(*end)) return -1;
  r->pos = (size_t)(end - r->buf);
  return 0;
}

static int read_size(reader *r, size_t *v) {
  if (!r->binary) return ascii_size(r, v);
  uint64_t x;
  if (take_bytes(r, &x, 8)) return -1;
  *v = (size_t)x;
  return 0;
}

/* A block header: three ints (dimension, entity tag, parametric or type)
 * and a count. */
static int block_header(reader *r, int h[3], size_t *n) {
  if (r->binary) {
    int32_t b[3];
    if (take_bytes(r, b, sizeof b)) return -1;
    h[0] = b[0], h[1] = b[1], h[2] = b[2];
  } else if (ascii_int(r, &h[0]) || ascii_int(r, &h[1]) || ascii_int(r, &h[2])) {
    return -1;
  }
  return read_size(r, n);
}

/* The section header's counts (blocks, items, smallest and largest tag). */
static int section_header(reader *r, size_t c[4]) {
  for (int i = 0; i < 4; i++)
    if (read_size(r, &c[i])) return -1;
  return 0;
}

/* The line closing a section (after its data's line feed). */
static int section_end(reader *r, const char *what) {
  size_t n;
  const char *s;
  if (!r->binary) skip_space(r);
  do s = next_line(r, &n);
  while (s && n == 0);
  return s && line_is(s, n, what) ? 0 : -1;
}

/* Whether block (d, t) comes after (pd, pt) in Gmsh's entity order. */
static int after(int d, int t, int pd, int pt) { return d > pd || (d == pd && t > pt); }

static int node_block(reader *r, dtm_msh_parsed *p, size_t *at, int *pd, int *pt) {
  int h[3];
  size_t n;
  if (block_header(r, h, &n) || h[0] < 0 || h[0] > 3 || !after(h[0], h[1], *pd, *pt) || n > p->nnodes - *at) return -1;
  *pd = h[0], *pt = h[1];
  size_t per = 3 + (size_t)(h[2] ? h[0] : 0);
  size_t *tags = p->node_tags + *at;
  double *xyz = p->xyz + 3 * *at;
  if (r->binary && take_bytes(r, tags, n * sizeof *tags)) return -1;
  for (size_t i = 0; !r->binary && i < n; i++)
    if (ascii_size(r, &tags[i])) return -1;
  if (r->binary && per == 3) { /* the coordinates as they are */
    *at += n;
    return take_bytes(r, xyz, 3 * n * sizeof *xyz);
  }
  for (size_t i = 0; i < n; i++)
    for (size_t k = 0; k < per; k++) {
      double v;
      if (r->binary ? take_bytes(r, &v, sizeof v) : ascii_double(r, &v)) return -1;
      if (k < 3) xyz[3 * i + k] = v;
    }
  *at += n;
  return 0;
}

static int read_nodes(reader *r, dtm_msh_parsed *p, long long bytes) {
  size_t c[4], at = 0;
  int pd = -1, pt = 0;
  if (section_header(r, c) || c[1] > (size_t)bytes / (r->binary ? 32 : 8)) return -1; /* more than the file holds */
  p->nnodes = c[1];
  p->node_tags = malloc((c[1] + 1) * sizeof *p->node_tags);
  p->xyz = malloc((3 * c[1] + 1) * sizeof *p->xyz);
  if (!p->node_tags || !p->xyz) return -1;
  for (size_t b = 0; b < c[0]; b++)
    if (node_block(r, p, &at, &pd, &pt)) return -1;
  return at == p->nnodes ? section_end(r, "$EndNodes") : -1;
}

/* n elements of nn nodes each: tags[n], conn[n nn]. */
static int element_data(reader *r, size_t n, int nn, size_t *tags, size_t *conn) {
  const size_t rec = 8 * (size_t)(1 + nn);
  for (size_t e = 0; e < n;) {
    if (!r->binary) {
      if (ascii_size(r, &tags[e])) return -1;
      for (int j = 0; j < nn; j++)
        if (ascii_size(r, &conn[e * (size_t)nn + (size_t)j])) return -1;
      e++;
      continue;
    }
    if (!fill(r, rec)) return -1;
    size_t k = (r->len - r->pos) / rec;
    if (k > n - e) k = n - e;
    const char *s = r->buf + r->pos;
    for (size_t i = 0; i < k; i++, e++, s += rec) {
      memcpy(&tags[e], s, 8);
      memcpy(&conn[e * (size_t)nn], s + 8, rec - 8);
    }
    r->pos += k * rec;
  }
  return 0;
}

static int element_block(reader *r, dtm_msh_parsed *p, long long bytes) {
  int h[3];
  size_t n;
  if (block_header(r, h, &n) || family_of(h[2]) < 0) return -1;
  int nn = dtm_msh_type_nodes(h[2]), fam = family_of(h[2]);
  if (n > (size_t)bytes / ((r->binary ? 8 : 2) * (size_t)(1 + nn))) return -1; /* more than the file can hold */
  dtm_msh_eblock *nb = realloc(p->blocks, ((size_t)p->nblocks + 1) * sizeof *nb);
  if (!nb) return -1;
  p->blocks = nb;
  dtm_msh_eblock *b = &p->blocks[p->nblocks++];
  *b = (dtm_msh_eblock){
      h[0], h[1], h[2], n, malloc((n + 1) * sizeof(size_t)), malloc((n * (size_t)nn + 1) * sizeof(size_t))};
  if (!b->tags || !b->conn) return -1;
  p->family[fam] += n;
  return element_data(r, n, nn, b->tags, b->conn);
}

int dtm_msh_block_order(const void *a, const void *b) {
  const dtm_msh_eblock *x = a, *y = b;
  if (x->dim != y->dim) return x->dim < y->dim ? -1 : 1;
  if (x->tag != y->tag) return x->tag < y->tag ? -1 : 1;
  return x->type < y->type ? -1 : x->type > y->type;
}

/* The blocks sorted; -1 when an entity has two of one family (Gmsh keeps
 * one list per family and entity, and would list both as its first type). */
static int sort_blocks(dtm_msh_parsed *p) {
  qsort(p->blocks, (size_t)p->nblocks, sizeof *p->blocks, dtm_msh_block_order);
  for (int b = 1; b < p->nblocks; b++)
    for (int a = b - 1; a >= 0 && p->blocks[a].dim == p->blocks[b].dim && p->blocks[a].tag == p->blocks[b].tag; a--)
      if (family_of(p->blocks[a].type) == family_of(p->blocks[b].type)) return -1;
  return 0;
}

static int read_elements(reader *r, dtm_msh_parsed *p, long long bytes) {
  size_t c[4];
  if (section_header(r, c) || c[0] > (size_t)bytes) return -1;
  for (size_t b = 0; b < c[0]; b++)
    if (element_block(r, p, bytes)) return -1;
  return section_end(r, "$EndElements") || sort_blocks(p) ? -1 : 0;
}

/* "$MeshFormat", "4.1 <binary> 8", and in a binary file the integer 1. */
static int read_format(reader *r) {
  size_t n;
  const char *s = next_line(r, &n);
  char line[64];
  double version;
  int type, dsize;
  if (!s || !line_is(s, n, "$MeshFormat") || !(s = next_line(r, &n)) || n >= sizeof line) return -1;
  memcpy(line, s, n), line[n] = '\0';
  if (sscanf(line, "%lf %d %d", &version, &type, &dsize) != 3 || version != 4.1 || (type && dsize != 8)) return -1;
  r->binary = type;
  int32_t one = 0;
  if (type && (take_bytes(r, &one, sizeof one) || one != 1)) return -1;
  return section_end(r, "$EndMeshFormat");
}

/* The sections up to $EndElements. */
static int read_sections(reader *r, dtm_msh_parsed *p, long long bytes) {
  static const char *const refused[] = {"$PartitionedEntities", "$GhostElements",  "$Parametrizations", "$NodeData",
                                        "$ElementData",         "$ElementNodeData"};
  size_t n;
  const char *s;
  int nodes = 0;
  if (read_format(r)) return -1;
  while ((s = next_line(r, &n))) {
    for (size_t i = 0; i < sizeof refused / sizeof *refused; i++)
      if (line_is(s, n, refused[i])) return -1;
    if (line_is(s, n, "$Nodes")) {
      if (nodes || read_nodes(r, p, bytes)) return -1;
      nodes = 1;
    } else if (line_is(s, n, "$Elements")) {
      return nodes ? read_elements(r, p, bytes) : -1;
    }
  }
  return -1;
}

int dtm_msh_parse(const char *path, dtm_msh_parsed *p) {
  struct stat st;
  memset(p, 0, sizeof *p);
  reader r = {fopen(path, "rb"), malloc(CHUNK + 1), 0, 0, 0, 0};
  int rc = -1;
  if (r.f && r.buf && !fstat(fileno(r.f), &st)) rc = read_sections(&r, p, (long long)st.st_size);
  if (r.f) fclose(r.f);
  free(r.buf);
  if (rc) dtm_msh_parsed_free(p);
  return rc;
}

void dtm_msh_parsed_free(dtm_msh_parsed *p) {
  free(p->node_tags);
  free(p->xyz);
  for (int b = 0; b < p->nblocks; b++) free(p->blocks[b].tags), free(p->blocks[b].conn);
  free(p->blocks);
  memset(p, 0, sizeof *p);
}
