/* `dtmap sweep SCENE.xml --sizes h1,h2,... [--csv F] [--plot F.png] [-v|-q]`:
 * mesh and analyse the scene at each size, print the cost/accuracy table,
 * write it as CSV and draw it as a PNG (defaults SCENE_sweep.csv and
 * SCENE_sweep.png in the current directory). Exit 0 on success, 2 for bad
 * input or usage (with a message saying what), 3 for internal errors. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/scene.h"
#include "dtmap/sweep.h"

static const char sweep_usage[] = "usage: dtmap sweep SCENE.xml --sizes h1,h2,... [--csv F] [--plot F.png] [-v|-q]\n"
                                  "\n"
                                  "Meshes the scene's geometry at each <meshing size> h (m; min-size is capped at h)\n"
                                  "and prints, per size: elements, nodes, the smallest element step, the recommended\n"
                                  "step, the steps the scene's <time duration> takes, its cost in element-steps with\n"
                                  "one global step and with ideal subcycling (levels dt_min 2^k), the smallest\n"
                                  "elements per cohesive zone and per wavelength, and dtmap's own time.\n"
                                  "  --sizes h1,h2,...  mesh sizes, m, comma-separated (required)\n"
                                  "  --csv F            table as CSV (default SCENE_sweep.csv)\n"
                                  "  --plot F.png       cost against accuracy, log-log (default SCENE_sweep.png)\n"
                                  "  -v, -q             more output (Gmsh's messages, error tracebacks) / table off\n";

typedef struct {
  const char *scene; /* SCENE.xml */
  const char *sizes; /* --sizes text */
  const char *csv;   /* --csv, or NULL for the default */
  const char *plot;  /* --plot, or NULL for the default */
  int verbosity;     /* 0 quiet, 1 normal, 2 verbose */
} sweep_opts;

static int sweep_usage_error(const char *what, const char *arg) {
  fprintf(stderr, "dtmap sweep: %s%s\n\n%s", what, arg, sweep_usage);
  return DTM_ERR_INPUT;
}

static int parse_opts(int argc, char **argv, sweep_opts *o) {
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    int has_next = i + 1 < argc;
    if (!strcmp(a, "--sizes") && has_next)
      o->sizes = argv[++i];
    else if (!strcmp(a, "--csv") && has_next)
      o->csv = argv[++i];
    else if (!strcmp(a, "--plot") && has_next)
      o->plot = argv[++i];
    else if (!strcmp(a, "-v"))
      o->verbosity = 2;
    else if (!strcmp(a, "-q"))
      o->verbosity = 0;
    else if (a[0] == '-')
      return sweep_usage_error("unknown option or missing value: ", a);
    else if (!o->scene)
      o->scene = a;
    else
      return sweep_usage_error("more than one scene: ", a);
  }
  if (!o->scene) return sweep_usage_error("needs a scene file", "");
  if (!o->sizes) return sweep_usage_error("needs --sizes h1,h2,... (mesh sizes in m)", "");
  return DTM_OK;
}

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
      return DTM_ERR(DTM_ERR_INPUT, "--sizes: '%.*s' is not a positive, finite size in m", len, p);
    }
    p = *end ? end + 1 : end;
  }
  *sizes = v, *n = cap;
  return DTM_OK;
}

/* SCENE<suffix> in the current directory, SCENE the scene's base name
 * without its extension. */
static void default_name(const char *scene, const char *suffix, char *buf, size_t len) {
  const char *base = strrchr(scene, '/');
  base = base ? base + 1 : scene;
  const char *dot = strrchr(base, '.');
  int n = dot ? (int)(dot - base) : (int)strlen(base);
  snprintf(buf, len, "%.*s%s", n, base, suffix);
}

/* Fail before a long sweep when an output's directory is not writable. */
static int check_writable(const char *path) {
  char dir[4096];
  const char *slash = strrchr(path, '/');
  snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) + 1 : 1, slash ? path : ".");
  if (access(dir, W_OK)) return DTM_ERR(DTM_ERR_INPUT, "%s: cannot write: %s", path, strerror(errno));
  return DTM_OK;
}

/* The CSV and PNG paths: the options, else SCENE_sweep.csv/.png. */
static void output_paths(const sweep_opts *o, char *csv, char *png, size_t len) {
  default_name(o->scene, "_sweep.csv", csv, len);
  default_name(o->scene, "_sweep.png", png, len);
  if (o->csv) snprintf(csv, len, "%s", o->csv);
  if (o->plot) snprintf(png, len, "%s", o->plot);
}

static int write_files(const sweep_opts *o, const dtm_sweep_row *rows, int n) {
  char csv[4096], png[4096];
  const char *base = strrchr(o->scene, '/');
  output_paths(o, csv, png, sizeof csv);
  DTM_CHECK(dtm_sweep_write_csv(csv, rows, n));
  DTM_CHECK(dtm_sweep_plot_titled(png, base ? base + 1 : o->scene, rows, n));
  if (o->verbosity) printf("\nwrote        %s, %s\n", csv, png);
  return DTM_OK;
}

static int sweep_scene(const sweep_opts *o, const double *sizes, int n) {
  dtm_scene *s = NULL;
  dtm_sweep_row *rows = calloc((size_t)n, sizeof *rows);
  if (!rows) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  char csv[4096], png[4096];
  output_paths(o, csv, png, sizeof csv);
  int r = check_writable(csv), started = 0;
  if (r == DTM_OK) r = check_writable(png);
  if (r == DTM_OK) r = dtm_scene_load(o->scene, &s);
  if (r == DTM_OK) r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0), started = r == DTM_OK;
  if (r == DTM_OK && o->verbosity) printf("dtmap sweep: %s, %d size%s\n\n", s->path, n, n > 1 ? "s" : "");
  if (r == DTM_OK) r = dtm_sweep_run(s, sizes, n, rows);
  if (r == DTM_OK && o->verbosity) dtm_sweep_print(rows, n, stdout);
  if (r == DTM_OK && o->verbosity && !(s->duration > 0))
    printf("(no <time duration>: steps and element-steps need one; the plot shows cost per simulated second)\n");
  if (r == DTM_OK) r = write_files(o, rows, n);
  if (started) dtm_gmsh_stop();
  dtm_scene_destroy(&s);
  free(rows);
  return r;
}

int dtm_cli_sweep(int argc, char **argv) {
  sweep_opts o = {NULL, NULL, NULL, NULL, 1};
  double *sizes = NULL;
  int n = 0, r = parse_opts(argc, argv, &o);
  if (r) return r;
  r = parse_sizes(o.sizes, &sizes, &n);
  if (r == DTM_OK) r = sweep_scene(&o, sizes, n);
  free(sizes);
  if (r) {
    fprintf(stderr, "dtmap: error: %s\n", dtm_error_message());
    if (o.verbosity > 1) fprintf(stderr, "traceback:\n%s", dtm_error_traceback());
  }
  return r;
}
