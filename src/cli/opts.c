/* The one option parser of the dtmap CLI, driven by each command's option
 * table: only the command's own options are accepted, numbers are parsed
 * strictly (the whole argument, finite, integers without a fraction, within
 * the declared range), `CMD --help` prints that command's help, and errors
 * name the option and the command. Also the error printing and default
 * output names every command shares. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/error.h"

static cli_opts defaults(void) {
  cli_opts o = {0};
  o.verbosity = 1;
  o.tol = 1e-4;
  o.lanczos_max = 400;
  o.max_iter = 3;
  o.max_added_mass = NAN; /* the scene's <time max-added-mass>, else none */
  o.steps = 2000;
  o.width = 1024;
  o.height = 768;
  return o;
}

int dtm_cli_usage_error(const cli_command *c, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fprintf(stderr, "dtmap %s: ", c->name);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fprintf(stderr, "\nusage: dtmap %s %s\n(dtmap %s --help lists its options)\n", c->name, c->args, c->name);
  return DTM_ERR_INPUT;
}

static const cli_option *find(const cli_command *c, const char *name) {
  for (const cli_option *p = c->options; p && p->name; p++)
    if (!strcmp(p->name, name)) return p;
  return NULL;
}

/* The whole text as a finite number; 0 on success. */
static int strict_number(const char *text, double *v) {
  char *end = NULL;
  *v = strtod(text, &end);
  return end == text || *end || !isfinite(*v) ? -1 : 0;
}

static int store_number(const cli_command *c, const cli_option *p, const char *text, cli_opts *o) {
  double v;
  int is_int = p->kind == CLI_INT;
  if (strict_number(text, &v) || (is_int && v != floor(v)) || v < p->lo || v > p->hi)
    return dtm_cli_usage_error(c, "%s '%s' is not %s in [%g, %g]", p->name, text, is_int ? "an integer" : "a number",
                               p->lo, p->hi);
  if (is_int)
    *(int *)((char *)o + p->offset) = (int)v;
  else
    *(double *)((char *)o + p->offset) = v;
  return DTM_OK;
}

/* Option p with its value (argv[*i + 1]) when it takes one. */
static int take(const cli_command *c, const cli_option *p, int argc, char **argv, int *i, cli_opts *o) {
  if (p->kind == CLI_FLAG) return *(int *)((char *)o + p->offset) = p->set, DTM_OK;
  if (*i + 1 >= argc) return dtm_cli_usage_error(c, "%s needs a value (%s)", p->name, p->value);
  const char *v = argv[++*i];
  if (p->kind == CLI_STRING) return *(const char **)((char *)o + p->offset) = v, DTM_OK;
  return store_number(c, p, v, o);
}

static int is_help(const char *a) { return !strcmp(a, "--help") || !strcmp(a, "-h"); }

int dtm_cli_parse(const cli_command *c, int argc, char **argv, cli_opts *o) {
  *o = defaults();
  for (int i = 2; i < argc; i++)
    if (is_help(argv[i])) return dtm_cli_print_help(c, stdout), -1;
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    const cli_option *p = find(c, a);
    if (p)
      DTM_CHECK(take(c, p, argc, argv, &i, o));
    else if (a[0] == '-' && a[1])
      return dtm_cli_usage_error(c, "unknown option '%s'", a);
    else if (!o->scene)
      o->scene = a;
    else
      return dtm_cli_usage_error(c, "more than one scene: '%s' and '%s'", o->scene, a);
  }
  if (!o->scene) return dtm_cli_usage_error(c, "needs a scene file");
  return DTM_OK;
}

int dtm_cli_fail(int code, int verbosity) {
  fprintf(stderr, "dtmap: error: %s\n", dtm_error_message());
  if (verbosity > 1) fprintf(stderr, "traceback:\n%s", dtm_error_traceback());
  return code;
}

void dtm_cli_default_out(const char *scene, const char *suffix, char *buf, size_t len) {
  const char *base = strrchr(scene, '/');
  base = base ? base + 1 : scene;
  const char *dot = strrchr(base, '.');
  int n = dot ? (int)(dot - base) : (int)strlen(base);
  snprintf(buf, len, "%.*s%s", n, base, suffix);
}
