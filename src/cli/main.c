/* The dtmap command line: the table of commands with their options, the
 * dispatch, `dtmap effects` and --version (the help, the man page and the
 * completion are printed from these tables by help.c). Exit codes: 0 ok,
 * 1 target or verification not met, 2 bad input or usage, 3 internal
 * error. */
#include <float.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/gmsh.h"
#include "dtmap/parallel.h"
#include "dtmap/registry.h"
#include "dtmap/version.h"
#include "dtmap/util.h"

#define OPT(field) offsetof(cli_opts, field)
#define POSITIVE DBL_MIN, DBL_MAX

#define VERBOSITY_OPTIONS                                                                                              \
  {"-v", CLI_FLAG, OPT(verbosity), 2, 0, 0, NULL, "more output: Gmsh's messages, error tracebacks"}, {                 \
    "-q", CLI_FLAG, OPT(verbosity), 0, 0, 0, NULL, "no summary on the terminal"                                        \
  }
#define THREADS_OPTION                                                                                                 \
  { "-j", CLI_INT, OPT(threads), 0, 1, 4096, "N", "threads (default: all cores)" }
#define TOP_OPTION                                                                                                     \
  { "--top", CLI_INT, OPT(top), 0, 0, 1e6, "N", "list the N smallest element steps (default 10; 0: none)" }
#define LANCZOS_OPTIONS                                                                                                \
  {"--tol", CLI_DOUBLE, OPT(tol), 0, DBL_MIN, 0.5, "T", "Lanczos relative residual (default 1e-4)"}, {                 \
    "--lanczos-max", CLI_INT, OPT(lanczos_max), 0, 1, 100000, "K", "Lanczos steps at most (default 400)"               \
  }

#define SEED_OPTION                                                                                                    \
  {                                                                                                                    \
    "--seed", CLI_INT, OPT(seed), 0, 1, 2147483647, "S",                                                               \
        "seed of the Lanczos start vector (default 20261121; the report gives it)"                                     \
  }

#define PICTURE_OPTIONS                                                                                                \
  {"--width", CLI_INT, OPT(width), 0, 64, 3800, "W", "picture width, pixels (default 1024)"}, {                        \
    "--height", CLI_INT, OPT(height), 0, 64, 3800, "H", "picture height, pixels (default 768)"                         \
  }

#define VERIFIED_OPTIONS                                                                                               \
  {"--verified",                                                                                                       \
   CLI_STRING,                                                                                                         \
   OPT(verified),                                                                                                      \
   0,                                                                                                                  \
   0,                                                                                                                  \
   0,                                                                                                                  \
   "V.json,...",                                                                                                       \
   "verify --accuracy reports: say whether their measured phase errors agree with the prediction"},                    \
  {                                                                                                                    \
    "--calibrate", CLI_FLAG, OPT(calibrate), 1, 0, 0, NULL,                                                            \
        "with --verified: scale each wave's predicted errors to the measured ones"                                     \
  }
#define FORMAT_OPTION                                                                                                  \
  {                                                                                                                    \
    "--format", CLI_STRING, OPT(format), 0, 0, 0, "F",                                                                 \
        "output .msh: ascii, binary or auto (binary above 1e5 elements; default: <output format>)"                     \
  }

static const cli_option run_options[] = {
    {"-o", CLI_STRING, OPT(out), 0, 0, 0, "OUT.msh", "output mesh (default: <output mesh>, else SCENE_dt.msh)"},
    {"--report", CLI_STRING, OPT(report), 0, 0, 0, "R.json",
     "JSON report (default: <output report>, if any; with -o X.msh: X.json)"},
    {"--posterior", CLI_FLAG, OPT(posterior), 1, 0, 0, NULL,
     "also estimate the global step (Lanczos); a converged one becomes the basis"},
    {"--png", CLI_STRING, OPT(png), 0, 0, 0, "PREFIX", "pictures PREFIX_worst.png and PREFIX_dt.png (Gmsh's renderer)"},
    PICTURE_OPTIONS,
    TOP_OPTION,
    FORMAT_OPTION,
    VERIFIED_OPTIONS,
    {"--views-only", CLI_FLAG, OPT(views_only), 1, 0, 0, NULL,
     "write only the views, to open over the input: gmsh IN.msh OUT.msh"},
    {"--solver-rule", CLI_STRING, OPT(solver_rule), 0, 0, 0, "LIST",
     "also a view 'dt SOLVER' of each solver's own element step (lsdyna,abaqus,calculix: any of them)"},
    {"--modes", CLI_INT, OPT(modes), 0, 1, 200, "N",
     "the lowest N elastic natural frequencies (Hz) of the free model, its rigid-body modes named"},
    {"--selective-mass", CLI_FLAG, OPT(selective_mass), 1, 0, 0, NULL,
     "selective mass scaling to the target: the scaled model's step, added mass and solver cost"},
    {"--target", CLI_DOUBLE, OPT(target), 0, POSITIVE, "DT",
     "with --selective-mass: the recommended step to reach, s (default: <time target>); with --modes: also each "
     "mode's shift under conventional mass (point masses) reaching it"},
    LANCZOS_OPTIONS,
    SEED_OPTION,
    THREADS_OPTION,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

static const cli_option verify_options[] = {
    {"--factor", CLI_DOUBLE, OPT(factor), 0, POSITIVE, "F", "verify F x the recommended step (default 1)"},
    {"--dt", CLI_DOUBLE, OPT(dt), 0, POSITIVE, "DT", "verify this step, s (instead of --factor)"},
    {"--steps", CLI_INT, OPT(steps), 0, 1, 1e9, "N", "time steps to run (default 2000)"},
    {"--posterior", CLI_FLAG, OPT(posterior), 1, 0, 0, NULL,
     "the recommended step of run --posterior (the global estimate as the basis)"},
    {"--report", CLI_STRING, OPT(report), 0, 0, 0, "V.json",
     "the step, steps, growth and verdict as JSON (with --accuracy: the wave, measured and predicted errors)"},
    {"--accuracy", CLI_FLAG, OPT(accuracy), 1, 0, 0, NULL,
     "instead: run a plane wave and compare its phase-speed error with the prediction"},
    {"--selective-mass", CLI_FLAG, OPT(selective_mass), 1, 0, 0, NULL,
     "instead: the selectively scaled model at the target (default step), --factor x its global step, or --dt"},
    {"--target", CLI_DOUBLE, OPT(target), 0, POSITIVE, "DT",
     "with --selective-mass: the recommended step it scales to, s (default: <time target>)"},
    {"--wave", CLI_STRING, OPT(wave), 0, 0, 0, "P|S", "--accuracy: the wave's branch (default P)"},
    {"--direction", CLI_STRING, OPT(direction), 0, 0, 0, "X,Y,Z", "--accuracy: direction of the wave (default 1,0,0)"},
    {"--freq", CLI_DOUBLE, OPT(freq), 0, POSITIVE, "F", "--accuracy: frequency, Hz (default: the report's)"},
    {"--periods", CLI_DOUBLE, OPT(periods), 0, 2, 1e6, "N",
     "--accuracy: the whole plane wave for N periods (default: a packet until it meets the boundary)"},
    TOP_OPTION,
    LANCZOS_OPTIONS,
    SEED_OPTION,
    THREADS_OPTION,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

static const cli_option refine_options[] = {
    {"--target", CLI_DOUBLE, OPT(target), 0, POSITIVE, "DT", "target recommended step, s (default: <time target>)"},
    {"-o", CLI_STRING, OPT(out), 0, 0, 0, "OUT.msh",
     "output mesh (default: <output mesh> as X_refined.msh, else SCENE_refined.msh)"},
    {"--report", CLI_STRING, OPT(report), 0, 0, 0, "R.json",
     "JSON report (default: <output report> as X_refined.json, if any; with -o X.msh: X.json)"},
    {"--max-iter", CLI_INT, OPT(max_iter), 0, 1, 30, "K", "remeshing rounds at most (default 3)"},
    {"--posterior", CLI_FLAG, OPT(posterior), 1, 0, 0, NULL,
     "refine on the global estimate (Lanczos), the step a solver then runs at fixed"},
    {"--max-added-mass", CLI_DOUBLE, OPT(max_added_mass), 0, 0, 100, "P",
     "where no mesh meets the target, add point masses up to P % of the model's mass"},
    {"--keep-counts", CLI_FLAG, OPT(keep_counts), 1, 0, 0, NULL,
     "keep the model's transfinite node counts (default: refine sets them)"},
    {"--optimise", CLI_STRING, OPT(optimise), 0, 0, 0, "LIST",
     "Gmsh's optimisers after each remesh, of gmsh,netgen,relocate,laplace, or none (default: none)"},
    {"--selective-mass", CLI_FLAG, OPT(selective_mass), 1, 0, 0, NULL,
     "where no mesh meets the target, also the kept mesh with selective mass scaling to it, beside point masses"},
    {"--modes", CLI_INT, OPT(modes), 0, 1, 200, "N",
     "with --selective-mass: the lowest N elastic frequencies of the kept mesh and their shifts under each way"},
    TOP_OPTION,
    LANCZOS_OPTIONS,
    FORMAT_OPTION,
    VERIFIED_OPTIONS,
    THREADS_OPTION,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

static const cli_option sweep_options[] = {
    {"--sizes", CLI_STRING, OPT(sizes), 0, 0, 0, "h1,h2,...",
     "mesh sizes in the scene's length unit (m, mm under mm-t-s), comma-separated (required)"},
    {"--csv", CLI_STRING, OPT(csv), 0, 0, 0, "F", "table as CSV (default SCENE_sweep.csv)"},
    {"--plot", CLI_STRING, OPT(plot), 0, 0, 0, "F.png", "cost against accuracy, log-log (default SCENE_sweep.png)"},
    VERIFIED_OPTIONS,
    THREADS_OPTION,
    VERBOSITY_OPTIONS,
    {NULL, 0, 0, 0, 0, 0, NULL, NULL}};

static const cli_option deck_options[] = {
    {"--solver", CLI_STRING, OPT(solver), 0, 0, 0, "S", "the solver: calculix, abaqus or lsdyna (required)"},
    {"-o", CLI_STRING, OPT(out), 0, 0, 0, "FILE", "the deck (default SCENE_S.inp, SCENE_lsdyna.k)"},
    {"--posterior", CLI_FLAG, OPT(posterior), 1, 0, 0, NULL,
     "estimate the global step (Lanczos); a converged one becomes the basis of the deck's step (also "
     "<time posterior=\"true\">)"},
    {"--target", CLI_DOUBLE, OPT(target), 0, POSITIVE, "DT", "reach this step, s, with mass added at the nodes"},
    {"--max-added-mass", CLI_DOUBLE, OPT(max_added_mass), 0, 0, 100, "P",
     "with --target: exit 1 if the mass needed is above P % of the model's (default: <time max-added-mass>)"},
    {"--lsdyna-step", CLI_STRING, OPT(lsdyna_step), 0, 0, 0, "conventional|proven",
     "LS-DYNA: TSSFAC <= 0.9 with its DT2MS mass scaling (conventional, the default), or dtmap's proven step as "
     "TSSFAC, above 1 where its estimate is lower (proven)"},
    {"--selective-mass", CLI_FLAG, OPT(selective_mass), 1, 0, 0, NULL,
     "with --target: reach it by the solver's own selective mass scaling (CalculiX, LS-DYNA IMSCL); Abaqus has "
     "none: mass at the nodes"},
    {"--report", CLI_STRING, OPT(report), 0, 0, 0, "R.json", "JSON report, with the deck's step and estimates"},
    LANCZOS_OPTIONS,
    SEED_OPTION,
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
     "SCENE.xml [-o OUT.msh] [--report R.json] [--posterior [--tol T] [--lanczos-max K] [--seed S]] [--png PREFIX "
     "[--width W] "
     "[--height H]] [--top N] [--format F] [--views-only] [--solver-rule LIST] [--modes N [--target DT]] [--verified "
     "V.json,... [--calibrate]] [--selective-mass [--target DT]] [-j N] [-v|-q]",
     "Meshes the scene's geometry (or reads its .msh), computes every element's critical\n"
     "explicit step for the effects the scene names, and writes the mesh with the views\n"
     "'dt', 'characteristic length', 'limiting effect', 'size suggestion', 'nodal dt',\n"
     "'dt <effect>', ... (open it in Gmsh), plus OUT.msh.opt. With --views-only (a <mesh>\n"
     "scene) OUT.msh holds only the views: gmsh IN.msh OUT.msh shows them on the input.\n"
     "--solver-rule lsdyna,abaqus,calculix adds one view per solver, 'dt lsdyna', ...: each\n"
     "element's step by that solver's own rule (the one its deck's header estimates with),\n"
     "and the summary gives each solver's smallest step, its element and centroid.\n"
     "--modes N adds the lowest N elastic natural frequencies of the free model (its\n"
     "rigid-body modes named by count) to the summary and the report; with --target DT,\n"
     "also each mode's shift when point masses at the nodes lift the step to DT, matched\n"
     "by mode shape (MAC): the accuracy price of conventional mass scaling.",
     run_options, dtm_cli_run},
    {"verify",
     "SCENE.xml [--factor F | --dt DT] [--steps N] [--posterior] [--tol T] [--lanczos-max K] [--seed S] [--report "
     "V.json] "
     "[--accuracy [--wave P|S] [--direction X,Y,Z] [--freq F] [--periods N]] [--selective-mass [--target DT]] "
     "[--top N] [-j N] [-v|-q]",
     "Simulates the scene's spectral effects on its mesh (central differences with the\n"
     "damping force on the lagged velocity; forward Euler for diffusion) from the top\n"
     "mode of the global estimate plus a random part, at F x the recommended step (by\n"
     "default exactly the step `run` reports; with --posterior that of `run --posterior`)\n"
     "or at DT. Exit 1 if the energy grows (the step is unstable). With --accuracy, a plane\n"
     "wave cos(k.x) in the host material (the largest by volume) is integrated undamped at\n"
     "that step instead, for several periods (on a periodic sample, a box meshed with\n"
     "periodic faces, the whole wave; else a packet, the default frequency raised until\n"
     "it fits); the peak of its projection on the plane-wave mode gives the measured\n"
     "phase-speed error, compared with the measures' prediction for the same frequency,\n"
     "direction and branch (docs/accuracy.md). Exit 1 beyond 20 % of it. run, sweep and\n"
     "refine read its --report with --verified (and use it with --calibrate).\n"
     "Its growth is the largest energy norm over the second half of the run over the\n"
     "norm at the start: bounded (a few units) when stable; unstable above 1e6 or not\n"
     "finite.",
     verify_options, dtm_cli_verify},
    {"refine",
     "SCENE.xml [--target DT] [-o OUT.msh] [--report R.json] [--max-iter K] [--posterior [--tol T] [--lanczos-max K]] "
     "[--max-added-mass P] [--selective-mass [--modes N]] [--keep-counts] [--optimise LIST] [--top N] [--format F] "
     "[--verified V.json,... [--calibrate]] [-j N] [-v|-q]",
     "Remeshes the scene's geometry with the size suggestion for the target step (the\n"
     "current size where a node meets it, the larger size that reaches it elsewhere) as\n"
     "the background size field, with the node counts of transfinite curves set from it,\n"
     "then Gmsh's optimisers, until the recommended step reaches DT (default: the scene's\n"
     "<time target>), keeping the cheapest mesh that does. With --posterior (or <time\n"
     "posterior=\"true\">) the step is the global estimate, which a solver must then be\n"
     "told to use. An input that meets DT is kept as it is. It stops when a round raises\n"
     "the cost without reaching DT, or when nothing a remesh changes limits the step;\n"
     "with --max-added-mass P point masses at the nodes that need them make up the rest,\n"
     "up to P % of the model's mass (view 'added mass at nodes'). With --selective-mass\n"
     "the kept mesh scaled selectively to DT is shown beside them (its step and certificate,\n"
     "added mass, solver cost, with --modes N the frequency shifts); it is not written into\n"
     "the mesh: dtmap deck --selective-mass gives it to a solver. Exit 1 if the written\n"
     "mesh does not meet DT.",
     refine_options, dtm_cli_refine},
    {"sweep",
     "SCENE.xml --sizes h1,h2,... [--csv F] [--plot F.png] [--verified V.json,... [--calibrate]] [-j N] [-v|-q]",
     "Meshes the scene's geometry at each <meshing size> h (m; min-size is capped at h)\n"
     "and prints, per size: elements, nodes, the element bound (the smallest element\n"
     "step), the recommended step, the whole steps the scene's <time duration> takes at\n"
     "it, its cost in element-steps with that one step and with ideal subcycling (levels\n"
     "of the recommended step x 2^k) and that speed-up, the smallest elements per\n"
     "cohesive zone and per wavelength, and dtmap's own time; then what each size buys\n"
     "and costs in hours: the worst phase-speed error at one frequency (<time f-max>,\n"
     "else the first mesh's default) with one step, with subcycling and with mass\n"
     "scaling to the target, elements across the diffusion length, the run time of each\n"
     "(<time cost-per-element-step>, else dtmap's CalculiX calibration) and whether every\n"
     "measure is in its band; then the table as CSV (units in the header) and the plot\n"
     "as PNG: error against hours, the band and the cheapest size inside it marked.\n"
     "The band column (1stp) judges the one global step only; the subcycled and\n"
     "mass-scaled errors are shown beside it, not judged. A size Gmsh cannot mesh (or\n"
     "whose mesh is refused) is a row saying why, the other sizes are written, and the\n"
     "exit code is 1.",
     sweep_options, dtm_cli_sweep},
    {"deck",
     "SCENE.xml --solver calculix|abaqus|lsdyna [-o FILE] [--posterior [--tol T] [--lanczos-max K] [--seed S]] "
     "[--target DT "
     "[--max-added-mass P] [--selective-mass]] [--lsdyna-step conventional|proven] [--report R.json] [-j N] "
     "[-v|-q]",
     "Analyses the scene as run does and writes the explicit solver's input: the nodes,\n"
     "every analysed element in the solver's element type, one element and one node set\n"
     "per physical group, the materials and sections, dtmap's step fixed as the\n"
     "increment (LS-DYNA: TSSFAC <= 0.9 x its own estimate, with its DT2MS mass scaling\n"
     "and the mass it will add predicted where the step is above that; --lsdyna-step\n"
     "proven: the TSSFAC that makes its estimate the step, above 1 where it is lower),\n"
     "the scene's duration, mass at the nodes for --target, and commented *INCLUDE slots for the\n"
     "loads, boundary conditions, contact and output requests. Prints the solver's own\n"
     "estimate for the mesh beside the step. An element the solver lacks is exit 2.",
     deck_options, dtm_cli_deck},
    {"snapshot", "RESULT.msh [--png PREFIX] [--width W] [--height H] [-v|-q]",
     "Draws a result of dtmap run with Gmsh's own renderer, as Gmsh shows it on opening\n"
     "(RESULT.msh.opt applied): PREFIX_worst.png (the below-target view over the faint\n"
     "model in 3D, with the recommended step; the worst element ringed in red and\n"
     "tagged with its tag and step) and PREFIX_dt.png (the dt map alone).\n"
     "Without a display (DISPLAY unset) dtmap starts a virtual one (Xvfb).",
     snapshot_options, dtm_cli_snapshot},
    {NULL, NULL, NULL, NULL, NULL}};

/* dtmap's version, the Gmsh it runs on, and the effect API it loads. */
static int print_version(void) {
  char gmsh[64];
  const char *api = NULL;
  printf("dtmap %s (libdtmap %s)\n", DTM_VERSION, dtm_version());
  if (dtm_gmsh_version(gmsh, sizeof gmsh, &api) == DTM_OK)
    printf("Gmsh %s (built against the Gmsh API %s)\n", gmsh, api);
  else
    printf("Gmsh: unknown (%s)\n", dtm_error_message());
  printf("effect API %d (external effects declare DTM_EFFECT_API_VERSION %d)\n", dtm_registry_api_version(),
         DTM_EFFECT_API_VERSION);
  return 0;
}

static int usage_error(const char *what, const char *arg) {
  fprintf(stderr, "dtmap: %s%s\n", what, arg);
  dtm_cli_print_usage(stderr);
  fprintf(stderr, "(dtmap --help explains the commands)\n");
  return 2;
}

/* A command, run in the supervisor's worker (supervise.c). */
typedef struct {
  const cli_command *c; /* the command */
  const cli_opts *o;    /* its options */
} command_job;

static int run_command(void *arg) {
  const command_job *j = arg;
  return j->c->main(j->o);
}

int main(int argc, char **argv) {
  dtm_memory_reuse(); /* large arrays reuse freed memory (src/base/memory.c) */
  dtm_cli_catch_signals();
  /* Whole lines on stdout even when it is a file: a warning or an error on
   * stderr then lands between two lines of the summary, never mid-word, in
   * `> log 2>&1`. */
  setvbuf(stdout, NULL, _IOLBF, 0);
  int onelab = dtm_cli_onelab(argc, argv);
  if (onelab >= 0) return onelab;
  const char *cmd = argc > 1 ? argv[1] : "";
  if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) return dtm_cli_print_overview();
  if (!strcmp(cmd, "--version"))
    return argc > 2 ? usage_error("--version takes no arguments: ", argv[2]) : print_version();
  if (!strcmp(cmd, "--generate")) return dtm_cli_generate(argc == 3 ? argv[2] : NULL); /* for the build */
  if (!strcmp(cmd, "effects"))
    return argc > 2 ? usage_error("effects takes no arguments: ", argv[2]) : dtm_cli_print_effects();
  for (const cli_command *c = dtm_cli_commands; c->name; c++) {
    if (strcmp(cmd, c->name)) continue;
    cli_opts o;
    if (c->main != dtm_cli_run && c->main != dtm_cli_verify && dtm_parallel_launched())
      return usage_error("only run is distributed; run this command without mpirun: ", c->name);
    int r = dtm_cli_parse(c, argc, argv, &o);
    if (r) return r < 0 ? 0 : r;
    command_job j = {c, &o};
    cli_supervised s = {run_command, &j, o.verbosity, NULL, NULL, NULL};
    return dtm_cli_supervise(&s);
  }
  const char *near = dtm_cli_near_command(cmd);
  if (argc > 1 && near) {
    char what[256];
    snprintf(what, sizeof what, "unknown command: %.64s (did you mean %s?)", cmd, near);
    return usage_error(what, "");
  }
  return argc > 1 ? usage_error("unknown command: ", cmd) : usage_error("no command given", "");
}
