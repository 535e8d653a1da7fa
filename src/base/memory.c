/* How much memory this process may use, for the kill switches that refuse
 * an input too big for the machine before anything is allocated: the
 * smallest of the machine's physical memory (MemTotal), the cgroup's limit
 * (v2 memory.max, v1 memory.limit_in_bytes) and the address-space and data
 * rlimits (ulimit -v, -d). Total memory, not what is free now: the switch
 * is for inputs that cannot fit at all, never for a busy machine. */
#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "base.h"

/* The first number in file after key (key NULL: at the start); 0 if none. */
static double number_in(const char *file, const char *key) {
  char line[256];
  double v = 0;
  FILE *f = fopen(file, "r");
  if (!f) return 0;
  while (fgets(line, sizeof line, f)) {
    const char *p = key ? strstr(line, key) : line;
    if (!p) continue;
    v = strtod(p + (key ? strlen(key) : 0), NULL);
    break;
  }
  fclose(f);
  return v;
}

static double at_most(double a, double b) { return b > 0 && b < a ? b : a; }

double dtm_memory_limit(void) {
  double m = number_in("/proc/meminfo", "MemTotal:") * 1024.0;
  if (!(m > 0)) m = 1e300;
  m = at_most(m, number_in("/sys/fs/cgroup/memory.max", NULL));
  m = at_most(m, number_in("/sys/fs/cgroup/memory/memory.limit_in_bytes", NULL));
  static const int limits[] = {RLIMIT_AS, RLIMIT_DATA};
  for (int i = 0; i < 2; i++) {
    struct rlimit r;
    if (!getrlimit(limits[i], &r) && r.rlim_cur != RLIM_INFINITY) m = at_most(m, (double)r.rlim_cur);
  }
  return m;
}

const char *dtm_bytes_text(double bytes, char *buf, size_t len) {
  static const char *const unit[] = {"B", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1000 && u < 5) bytes /= 1000, u++;
  snprintf(buf, len, "%.3g %s", bytes, unit[u]);
  return buf;
}

/* glibc gives every allocation above a threshold (at most 32 MB) a mapping
 * of its own and unmaps it when freed, so each per-element array of a large
 * mesh (80 MB at 1e7 tets) came as fresh pages the kernel zeroes on first
 * touch, although Gmsh's copies of the element arrays, the locality
 * order's scratch, the measures' work arrays and, once written, Gmsh's
 * model had just been freed. With no mappings every allocation comes from
 * the heap and takes freed space first; up to KEEP_TOP bytes free at the
 * heap's top stay with the process for the next stage (glibc's default
 * gives back all beyond 128 kB, which the next array then faults in
 * again); when more is free there it is given back, so the peak stays near
 * what it was. Measured
 * in docs/performance-big.md (bench/perf_big.sh): a third fewer page
 * faults at 1e7 tets, a quarter fewer from a geometry at 1e6. KEEP_TOP is
 * 256 MB, not 64: what the 3D mesher frees then serves Gmsh's listing of
 * the elements (an 80 MB vector and its copy for the C API) without fresh
 * pages; from a geometry at 1e6 tets the run took 120,000 page faults
 * against 134,000-158,000 and its extraction about 25 ms less, its peak
 * RSS 369 MB against 363-400 MB; at 1.2e6 and 1e7 tets from a .msh the
 * peak and the faults did not move (2245 MB at 1e7). */
#define KEEP_TOP (256 << 20)

void dtm_memory_reuse(void) {
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, KEEP_TOP);
}
