/* The dtmap command line: dispatch to run, verify, refine, sweep and
 * effects, plus --help and --version. Exit codes: 0 ok, 1 target or
 * verification not met, 2 bad input or usage, 3 internal error. */
#include <stdio.h>
#include <string.h>

#include "dtmap/registry.h"
#include "cli.h"
#include "opts.h"

const char dtm_cli_usage_short[] =
    "usage: dtmap run SCENE.xml [-o OUT.msh] [--report R.json] [--posterior] [-j N] [-v|-q]\n"
    "       dtmap verify SCENE.xml [--factor F | --dt DT] [--steps N] [-j N] [-v|-q]\n"
    "       dtmap refine SCENE.xml --target DT [-o OUT.msh] [--report R.json] [--max-iter K]\n"
    "       dtmap sweep SCENE.xml --sizes h1,h2,... [--csv F] [--plot F.png]\n"
    "       dtmap effects        list the effects a scene can name\n"
    "       dtmap --help | --version\n";

static const char usage_long[] =
    "\n"
    "run    meshes the scene's geometry (or reads its .msh), computes every element's\n"
    "       critical explicit step for the effects the scene names, and writes the mesh\n"
    "       with the views 'dt', 'characteristic length', 'limiting effect', 'size\n"
    "       suggestion', 'nodal dt', 'dt <effect>', ... (open it in Gmsh), plus OUT.msh.opt.\n"
    "  -o OUT.msh       output mesh (default: the scene's <output mesh>, else SCENE_dt.msh)\n"
    "  --report R.json  JSON report (default: the scene's <output report>, if any)\n"
    "  --posterior      also estimate the global step by Lanczos on the lumped-mass\n"
    "                   problem (--tol T, default 1e-4; --lanczos-max K steps, default 400)\n"
    "  -j N             threads (default: all cores)\n"
    "  -v, -q           more output (Gmsh's messages, error tracebacks) / no summary\n"
    "\n"
    "verify simulates the scene's spectral effects on its mesh (central differences\n"
    "       with the damping force on the lagged velocity; forward Euler for diffusion)\n"
    "       from the top mode of the global estimate plus a random part, at --factor F x\n"
    "       the recommended step (default 1) or at --dt DT, for --steps N (default 2000).\n"
    "       Exit 1 if the energy grows (the step is unstable).\n"
    "\n"
    "refine remeshes the scene's geometry with the size suggestion for --target DT as\n"
    "       the background size field, then Gmsh's optimisers, at most --max-iter K\n"
    "       rounds (default 3), until the recommended step reaches DT. Exit 1 if not.\n"
    "\n"
    "sweep  meshes the scene at each size and tabulates elements, steps, the cost of\n"
    "       the scene's duration with and without subcycling, and accuracy; CSV + PNG.\n"
    "\n"
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
  if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help"))
    return printf("%s%s", dtm_cli_usage_short, usage_long), 0;
  if (!strcmp(cmd, "--version")) return printf("dtmap %s\n", DTM_VERSION), 0;
  if (!strcmp(cmd, "run")) return dtm_cli_run(argc, argv, 0);
  if (!strcmp(cmd, "verify")) return dtm_cli_run(argc, argv, 1);
  if (!strcmp(cmd, "refine")) return dtm_cli_refine(argc, argv);
  if (!strcmp(cmd, "sweep")) return dtm_cli_sweep(argc, argv);
  if (!strcmp(cmd, "effects")) return cmd_effects();
  return dtm_cli_usage_error(argc > 1 ? "unknown command '%s'" : "%s", argc > 1 ? cmd : "no command given");
}
