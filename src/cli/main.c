/* The dtmap command line: the table of commands with their options, the
 * dispatch, `dtmap effects`, --help and --version. Exit codes: 0 ok, 1 target
 * or verification not met, 2 bad input or usage, 3 internal error. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/registry.h"

#define OPT(field) offsetof(cli_opts, field)
#define POSITIVE DBL_MIN, DBL_MAX

#define VERBOSITY_OPTIONS                                                                                              \
  {"-v", CLI_FLAG, OPT(verbosity), 2, 0, 0, NULL, "more output: Gmsh's messages, error tracebacks"}, {                 \
    "-q", CLI_FLAG, OPT(verbosity), 0, 0, 0, NULL, "no summary on the terminal"                                        \
  }
#define THREADS_OPTION                                                                                                 \
  { "-j", CLI_INT, OPT(threads), 0, 1, 4096, "N", "threads (default: all cores)" }
#define LANCZOS_OPTIONS                                                                                                \
  {"--tol", CLI_DOUBLE, OPT(tol), 0, DBL_MIN, 0.5, "T", "Lanczos relative residual (default 1e-4)"}, {                 \
    "--lanczos-max", CLI_INT, OPT(lanczos_max), 0, 1, 100000, "K", "Lanczos steps at most (default 400)"               \
  }

#define PICTURE_OPTIONS                                                                                                \
  {"--width", CLI_INT, OPT(width), 0, 64, 3800, "W", "picture width, pixels (default 1024)"}, {                        \
    "--height", CLI_INT, OPT(height), 0, 64, 3800, "H", "picture height, pixels (default 768)"                         \
  }

#define FORMAT_OPTION                                                                                                  \
  {                                                                                                                    \
    "--format", CLI_STRING, OPT(format), 0, 0, 0, "F",                                                                 \
        "output .msh: ascii, binary or auto (binary above 1e5 elements; default: <output format>)"                     \
  }

static const cli_option run_options[] = {
    {"-o", CLI_STRING, OPT(out), 0, 0, 0, "OUT.msh", "output mesh (default: <output mesh>, else SCENE_dt.msh)"},
    {"--report", CLI_STRING, OPT(report), 0, 0, 0, "R.json", "JSON report (default: <output report>, if any)"},
    {"--posterior", CLI_FLAG, OPT(posterior), 1, 0, 0, NULL, "also estimate the global step (Lanczos)"},
    {"--png", CLI_STRING, OPT(png), 0, 0, 0, "PREFIX", "pictures PREFIX_worst.png and PREFIX_dt.png (Gmsh's renderer)"},
    PICTURE_OPTIONS,
    FORMAT_OPTION,
    {"--views-only", CLI_FLAG, OPT(views_only), 1, 0, 0, NULL,
     "write only the views, to open over the input: gmsh IN.msh OUT.msh"},
    LANCZOS_OPTIONS,
    THREADS_OPTION,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

static const cli_option verify_options[] = {
    {"--factor", CLI_DOUBLE, OPT(factor), 0, POSITIVE, "F", "verify F x the recommended step (default 1)"},
    {"--dt", CLI_DOUBLE, OPT(dt), 0, POSITIVE, "DT", "verify this step, s (instead of --factor)"},
    {"--steps", CLI_INT, OPT(steps), 0, 1, 1e9, "N", "time steps to run (default 2000)"},
    LANCZOS_OPTIONS,
    THREADS_OPTION,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

static const cli_option refine_options[] = {
    {"--target", CLI_DOUBLE, OPT(target), 0, POSITIVE, "DT", "target recommended step, s (required)"},
    {"-o", CLI_STRING, OPT(out), 0, 0, 0, "OUT.msh", "output mesh (default: <output mesh>, else SCENE_dt.msh)"},
    {"--report", CLI_STRING, OPT(report), 0, 0, 0, "R.json", "JSON report (default: <output report>, if any)"},
    {"--max-iter", CLI_INT, OPT(max_iter), 0, 1, 31, "K", "remeshing rounds at most (default 3)"},
    FORMAT_OPTION,
    THREADS_OPTION,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

static const cli_option sweep_options[] = {
    {"--sizes", CLI_STRING, OPT(sizes), 0, 0, 0, "h1,h2,...", "mesh sizes, m, comma-separated (required)"},
    {"--csv", CLI_STRING, OPT(csv), 0, 0, 0, "F", "table as CSV (default SCENE_sweep.csv)"},
    {"--plot", CLI_STRING, OPT(plot), 0, 0, 0, "F.png", "cost against accuracy, log-log (default SCENE_sweep.png)"},
    THREADS_OPTION,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

static const cli_option snapshot_options[] = {
    {"--png", CLI_STRING, OPT(png), 0, 0, 0, "PREFIX", "picture prefix (default: RESULT without .msh)"},
    PICTURE_OPTIONS,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

const cli_command dtm_cli_commands[] = {
    {"run",
     "SCENE.xml [-o OUT.msh] [--report R.json] [--posterior] [--png PREFIX] [--format F] [--views-only] [-j N] [-v|-q]",
     "Meshes the scene's geometry (or reads its .msh), computes every element's critical\n"
     "explicit step for the effects the scene names, and writes the mesh with the views\n"
     "'dt', 'characteristic length', 'limiting effect', 'size suggestion', 'nodal dt',\n"
     "'dt <effect>', ... (open it in Gmsh), plus OUT.msh.opt. With --views-only (a <mesh>\n"
     "scene) OUT.msh holds only the views: gmsh IN.msh OUT.msh shows them on the input.",
     run_options, dtm_cli_run},
    {"verify", "SCENE.xml [--factor F | --dt DT] [--steps N] [-j N] [-v|-q]",
     "Simulates the scene's spectral effects on its mesh (central differences with the\n"
     "damping force on the lagged velocity; forward Euler for diffusion) from the top\n"
     "mode of the global estimate plus a random part, at F x the recommended step or at\n"
     "DT. Exit 1 if the energy grows (the step is unstable).",
     verify_options, dtm_cli_verify},
    {"refine", "SCENE.xml --target DT [-o OUT.msh] [--report R.json] [--max-iter K] [--format F] [-j N] [-v|-q]",
     "Remeshes the scene's geometry with the size suggestion for the target step as the\n"
     "background size field, then Gmsh's optimisers, until the recommended step reaches\n"
     "DT. Exit 1 if it does not.",
     refine_options, dtm_cli_refine},
    {"sweep", "SCENE.xml --sizes h1,h2,... [--csv F] [--plot F.png] [-j N] [-v|-q]",
     "Meshes the scene's geometry at each <meshing size> h (m; min-size is capped at h)\n"
     "and prints, per size: elements, nodes, the smallest element step, the recommended\n"
     "step, the steps the scene's <time duration> takes, its cost in element-steps with\n"
     "one global step and with ideal subcycling (levels dt_min 2^k), the smallest\n"
     "elements per cohesive zone and per wavelength, and dtmap's own time; CSV + PNG.",
     sweep_options, dtm_cli_sweep},
    {"snapshot", "RESULT.msh [--png PREFIX] [--width W] [--height H] [-v|-q]",
     "Draws a result of dtmap run with Gmsh's own renderer, as Gmsh shows it on opening\n"
     "(RESULT.msh.opt applied): PREFIX_worst.png (the below-target view over the faint\n"
     "model in 3D, with the recommended step) and PREFIX_dt.png (the dt map alone).\n"
     "Without a display (DISPLAY unset) dtmap starts a virtual one (Xvfb).",
     snapshot_options, dtm_cli_snapshot},
    {NULL, NULL, NULL, NULL, NULL}};

static const char lengths_help[] =
    "Element step of the elastic effect, <elastic length=...>:\n"
    "  eigen         2/sqrt(lambda_max(Me^-1 Ke)), lumped mass (default; provably safe)\n"
    "  safe          2/sqrt(d+1) (sum_a h_a^-2)^-1/2 / C_D on simplices (safe for nu >= 0)\n"
    "  min-edge      shortest edge / C_D            UNSAFE: up to 17x too large on slivers\n"
    "  min-altitude  smallest altitude / C_D        UNSAFE on needles (1.06-1.13x)\n"
    "  inradius      2 x inradius / C_D             UNSAFE on needle triangles (1.05x)\n"
    "  volume-area   V / A_max / C_D                UNSAFE on hex and quad (1.04-1.21x)\n"
    "\n"
    "Exit codes: 0 success, 1 target or verification not met, 2 bad input or usage,\n"
    "3 internal error.\n";

static void print_usage(FILE *f) {
  for (const cli_command *c = dtm_cli_commands; c->name; c++)
    fprintf(f, "%s dtmap %s %s\n", c == dtm_cli_commands ? "usage:" : "      ", c->name, c->args);
  fprintf(f, "       dtmap effects        list the effects a scene can name\n");
  fprintf(f, "       dtmap --help | --version\n");
  fprintf(f, "       dtmap [run] [SCENE.xml] [-v|-q] [-j N] -onelab NAME ADDRESS   (as Gmsh's ONELAB solver)\n");
}

static int print_help(void) {
  print_usage(stdout);
  for (const cli_command *c = dtm_cli_commands; c->name; c++) printf("\n%-6s %s\n", c->name, c->about);
  printf("\nEach command's options: dtmap CMD --help.\n\n%s", lengths_help);
  return 0;
}

/* "[lo, hi]" style range of a number, or "" when unbounded. */
static void range_text(double lo, double hi, unsigned open, char *buf, size_t n) {
  buf[0] = '\0';
  if (isfinite(lo) && isfinite(hi))
    snprintf(buf, n, "%s%g, %g%s", open & DTM_OPEN_LO ? "(" : "[", lo, hi, open & DTM_OPEN_HI ? ")" : "]");
  else if (isfinite(lo))
    snprintf(buf, n, "%s %g", open & DTM_OPEN_LO ? ">" : ">=", lo);
  else if (isfinite(hi))
    snprintf(buf, n, "%s %g", open & DTM_OPEN_HI ? "<" : "<=", hi);
}

static void print_param(const dtm_param *p) {
  char what[256] = "";
  if (p->type == DTM_PARAM_NUMBER) range_text(p->lo, p->hi, p->open, what, sizeof what);
  for (int i = 0; p->type == DTM_PARAM_CHOICE && p->choices[i]; i++)
    snprintf(what + strlen(what), sizeof what - strlen(what), "%s%s", i ? "|" : "", p->choices[i]);
  if (p->type == DTM_PARAM_GROUPS) snprintf(what, sizeof what, "physical groups");
  printf("    %-18s %s%s%s%s%s%s%s%s\n", p->name, what, p->unit && p->unit[0] ? " " : "", p->unit ? p->unit : "",
         p->def ? ", default " : "", p->def ? p->def : "", p->required ? ", required" : "", "; ", p->help);
}

static void print_property(const dtm_property *p) {
  char range[128];
  range_text(p->lo, p->hi, p->open, range, sizeof range);
  printf("    %-18s %s%s%s%s; %s\n", p->name, range, p->unit[0] ? " " : "", p->unit, p->required ? ", required" : "",
         p->help);
}

static void print_effect(const dtm_effect_class *c) {
  static const char *const schemes[] = {"modifies the wave steps", "central differences", "forward Euler"};
  printf("%s: %s\n  %s", c->name, c->summary, schemes[c->scheme]);
  if (c->role & DTM_ROLE_LIMITS) printf(", dt ~ h^%g", c->exponent);
  printf("\n");
  if (c->params && c->params->name) printf("  attributes:\n");
  for (const dtm_param *p = c->params; p && p->name; p++) print_param(p);
  if (c->properties && c->properties->name) printf("  material properties:\n");
  for (const dtm_property *p = c->properties; p && p->name; p++) print_property(p);
  if (c->indicator.name) printf("  accuracy: view '%s' (%s)\n", c->indicator.view, c->indicator.help);
}

static int cmd_effects(void) {
  for (int i = 0; i < dtm_registry_count(); i++) print_effect(dtm_registry_get(i)), printf("\n");
  printf("effect: an external effect, <effect library=\"libX.so\" name=\"X\" .../>; its attributes and\n"
         "  properties are those its library declares (see docs/effects.md)\n");
  return 0;
}

static int usage_error(const char *what, const char *arg) {
  fprintf(stderr, "dtmap: %s%s\n", what, arg);
  print_usage(stderr);
  fprintf(stderr, "(dtmap --help explains the commands)\n");
  return 2;
}

int main(int argc, char **argv) {
  int onelab = dtm_cli_onelab(argc, argv);
  if (onelab >= 0) return onelab;
  const char *cmd = argc > 1 ? argv[1] : "";
  if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) return print_help();
  if (!strcmp(cmd, "--version")) return printf("dtmap %s\n", DTM_VERSION), 0;
  if (!strcmp(cmd, "effects")) return argc > 2 ? usage_error("effects takes no arguments: ", argv[2]) : cmd_effects();
  for (const cli_command *c = dtm_cli_commands; c->name; c++) {
    if (strcmp(cmd, c->name)) continue;
    cli_opts o;
    int r = dtm_cli_parse(c, argc, argv, &o);
    if (r) return r < 0 ? 0 : r;
    dtm_cli_progress_start(o.verbosity);
    r = c->main(&o);
    dtm_cli_progress_stop();
    return r;
  }
  return argc > 1 ? usage_error("unknown command: ", cmd) : usage_error("no command given", "");
}
