/* The one option parser of the dtmap CLI, driven by each command's option
 * table: only the command's own options are accepted, numbers are parsed
 * strictly (the whole argument, finite, integers without a fraction, within
 * the declared range), `CMD --help` prints that command's help, and errors
 * name the option and the command. Also the error printing and default
 * output names every command shares. */
#include <errno.h>
#include <float.h>
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
  o.top = 10;
  o.max_added_mass = NAN; /* the scene's <time max-added-mass>, else none */
  o.steps = 2000;
  o.width = 1024;
  o.height = 768;
  return o;
}

int dtm_cli_usage_error(const cli_command *c, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fflush(stdout);
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

/* The range of option p as a reader writes it: "(0, 0.5]" for a positive
 * number, "[1, inf)" without an upper end. */
static const char *range(const cli_option *p, char *buf, size_t len) {
  char lo[32], hi[32];
  if (p->lo == DBL_MIN)
    snprintf(lo, sizeof lo, "(0");
  else
    snprintf(lo, sizeof lo, "[%g", p->lo);
  if (p->hi == DBL_MAX)
    snprintf(hi, sizeof hi, "inf)");
  else
    snprintf(hi, sizeof hi, "%g]", p->hi);
  snprintf(buf, len, "range %s, %s", lo, hi);
  return buf;
}

/* Why text is not a number of option p, into why ("" when it is one); the
 * value parsed into *v. Says what in the text was wrong: nothing, no
 * digits, the characters after the number, overflow, a fraction where an
 * integer is needed, or the bound it crosses. */
static void number_problem(const cli_option *p, const char *text, double *v, char *why, size_t len) {
  char *end = NULL, buf[96];
  int is_int = p->kind == CLI_INT;
  why[0] = '\0';
  errno = 0;
  *v = strtod(text, &end);
  if (!text[0])
    snprintf(why, len, "is empty: give %s", is_int ? "an integer" : "a number");
  else if (end == text)
    snprintf(why, len, "is not a number: it does not start with digits");
  else if (*end)
    snprintf(why, len, "is not a number: '%s' follows the number %.*s", end, (int)(end - text), text);
  else if (isinf(*v) && errno == ERANGE)
    snprintf(why, len, "is too large for a number (above %g)", DBL_MAX);
  else if (!isfinite(*v))
    snprintf(why, len, "is not a finite number");
  else if (is_int && *v != floor(*v))
    snprintf(why, len, "is not an integer: it has a fraction");
  else if (p->lo == DBL_MIN && p->hi == DBL_MAX && !(*v > 0))
    snprintf(why, len, "must be above 0");
  else if (*v < p->lo)
    snprintf(why, len, "is below %g, the least %s takes (%s)", p->lo, p->name, range(p, buf, sizeof buf));
  else if (*v > p->hi)
    snprintf(why, len, "is above %g, the most %s takes (%s)", p->hi, p->name, range(p, buf, sizeof buf));
}

static int store_number(const cli_command *c, const cli_option *p, const char *text, cli_opts *o) {
  double v;
  char why[512];
  number_problem(p, text, &v, why, sizeof why);
  if (why[0]) return dtm_cli_usage_error(c, "%s '%s' %s", p->name, text, why);
  if (p->kind == CLI_INT)
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

/* Edit distance between a and b, transpositions counting one (optimal
 * string alignment); names are short, so a small table does. */
static int distance(const char *a, const char *b) {
  enum { N = 40 };
  size_t n = strlen(a), m = strlen(b);
  if (n >= N || m >= N) return N;
  int d[N][N];
  for (size_t i = 0; i <= n; i++) d[i][0] = (int)i;
  for (size_t j = 0; j <= m; j++) d[0][j] = (int)j;
  for (size_t i = 1; i <= n; i++)
    for (size_t j = 1; j <= m; j++) {
      int cost = a[i - 1] != b[j - 1], best = d[i - 1][j - 1] + cost;
      if (d[i - 1][j] + 1 < best) best = d[i - 1][j] + 1;
      if (d[i][j - 1] + 1 < best) best = d[i][j - 1] + 1;
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && d[i - 2][j - 2] + 1 < best)
        best = d[i - 2][j - 2] + 1;
      d[i][j] = best;
    }
  return d[n][m];
}

/* The commands other than c that have option name, as "refine, deck";
 * "" when none. */
static void owners(const cli_command *c, const char *name, char *buf, size_t len) {
  size_t k = 0;
  buf[0] = '\0';
  for (const cli_command *d = dtm_cli_commands; d->name; d++)
    if (d != c && find(d, name) && k < len) k += (size_t)snprintf(buf + k, len - k, "%s%s", k ? ", " : "", d->name);
}

/* The option nearest to a (at most 2 edits, and at most a third of its
 * letters): c's own first, else any command's; NULL when none is near. */
static const char *nearest(const cli_command *c, const char *a) {
  const char *best = NULL;
  int bd = 3, limit = (int)strlen(a) / 3;
  for (int own = 1; own >= 0 && !best; own--)
    for (const cli_command *d = dtm_cli_commands; d->name; d++) {
      if ((d == c) != own) continue;
      for (const cli_option *p = d->options; p && p->name; p++) {
        int k = distance(a, p->name);
        if (k < bd && k <= limit && strcmp(a, p->name)) bd = k, best = p->name;
      }
    }
  return best;
}

const char *dtm_cli_near_command(const char *name) {
  static const char *const others[] = {"effects", "help", NULL};
  const char *best = NULL;
  int bd = 3, limit = (int)strlen(name) / 3;
  for (const cli_command *d = dtm_cli_commands; d->name; d++) {
    int k = distance(name, d->name);
    if (k < bd && k <= limit && k > 0) bd = k, best = d->name;
  }
  for (int i = 0; others[i]; i++) {
    int k = distance(name, others[i]);
    if (k < bd && k <= limit && k > 0) bd = k, best = others[i];
  }
  return best;
}

/* "unknown option", with where it belongs (another command's option) or the
 * option it likely misspells. */
static int unknown_option(const cli_command *c, const char *a) {
  char who[256];
  owners(c, a, who, sizeof who);
  if (who[0]) return dtm_cli_usage_error(c, "unknown option '%s': it is an option of %s, not of %s", a, who, c->name);
  const char *near = nearest(c, a);
  if (!near) return dtm_cli_usage_error(c, "unknown option '%s'", a);
  if (find(c, near)) return dtm_cli_usage_error(c, "unknown option '%s': did you mean %s?", a, near);
  owners(c, near, who, sizeof who);
  return dtm_cli_usage_error(c, "unknown option '%s': did you mean %s? (an option of %s, not of %s)", a, near, who,
                             c->name);
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
      return unknown_option(c, a);
    else if (!o->scene)
      o->scene = a;
    else
      return dtm_cli_usage_error(c, "more than one scene: '%s' and '%s'", o->scene, a);
  }
  if (!o->scene) return dtm_cli_usage_error(c, "needs a scene file");
  return DTM_OK;
}

int dtm_cli_fail(int code, int verbosity) {
  fflush(stdout); /* the summary so far first, then the error after it */
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
