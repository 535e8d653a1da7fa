/* The vector work of the global Lanczos run (lanczos.c): the passes of one
 * step, Gram-Schmidt against the stored basis and the Ritz vector. The
 * basis vectors are stored as they come out of a step, unnormalised, each
 * with its scale (v_j = sc_j V_j), so that no pass is spent normalising.
 * Every pass runs over chunks of DTM_VCHUNK unknowns: each chunk's dot is
 * summed in eight interleaved partial sums (one running sum would wait on
 * each addition's latency) and the chunks' sums are added in their order,
 * so a result has the same bits on any thread count. Above LZ_PAR_CHUNKS
 * chunks the chunks are shared among OpenMP's threads (the run's -j): at
 * 1.2e6 tets the serial passes took a third of the global estimate's wall
 * time while the second core waited for the next product. */
#include <stddef.h>

#include "spectral.h"

#define LANES 8          /* independent partial sums of a chunk's dot */
#define LZ_PAR_CHUNKS 16 /* chunks (65,536 unknowns) from which the threads share a pass */

size_t dtm_vchunks(size_t n) { return n ? (n + DTM_VCHUNK - 1) / DTM_VCHUNK : 1; }

static size_t lo_of(size_t b) { return b * DTM_VCHUNK; }
static size_t hi_of(size_t b, size_t n) { return lo_of(b) + DTM_VCHUNK < n ? lo_of(b) + DTM_VCHUNK : n; }

static double lanes_sum(const double *p) { return ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7])); }

static double chunk_dot(size_t m, const double *x, const double *y) {
  double p[LANES] = {0};
  size_t i = 0;
  for (; i + LANES <= m; i += LANES)
    for (int l = 0; l < LANES; l++) p[l] += x[i + l] * y[i + l];
  for (; i < m; i++) p[0] += x[i] * y[i];
  return lanes_sum(p);
}

/* One chunk of dtm_vstep: w = s w - t x, then w . y and w . w. */
static void chunk_step(size_t m, double *w, double s, double t, const double *x, const double *y, double d[2]) {
  double p[LANES] = {0}, q[LANES] = {0};
  size_t i = 0;
  for (; i + LANES <= m; i += LANES)
    for (int l = 0; l < LANES; l++) {
      double v = s * w[i + l] - t * x[i + l];
      w[i + l] = v;
      p[l] += v * y[i + l];
      q[l] += v * v;
    }
  for (; i < m; i++) {
    double v = s * w[i] - t * x[i];
    w[i] = v;
    p[0] += v * y[i];
    q[0] += v * v;
  }
  d[0] = lanes_sum(p), d[1] = lanes_sum(q);
}

void dtm_vstep(size_t n, double *w, double s, double t, const double *x, const double *y, double *part, double d[2]) {
  size_t nb = dtm_vchunks(n);
#pragma omp parallel for schedule(static) if (nb >= LZ_PAR_CHUNKS)
  for (size_t b = 0; b < nb; b++) {
    size_t lo = lo_of(b);
    chunk_step(hi_of(b, n) - lo, w + lo, s, t, x + lo, y + lo, part + 2 * b);
  }
  d[0] = d[1] = 0;
  for (size_t b = 0; b < nb; b++) d[0] += part[2 * b], d[1] += part[2 * b + 1];
}

void dtm_vproject(size_t n, const double *w, double *const *V, const double *sc, int nv, double *part, double *c) {
  size_t nb = dtm_vchunks(n), k = (size_t)nv;
#pragma omp parallel for schedule(static) if (nb >= LZ_PAR_CHUNKS)
  for (size_t b = 0; b < nb; b++) {
    size_t lo = lo_of(b), m = hi_of(b, n) - lo;
    for (size_t j = 0; j < k; j++) part[b * k + j] = chunk_dot(m, w + lo, V[j] + lo);
  }
  for (size_t j = 0; j < k; j++) {
    double s = 0;
    for (size_t b = 0; b < nb; b++) s += part[b * k + j];
    c[j] = sc[j] * s;
  }
}

double dtm_vsubtract(size_t n, double *w, double *const *V, const double *sc, const double *c, int nv, double *part) {
  size_t nb = dtm_vchunks(n);
#pragma omp parallel for schedule(static) if (nb >= LZ_PAR_CHUNKS)
  for (size_t b = 0; b < nb; b++) {
    size_t lo = lo_of(b), hi = hi_of(b, n);
    for (int j = 0; j < nv; j++) {
      double f = c[j] * sc[j];
      const double *v = V[j];
      for (size_t i = lo; i < hi; i++) w[i] -= f * v[i];
    }
    part[b] = chunk_dot(hi - lo, w + lo, w + lo);
  }
  double s = 0;
  for (size_t b = 0; b < nb; b++) s += part[b];
  return s;
}

void dtm_vcombine(size_t n, double *y, double *const *V, const double *sc, const double *c, int nv) {
  size_t nb = dtm_vchunks(n);
#pragma omp parallel for schedule(static) if (nb >= LZ_PAR_CHUNKS)
  for (size_t b = 0; b < nb; b++) {
    size_t lo = lo_of(b), hi = hi_of(b, n);
    for (size_t i = lo; i < hi; i++) y[i] = 0;
    for (int j = 0; j < nv; j++) {
      double f = c[j] * sc[j];
      const double *v = V[j];
      for (size_t i = lo; i < hi; i++) y[i] += f * v[i];
    }
  }
}
