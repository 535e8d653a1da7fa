/* The parts of a mesh's blocks that share one integration rule, for the
 * global operator (operator.c): the elements of a second-order block that
 * the kernel integrates with a levelled rule because they are curved
 * (src/kernel/curved.c) are moved into one part per level, so that the
 * operator integrates every element exactly as its element bound does.
 * A block with no curved element (every linear block, every straight-sided
 * mesh) is one part that views the mesh's own arrays: nothing is copied
 * and nothing costs more than before. The levels are those an analysis
 * kept, or found here in parallel;
 * the parts keep the mesh order of their elements. Under the "calculix"
 * model every tet10 is in the part of CalculiX's C3D10 rule. The tet10 the
 * full rule integrates whose map is affine (every straight-sided tet10 of a
 * Gmsh mesh, to 1e-14) get a part of their own (DTM_RULE_AFFINE), whose
 * stiffness the operator integrates exactly with 4 points instead of 14. */
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "spectral.h"
#include "reference.h"

/* lev[e] = the rule level of element e of block b (0: full rule): from
 * the converged levels kept (when not NULL), else searched; an affine
 * tet10 of the full rule's part goes to the part DTM_RULE_AFFINE. */
static void block_levels(const dtm_mesh *m, const dtm_block *b, int model, const unsigned char *kept,
                         unsigned char *lev) {
  long n = (long)b->n;
#pragma omp parallel for schedule(dynamic, 1024)
  for (long e = 0; e < n; e++) {
    double x[DTM_K_NODES * 3];
    dtm_qrule q;
    int gathered = !kept;
    if (gathered) dtm_mesh_gather_one(m, b, e, x);
    lev[e] =
        (unsigned char)(kept ? dtm_ref_rule_id(b->type, model, kept[e]) : dtm_ref_rule_elem(b->type, x, model, &q));
    if (lev[e] || b->type != DTM_TET10) continue;
    if (!gathered) dtm_mesh_gather_one(m, b, e, x);
    if (dtm_elem_affine(b->type, x)) lev[e] = DTM_RULE_AFFINE;
  }
}

/* Copy into part p the elements e of b with lev[e] == level. */
static int fill_part(const dtm_block *b, const unsigned char *lev, int level, size_t count, dtm_rule_part *p) {
  size_t nn = (size_t)b->nn, k = 0;
  p->blk = *b;
  p->blk.n = count, p->level = level;
  p->blk.tags = malloc((count + 1) * sizeof(size_t));
  p->blk.conn = malloc((count * nn + 1) * sizeof(size_t));
  p->blk.mat = malloc((count + 1) * sizeof(int));
  p->blk.section = b->section ? malloc((count + 1) * sizeof(int)) : NULL;
  p->orig = malloc((count + 1) * sizeof(size_t));
  p->blk.group = NULL, p->blk.gmask = NULL, p->blk.entity = NULL;
  if (!p->blk.tags || !p->blk.conn || !p->blk.mat || (b->section && !p->blk.section) || !p->orig)
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t e = 0; e < b->n; e++) {
    if (lev[e] != level) continue;
    p->orig[k] = e;
    p->blk.tags[k] = b->tags ? b->tags[e] : e;
    p->blk.mat[k] = b->mat[e];
    if (b->section) p->blk.section[k] = b->section[e];
    memcpy(p->blk.conn + k * nn, b->conn + e * nn, nn * sizeof(size_t));
    k++;
  }
  return DTM_OK;
}

/* Rules a block's elements may have: the full one (0), the levels 1 ..
 * DTM_K_LEVEL_MAX, CalculiX's C3D10 rule (DTM_K_RULE_C3D10) and the
 * affine tet10's (DTM_RULE_AFFINE). */
#define RULES (DTM_RULE_AFFINE + 1)

/* Append the parts of block ib to *ps (room for RULES). */
static int block_parts(const dtm_mesh *m, int ib, int model, const unsigned char *kept, dtm_rule_part *ps, int *np) {
  const dtm_block *b = &m->blocks[ib];
  size_t count[RULES] = {0};
  unsigned char *lev = dtm_ref_levelled(b->type) ? calloc(b->n + 1, 1) : NULL;
  if (lev) block_levels(m, b, model, kept, lev);
  for (size_t e = 0; lev && e < b->n; e++) count[lev[e]]++;
  int one = lev && b->n ? lev[0] : 0; /* the rule of every element, if they share one */
  if (!lev || count[one] == b->n) {   /* the block as it is */
    ps[*np] = (dtm_rule_part){*b, one, ib, NULL};
    (*np)++;
    free(lev);
    return DTM_OK;
  }
  int r = DTM_OK;
  for (int l = 0; l < RULES && !r; l++) {
    if (!count[l]) continue;
    ps[*np].block = ib;
    r = fill_part(b, lev, l, count[l], &ps[(*np)++]);
  }
  free(lev);
  return r;
}

int dtm_rule_parts(const dtm_mesh *m, int model, const unsigned char *const *kept, dtm_rule_part **parts, int *nparts) {
  *nparts = 0;
  *parts = calloc((size_t)m->nblocks * RULES + 1, sizeof **parts);
  if (!*parts) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int ib = 0; ib < m->nblocks; ib++) DTM_CHECK(block_parts(m, ib, model, kept ? kept[ib] : NULL, *parts, nparts));
  return DTM_OK;
}

void dtm_rule_parts_free(dtm_rule_part *parts, int n) {
  for (int i = 0; parts && i < n; i++) {
    if (!parts[i].orig) continue;
    free(parts[i].orig), free(parts[i].blk.tags), free(parts[i].blk.conn);
    free(parts[i].blk.mat), free(parts[i].blk.section);
  }
  free(parts);
}
