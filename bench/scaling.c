/* Strong and weak scaling of the distributed run (docs/scaling.md; run by
 * bench/scaling.sh, not by ctest). Meshes the bundled box with Gmsh at the
 * sizes given, splits each mesh into P part files with Gmsh (METIS), runs
 * `mpirun -n P dtmap run` on them with the global estimate, and prints, as
 * Markdown tables, the wall time of each run and, from its report, the
 * slowest part's time per stage, the elements and ghost nodes per part and
 * the peak memory per rank, and for the global estimate the slowest part's
 * CPU time per operator product (its own work, whatever shares its core)
 * and wall time of the ghost exchanges per product; each figure is the
 * smallest of 5 runs, as other work shares the machine. The serial run (no
 * MPI) of the whole mesh is the first row of the strong-scaling table.
 * usage: bench_scaling DTMAP "MPIRUN ARGS" SRC WORKDIR STRONG_H WEAK_H1 WEAK_H2 WEAK_H4 */
#include <cJSON.h>
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "testutil.h"

static const char *dtmap, *mpirun, *src, *work;

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void die(const char *what) {
  fprintf(stderr, "bench_scaling: %s\n", what);
  exit(1);
}

/* box_h.msh at size h, its splits into 2 and 4 parts (box_h_P_k.msh), and
 * itself as the one part of a split into 1 (Gmsh 4.8 does not partition
 * into one). */
static void mesh_and_split(double h) {
  char path[4096];
  int ierr = 0;
  snprintf(path, sizeof path, "%s/geometries/box.geo", src);
  gmshClear(&ierr);
  gmshOpen(path, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", h, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMin", h / 4, &ierr);
  gmshModelMeshGenerate(3, &ierr);
  snprintf(path, sizeof path, "%s/box_%g.msh", work, h);
  gmshOptionSetNumber("Mesh.Binary", 1, &ierr);
  gmshWrite(path, &ierr);
  char one[4096];
  snprintf(one, sizeof one, "%s/box_%g_1_1.msh", work, h); /* one part: the whole mesh */
  gmshWrite(one, &ierr);
  for (int p = 2; p <= 4 && !ierr; p *= 2) {
    gmshClear(&ierr);
    gmshOpen(path, &ierr);
    gmshOptionSetNumber("Mesh.PartitionCreateTopology", 0, &ierr); /* see src/gmsh/partition.c */
    gmshModelMeshPartition(p, &ierr);
    if (ierr) die("partitioning failed");
    gmshOptionSetNumber("Mesh.PartitionSplitMeshFiles", 1, &ierr);
    char parts[4096];
    snprintf(parts, sizeof parts, "%s/box_%g_%d.msh", work, h, p);
    gmshWrite(parts, &ierr);
    gmshOptionSetNumber("Mesh.PartitionSplitMeshFiles", 0, &ierr);
  }
  gmshOptionSetNumber("Mesh.Binary", 0, &ierr);
  if (ierr) die("meshing or splitting failed");
}

static void scene(double h, int p) {
  char path[4096], mesh[512];
  if (p)
    snprintf(mesh, sizeof mesh, "<mesh file=\"box_%g_%d.msh\" partitions=\"%d\"/>", h, p, p);
  else
    snprintf(mesh, sizeof mesh, "<mesh file=\"box_%g.msh\"/>", h);
  snprintf(path, sizeof path, "%s/s_%g_%d.xml", work, h, p);
  FILE *f = fopen(path, "w");
  if (!f) die("cannot write a scene");
  fprintf(f,
          "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n  %s\n"
          "  <material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
          "  <effects><elastic/></effects>\n  <time target=\"4e-7\" duration=\"1e-4\"/>\n</dtmap-scene>\n",
          mesh);
  fclose(f);
}

static const cJSON *at(const cJSON *o, const char *a, const char *b) {
  return cJSON_GetObjectItem(b ? cJSON_GetObjectItem(o, a) : o, b ? b : a);
}

/* Largest entry of a numeric array; *lo gets the smallest. */
static double array_max(const cJSON *arr, double *lo) {
  double mx = 0, mn = INFINITY;
  for (int i = 0; i < cJSON_GetArraySize(arr); i++) {
    double v = cJSON_GetArrayItem(arr, i)->valuedouble;
    mx = fmax(mx, v), mn = fmin(mn, v);
  }
  if (lo) *lo = mn;
  return mx;
}

static double stage(const cJSON *rep, int p, const char *name) {
  if (!p) return cJSON_GetObjectItem(cJSON_GetObjectItem(rep, "timings"), name)->valuedouble;
  const cJSON *t = at(rep, "parallel", "timings");
  return array_max(cJSON_GetObjectItem(t, name), NULL);
}

/* The figures of one run: wall time, slowest part per stage. */
enum { F_WALL, F_READ, F_LAYOUT, F_MAP, F_GLOBAL, F_CPU, F_EXCHANGE, F_OUTPUT, F_COUNT };

static void figures(const cJSON *r, int p, double wall, double *f) {
  f[F_CPU] = p ? stage(r, p, "products_cpu") : NAN;
  f[F_EXCHANGE] = p ? stage(r, p, "exchange") : NAN;
  f[F_WALL] = wall;
  f[F_READ] = stage(r, p, p ? "read" : "mesh");
  f[F_LAYOUT] = stage(r, p, p ? "layout" : "extract");
  f[F_MAP] = stage(r, p, "effects") + stage(r, p, "nodal");
  f[F_GLOBAL] = stage(r, p, "global");
  f[F_OUTPUT] = stage(r, p, "output");
}

/* One run (p = 0: serial); returns its report. */
static cJSON *run_once(double h, int p, double *f) {
  char cmd[8192], rep[4096], launch[1024] = "";
  if (p) snprintf(launch, sizeof launch, "%s -n %d ", mpirun, p);
  snprintf(rep, sizeof rep, "%s/r_%g_%d.json", work, h, p);
  snprintf(cmd, sizeof cmd, "cd %s && %s%s run s_%g_%d.xml -o out_%g_%d.msh --report %s --posterior -q -j 1", work,
           launch, dtmap, h, p, h, p, rep);
  double t0 = now();
  if (system(cmd)) die(cmd);
  cJSON *r = tu_json_load(rep);
  if (!r) die("no report");
  figures(r, p, now() - t0, f);
  return r;
}

#define REPEAT 5 /* runs per row; each figure is the smallest (the machine is shared) */

/* REPEAT runs (p = 0: serial); prints one table row. */
static void run(double h, int p) {
  double best[F_COUNT], f[F_COUNT];
  cJSON *r = NULL;
  scene(h, p);
  for (int k = 0; k < REPEAT; k++) {
    cJSON_Delete(r);
    r = run_once(h, p, f);
    for (int i = 0; i < F_COUNT; i++) best[i] = k ? fmin(best[i], f[i]) : f[i];
  }
  double el = at(r, "mesh", "elements")->valuedouble, lo = el, mem = 0, memlo = 0, ghosts = 0;
  char memory[64] = "-", label[16] = "serial";
  if (p) {
    array_max(at(r, "parallel", "elements"), &lo);
    mem = array_max(at(r, "parallel", "memory_bytes"), &memlo) / 1048576.0, memlo /= 1048576.0;
    for (int i = 0; i < p; i++) ghosts += cJSON_GetArrayItem(at(r, "parallel", "ghost_nodes"), i)->valuedouble;
    snprintf(memory, sizeof memory, "%.0f-%.0f", memlo, mem), snprintf(label, sizeof label, "%d", p);
  }
  const cJSON *lz = cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(r, "effect_minima"), 0), "lanczos");
  int products = cJSON_GetObjectItem(lz, "iterations")->valueint;
  char cpu[32] = "-", exch[32] = "-"; /* not measured by the serial run */
  if (p) snprintf(cpu, sizeof cpu, "%.1f", 1e3 * best[F_CPU] / products);
  if (p) snprintf(exch, sizeof exch, "%.2f", 1e3 * best[F_EXCHANGE] / products);
  printf("| %s | %.0f | %.0f | %.0f | %.2f | %.2f | %.3f | %.3f | %.3f | %d | %.1f | %s | %s | %.2f | %s |\n", label,
         el, lo, ghosts, best[F_WALL], best[F_READ], best[F_LAYOUT], best[F_MAP], best[F_GLOBAL], products,
         1e3 * best[F_GLOBAL] / products, cpu, exch, best[F_OUTPUT], memory);
  fflush(stdout);
  cJSON_Delete(r);
}

static void header(void) {
  printf("| P | elements | smallest part | ghost nodes | wall (s) | read (s) | layout (s) | element map + nodal "
         "(s) | global (s) | products | global / product (ms) | product CPU, one part (ms) | exchange / product "
         "(ms) | output (s) | memory per rank (MB) |\n");
  printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
}

int main(int argc, char **argv) {
  if (argc < 9) die("usage: bench_scaling DTMAP \"MPIRUN ARGS\" SRC WORKDIR STRONG_H WEAK_H1 WEAK_H2 WEAK_H4");
  dtmap = argv[1], mpirun = argv[2], src = argv[3], work = argv[4];
  double strong = atof(argv[5]), weak[3] = {atof(argv[6]), atof(argv[7]), atof(argv[8])};
  int ierr = 0;
  gmshInitialize(0, NULL, 0, &ierr);
  gmshOptionSetNumber("General.Terminal", 0, &ierr);
  gmshOptionSetNumber("General.NumThreads", 1, &ierr);
  printf("### Strong scaling: one mesh (box, size %g m)\n\n", strong);
  mesh_and_split(strong);
  header();
  for (int p = 0; p <= 4; p = p ? 2 * p : 1) run(strong, p);
  printf("\n### Weak scaling: about the same elements per rank\n\n");
  header();
  for (int i = 0; i < 3; i++) {
    if (weak[i] != strong) mesh_and_split(weak[i]);
    run(weak[i], 1 << i);
  }
  gmshFinalize(&ierr);
  return 0;
}
