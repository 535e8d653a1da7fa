/* The dtmap command line: `dtmap run SCENE.xml [-o OUT.msh] [--report R.json]
 * [-j N] [-v|-q]`, `dtmap effects`, `--help`, `--version`. Exit codes: 0 ok,
 * 1 target or verification not met, 2 bad input or usage, 3 internal error. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/analysis.h"
#include "dtmap/gmsh.h"
#include "dtmap/registry.h"
#include "dtmap/scene.h"

static const char usage[] =
    "usage: dtmap run SCENE.xml [-o OUT.msh] [--report R.json] [-j N] [-v|-q]\n"
    "       dtmap effects        list the effects a scene can name\n"
    "       dtmap --help | --version\n"
    "\n"
    "run    meshes the scene's geometry (or reads its .msh), computes every element's\n"
    "       critical explicit step for the effects the scene names, and writes the mesh\n"
    "       with the views 'dt', 'characteristic length', 'limiting effect', 'size\n"
    "       suggestion' and 'dt <effect>' (open it in Gmsh), plus OUT.msh.opt.\n"
    "  -o OUT.msh       output mesh (default: the scene's <output mesh>, else SCENE_dt.msh)\n"
    "  --report R.json  JSON report (default: the scene's <output report>, if any)\n"
    "  -j N             threads for the element loop (default: all cores)\n"
    "  -v, -q           more output (Gmsh's messages, error tracebacks) / summary off\n"
    "\n"
    "Element step of the elastic effect, <elastic length=...>:\n"
    "  eigen         2/sqrt(lambda_max(Me^-1 Ke)), lumped mass (default; provably safe)\n"
    "  safe          2/sqrt(d+1) (sum_a h_a^-2)^-1/2 / C_D on simplices (safe)\n"
    "  min-edge      shortest edge / C_D            UNSAFE: up to 17x too large on slivers\n"
    "  min-altitude  smallest altitude / C_D        UNSAFE on needles (1.06-1.13x)\n"
    "  inradius      2 x inradius / C_D             UNSAFE on needle triangles (1.05x)\n"
    "  volume-area   V / A_max / C_D                UNSAFE on hex and quad (1.04-1.21x)\n"
    "\n"
    "Exit codes: 0 success, 1 target or verification not met, 2 bad input or usage,\n"
    "3 internal error.\n";

typedef struct {
  const char *scene;   /* SCENE.xml */
  const char *out;     /* -o, or NULL */
  const char *report;  /* --report, or NULL */
  int threads;         /* -j, 0 = default */
  int verbosity;       /* 0 quiet, 1 normal, 2 verbose */
} run_opts;

static int usage_error(const char *fmt, const char *arg) {
  fprintf(stderr, "dtmap: ");
  fprintf(stderr, fmt, arg);
  fprintf(stderr, "\n%s", usage);
  return DTM_ERR_INPUT;
}

static int parse_run(int argc, char **argv, run_opts *o) {
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    int has_next = i + 1 < argc;
    if (!strcmp(a, "-o") && has_next) o->out = argv[++i];
    else if (!strcmp(a, "--report") && has_next) o->report = argv[++i];
    else if (!strcmp(a, "-j") && has_next) o->threads = atoi(argv[++i]);
    else if (!strcmp(a, "-v")) o->verbosity = 2;
    else if (!strcmp(a, "-q")) o->verbosity = 0;
    else if (a[0] == '-') return usage_error("unknown option or missing value: %s", a);
    else if (!o->scene) o->scene = a;
    else return usage_error("more than one scene: %s", a);
  }
  if (!o->scene) return usage_error("%s", "run needs a scene file");
  if (o->threads < 0) return usage_error("%s", "-j needs a positive number");
  return DTM_OK;
}

static int fail(int code, int verbosity) {
  fprintf(stderr, "dtmap: error: %s\n", dtm_error_message());
  if (verbosity > 1) fprintf(stderr, "traceback:\n%s", dtm_error_traceback());
  return code;
}

/* SCENE_dt.msh in the current directory. */
static void default_out(const char *scene, char *buf, size_t len) {
  const char *base = strrchr(scene, '/');
  base = base ? base + 1 : scene;
  const char *dot = strrchr(base, '.');
  int n = dot ? (int)(dot - base) : (int)strlen(base);
  snprintf(buf, len, "%.*s_dt.msh", n, base);
}

static int write_outputs(const dtm_analysis *a, const run_opts *o, double *t_out) {
  char def[4096];
  const dtm_scene *s = a->scene;
  const char *out = o->out ? o->out : s->out_mesh;
  if (!out) default_out(s->path, def, sizeof def), out = def;
  const char *rep = o->report ? o->report : s->out_report;
  double t0 = dtm_wtime();
  DTM_CHECK(dtm_output_write(a, out));
  *t_out = dtm_wtime() - t0;
  if (rep) DTM_CHECK(dtm_report_write(a, rep));
  if (o->verbosity) printf("\nwrote        %s (+ .opt)%s%s\n", out, rep ? ", " : "", rep ? rep : "");
  return DTM_OK;
}

static int run_analysis(dtm_scene *s, const run_opts *o, double t_scene) {
  dtm_analysis *a = NULL;
  int r = dtm_gmsh_start(o->verbosity > 1 ? 2 : 0);
  if (r == DTM_OK) r = dtm_analysis_run(s, &a);
  if (r == DTM_OK) {
    a->timings[DTM_T_SCENE] = t_scene;
    if (o->verbosity) dtm_summary_print(a, stdout);
    r = write_outputs(a, o, &a->timings[DTM_T_OUTPUT]);
  }
  dtm_analysis_destroy(&a);
  dtm_gmsh_stop();
  return r;
}

static int cmd_run(int argc, char **argv) {
  run_opts o = {NULL, NULL, NULL, 0, 1};
  int r = parse_run(argc, argv, &o);
  if (r) return r;
  if (o.threads > 0) omp_set_num_threads(o.threads);
  dtm_scene *s = NULL;
  double t0 = dtm_wtime();
  r = dtm_scene_load(o.scene, &s);
  if (r == DTM_OK) {
    if (o.verbosity) printf("dtmap %s: %s\n", DTM_VERSION, s->path);
    r = run_analysis(s, &o, dtm_wtime() - t0);
  }
  dtm_scene_destroy(&s);
  return r ? fail(r, o.verbosity) : 0;
}

static int cmd_effects(void) {
  for (int i = 0; i < dtm_registry_count(); i++) {
    const dtm_effect_class *c = dtm_registry_get(i);
    printf("%-10s %s\n", c->name, c->summary);
  }
  printf("%-10s %s\n", "effect", "external effect: <effect library=\"libX.so\" name=\"X\"/>");
  return 0;
}

int main(int argc, char **argv) {
  const char *cmd = argc > 1 ? argv[1] : "";
  if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) return printf("%s", usage), 0;
  if (!strcmp(cmd, "--version")) return printf("dtmap %s\n", DTM_VERSION), 0;
  if (!strcmp(cmd, "run")) return cmd_run(argc, argv);
  if (!strcmp(cmd, "effects")) return cmd_effects();
  return usage_error(argc > 1 ? "unknown command '%s'" : "%s", argc > 1 ? cmd : "no command given");
}
