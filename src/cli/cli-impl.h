/* Private to the dtmap CLI (src/cli/): each command is a table entry that
 * declares its options (name, kind, value range, help), so one parser
 * serves every command, accepts only that command's options, parses numbers
 * strictly, and prints that command's help; `dtmap --help` is built from
 * the same tables. The CLI uses only libdtmap's public API. */
#ifndef DTM_CLI_IMPL_H
#define DTM_CLI_IMPL_H

#include <stddef.h>

#include "dtmap/deck.h"
#include "dtmap/output.h"
#include "dtmap/sweep.h"

/* Every option of every command; a command reads the ones it declares. */
typedef struct {
  const char *scene;     /* SCENE.xml (the one positional argument) */
  const char *out;       /* -o OUT.msh, or NULL */
  const char *report;    /* --report R.json, or NULL */
  const char *sizes;     /* sweep --sizes h1,h2,... */
  const char *csv;       /* sweep --csv, or NULL */
  const char *plot;      /* sweep --plot, or NULL */
  const char *format;    /* --format ascii|binary|auto, or NULL (the scene's) */
  int views_only;        /* run --views-only */
  int threads;           /* -j N, 0 = all cores */
  int verbosity;         /* 0 quiet (-q), 1 normal, 2 verbose (-v) */
  int posterior;         /* run/verify --posterior */
  int top;               /* --top N: elements listed as the smallest steps (default 10; 0: none) */
  double tol;            /* --tol: Lanczos relative residual */
  int lanczos_max;       /* --lanczos-max: Lanczos steps */
  int seed;              /* --seed: the Lanczos start vector's seed (0: the default) */
  int max_iter;          /* refine --max-iter: rounds */
  double max_added_mass; /* refine --max-added-mass: % of the model's mass (NaN: the scene's) */
  int keep_counts;       /* refine --keep-counts: the model's transfinite node counts stay */
  const char *optimise;  /* refine --optimise LIST: Gmsh's optimiser passes, or NULL (the default) */
  double target; /* refine --target, s (0: the scene's <time target>); run --target: with --modes or --selective-mass */
  double factor; /* verify --factor: multiple of the recommended step (0: not given, 1) */
  double dt;     /* verify --dt, s (0: use factor x recommended) */
  int steps;     /* verify --steps */
  int accuracy;  /* verify --accuracy: the plane-wave phase check instead of the stability run */
  const char *wave;        /* verify --wave P|S (NULL: P) */
  const char *direction;   /* verify --direction x,y,z (NULL: the x axis) */
  double freq;             /* verify --freq, Hz (0: the report's frequency) */
  double periods;          /* verify --periods (0: 30) */
  const char *verified;    /* run/sweep/refine --verified: verify --accuracy reports, comma-separated */
  int calibrate;           /* run/sweep/refine --calibrate: the measures use their measured errors */
  const char *png;         /* run/snapshot --png PREFIX: pictures PREFIX_worst.png, PREFIX_dt.png */
  int width, height;       /* their size, pixels */
  const char *solver;      /* deck --solver NAME */
  const char *lsdyna_step; /* deck --lsdyna-step conventional|proven (NULL: conventional) */
  int selective_mass;      /* deck --selective-mass: the solver's own selective mass scaling for --target;
                              run and verify --selective-mass: the scaled model at the target (--target, else
                              <time target>) */
  const char *solver_rule; /* run --solver-rule LIST: solvers whose own element steps become views */
  int modes;               /* run --modes N: the lowest N elastic natural frequencies (0: none) */
} cli_opts;

typedef enum { CLI_FLAG, CLI_STRING, CLI_DOUBLE, CLI_INT } cli_kind;

/* One option of a command. */
typedef struct {
  const char *name;  /* "-o", "--report" */
  cli_kind kind;     /* what follows it */
  size_t offset;     /* offsetof(cli_opts, field) */
  int set;           /* CLI_FLAG: the value stored */
  double lo, hi;     /* numbers: admissible range [lo, hi] */
  const char *value; /* value name in the usage ("OUT.msh") */
  const char *help;  /* one line */
} cli_option;

/* One command. */
typedef struct cli_command {
  const char *name;               /* "run" */
  const char *args;               /* usage after the name: "SCENE.xml [-o OUT.msh] ..." */
  const char *about;              /* paragraph for --help */
  const cli_option *options;      /* its options, terminated by a NULL name */
  int (*main)(const cli_opts *o); /* returns the exit code */
} cli_command;

/* The commands (main.c), terminated by a NULL name. */
extern const struct cli_command dtm_cli_commands[];

/* Parse argv[2..] for command c into o (defaults first). Returns 0, the
 * usage exit code 2 after printing what is wrong, or -1 when --help was
 * asked for and printed (the caller exits 0). */
int dtm_cli_parse(const struct cli_command *c, int argc, char **argv, cli_opts *o);
/* The command name (or "effects", "help") a misspelt name likely means (at
 * most 2 edits, a third of its letters), or NULL. */
const char *dtm_cli_near_command(const char *name);
/* Print "dtmap CMD: <message>" and how to get help to stderr; returns 2. */
int dtm_cli_usage_error(const struct cli_command *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The documentation (help.c), all from the command tables: the help of
 * one command (usage line, about, options); the usage lines of every
 * command (stream is a FILE *); `dtmap --help`; `dtmap effects` (effects.c,
 * to stdout or a stream); and, for the build, the
 * man page or the bash completion on stdout (what: "man" or
 * "bash-completion"). The int functions return the exit code. */
void dtm_cli_print_help(const struct cli_command *c, void *stream);
void dtm_cli_print_usage(void *stream);
int dtm_cli_print_overview(void);
int dtm_cli_print_effects(void);
void dtm_cli_print_effects_to(void *stream);
int dtm_cli_generate(const char *what);
/* --top as dtm_results.top counts it (there 0 is the default, < 0 none). */
static inline int dtm_cli_top(const cli_opts *o) { return o->top > 0 ? o->top : -1; }
/* Print the pending error (and traceback when verbose); returns code. */
int dtm_cli_fail(int code, int verbosity);
/* --verified and --calibrate (src/cli/verified.c): read verify --accuracy's
 * reports, say whether each agrees with the prediction, and give the
 * scene's measures the ratios measured / predicted (applied with
 * --calibrate). */
int dtm_cli_verified(dtm_scene *s, const cli_opts *o);
/* SCENE<suffix> in the current directory (SCENE: the scene's base name
 * without its extension). */
void dtm_cli_default_out(const char *scene, const char *suffix, char *buf, size_t len);

/* The encoding --format names into *out (DTM_MSH_*; NULL: DTM_MSH_AUTO);
 * the usage exit code 2 for another word. */
int dtm_cli_format(const struct cli_command *c, const char *word, int *out);

/* The files run and refine write, and where each name came from. */
typedef struct {
  char mesh[4096];        /* output mesh (its .opt goes beside it) */
  char mesh_from[4200];   /* "-o", "scene.xml:12: <output mesh>", "default output" */
  char report[4096];      /* JSON report, "" for none */
  char report_from[4200]; /* "--report" or "scene.xml:12: <output report>" */
  char pictures[2][4200]; /* run --png PREFIX: PREFIX_worst.png, PREFIX_dt.png; "" for none */
} cli_outputs;
/* The outputs of run and refine for scene s and options o; suffix (refine:
 * "_refined", NULL for run) goes before the extension of the scene's and
 * the default names. */
void dtm_cli_output_names(const dtm_scene *s, const cli_opts *o, const char *suffix, cli_outputs *out);
/* Check them before any work (dtm_output_path_check, and no two alike). */
int dtm_cli_check_outputs(const dtm_scene *s, const cli_outputs *out);
/* Write the output mesh (+ .opt) and the report of res where o and the
 * scene say; res->t_output accumulates the mesh's write time, s. With a
 * suffix (refine: "_refined") the defaults are the scene's <output> names
 * with the suffix before the extension, else SCENE<suffix>.msh and no
 * report, so they never overwrite what `run` writes for the same scene.
 * *begun (when begun is not NULL and *begun is set): the output already
 * begun with the mesh in it (taken over). */
int dtm_cli_write_outputs(dtm_results *res, const cli_opts *o, const char *suffix, dtm_output_file **begun);

/* The pictures of a result msh (with its .opt) through Gmsh's renderer:
 * PREFIX_worst.png (the views as the .opt shows them: the worst elements)
 * and PREFIX_dt.png (the dt map alone), width x height pixels, under a
 * virtual display when there is none. */
int dtm_cli_pictures(const char *msh, const char *prefix, int width, int height, int verbosity);
/* Call draw(arg) with a working X display: DISPLAY, or an Xvfb started for
 * the call (and stopped after). */
int dtm_cli_with_display(int (*draw)(void *arg), void *arg);
/* `-onelab NAME ADDRESS` anywhere in argv: run the ONELAB client and return
 * its exit code; -1 when argv has no -onelab. */
int dtm_cli_onelab(int argc, char **argv);
/* The progress line (progress.c): on a terminal and unless quiet
 * (verbosity 0), draw long stages on stderr. start: in one process (place,
 * draw, hook); stop erases the line and ends the drawing thread. Under the
 * supervisor: place puts the record in shared memory before the fork, hook
 * (in the worker) records the library's stages in it, draw (in the
 * supervisor) starts the thread that draws them and, once a second, hands
 * the open stages' path ("refine round 1 > meshing") and the time since
 * the outermost began (s) to relay (NULL: none); stage gives the
 * innermost open stage's name (returns how many are open). */
typedef void (*cli_progress_relay)(void *user, const char *stages, double seconds);
void dtm_cli_progress_start(int verbosity);
void dtm_cli_progress_stop(void);
void dtm_cli_progress_place(void);
void dtm_cli_progress_hook(void);
void dtm_cli_progress_draw(int verbosity, cli_progress_relay relay, void *user);
int dtm_cli_progress_stage(char *buf, size_t len);

/* A job for the supervisor (supervise.c). */
typedef struct {
  int (*job)(void *arg);                            /* the whole command, run in the worker: its exit code */
  void *arg;                                        /* its argument */
  int verbosity;                                    /* 0: no progress line */
  cli_progress_relay relay;                         /* the supervisor's relay of the worker's stages, or NULL */
  void (*crashed)(void *user, const char *message); /* told after the worker died by a signal, or NULL */
  void *user;                                       /* their argument */
} cli_supervised;
/* Run s->job in a worker process and wait for it: its exit code; 3 after
 * it died by a signal (reported on stderr and to s->crashed); the
 * supervisor dies by SIGINT, SIGTERM or SIGHUP when it received one (after
 * passing it on and waiting). An MPI rank runs the job in this process. */
int dtm_cli_supervise(const cli_supervised *s);
/* SIGINT, SIGTERM, SIGHUP remove the temporaries being written, then end
 * the process as the signal would (an unsupervised process, the worker). */
void dtm_cli_catch_signals(void);
/* Warn on stderr about the elements analysed although inverted at a node. */
void dtm_cli_warn_flagged(const dtm_analysis *a);
/* The same for curved elements whose step depends on the rule (warn.c). */
void dtm_cli_warn_curved(const dtm_analysis *a);
/* A density, wave speed or model size that looks like a unit error
 * (docs/units.md), on stderr. */
void dtm_cli_warn_units(const dtm_analysis *a);

/* The commands. */
int dtm_cli_run(const cli_opts *o);
int dtm_cli_verify(const cli_opts *o);
int dtm_cli_refine(const cli_opts *o);
int dtm_cli_sweep(const cli_opts *o);
int dtm_cli_snapshot(const cli_opts *o);
int dtm_cli_deck(const cli_opts *o);

/* The sweep plot (plot.c; PLplot lives on the CLI side because it exits
 * the process on some errors). Cost (element-steps, with and without
 * subcycling) against accuracy (elements per wavelength or per zone when
 * available, else 1/h) on log axes into a PNG, atomically. With a title
 * naming the scene (NULL: "dtmap sweep"). Without a duration (steps NaN)
 * the y axis is the cost per simulated second, elements / recommended
 * step. DTM_ERR_INPUT when path cannot be written or no row has a positive,
 * finite cost and accuracy value. */
int dtm_cli_sweep_plot(const char *path, const dtm_sweep_row *rows, int n);
/* 1 when this dtmap draws plots (built with PLplot; else noplot.c stands
 * in for plot.c and the plot functions fail with DTM_ERR_INPUT). */
int dtm_cli_can_plot(void);
int dtm_cli_sweep_plot_titled(const char *path, const char *title, const dtm_sweep_row *rows, int n);

/* The sweep plot's label layout (labels.c), in mm on the page. */
typedef struct {
  double x0, y0, x1, y1; /* lower left and upper right corners */
} dtm_plot_box;
typedef struct {
  double px, py; /* the point it names */
  double radius; /* half its marker's size */
  double w, h;   /* the label's size */
} dtm_plot_label;
typedef struct {
  dtm_plot_box frame;       /* the labels stay inside it (the plot's box) */
  const dtm_plot_box *hard; /* [nhard] what no label may cover: every point's marker, the legend */
  int nhard;
  const double (*seg)[4]; /* [nseg] the curves' segments (x0, y0, x1, y1): crossed only if need be */
  int nseg;
  double gap; /* space between a marker and its label */
} dtm_plot_scene;
/* out[n]: each label's box, placed in order clear of s and of the labels
 * before it. */
void dtm_cli_place_labels(const dtm_plot_scene *s, const dtm_plot_label *labels, int n, dtm_plot_box *out);

/* What the last sweep plot drew, per panel (for tests): the frame, the
 * points' markers, the labels and the legend, in mm on the page. */
#define DTM_PLOT_MAX 64 /* points per curve */
typedef struct {
  dtm_plot_box frame;                   /* the plot's box */
  dtm_plot_box legend;                  /* the legend's box */
  int npoints;                          /* markers of every curve */
  dtm_plot_box point[3 * DTM_PLOT_MAX]; /* their boxes */
  int nlabels;                          /* labels drawn */
  dtm_plot_box label[DTM_PLOT_MAX];     /* their boxes */
  char text[DTM_PLOT_MAX][64];          /* their text */
} dtm_plot_panel;
typedef struct {
  int npanels;             /* panels drawn (0: the plot without measures) */
  dtm_plot_panel panel[2]; /* phase error, then counts */
} dtm_plot_layout;
const dtm_plot_layout *dtm_cli_sweep_plot_layout(void);

/* The summary's line of one solver: the step it takes with dtmap's deck,
 * why, and the hours the scene's duration takes (or why not known). */
void dtm_cli_print_solver_run(const char *solver, const dtm_solver_run *r);

#endif
