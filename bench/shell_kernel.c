/* Benchmark (not a test): the shell kernel's bounds per element, the
 * reference path (dtm_kernel_shell_physical, dtm_kernel_shell_scale)
 * against the faster one (dtm_kernel_shell_bounds), on the triangles or
 * quadrangles of a jittered cylindrical panel (radius 1 m, 60 degrees,
 * 1.2 m long, like geometries/stiffened_panel.geo) at size h with a 5 mm
 * steel skin. Prints microseconds per element of each path (one thread,
 * best of 3), the largest relative difference of lambda_membrane, s and
 * lambda_physical between them, and how many elements the Cholesky
 * certificate settled (s = 1).
 *
 * Usage: bench_shell_kernel [tri|quad] [h (m)] [thickness (m)] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../src/kernel/structural.h"

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double rel(double a, double b) { return a == b ? 0 : fabs(a - b) / fmax(fabs(a), fabs(b)); }

int main(int argc, char **argv) {
  int quad = argc > 1 && !strcmp(argv[1], "quad");
  double h = argc > 2 ? atof(argv[2]) : 0.005, t = argc > 3 ? atof(argv[3]) : 0.005;
  int na = (int)(1.0472 / h), nl = (int)(1.2 / h), nn = quad ? 4 : 3;
  size_t ne = (size_t)na * nl * (quad ? 1 : 2);
  double *x = malloc(ne * 12 * sizeof *x), *node = malloc((size_t)(na + 1) * (nl + 1) * 3 * sizeof *node);
  srand(1);
  for (int i = 0; i <= na; i++)
    for (int j = 0; j <= nl; j++) {
      double ja = i && j && i < na && j < nl ? 0.3 : 0, a = -0.5236 + (i + ja * (rand() / (double)RAND_MAX - .5)) * h;
      double y = (j + ja * (rand() / (double)RAND_MAX - .5)) * h, *p = node + 3 * ((size_t)i * (nl + 1) + j);
      p[0] = sin(a), p[1] = y, p[2] = cos(a);
    }
  size_t k = 0;
  for (int i = 0; i < na; i++)
    for (int j = 0; j < nl; j++) {
      int c[4] = {i * (nl + 1) + j, (i + 1) * (nl + 1) + j, (i + 1) * (nl + 1) + j + 1, i * (nl + 1) + j + 1};
      int tris[2][3] = {{c[0], c[1], c[2]}, {c[0], c[2], c[3]}};
      for (int q = 0; q < (quad ? 1 : 2); q++, k++)
        for (int a = 0; a < nn; a++) memcpy(x + 12 * k + 3 * a, node + 3 * (quad ? c[a] : tris[q][a]), 3 * sizeof *x);
    }
  dtm_shell_section sec = {210e9, 0.3, 7850, t, 0};
  double *ref = malloc(ne * 3 * sizeof *ref), *fast = malloc(ne * 3 * sizeof *fast), m[DTM_STRUCT_DOF];
  double best_ref = INFINITY, best_fast = INFINITY, best_scale_ref = INFINITY, best_scale_fast = INFINITY;
  int n;
  for (int rep = 0; rep < 3; rep++) {
    double t0 = now();
    for (size_t e = 0; e < ne; e++)
      if (dtm_kernel_shell_physical(quad ? 3 : 2, &sec, x + 12 * e, ref + 3 * e, m, &n)) return 1;
    double t1 = now();
    for (size_t e = 0; e < ne; e++)
      if (dtm_kernel_shell_bounds(quad ? 3 : 2, &sec, x + 12 * e, DTM_STRUCT_NEED_SCALE | DTM_STRUCT_NEED_PHYSICAL, 0,
                                  fast + 3 * e, m, &n))
        return 1;
    double t2 = now(), b[3];
    for (size_t e = 0; e < ne; e++)
      if (dtm_kernel_shell_scale(quad ? 3 : 2, &sec, x + 12 * e, b, m, &n)) return 1;
    double t3 = now();
    for (size_t e = 0; e < ne; e++)
      if (dtm_kernel_shell_bounds(quad ? 3 : 2, &sec, x + 12 * e, DTM_STRUCT_NEED_SCALE, 0, b, m, &n)) return 1;
    double t4 = now();
    best_ref = fmin(best_ref, t1 - t0), best_fast = fmin(best_fast, t2 - t1);
    best_scale_ref = fmin(best_scale_ref, t3 - t2), best_scale_fast = fmin(best_scale_fast, t4 - t3);
  }
  double d[3] = {0, 0, 0};
  size_t cert = 0;
  for (size_t e = 0; e < ne; e++) {
    for (int i = 0; i < 3; i++) d[i] = fmax(d[i], rel(ref[3 * e + i], fast[3 * e + i]));
    cert += fast[3 * e + 1] == 1 && fast[3 * e + 2] == fast[3 * e];
  }
  printf("%zu %s, h %g m, t %g m: both conventions %.2f -> %.2f us/element, scaled alone %.2f -> %.2f us/element;\n"
         "max relative difference lambda_membrane %.2e, s %.2e, lambda_physical %.2e; certified s = 1: %zu (%.1f %%)\n",
         ne, quad ? "quad4" : "tri3", h, t, 1e6 * best_ref / ne, 1e6 * best_fast / ne, 1e6 * best_scale_ref / ne,
         1e6 * best_scale_fast / ne, d[0], d[1], d[2], cert, 100.0 * cert / ne);
  free(x), free(node), free(ref), free(fast);
  return 0;
}
