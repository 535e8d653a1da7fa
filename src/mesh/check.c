/* The consistency check of a mesh before dtmap computes on it: finite node
 * coordinates, element nodes that exist, and shapes the kernels can
 * analyse. dtmap's invalid-element policy lives here: an element whose
 * Jacobian is safely positive at every integration point is analysed, and
 * flagged when it is not at some node (an inverted corner of a distorted
 * hex, a curved edge folding back at its end node); an element inverted,
 * folded or flat at an integration point has no meaningful element
 * matrices and stops the run, with every such element counted and the
 * first 20 named by tag, group and centroid. A mesh whose elements appear
 * twice (src/mesh/duplicates.c) is refused next. The shapes are classified in
 * parallel; the few bad or flagged elements are then revisited in order,
 * so the messages and the flagged list do not depend on the thread count. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/mesh.h"
#include "mesh-impl.h"

#define LIST_MAX 20 /* elements named in a refusal */

const char *dtm_mesh_element_place(const dtm_mesh *m, int b, size_t e, char *buf, size_t len) {
  const dtm_block *blk = &m->blocks[b];
  double c[3] = {0, 0, 0};
  for (int a = 0; a < blk->nn; a++) {
    size_t v = blk->conn[e * (size_t)blk->nn + a];
    for (int i = 0; i < 3 && v < m->nnodes; i++) c[i] += m->xyz[3 * v + i] / blk->nn;
  }
  char lbl[64], grp[96];
  int g = blk->group ? blk->group[e] : -1;
  if (g >= 0 && g < m->ngroups)
    snprintf(grp, sizeof grp, "in group '%s'", dtm_mesh_group_label(m, g, lbl, sizeof lbl));
  else
    snprintf(grp, sizeof grp, "in no physical group");
  snprintf(buf, len, "element %zu (%s) %s at (%.6g, %.6g, %.6g)%s%s", blk->tags[e], dtm_elem_name(blk->type), grp, c[0],
           c[1], c[2], m->length_unit ? " " : "", m->length_unit ? m->length_unit : "");
  return buf;
}

static int check_nodes(const dtm_mesh *m, const char *src) {
  for (size_t v = 0; v < m->nnodes; v++) {
    const double *p = m->xyz + 3 * v;
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
      return DTM_ERR(DTM_ERR_INPUT, "%s: node %zu has coordinates (%g, %g, %g), which are not finite", src,
                     m->node_tags ? m->node_tags[v] : v + 1, p[0], p[1], p[2]);
  }
  for (int b = 0; b < m->nblocks; b++) {
    const dtm_block *blk = &m->blocks[b];
    for (size_t k = 0; k < blk->n * (size_t)blk->nn; k++)
      if (blk->conn[k] >= m->nnodes)
        return DTM_ERR(DTM_ERR_INPUT, "%s: element %zu (%s) references a node that does not exist", src,
                       blk->tags[k / (size_t)blk->nn], dtm_elem_name(blk->type));
  }
  return DTM_OK;
}

static void shape_of(const dtm_mesh *m, const dtm_block *blk, size_t e, dtm_shape *s) {
  double x[DTM_MAX_NODES * 3];
  dtm_mesh_gather_one(m, blk, e, x);
  dtm_kernel_shape(blk->type, x, s);
}

/* status[e] = the DTM_SHAPE_* of every element of block b. */
static void classify(const dtm_mesh *m, const dtm_block *blk, unsigned char *status) {
  long n = (long)blk->n;
#pragma omp parallel for schedule(static)
  for (long e = 0; e < n; e++) {
    dtm_shape s;
    shape_of(m, blk, (size_t)e, &s);
    status[e] = (unsigned char)s.status;
  }
}

/* What the check found: refused elements (count, listed text) and the
 * flagged ones. */
typedef struct {
  size_t nbad;          /* elements refused */
  char list[6144];      /* the first LIST_MAX of them, one per line */
  size_t cap;           /* allocated entries of flagged */
  dtm_flagged *flagged; /* elements analysed but flagged */
  size_t nflagged;      /* entries used */
} findings;

static void note_bad(const dtm_mesh *m, int b, size_t e, const dtm_shape *s, findings *f) {
  char place[256];
  size_t used = strlen(f->list);
  if (f->nbad++ >= LIST_MAX) return;
  dtm_mesh_element_place(m, b, e, place, sizeof place);
  snprintf(f->list + used, sizeof f->list - used, "\n  %s: %s, scaled Jacobian %.3g", place,
           dtm_shape_describe(s->status), s->min_jacobian);
}

static int note_flagged(int b, size_t e, const dtm_shape *s, findings *f) {
  if (f->nflagged == f->cap) {
    size_t cap = f->cap ? 2 * f->cap : 16;
    dtm_flagged *p = realloc(f->flagged, cap * sizeof *p);
    if (!p) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    f->flagged = p, f->cap = cap;
  }
  f->flagged[f->nflagged++] = (dtm_flagged){b, e, s->min_jacobian, s->node};
  return DTM_OK;
}

static int check_block(const dtm_mesh *m, int b, unsigned char *status, findings *f) {
  const dtm_block *blk = &m->blocks[b];
  classify(m, blk, status);
  for (size_t e = 0; e < blk->n; e++) {
    if (status[e] == DTM_SHAPE_VALID) continue;
    dtm_shape s;
    shape_of(m, blk, e, &s);
    if (s.status == DTM_SHAPE_CORNER)
      DTM_CHECK(note_flagged(b, e, &s, f));
    else
      note_bad(m, b, e, &s, f);
  }
  return DTM_OK;
}

static int refuse(const char *src, const findings *f) {
  char more[64] = "";
  if (f->nbad > LIST_MAX) snprintf(more, sizeof more, "\n  ... and %zu more", f->nbad - LIST_MAX);
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s: %zu element%s cannot be analysed: an element needs a positive Jacobian at every "
                 "integration point (second-order simplices: everywhere, by a Bezier bound)%s%s",
                 src, f->nbad, f->nbad == 1 ? "" : "s", f->list, more);
}

int dtm_mesh_check(dtm_mesh *m, const char *src) {
  DTM_CHECK(check_nodes(m, src));
  size_t most = 0;
  for (int b = 0; b < m->nblocks; b++) most = m->blocks[b].n > most ? m->blocks[b].n : most;
  unsigned char *status = malloc(most + 1);
  findings *f = calloc(1, sizeof *f);
  int r = status && f ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int b = 0; b < m->nblocks && r == DTM_OK; b++) r = check_block(m, b, status, f);
  if (r == DTM_OK && f->nbad) r = refuse(src, f);
  if (r == DTM_OK) r = dtm_mesh_check_duplicates(m, src);
  if (r == DTM_OK) {
    free(m->flagged);
    m->flagged = f->flagged, m->nflagged = f->nflagged, f->flagged = NULL;
  }
  if (f) free(f->flagged);
  free(f);
  free(status);
  return r;
}
