/* The distributed-run test helpers (parts.h): mpirun, Gmsh meshing and
 * splitting, and view comparison by tag. */
#include "parts.h"

#include <gmshc.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef DTM_TEST_MPIRUN
#define DTM_TEST_MPIRUN "mpirun"
#endif

int tu_mpirun(char **out, int np, const char *fmt, ...) {
  char cmd[8000];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(cmd, sizeof cmd, fmt, ap);
  va_end(ap);
  return tu_run(out, "%s -n %d %s", DTM_TEST_MPIRUN, np, cmd);
}

int tu_run_pair(const char *dir, int np, const char *scene_serial, const char *scene_parts, const char *tag) {
  char *out = NULL;
  int rc = tu_run(&out, "cd %s && %s run %s -o %s_ser.msh --report %s_ser.json --posterior --tol 1e-10 -q", dir,
                  tu_cli(), scene_serial, tag, tag);
  if (rc) fprintf(stderr, "%s", out);
  free(out);
  rc |= tu_mpirun(&out, np, "sh -c 'cd %s && %s run %s -o %s_par.msh --report %s_par.json --posterior --tol 1e-9 -q'",
                  dir, tu_cli(), scene_parts, tag, tag);
  if (rc) fprintf(stderr, "%s", out);
  free(out);
  return rc;
}

void tu_mesh_and_split(const char *geo, int dim, double h, const char *dir, const char *name, int nparts) {
  char path[4096];
  int ierr = 0;
  snprintf(path, sizeof path, "%s/geometries/%s", tu_src(), geo);
  gmshClear(&ierr);
  gmshOpen(path, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", h, &ierr);
  gmshModelMeshGenerate(dim, &ierr);
  snprintf(path, sizeof path, "%s/%s.msh", dir, name);
  gmshWrite(path, &ierr);
  gmshOptionSetNumber("Mesh.PartitionCreateTopology", 0, &ierr); /* see src/gmsh/partition.c */
  gmshModelMeshPartition(nparts, &ierr);
  gmshOptionSetNumber("Mesh.PartitionSplitMeshFiles", 1, &ierr);
  snprintf(path, sizeof path, "%s/%s_parts.msh", dir, name);
  gmshWrite(path, &ierr);
  gmshOptionSetNumber("Mesh.PartitionSplitMeshFiles", 0, &ierr);
  if (ierr) fprintf(stderr, "meshing or splitting %s failed\n", geo), abort();
}

int tu_view_pair(const char *whole, const char *parts, int nparts, const char *name, tu_view *a, tu_view *b) {
  char path[4096];
  int ierr = 0;
  const char *dot = strrchr(parts, '.');
  gmshClear(&ierr);
  gmshOpen(whole, &ierr);
  int ra = tu_view_read(name, a);
  gmshClear(&ierr);
  for (int k = 1; k <= nparts; k++) {
    snprintf(path, sizeof path, "%.*s_%d%s", (int)(dot - parts), parts, k, dot);
    if (k == 1)
      gmshOpen(path, &ierr);
    else
      gmshMerge(path, &ierr);
  }
  int rb = tu_view_read(name, b);
  return ra || rb || ierr ? -1 : 0;
}

int tu_view_list(const char *path, char (*names)[96], int max) {
  int ierr = 0, *tags = NULL, k = 0;
  size_t n = 0;
  gmshClear(&ierr);
  gmshOpen(path, &ierr);
  gmshViewGetTags(&tags, &n, &ierr);
  for (size_t i = 0; i < n && k < max; i++) {
    char opt[64], *val = NULL;
    snprintf(opt, sizeof opt, "View[%d].Name", gmshViewGetIndex(tags[i], &ierr));
    gmshOptionGetString(opt, &val, &ierr);
    snprintf(names[k++], 96, "%s", val ? val : "");
    gmshFree(val);
  }
  gmshFree(tags);
  return k;
}

typedef struct {
  size_t tag;
  double v;
} tag_value;

static int by_tag(const void *x, const void *y) {
  size_t a = ((const tag_value *)x)->tag, b = ((const tag_value *)y)->tag;
  return a < b ? -1 : a > b;
}

static tag_value *sorted(const tu_view *v) {
  tag_value *t = malloc((v->n + 1) * sizeof *t);
  for (size_t i = 0; i < v->n; i++) t[i].tag = v->tags[i], t[i].v = v->values[i];
  qsort(t, v->n, sizeof *t, by_tag);
  return t;
}

void tu_view_compare(const tu_view *a, const tu_view *b, tu_view_diff *d) {
  tag_value *x = sorted(a), *y = sorted(b);
  size_t j = 0;
  double diff = 0, big = 0;
  memset(d, 0, sizeof *d);
  d->missing = a->n > b->n ? a->n - b->n : b->n - a->n;
  for (size_t i = 0; i < a->n; i++) {
    while (j < b->n && y[j].tag < x[i].tag) j++;
    if (j == b->n || y[j].tag != x[i].tag) {
      d->missing++;
      continue;
    }
    d->bitequal += memcmp(&x[i].v, &y[j].v, sizeof(double)) == 0;
    double rel = fabs(y[j].v - x[i].v) / fmax(fabs(x[i].v), 1e-300);
    d->worst = fmax(d->worst, rel);
    diff = fmax(diff, fabs(y[j].v - x[i].v)), big = fmax(big, fabs(x[i].v));
  }
  d->scaled = diff / fmax(big, 1e-300);
  free(x), free(y);
}
