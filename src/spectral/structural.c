/* The shells and beams of the global operator: elements whose nodes carry
 * three rotations besides the three translations. Their element matrices
 * (stiffness and lumped mass in global axes, under their section's rotary
 * convention: src/kernel/structural.h) are computed once and stored, and
 * the product applies them element by element after the continuum blocks.
 * A stiffness is stored as the rows of its upper triangle, one element after
 * the other (a tri3 shell's 171 numbers instead of a padded 24 x 24 block:
 * a third of the memory, and of the traffic of every product); the product
 * reads each number once for both of its places, so the operator is exactly
 * symmetric.
 * Rotation unknowns are appended after the translations: the triple of
 * node v's rotations starts at nnodes * 3 + 3 r, r its rank among the
 * nodes with rotations (in node order). The continuum path of the operator
 * sees these elements with zero coefficients. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/section.h"
#include "structural-impl.h"
#include "structural.h"

int dtm_op_struct_is(const dtm_operator_coeffs *c) {
  return c->kind == DTM_OP_ELASTIC && c->section && dtm_section_has_rotations(c->section->kind);
}

/* Numbers in the upper triangle of an n x n matrix. */
static size_t packed(size_t n) { return n * (n + 1) / 2; }

/* Count the structural elements and their stored stiffness numbers, and
 * mark the nodes with rotations. */
static size_t count(const dtm_mesh *m, const dtm_operator_coeffs *c, int nmat, char *mark, size_t *nk) {
  size_t n = 0;
  *nk = 0;
  for (int ib = 0; ib < m->nblocks; ib++) {
    const dtm_block *b = &m->blocks[ib];
    for (size_t e = 0; e < b->n; e++) {
      int slot = b->mat[e] + (b->section ? nmat * (b->section[e] + 1) : 0);
      if (!dtm_op_struct_is(&c[slot])) continue;
      n++, *nk += packed(6 * (size_t)b->nn);
      for (int a = 0; a < b->nn; a++) mark[b->conn[e * (size_t)b->nn + a]] = 1;
    }
  }
  return n;
}

static int alloc_all(dtm_op_struct *s, size_t nnodes, size_t nk) {
  s->ndof = calloc(s->n + 1, sizeof *s->ndof);
  s->idx = malloc((s->n * DTM_STRUCT_DOF + 1) * sizeof *s->idx);
  s->K = malloc((nk + 1) * sizeof *s->K);
  s->koff = malloc((s->n + 1) * sizeof *s->koff);
  s->m = malloc((s->n * DTM_STRUCT_DOF + 1) * sizeof *s->m);
  s->slot = malloc((s->n + 1) * sizeof *s->slot);
  s->rot_of = malloc((nnodes + 1) * sizeof *s->rot_of);
  s->fe = malloc((s->n * DTM_STRUCT_DOF + 1) * sizeof *s->fe);
  if (!s->ndof || !s->idx || !s->K || !s->koff || !s->m || !s->slot || !s->rot_of || !s->fe)
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  return DTM_OK;
}

/* Rotation ranks of the marked nodes, and the node of each rank. */
static int number_rotations(dtm_op_struct *s, const char *mark, size_t nnodes) {
  s->nrot = 0;
  for (size_t v = 0; v < nnodes; v++) s->rot_of[v] = mark[v] ? s->nrot++ : SIZE_MAX;
  s->rot_node = malloc((s->nrot + 1) * sizeof *s->rot_node);
  if (!s->rot_node) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t v = 0; v < nnodes; v++)
    if (mark[v]) s->rot_node[s->rot_of[v]] = v;
  return DTM_OK;
}

/* The element's matrices under its section's convention; a shell whose
 * bounds an analysis kept takes its rotary scale from them (its physical
 * matrices with the rotary masses times the scale: what the scaled
 * convention computes, without solving for the scale again). */
static int kept_matrices(const dtm_op_struct *s, const dtm_mesh *m, const dtm_block *b, size_t e,
                         const dtm_operator_coeffs *c, const double *x, dtm_struct_matrices *mat) {
  const dtm_section_bounds *k = s->kept && s->kept[b - m->blocks] ? &s->kept[b - m->blocks][e] : NULL;
  if (!k || !k->nn || c->section->kind != DTM_SECTION_SHELL)
    return dtm_section_matrices(c->section, b->type, c->E, c->nu, c->capacity, x, mat);
  dtm_section physical = *c->section;
  physical.rotary = DTM_ROTARY_PHYSICAL_INERTIA;
  DTM_CHECK(dtm_section_matrices(&physical, b->type, c->E, c->nu, c->capacity, x, mat));
  for (int i = 0; i < 6 * mat->nn; i++)
    if (i % 6 >= 3) mat->m[i] *= k->scale, mat->M[i * 6 * mat->nn + i] = mat->m[i];
  return DTM_OK;
}

/* Element i: block b's element e, matrices and dof indices. */
static int one(dtm_op_struct *s, size_t i, const dtm_mesh *m, const dtm_block *b, size_t e,
               const dtm_operator_coeffs *c) {
  double x[3 * 4];
  dtm_struct_matrices mat;
  const size_t *conn = b->conn + e * (size_t)b->nn;
  if (b->nn > 4)
    return DTM_ERR(DTM_ERR_INPUT, "a %s section takes no %s elements", dtm_section_kind_name(c->section->kind),
                   dtm_elem_name(b->type));
  for (int a = 0; a < b->nn; a++) memcpy(x + 3 * a, m->xyz + 3 * conn[a], 3 * sizeof *x);
  if (kept_matrices(s, m, b, e, c, x, &mat)) {
    char place[256];
    dtm_mesh_element_place(m, (int)(b - m->blocks), e, place, sizeof place);
    return DTM_ERR(DTM_ERR_INPUT, "%s: %s", place, dtm_error_message());
  }
  int n = 6 * b->nn;
  s->ndof[i] = n;
  for (int a = 0; a < b->nn; a++)
    for (int k = 0; k < 3; k++) {
      s->idx[i * DTM_STRUCT_DOF + 6 * a + k] = conn[a] * 3 + (size_t)k;
      s->idx[i * DTM_STRUCT_DOF + 6 * a + 3 + k] = s->base + 3 * s->rot_of[conn[a]] + (size_t)k;
    }
  double *K = s->K + s->koff[i];
  for (int r = 0; r < n; r++) {
    memcpy(K, mat.K + (size_t)r * n + r, (size_t)(n - r) * sizeof *K);
    K += n - r;
    s->m[i * DTM_STRUCT_DOF + r] = mat.M[(size_t)r * n + r];
  }
  return DTM_OK;
}

/* The blocks and element indices of the structural elements, in order,
 * and where each one's stiffness starts. */
static void locate(dtm_op_struct *s, const dtm_mesh *m, const dtm_operator_coeffs *c, int nmat, int *blk, size_t *el) {
  size_t i = 0, k = 0;
  for (int ib = 0; ib < m->nblocks; ib++) {
    const dtm_block *b = &m->blocks[ib];
    for (size_t e = 0; e < b->n; e++) {
      int slot = b->mat[e] + (b->section ? nmat * (b->section[e] + 1) : 0);
      if (!dtm_op_struct_is(&c[slot])) continue;
      s->slot[i] = slot, blk[i] = ib, s->koff[i] = k, el[i++] = e;
      k += packed(6 * (size_t)b->nn);
    }
  }
}

/* Every element's matrices, in parallel (the error records are
 * thread-local); the first element that fails is redone to report it. */
static int fill(dtm_op_struct *s, const dtm_mesh *m, const dtm_operator_coeffs *c, int nmat) {
  int *blk = malloc((s->n + 1) * sizeof *blk);
  size_t *el = malloc((s->n + 1) * sizeof *el), bad = s->n;
  if (!blk || !el) return free(blk), free(el), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  locate(s, m, c, nmat, blk, el);
#pragma omp parallel for schedule(static) reduction(min : bad)
  for (size_t i = 0; i < s->n; i++)
    if (one(s, i, m, &m->blocks[blk[i]], el[i], &c[s->slot[i]]) && i < bad) bad = i;
  int r = bad < s->n ? one(s, bad, m, &m->blocks[blk[bad]], el[bad], &c[s->slot[bad]]) : DTM_OK;
  free(blk), free(el);
  return r;
}

int dtm_op_struct_setup(dtm_op_struct *s, const dtm_mesh *m, const dtm_operator_coeffs *c, int nmat,
                        const dtm_section_bounds *const *kept) {
  memset(s, 0, sizeof *s);
  s->kept = kept;
  char *mark = calloc(m->nnodes + 1, 1);
  if (!mark) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t nk;
  s->n = count(m, c, nmat, mark, &nk);
  s->base = m->nnodes * 3;
  int r = s->n ? alloc_all(s, m->nnodes, nk) : DTM_OK;
  if (s->n && r == DTM_OK) r = number_rotations(s, mark, m->nnodes);
  free(mark);
  if (s->n && r == DTM_OK) r = fill(s, m, c, nmat);
  return r;
}

void dtm_op_struct_masses(const dtm_op_struct *s, const double *alpha_of_slot, double *mass, double *mass_alpha) {
  for (size_t i = 0; i < s->n; i++)
    for (int r = 0; r < s->ndof[i]; r++) {
      size_t k = s->idx[i * DTM_STRUCT_DOF + r];
      double mk = s->m[i * DTM_STRUCT_DOF + r];
      mass[k] += mk;
      if (mass_alpha) mass_alpha[k] += alpha_of_slot[s->slot[i]] * mk;
    }
}

/* fe = f K_e u of element i, from the upper triangle of K_e: each stored
 * number K_rq (q > r) serves row r and, as K_qr, row q. */
static void element_product(const dtm_op_struct *s, size_t i, const double *u, double f, double *fe) {
  int n = s->ndof[i];
  const size_t *idx = s->idx + i * DTM_STRUCT_DOF;
  const double *K = s->K + s->koff[i];
  double ue[DTM_STRUCT_DOF], acc[DTM_STRUCT_DOF] = {0};
  for (int r = 0; r < n; r++) ue[r] = u[idx[r]];
  for (int r = 0; r < n; r++) {
    double a = *K++ * ue[r];
    for (int q = r + 1; q < n; q++, K++) a += *K * ue[q], acc[q] += *K * ue[r];
    acc[r] += a;
  }
  for (int r = 0; r < n; r++) fe[r] = f * acc[r];
}

void dtm_op_struct_apply(const dtm_op_struct *s, const double *u, const double *beta_of_slot, double *y) {
#pragma omp parallel for schedule(static) if (s->n > 2000)
  for (size_t i = 0; i < s->n; i++)
    element_product(s, i, u, beta_of_slot ? beta_of_slot[s->slot[i]] : 1.0, s->fe + i * DTM_STRUCT_DOF);
  for (size_t i = 0; i < s->n; i++)
    for (int r = 0; r < s->ndof[i]; r++) y[s->idx[i * DTM_STRUCT_DOF + r]] += s->fe[i * DTM_STRUCT_DOF + r];
}

void dtm_op_struct_free(dtm_op_struct *s) {
  free(s->ndof), free(s->idx), free(s->K), free(s->koff), free(s->m), free(s->slot), free(s->rot_of), free(s->rot_node);
  free(s->fe);
  memset(s, 0, sizeof *s);
}
