/* `-onelab NAME ADDRESS` anywhere on dtmap's command line: Gmsh runs its
 * solvers as `EXE [args] -onelab NAME ADDRESS`. The other arguments may be
 * the command `run`, a scene file (instead of MODEL.xml beside the model
 * open in Gmsh) and -v, -q, -j N; then the ONELAB client takes over, in a
 * supervised worker like every command that runs Gmsh. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli-impl.h"
#include "onelab.h"

static int onelab_usage(const char *what, const char *arg) {
  fprintf(stderr, "dtmap -onelab: %s%s\nusage: dtmap [run] [SCENE.xml] [-v|-q] [-j N] -onelab NAME ADDRESS\n", what,
          arg);
  return 2;
}

static int threads_arg(const char *text, int *threads) {
  char *end = NULL;
  long v = strtol(text, &end, 10);
  if (!*text || *end || v < 1 || v > 4096) return -1;
  *threads = (int)v;
  return 0;
}

/* Fill o from the arguments that are not -onelab NAME ADDRESS (at). */
static int other_args(int argc, char **argv, int at, dtm_onelab_opts *o) {
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (i >= at && i <= at + 2) continue;
    if (i == 1 && !strcmp(a, "run")) continue;
    if (!strcmp(a, "-v") || !strcmp(a, "-q"))
      o->verbosity = a[1] == 'v' ? 2 : 0;
    else if (!strcmp(a, "-j")) {
      if (i + 1 >= argc || i + 1 == at || threads_arg(argv[i + 1], &o->threads))
        return onelab_usage("-j needs a thread count from 1 to 4096", "");
      i++;
    } else if (a[0] != '-' && !o->scene)
      o->scene = a;
    else
      return onelab_usage("unexpected argument ", a);
  }
  return 0;
}

/* The supervisor's side (supervise.c): the worker serves, the supervisor
 * relays its stages and its crash to Gmsh. */
static int serve(void *cl) { return dtm_onelab_serve(cl); }
static void relay(void *cl, const char *stages, double seconds) { dtm_onelab_progress(cl, stages, seconds); }
static void crashed(void *cl, const char *message) { dtm_onelab_crashed(cl, message); }

int dtm_cli_onelab(int argc, char **argv) {
  int at = -1;
  for (int i = 1; i < argc; i++)
    if (!strcmp(argv[i], "-onelab")) at = i;
  if (at < 0) return -1;
  if (at + 2 >= argc) return onelab_usage("-onelab needs a client name and Gmsh's socket address", "");
  dtm_onelab_opts o = {argv[at + 1], argv[at + 2], NULL, 1, 0};
  dtm_onelab_client *cl = NULL;
  int r = other_args(argc, argv, at, &o);
  if (r) return r;
  r = dtm_onelab_open(&o, &cl);
  cli_supervised s = {serve, cl, o.verbosity, relay, crashed, cl};
  if (r == 0) r = dtm_cli_supervise(&s);
  dtm_onelab_close(&cl);
  return r;
}
