/* Hard-case corpus helpers: building single-type meshes by hand (nodes,
 * positively oriented simplices, Kuhn-split grid cells), writing them or
 * the current Gmsh model to a .msh with named physical groups, writing a
 * scene that reads that mesh, and checking one case through the CLI:
 * Lanczos converged for every spectral effect, element and nodal bounds
 * at or below the global estimate, verify bounded at the recommended step
 * and unbounded at 1.05 x the smallest unsafe side of the global bracket. */
#include "hardcase.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "testutil.h"

/* ---------- building a mesh ---------- */

void hc_mesh_init(hc_mesh *m, int dim, int type, int npe, const char *group0) {
  memset(m, 0, sizeof *m);
  m->dim = dim, m->type = type, m->npe = npe;
  m->groups[0] = group0, m->ngroups = 1;
}

void hc_mesh_free(hc_mesh *m) {
  free(m->xyz), free(m->conn), free(m->group);
  memset(m, 0, sizeof *m);
}

size_t hc_node(hc_mesh *m, double x, double y, double z) {
  if (m->nn == m->cap_n) {
    m->cap_n = m->cap_n ? 2 * m->cap_n : 64;
    m->xyz = realloc(m->xyz, 3 * m->cap_n * sizeof *m->xyz);
    assert_non_null(m->xyz);
  }
  double *p = m->xyz + 3 * m->nn++;
  p[0] = x, p[1] = y, p[2] = z;
  return m->nn;
}

void hc_elem(hc_mesh *m, const size_t *nodes, int group) {
  if (m->ne == m->cap_e) {
    m->cap_e = m->cap_e ? 2 * m->cap_e : 64;
    m->conn = realloc(m->conn, (size_t)m->npe * m->cap_e * sizeof *m->conn);
    m->group = realloc(m->group, m->cap_e * sizeof *m->group);
    assert_true(m->conn && m->group);
  }
  assert_true(group >= 0 && group < m->ngroups);
  memcpy(m->conn + (size_t)m->npe * m->ne, nodes, (size_t)m->npe * sizeof *nodes);
  m->group[m->ne++] = group;
}

static const double *xyz_of(const hc_mesh *m, size_t tag) { return m->xyz + 3 * (tag - 1); }

double hc_simplex_measure(const hc_mesh *m, const size_t *n) {
  const double *a = xyz_of(m, n[0]);
  double e[3][3];
  for (int k = 1; k < m->npe; k++)
    for (int c = 0; c < 3; c++) e[k - 1][c] = xyz_of(m, n[k])[c] - a[c];
  if (m->npe == 3) return 0.5 * (e[0][0] * e[1][1] - e[0][1] * e[1][0]);
  return (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
          e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
         6.0;
}

static double longest_edge(const hc_mesh *m, const size_t *n) {
  double l = 0;
  for (int i = 0; i < m->npe; i++)
    for (int k = i + 1; k < m->npe; k++) {
      const double *a = xyz_of(m, n[i]), *b = xyz_of(m, n[k]);
      l = fmax(l, sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2])));
    }
  return l;
}

void hc_simplex(hc_mesh *m, const size_t *nodes, int group) {
  size_t n[4];
  memcpy(n, nodes, (size_t)m->npe * sizeof *n);
  double v = hc_simplex_measure(m, n), l = longest_edge(m, n);
  assert_true(fabs(v) > 1e-12 * pow(l, m->npe - 1)); /* not degenerate */
  if (v < 0) {
    size_t t = n[0];
    n[0] = n[1], n[1] = t;
  }
  hc_elem(m, n, group);
}

/* A copy of element e with node `from` replaced by `to`, appended. */
static void append_replaced(hc_mesh *m, size_t e, size_t from, size_t to) {
  size_t n[8];
  memcpy(n, m->conn + (size_t)m->npe * e, (size_t)m->npe * sizeof *n);
  for (int k = 0; k < m->npe; k++)
    if (n[k] == from) n[k] = to;
  hc_elem(m, n, m->group[e]);
}

static int has_node(const hc_mesh *m, size_t e, size_t tag) {
  for (int k = 0; k < m->npe; k++)
    if (m->conn[(size_t)m->npe * e + (size_t)k] == tag) return 1;
  return 0;
}

size_t hc_split_edge(hc_mesh *m, size_t a, size_t b, size_t p) {
  size_t ne = m->ne, count = 0;
  for (size_t e = 0; e < ne; e++) {
    if (!has_node(m, e, a) || !has_node(m, e, b)) continue;
    append_replaced(m, e, a, p);
    for (int k = 0; k < m->npe; k++)
      if (m->conn[(size_t)m->npe * e + (size_t)k] == b) m->conn[(size_t)m->npe * e + (size_t)k] = p;
    count++;
  }
  return count;
}

void hc_split_simplex(hc_mesh *m, size_t e, size_t p) {
  for (int k = 1; k < m->npe; k++) append_replaced(m, e, m->conn[(size_t)m->npe * e + (size_t)k], p);
  m->conn[(size_t)m->npe * e] = p; /* after the appends: hc_elem may move conn */
}

double hc_aspect(const hc_mesh *m, size_t e) {
  const size_t *n = m->conn + (size_t)m->npe * e;
  double lo = INFINITY, hi = 0;
  for (int a = 0; a < m->npe; a++)
    for (int b = a + 1; b < m->npe; b++) {
      const double *p = xyz_of(m, n[a]), *q = xyz_of(m, n[b]);
      double l = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
      lo = fmin(lo, l), hi = fmax(hi, l);
    }
  return hi / lo;
}

/* ---------- structured builders ---------- */

size_t hc_grid_tag(size_t first, int nx, int ny, int i, int j, int k) {
  return first + (size_t)i + (size_t)(nx + 1) * ((size_t)j + (size_t)(ny + 1) * (size_t)k);
}

size_t hc_grid_nodes(hc_mesh *m, const double *x, int nx, const double *y, int ny, const double *z, int nz) {
  size_t first = m->nn + 1;
  for (int k = 0; k <= nz; k++)
    for (int j = 0; j <= ny; j++)
      for (int i = 0; i <= nx; i++) hc_node(m, x[i], y[j], nz ? z[k] : 0.0);
  return first;
}

void hc_kuhn_cell(hc_mesh *m, size_t first, int nx, int ny, int i, int j, int k, int group) {
  static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int p = 0; p < 6; p++) {
    int c[3] = {i, j, k};
    size_t t[4];
    t[0] = hc_grid_tag(first, nx, ny, c[0], c[1], c[2]);
    for (int s = 0; s < 3; s++) c[perm[p][s]]++, t[s + 1] = hc_grid_tag(first, nx, ny, c[0], c[1], c[2]);
    hc_simplex(m, t, group);
  }
}

void hc_box(hc_mesh *m, const double *x, int nx, const double *y, int ny, const double *z, int nz) {
  size_t first = hc_grid_nodes(m, x, nx, y, ny, z, nz);
  for (int k = 0; k < nz; k++)
    for (int j = 0; j < ny; j++)
      for (int i = 0; i < nx; i++) hc_kuhn_cell(m, first, nx, ny, i, j, k, 0);
}

void hc_rect(hc_mesh *m, const double *x, int nx, const double *y, int ny) {
  size_t first = hc_grid_nodes(m, x, nx, y, ny, NULL, 0);
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) {
      size_t a = hc_grid_tag(first, nx, ny, i, j, 0), b = a + 1, d = hc_grid_tag(first, nx, ny, i, j + 1, 0);
      size_t t1[3] = {a, b, d + 1}, t2[3] = {a, d + 1, d};
      hc_simplex(m, t1, 0), hc_simplex(m, t2, 0);
    }
}

void hc_bar(hc_mesh *m, const double *x, int n) {
  size_t first = m->nn + 1;
  for (int i = 0; i <= n; i++) hc_node(m, x[i], 0, 0);
  for (int i = 0; i < n; i++) {
    size_t e[2] = {first + (size_t)i, first + (size_t)i + 1};
    hc_elem(m, e, 0);
  }
}

/* ---------- writing meshes ---------- */

static void msh_path(const char *name, const char *ext, char *buf, size_t len) {
  snprintf(buf, len, "%s/%s.%s", tu_tmpdir(), name, ext);
}

/* Elements of group g as tags and connectivity (malloc'ed). */
static size_t group_elements(const hc_mesh *m, int g, size_t **tags, size_t **conn) {
  size_t n = 0, npe = (size_t)m->npe;
  *tags = malloc((m->ne + 1) * sizeof **tags);
  *conn = malloc((m->ne * npe + 1) * sizeof **conn);
  assert_true(*tags && *conn);
  for (size_t e = 0; e < m->ne; e++) {
    if (m->group[e] != g) continue;
    (*tags)[n] = e + 1;
    memcpy(*conn + n * npe, m->conn + e * npe, npe * sizeof **conn);
    n++;
  }
  return n;
}

void hc_model_write(const char *name, double scale) {
  char path[600];
  int ierr = 0;
  msh_path(name, "msh", path, sizeof path);
  gmshOptionSetNumber("Mesh.ScalingFactor", scale, &ierr);
  gmshWrite(path, &ierr);
  assert_int_equal(ierr, 0);
  gmshOptionSetNumber("Mesh.ScalingFactor", 1.0, &ierr);
}

void hc_mesh_write(const hc_mesh *m, const char *name) {
  int ierr = 0;
  gmshClear(&ierr);
  gmshModelAdd(name, &ierr);
  for (int g = 0; g < m->ngroups; g++) gmshModelAddDiscreteEntity(m->dim, g + 1, NULL, 0, &ierr);
  size_t *tags = malloc(m->nn * sizeof *tags), *etags = NULL, *conn = NULL;
  assert_non_null(tags);
  for (size_t i = 0; i < m->nn; i++) tags[i] = i + 1;
  gmshModelMeshAddNodes(m->dim, 1, tags, m->nn, m->xyz, 3 * m->nn, NULL, 0, &ierr);
  free(tags);
  assert_int_equal(ierr, 0);
  for (int g = 0; g < m->ngroups; g++) {
    size_t n = group_elements(m, g, &etags, &conn);
    int ent = g + 1;
    gmshModelMeshAddElementsByType(ent, m->type, etags, n, conn, n * (size_t)m->npe, &ierr);
    assert_int_equal(ierr, 0);
    gmshModelAddPhysicalGroup(m->dim, &ent, 1, ent, &ierr);
    gmshModelSetPhysicalName(m->dim, ent, m->groups[g], &ierr);
    free(etags), free(conn);
  }
  hc_model_write(name, 1.0);
}

size_t hc_model_census(int dim, char *buf, size_t len) {
  int *types = NULL, ierr = 0;
  size_t nt = 0, **et = NULL, *etn = NULL, etnn = 0, **nt_ = NULL, *ntn = NULL, ntnn = 0, total = 0;
  gmshModelMeshGetElements(&types, &nt, &et, &etn, &etnn, &nt_, &ntn, &ntnn, dim, -1, &ierr);
  buf[0] = '\0';
  for (size_t i = 0; i < nt; i++) {
    char *ename = NULL;
    int d, order, nn, npv;
    double *lc = NULL;
    size_t nlc = 0, used = strlen(buf);
    gmshModelMeshGetElementProperties(types[i], &ename, &d, &order, &nn, &lc, &nlc, &npv, &ierr);
    snprintf(buf + used, len - used, "%s%s %zu", i ? ", " : "", ename ? ename : "?", etn[i]);
    total += etn[i];
    gmshFree(ename), gmshFree(lc), gmshFree(et[i]), gmshFree(nt_[i]);
  }
  gmshFree(types), gmshFree(et), gmshFree(etn), gmshFree(nt_), gmshFree(ntn);
  return total;
}

/* ---------- scenes and the CLI ---------- */

void hc_scene_write(const char *name, const char *materials, const char *effects) {
  char path[600], text[8192];
  msh_path(name, "xml", path, sizeof path);
  snprintf(text, sizeof text,
           "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n  <mesh file=\"%s.msh\"/>\n%s\n"
           "  <effects>%s</effects>\n</dtmap-scene>\n",
           name, materials, effects);
  tu_write(path, text);
}

static double wall(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* `dtmap run` writing name_dt.msh and name.json; fails the test on error. */
static cJSON *run_report(const char *name, int posterior) {
  char scene[600], rep[600], *log = NULL;
  msh_path(name, "xml", scene, sizeof scene);
  msh_path(name, "json", rep, sizeof rep);
  int code = tu_run(&log, "%s run %s -q%s -o %s/%s_dt.msh --report %s", tu_cli(), scene,
                    posterior ? " --posterior" : "", tu_tmpdir(), name, rep);
  if (code) fprintf(stderr, "%s: dtmap run exited %d:\n%s\n", name, code, log);
  free(log);
  assert_int_equal(code, 0);
  cJSON *j = tu_json_load(rep);
  assert_non_null(j);
  return j;
}

double hc_run_number(const char *name, int posterior, const char *dotted) {
  cJSON *j = run_report(name, posterior);
  double v = tu_json_number(j, dotted);
  cJSON_Delete(j);
  return v;
}

/* Largest growth in the table `dtmap verify` prints ("  NAME GROWTH [..."). */
static double parse_growth(const char *log) {
  const char *p = log ? strstr(log, "verdict") : NULL;
  double worst = NAN;
  while (p && (p = strchr(p, '\n')) != NULL) {
    char eff[64];
    double g;
    p++;
    if (sscanf(p, " %63s %lf", eff, &g) == 2 && strchr(p, '[') && (isnan(worst) || g > worst)) worst = g;
  }
  return worst;
}

/* `dtmap verify` with extra arguments; the exit code, and the growth. */
static int verify(const char *name, const char *args, double *growth) {
  char scene[600], *log = NULL;
  msh_path(name, "xml", scene, sizeof scene);
  int code = tu_run(&log, "%s verify %s %s", tu_cli(), scene, args);
  *growth = parse_growth(log);
  if (code != 0 && code != 1) fprintf(stderr, "%s: dtmap verify %s exited %d:\n%s\n", name, args, code, log);
  free(log);
  return code;
}

/* Every effect with a Lanczos run converged; the smallest unsafe side. */
static void scan_lanczos(const cJSON *rep, hc_result *r) {
  const cJSON *e, *mins = cJSON_GetObjectItemCaseSensitive(rep, "effect_minima");
  int found = 0;
  r->unsafe = INFINITY, r->iterations = 0;
  cJSON_ArrayForEach(e, mins) {
    const cJSON *lz = cJSON_GetObjectItemCaseSensitive(e, "lanczos");
    if (!lz) continue;
    found++;
    assert_true(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(lz, "converged")));
    const cJSON *br = cJSON_GetObjectItemCaseSensitive(lz, "dt_bracket");
    assert_true(cJSON_IsArray(br) && cJSON_GetArraySize(br) == 2);
    double lo = cJSON_GetArrayItem(br, 0)->valuedouble, hi = cJSON_GetArrayItem(br, 1)->valuedouble;
    assert_true(lo > 0 && lo <= hi);
    if (hi < r->unsafe) {
      const cJSON *nm = cJSON_GetObjectItemCaseSensitive(e, "name");
      r->unsafe = hi, r->theta = tu_json_number(lz, "theta");
      snprintf(r->effect, sizeof r->effect, "%s", cJSON_IsString(nm) ? nm->valuestring : "?");
    }
    r->iterations = (int)fmax(r->iterations, tu_json_number(lz, "iterations"));
  }
  assert_true(found > 0);
}

static void read_result(const cJSON *j, hc_result *r) {
  r->elements = (size_t)tu_json_number(j, "mesh.elements");
  r->dt_min = tu_json_number(j, "dt.min");
  r->dt_nodal = tu_json_number(j, "dt.nodal");
  r->dt_global = tu_json_number(j, "dt.global");
  r->recommended = tu_json_number(j, "dt.recommended");
  const cJSON *b = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "dt"), "basis");
  snprintf(r->basis, sizeof r->basis, "%s", cJSON_IsString(b) ? b->valuestring : "?");
  scan_lanczos(j, r);
}

void hc_table_header(void) {
  printf("| case | elements | dt.min/dt.global | dt.nodal/dt.global | Lanczos its | limiting | basis | "
         "growth at recommended | growth at 1.05 x unsafe | seconds |\n");
}

static void print_row(const char *name, const hc_result *r) {
  printf("| %s | %zu | %.4f | %.4f | %d | %s | %s | %.4g | %.4g | %.2f |\n", name, r->elements,
         r->dt_min / r->dt_global, r->dt_nodal / r->dt_global, r->iterations, r->effect, r->basis, r->growth_ok,
         r->growth_bad, r->seconds);
  fflush(stdout);
}

void hc_check(const char *name, hc_result *r) {
  double t0 = wall();
  memset(r, 0, sizeof *r);
  cJSON *j = run_report(name, 1);
  read_result(j, r);
  cJSON_Delete(j);
  /* Both bounds are rigorous, so at or below the true 2/omega_max and thus
   * below every unsafe side. dt.global is the safe side, below the truth
   * by at most the Lanczos residual, so a bound that is exact (a uniform
   * bar) could exceed it by ~tol; no case here is that tight (<= 0.95). */
  assert_true(isfinite(r->dt_global) && r->dt_global > 0);
  assert_true(r->dt_min <= (1 + 1e-9) * r->dt_global);
  assert_true(isfinite(r->dt_nodal) && r->dt_nodal <= (1 + 1e-9) * r->dt_global);
  assert_true(r->dt_min <= (1 + 1e-12) * r->dt_nodal); /* the nodal bound is the tighter */
  char args[128];
  int ok = verify(name, "--posterior --steps 2000", &r->growth_ok); /* run --posterior's recommended step */
  snprintf(args, sizeof args, "--dt %.17g --steps 2000", 1.05 * r->unsafe);
  int bad = verify(name, args, &r->growth_bad);
  r->seconds = wall() - t0;
  print_row(name, r);
  assert_int_equal(ok, 0);
  assert_int_equal(bad, 1);
}

int hc_group_setup(void **state) {
  hc_table_header();
  (void)state;
  return 0;
}
