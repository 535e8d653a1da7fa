/* `dtmap sweep SCENE.xml --sizes h1,h2,... [--csv F] [--plot F.png]`: mesh
 * and analyse the scene at each size, print the cost/accuracy table, write
 * it as CSV and draw it as a PNG (defaults SCENE_sweep.csv and
 * SCENE_sweep.png in the current directory; a dtmap built without PLplot
 * writes no PNG unless --plot asks for one, which is then an error before
 * the sweep starts). A size Gmsh cannot mesh, or crashes in (each size is
 * meshed in a child process, contained), is a row with its reason; the
 * other sizes are written. Exit 0 on success, 1 when some size gave no
 * figures (the others written), 2 for bad input or usage (with a message
 * saying what; also when no size gave figures), 3 for internal errors. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "dtmap/scene.h"
#include "dtmap/sweep.h"

/* Parse "h1,h2,..." into a malloc'ed array of positive finite sizes. */
static int parse_sizes(const char *text, double **sizes, int *n) {
  int cap = 1;
  for (const char *p = text; *p; p++) cap += *p == ',';
  double *v = malloc((size_t)cap * sizeof *v);
  if (!v) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  const char *p = text;
  for (int i = 0; i < cap; i++) {
    char *end = NULL;
    v[i] = strtod(p, &end);
    if (end == p || (*end && *end != ',') || !(v[i] > 0) || !isfinite(v[i])) {
      free(v);
      int len = (int)strcspn(p, ",");
      return DTM_ERR(DTM_ERR_INPUT, "--sizes: '%.*s' is not a positive, finite size (m, or mm under mm-t-s)", len, p);
    }
    p = *end ? end + 1 : end;
  }
  *sizes = v, *n = cap;
  return DTM_OK;
}

/* The CSV and PNG paths: the options, else SCENE_sweep.csv/.png; png is
 * "" when this dtmap cannot plot and no plot was asked for. */
static void output_paths(const cli_opts *o, char *csv, char *png, size_t len) {
  dtm_cli_default_out(o->scene, "_sweep.csv", csv, len);
  dtm_cli_default_out(o->scene, "_sweep.png", png, len);
  if (o->csv) snprintf(csv, len, "%s", o->csv);
  if (o->plot) snprintf(png, len, "%s", o->plot);
  if (!o->plot && !dtm_cli_can_plot()) png[0] = '\0';
}

/* Fail before a long sweep when an output cannot be written. */
static int check_outputs(const dtm_scene *s, const cli_opts *o, const char *csv, const char *png) {
  DTM_CHECK(dtm_output_path_check(s, csv, NULL, o->csv ? "--csv" : "default CSV"));
  if (png[0]) DTM_CHECK(dtm_output_path_check(s, png, NULL, o->plot ? "--plot" : "default plot"));
  if (strcmp(csv, png)) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT, "--csv %s and --plot %s: two outputs with one name", csv, png);
}

/* The CSV (every row, the failed ones with their reason) and the plot (the
 * rows with figures). */
static int write_files(const cli_opts *o, const dtm_sweep_row *rows, int n) {
  char csv[4096], png[4096];
  const char *base = strrchr(o->scene, '/');
  output_paths(o, csv, png, sizeof csv);
  DTM_CHECK(dtm_sweep_write_csv(csv, rows, n));
  dtm_sweep_row *ok = malloc((size_t)n * sizeof *ok);
  if (!ok) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int k = 0;
  for (int i = 0; i < n; i++)
    if (!rows[i].failed[0]) ok[k++] = rows[i];
  int r = png[0] ? dtm_cli_sweep_plot_titled(png, base ? base + 1 : o->scene, ok, k) : DTM_OK;
  free(ok);
  DTM_CHECK(r);
  if (o->verbosity) printf("\nwrote        %s%s%s\n", csv, png[0] ? ", " : " (no plot: built without PLplot)", png);
  return DTM_OK;
}

/* On stderr, even with -q, as `run` does: the sizes whose mesh has
 * elements inverted at a node (analysed; `run` at that size lists them). */
static void warn_flagged(const dtm_sweep_row *rows, int n) {
  for (int i = 0; i < n; i++)
    if (rows[i].flagged)
      fprintf(stderr,
              "dtmap: warning: at size %g %s, %zu element%s inverted at a node but valid at every integration "
              "point: analysed (dtmap run at that size names them)\n",
              rows[i].h, rows[i].length_unit, rows[i].flagged, rows[i].flagged == 1 ? " is" : "s are");
}

/* On stderr, even with -q: each size that gave no figures, and why
 * (written: the others were written; else every size failed and the
 * first is the command's error); returns how many. */
static int warn_failed(const dtm_sweep_row *rows, int n, int written) {
  int k = 0;
  for (int i = 0; i < n; i++) {
    if (!rows[i].failed[0]) continue;
    if (written || k)
      fprintf(stderr, "dtmap: error: sweep at size %g %s: %s%s\n", rows[i].h, rows[i].length_unit, rows[i].failed,
              written ? " (a row of the table and the CSV; the other sizes are written)" : "");
    k++;
  }
  return k;
}

/* DTM_OK, or 1 (the exit code) when some size gave no figures. */
static int sweep_scene(const cli_opts *o, const double *sizes, int n) {
  dtm_scene *s = NULL;
  dtm_sweep_row *rows = calloc((size_t)n, sizeof *rows);
  if (!rows) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  char csv[4096], png[4096];
  output_paths(o, csv, png, sizeof csv);
  int r = dtm_scene_load(o->scene, &s), started = 0;
  if (r == DTM_OK) r = check_outputs(s, o, csv, png);
  if (r == DTM_OK) r = dtm_cli_verified(s, o);
  if (r == DTM_OK && png[0] && !dtm_cli_can_plot()) r = dtm_cli_sweep_plot(png, rows, n);
  if (r == DTM_OK) r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0), started = r == DTM_OK;
  dtm_gmsh_contain(1, -1); /* every size meshed in a child: a crash in Gmsh fails that size's row, not the sweep */
  if (r == DTM_OK && o->verbosity) printf("dtmap sweep: %s, %d size%s\n\n", s->path, n, n > 1 ? "s" : "");
  if (r == DTM_OK && (r = dtm_sweep_run(s, sizes, n, rows)) != DTM_OK) warn_failed(rows, n, 0);
  if (r == DTM_OK && o->verbosity) dtm_sweep_print(rows, n, stdout);
  if (r == DTM_OK) warn_flagged(rows, n);
  if (r == DTM_OK && o->verbosity && !(s->duration > 0))
    printf("(no <time duration>: steps and element-steps need one; the plot shows cost per simulated second)\n");
  if (r == DTM_OK) r = write_files(o, rows, n);
  if (r == DTM_OK && warn_failed(rows, n, 1)) r = -1;
  if (started) dtm_gmsh_stop();
  dtm_scene_destroy(&s);
  free(rows);
  return r;
}

int dtm_cli_sweep(const cli_opts *o) {
  if (!o->sizes)
    return dtm_cli_usage_error(
        &dtm_cli_commands[3], "needs --sizes h1,h2,... (mesh sizes in the scene's length unit: m, or mm under mm-t-s)");
  if (o->threads > 0) omp_set_num_threads(o->threads);
  double *sizes = NULL;
  int n = 0, r = parse_sizes(o->sizes, &sizes, &n);
  if (r == DTM_OK) r = sweep_scene(o, sizes, n);
  free(sizes);
  if (r < 0) return 1; /* some sizes failed: their rows say why */
  return r ? dtm_cli_fail(r, o->verbosity) : 0;
}
