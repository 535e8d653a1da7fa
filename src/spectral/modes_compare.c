/* The accuracy price of a modified mass in frequencies: each elastic mode
 * of a base model matched to the modified model's mode of the same shape
 * and its frequency shift in percent; and the conventional alternative,
 * point masses at the nodes, as a diagonal extra mass for
 * dtm_modes_lowest; and the added part of a whole mass matrix (selective
 * mass scaling's M_s = M + M_add travels whole).
 *
 * Added mass reorders modes whose frequencies are close (a bending mode
 * that gains more mass than a torsion mode drops below it), so modes are
 * matched by shape, not by index: the modal assurance criterion weighted
 * by the base's lumped mass, MAC(a, b) = (a^T M b)^2 / (a^T M a b^T M b),
 * 1 for the same shape, 0 for M-orthogonal ones. The pairs are taken
 * greedily in descending MAC, each mode of either model at most once,
 * down to DTM_MODES_MAC_MIN (0.8, the usual threshold for "the same
 * mode"): a base mode left without a pair is reported as unmatched (its
 * shape changed, or its partner lies above the modes computed). Modes of a
 * multiple eigenvalue have no unique shapes, so they may split their MAC
 * and be left unmatched: compare the sum over the pair then. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/operator.h"

/* (a^T M b) over the lumped mass. */
static double m_dot(const double *m, size_t n, const double *a, const double *b) {
  double s = 0;
  for (size_t i = 0; i < n; i++) s += a[i] * m[i] * b[i];
  return s;
}

/* mac[i][j] for base elastic mode i and modified elastic mode j. */
static void mac_table(const double *m, const dtm_modes *base, const dtm_modes *mod, double *mac) {
  size_t n = base->ndof;
  for (int i = 0; i < base->nelastic; i++) {
    const double *a = base->shape + (size_t)(base->nrigid + i) * n;
    double aa = m_dot(m, n, a, a);
    for (int j = 0; j < mod->nelastic; j++) {
      const double *b = mod->shape + (size_t)(mod->nrigid + j) * n;
      double ab = m_dot(m, n, a, b), bb = m_dot(m, n, b, b);
      mac[(size_t)i * mod->nelastic + j] = aa > 0 && bb > 0 ? ab * ab / (aa * bb) : 0.0;
    }
  }
}

/* The best pair of modes not yet taken, or 0 when none reaches the threshold. */
static int best_pair(const double *mac, int nb, int nm, const int *base_of, const int *taken, int *bi, int *bj) {
  double best = -1;
  for (int i = 0; i < nb; i++)
    for (int j = 0; j < nm; j++)
      if (base_of[i] < 0 && !taken[j] && mac[(size_t)i * nm + j] > best)
        best = mac[(size_t)i * nm + j], *bi = i, *bj = j;
  return best >= DTM_MODES_MAC_MIN;
}

int dtm_modes_compare(const dtm_operator *op, const dtm_modes *base, const dtm_modes *mod, dtm_mode_shift *out) {
  int nb = base->nelastic, nm = mod->nelastic, bi = 0, bj = 0;
  if (base->ndof != dtm_operator_ndof(op) || mod->ndof != base->ndof)
    return DTM_ERR(DTM_ERR_INPUT, "modes compared over %zu and %zu unknowns, the model has %zu", base->ndof, mod->ndof,
                   dtm_operator_ndof(op));
  double *mac = malloc(((size_t)nb * nm + 1) * sizeof *mac);
  int *base_of = malloc(((size_t)nb + 1) * sizeof *base_of), *taken = calloc((size_t)nm + 1, sizeof *taken);
  if (!mac || !base_of || !taken)
    return free(mac), free(base_of), free(taken), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  mac_table(dtm_operator_mass(op), base, mod, mac);
  for (int i = 0; i < nb; i++) base_of[i] = -1;
  while (best_pair(mac, nb, nm, base_of, taken, &bi, &bj)) base_of[bi] = bj, taken[bj] = 1;
  for (int i = 0; i < nb; i++) {
    double top = 0;
    for (int j = 0; j < nm; j++) top = fmax(top, mac[(size_t)i * nm + j]);
    int j = base_of[i];
    double fb = base->mode[base->nrigid + i].freq;
    out[i] = (dtm_mode_shift){i, j, j >= 0 ? mac[(size_t)i * nm + j] : top,
                              j >= 0 ? 100.0 * (mod->mode[mod->nrigid + j].freq / fb - 1.0) : NAN};
  }
  free(mac), free(base_of), free(taken);
  return DTM_OK;
}

int dtm_csr_point_masses(const dtm_operator *op, const double *kg, size_t nnodes, dtm_csr *out) {
  size_t n = dtm_operator_ndof(op), nc = (size_t)dtm_operator_ncomp(op);
  memset(out, 0, sizeof *out);
  if (nnodes * nc > n)
    return DTM_ERR(DTM_ERR_INPUT, "%zu nodes of point masses, the model has %zu unknowns", nnodes, n);
  out->n = n;
  out->rowptr = malloc((n + 1) * sizeof *out->rowptr), out->col = malloc((n + 1) * sizeof *out->col);
  out->val = malloc((n + 1) * sizeof *out->val);
  if (!out->rowptr || !out->col || !out->val) return dtm_csr_free(out), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t k = 0;
  for (size_t i = 0; i < n; i++) {
    double v = kg && i < nnodes * nc ? kg[i / nc] : 0.0;
    if (!(isfinite(v) && v >= 0))
      return dtm_csr_free(out), DTM_ERR(DTM_ERR_INPUT, "a point mass of %g kg at node index %zu", v, i / nc);
    out->rowptr[i] = k;
    if (v > 0) out->col[k] = i, out->val[k++] = v;
  }
  out->rowptr[n] = k;
  return DTM_OK;
}

/* Row i of full with lumped[i] taken off its diagonal into out at *k. */
static void row_minus(const dtm_csr *full, size_t i, double lumped, dtm_csr *out, size_t *k) {
  out->rowptr[i] = *k;
  for (size_t q = full->rowptr[i]; q < full->rowptr[i + 1]; q++) {
    double v = full->val[q] - (full->col[q] == i ? lumped : 0.0);
    if (v != 0) out->col[*k] = full->col[q], out->val[(*k)++] = v;
  }
}

int dtm_csr_minus_lumped(const dtm_operator *op, const dtm_csr *full, dtm_csr *out) {
  size_t n = dtm_operator_ndof(op), nnz = full->rowptr[full->n];
  memset(out, 0, sizeof *out);
  if (full->n != n) return DTM_ERR(DTM_ERR_INPUT, "a mass matrix of %zu rows, the model has %zu unknowns", full->n, n);
  out->n = n;
  out->rowptr = malloc((n + 1) * sizeof *out->rowptr), out->col = malloc((nnz + 1) * sizeof *out->col);
  out->val = malloc((nnz + 1) * sizeof *out->val);
  if (!out->rowptr || !out->col || !out->val) return dtm_csr_free(out), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  size_t k = 0;
  const double *m = dtm_operator_mass(op);
  for (size_t i = 0; i < n; i++) row_minus(full, i, m[i], out, &k);
  out->rowptr[n] = k;
  return DTM_OK;
}
