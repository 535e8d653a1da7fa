/* Option parsing, error printing and default names shared by the dtmap
 * CLI commands. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "opts.h"

static int number_arg(const char *s, double *v) {
  char *end = NULL;
  *v = strtod(s, &end);
  return end != s && !*end && *v > 0;
}

int dtm_cli_usage_error(const char *fmt, const char *arg) {
  fprintf(stderr, "dtmap: ");
  fprintf(stderr, fmt, arg);
  fprintf(stderr, "\n%s(dtmap --help explains the commands)\n", dtm_cli_usage_short);
  return DTM_ERR_INPUT;
}

/* Options with a numeric value; 1 if a was one of them. */
static int parse_number(const char *a, const char *v, run_opts *o, int *bad) {
  double x = 0;
  double *dst = !strcmp(a, "--tol")      ? &o->tol
                : !strcmp(a, "--factor") ? &o->factor
                : !strcmp(a, "--dt")     ? &o->dt
                                         : NULL;
  int *idst = !strcmp(a, "--steps")         ? &o->steps
              : !strcmp(a, "--max-iter")    ? &o->max_iter
              : !strcmp(a, "--lanczos-max") ? &o->lanczos_max
              : !strcmp(a, "-j")            ? &o->threads
                                            : NULL;
  if (!strcmp(a, "--target")) dst = &o->target;
  if (!dst && !idst) return 0;
  *bad = !v || !number_arg(v, &x);
  if (dst)
    *dst = x;
  else
    *idst = (int)x;
  return 1;
}

int dtm_cli_parse(int argc, char **argv, run_opts *o) {
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    int has_next = i + 1 < argc, bad = 0;
    if (parse_number(a, has_next ? argv[i + 1] : NULL, o, &bad)) {
      if (bad) return dtm_cli_usage_error("%s needs a positive number", a);
      i++;
    } else if (!strcmp(a, "-o") && has_next)
      o->out = argv[++i];
    else if (!strcmp(a, "--report") && has_next)
      o->report = argv[++i];
    else if (!strcmp(a, "--posterior"))
      o->posterior = 1;
    else if (!strcmp(a, "-v"))
      o->verbosity = 2;
    else if (!strcmp(a, "-q"))
      o->verbosity = 0;
    else if (a[0] == '-')
      return dtm_cli_usage_error("unknown option or missing value: %s", a);
    else if (!o->scene)
      o->scene = a;
    else
      return dtm_cli_usage_error("more than one scene: %s", a);
  }
  if (!o->scene) return dtm_cli_usage_error("%s", "run needs a scene file");
  return DTM_OK;
}

int dtm_cli_fail(int code, int verbosity) {
  fprintf(stderr, "dtmap: error: %s\n", dtm_error_message());
  if (verbosity > 1) fprintf(stderr, "traceback:\n%s", dtm_error_traceback());
  return code;
}

/* SCENE<suffix> in the current directory. */
void dtm_cli_default_out(const char *scene, const char *suffix, char *buf, size_t len) {
  const char *base = strrchr(scene, '/');
  base = base ? base + 1 : scene;
  const char *dot = strrchr(base, '.');
  int n = dot ? (int)(dot - base) : (int)strlen(base);
  snprintf(buf, len, "%.*s%s", n, base, suffix);
}

run_opts dtm_cli_defaults(void) { return (run_opts){NULL, NULL, NULL, 0, 1, 0, 1e-4, 400, 3, 0.0, 1.0, 0.0, 2000}; }
