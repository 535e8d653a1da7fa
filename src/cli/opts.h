/* Shared pieces of the dtmap CLI commands: their options, parsing,
 * error reporting and default output names. */
#ifndef DTM_CLI_OPTS_H
#define DTM_CLI_OPTS_H

#include <stddef.h>

typedef struct {
  const char *scene;  /* SCENE.xml */
  const char *out;    /* -o, or NULL */
  const char *report; /* --report, or NULL */
  int threads;        /* -j, 0 = default */
  int verbosity;      /* 0 quiet, 1 normal, 2 verbose */
  int posterior;      /* --posterior */
  double tol;         /* --tol, Lanczos relative residual */
  int lanczos_max;    /* --lanczos-max: Lanczos products */
  int max_iter;       /* refine --max-iter: rounds */
  double target;      /* refine --target, s */
  double factor;      /* verify --factor */
  double dt;          /* verify --dt (0: use factor x recommended) */
  int steps;          /* verify --steps */
} run_opts;

/* The usage lines (main.c); --help adds the long description. */
extern const char dtm_cli_usage_short[];
/* Print "dtmap: <fmt>" and the usage to stderr; returns DTM_ERR_INPUT. */
int dtm_cli_usage_error(const char *fmt, const char *arg);
/* Parse argv[2..] of run, verify and refine into o (defaults set by caller). */
int dtm_cli_parse(int argc, char **argv, run_opts *o);
/* Print the pending error (and traceback when verbose); returns code. */
int dtm_cli_fail(int code, int verbosity);
/* SCENE_dt.msh (with suffix) in the current directory. */
void dtm_cli_default_out(const char *scene, const char *suffix, char *buf, size_t len);
/* Defaults of every option. */
run_opts dtm_cli_defaults(void);

int dtm_cli_run(int argc, char **argv, int verify);
struct dtm_analysis;
/* Write the output mesh (+ .opt) and the report of a; *t_out its time, s. */
int dtm_cli_write_outputs(const struct dtm_analysis *a, const run_opts *o, double *t_out);
int dtm_cli_refine(int argc, char **argv);

#endif
