/* The output .msh in each encoding dtmap writes, read back through Gmsh:
 * - ASCII and binary files hold the mesh and the views; Gmsh reads every
 *   view back with the same tags and bit-identical values (ASCII writes
 *   %.17g, binary the doubles themselves); the header says which encoding;
 * - a small mesh with format auto is ASCII;
 * - a views-only file has no mesh, and merged over the input .msh gives
 *   the same views on the unchanged input mesh;
 * - views-only without a <mesh> input, and an unknown --format, are bad
 *   input (exit 2);
 * - the .opt (merged as Gmsh opens the file) gives every step view a colour
 *   range that holds its smallest and largest values even after Gmsh's
 *   rounding of its log scale's interval bounds (an element outside every
 *   interval is not drawn). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "testutil.h"

#define MESHING "size=\"0.3\" dim=\"3\"" /* about 200 tets */

static void tmp_path(char *buf, size_t len, const char *name) { snprintf(buf, len, "%s/%s", tu_tmpdir(), name); }

static int contains(const char *buf, size_t n, const char *what) {
  size_t k = strlen(what);
  for (size_t i = 0; i + k <= n; i++)
    if (!memcmp(buf + i, what, k)) return 1;
  return 0;
}

/* Expected values by tag: element tags of the analysis (or node tags),
 * compared exactly with what Gmsh read. */
static void check_view(const char *name, const size_t *tags, const double *vals, size_t n) {
  tu_view v;
  assert_int_equal(tu_view_read(name, &v), 0);
  assert_int_equal(v.n, n);
  size_t maxtag = 0;
  for (size_t i = 0; i < n; i++) maxtag = tags[i] > maxtag ? tags[i] : maxtag;
  double *by_tag = calloc(maxtag + 1, sizeof *by_tag);
  for (size_t i = 0; i < n; i++) by_tag[tags[i]] = vals[i];
  for (size_t i = 0; i < v.n; i++) {
    assert_true(v.tags[i] <= maxtag);
    assert_true(v.values[i] == by_tag[v.tags[i]]); /* exact: %.17g and binary both round-trip */
  }
  free(by_tag);
  tu_view_free(&v);
}

static void check_all(const dtm_analysis *a) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t nel = dtm_analysis_nelements(a), *etags = malloc(nel * sizeof *etags), k = 0, nsz = 0;
  for (int b = 0; b < m->nblocks; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++) etags[k++] = m->blocks[b].tags[e];
  check_view("dt", etags, dtm_analysis_dt(a), nel);
  check_view("characteristic length", etags, dtm_analysis_length(a), nel);
  double *lim = malloc(nel * sizeof *lim); /* integers, written as numbers */
  for (size_t i = 0; i < nel; i++) lim[i] = dtm_analysis_limiting(a)[i];
  check_view("limiting effect", etags, lim, nel);
  check_view("dt elastic", etags, dtm_analysis_effect_dt(a, 0), nel); /* every value finite here: all kept */
  free(lim);
  const double *sz = dtm_analysis_size_suggestion(a);
  size_t *ntags = malloc(m->nnodes * sizeof *ntags);
  double *nvals = malloc(m->nnodes * sizeof *nvals);
  for (size_t v = 0; v < m->nnodes; v++)
    if (sz[v] == sz[v]) ntags[nsz] = m->node_tags[v], nvals[nsz++] = sz[v];
  check_view("size suggestion", ntags, nvals, nsz);
  free(etags), free(ntags), free(nvals);
}

static double view_number(int i, const char *what) {
  char name[96];
  double v = NAN;
  int ierr = 0;
  snprintf(name, sizeof name, "View[%d].%s", i, what);
  gmshOptionGetNumber(name, &v, &ierr);
  return ierr ? NAN : v;
}

/* Every step view (its name "dt", "dt ...", "nodal dt" or "... [s]") is on
 * a custom range: Gmsh's first and last interval bounds of its 12 discrete
 * intervals on a log scale, 10^(log10 lo + k (log10 hi - log10 lo) / 12)
 * for k = 0 and 12 (PViewOptions::getScaleValue), hold the view's smallest
 * and largest values (View.Min, View.Max); the widening is at most 1e-5
 * relative, below what the bar's three digits show. Returns the count. */
static int check_ranges(void) {
  int n = tu_view_count(), checked = 0, ierr = 0;
  for (int i = 0; i < n; i++) {
    char key[64], *name = NULL;
    snprintf(key, sizeof key, "View[%d].Name", i);
    gmshOptionGetString(key, &name, &ierr);
    int step = !strcmp(name, "dt") || !strncmp(name, "dt ", 3) || !strcmp(name, "nodal dt") || strstr(name, "[s]");
    gmshFree(name);
    if (!step) continue;
    double lo = view_number(i, "CustomMin"), hi = view_number(i, "CustomMax");
    double vmin = view_number(i, "Min"), vmax = view_number(i, "Max");
    assert_true(view_number(i, "RangeType") == 2);
    assert_true(pow(10., log10(lo)) <= vmin && pow(10., log10(lo) + 12 * (log10(hi) - log10(lo)) / 12) >= vmax);
    assert_true(lo >= vmin * (1 - 1e-5) && hi <= vmax * (1 + 1e-5));
    checked++;
  }
  return checked;
}

static void round_trip(int format, const char *header) {
  dtm_scene *s = NULL;
  tu_steel_scene("cube", "<geometry file=\"cube.geo\"/>", MESHING, "");
  dtm_analysis *a = tu_analyse("cube", &s);
  char out[600];
  tmp_path(out, sizeof out, "cube_out.msh");
  dtm_results res = {a, NULL, NULL, 0, 0, 0, 0, {NULL}, {NULL}, NULL, NULL};
  dtm_output_opts o = {format, 0, 0, 0};
  assert_int_equal(dtm_output_write_ex(&res, out, &o), 0);
  size_t n;
  char *buf = tu_slurp(out, &n);
  assert_int_equal(strncmp(buf, header, strlen(header)), 0);
  assert_true(contains(buf, n, "$Nodes"));
  free(buf);
  int ierr = 0;
  gmshClear(&ierr);
  gmshOpen(out, &ierr);
  assert_int_equal(ierr, 0);
  check_all(a);
  assert_true(check_ranges() >= 3); /* dt, dt elastic, nodal dt, below target or smallest 1 % */
  gmshClear(&ierr);
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
}

static void ascii(void **unused) {
  round_trip(DTM_MSH_ASCII, "$MeshFormat\n4.1 0 8\n");
  (void)unused;
}
static void binary(void **unused) {
  round_trip(DTM_MSH_BINARY, "$MeshFormat\n4.1 1 8\n");
  (void)unused;
}
static void auto_small_is_ascii(void **unused) {
  round_trip(DTM_MSH_AUTO, "$MeshFormat\n4.1 0 8\n");
  (void)unused;
}

/* The input .msh of the views-only case: the cube meshed by Gmsh. */
static void make_input(const char *msh) {
  char path[600];
  int ierr = 0;
  tmp_path(path, sizeof path, "cube.geo");
  gmshClear(&ierr);
  gmshOpen(path, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", 0.3, &ierr);
  gmshModelMeshGenerate(3, &ierr);
  gmshWrite(msh, &ierr);
  assert_int_equal(ierr, 0);
  gmshClear(&ierr);
}

static size_t model_elements(int dim) {
  int *types = NULL, ierr = 0;
  size_t nt = 0, **et = NULL, *net = NULL, ne = 0, **nt2 = NULL, *nnt = NULL, nn = 0, total = 0;
  gmshModelMeshGetElements(&types, &nt, &et, &net, &ne, &nt2, &nnt, &nn, dim, -1, &ierr);
  for (size_t i = 0; i < nt; i++) total += net[i], gmshFree(et[i]), gmshFree(nt2[i]);
  gmshFree(types), gmshFree(et), gmshFree(net), gmshFree(nt2), gmshFree(nnt);
  return total;
}

static void views_only(void **unused) {
  char in[600], out[600];
  tmp_path(in, sizeof in, "cube_in.msh");
  tmp_path(out, sizeof out, "cube_views.msh");
  make_input(in);
  tu_steel_scene("from_msh", "<mesh file=\"cube_in.msh\"/>", MESHING, "");
  dtm_scene *s = NULL;
  dtm_analysis *a = tu_analyse("from_msh", &s);
  dtm_results res = {a, NULL, NULL, 0, 0, 0, 0, {NULL}, {NULL}, NULL, NULL};
  for (int format = DTM_MSH_ASCII; format <= DTM_MSH_BINARY; format++) {
    dtm_output_opts o = {format, 1, 0, 0};
    int ierr = 0;
    gmshClear(&ierr);
    gmshOpen(in, &ierr); /* the analysis' model, as dtmap run leaves it */
    assert_int_equal(dtm_output_write_ex(&res, out, &o), 0);
    size_t n;
    char *buf = tu_slurp(out, &n);
    assert_false(contains(buf, n, "$Nodes"));
    assert_false(contains(buf, n, "$Elements"));
    free(buf);
    gmshClear(&ierr);
    gmshOpen(in, &ierr);
    size_t before = model_elements(3);
    gmshMerge(out, &ierr);
    assert_int_equal(ierr, 0);
    assert_int_equal(model_elements(3), before);
    assert_int_equal(before, dtm_analysis_nelements(a));
    check_all(a);
  }
  int ierr = 0;
  gmshClear(&ierr);
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
  (void)unused;
}

static void views_only_needs_mesh(void **unused) {
  dtm_scene *s = NULL;
  tu_steel_scene("cube", "<geometry file=\"cube.geo\"/>", MESHING, "");
  dtm_analysis *a = tu_analyse("cube", &s);
  char out[600];
  tmp_path(out, sizeof out, "never.msh");
  dtm_results res = {a, NULL, NULL, 0, 0, 0, 0, {NULL}, {NULL}, NULL, NULL};
  dtm_output_opts o = {DTM_MSH_AUTO, 1, 0, 0};
  assert_int_equal(dtm_output_write_ex(&res, out, &o), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "views-only"));
  assert_false(tu_exists(out));
  dtm_error_clear();
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
  (void)unused;
}

static void cli_format_words(void **unused) {
  char *log = NULL, scene[600];
  tu_steel_scene("cli", "<geometry file=\"cube.geo\"/>", MESHING, "<output format=\"binary\"/>");
  tmp_path(scene, sizeof scene, "cli.xml");
  assert_int_equal(tu_run(&log, "cd %s && %s run %s --format hex -q", tu_tmpdir(), tu_cli(), scene), 2);
  assert_non_null(strstr(log, "--format 'hex'"));
  free(log);
  assert_int_equal(tu_run(&log, "cd %s && %s run %s -q -o cli_out.msh", tu_tmpdir(), tu_cli(), scene), 0);
  free(log);
  size_t n;
  char out[600];
  tmp_path(out, sizeof out, "cli_out.msh");
  char *buf = tu_slurp(out, &n);
  assert_int_equal(strncmp(buf, "$MeshFormat\n4.1 1 8\n", 20), 0); /* the scene's <output format="binary"> */
  free(buf);
  assert_int_equal(tu_run(&log, "cd %s && %s run %s --views-only --png p -q", tu_tmpdir(), tu_cli(), scene), 2);
  assert_non_null(strstr(log, "--views-only"));
  free(log);
  assert_int_equal(tu_run(&log, "cd %s && %s run %s --views-only -q -o v.msh", tu_tmpdir(), tu_cli(), scene), 2);
  assert_non_null(strstr(log, "views-only"));
  free(log);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_cube_geo("cube.geo", "");
  if (dtm_gmsh_start(0)) return 3;
  const struct CMUnitTest tests[] = {cmocka_unit_test(ascii),
                                     cmocka_unit_test(binary),
                                     cmocka_unit_test(auto_small_is_ascii),
                                     cmocka_unit_test(views_only),
                                     cmocka_unit_test(views_only_needs_mesh),
                                     cmocka_unit_test(cli_format_words)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_gmsh_stop();
  return r;
}
