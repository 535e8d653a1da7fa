/* Helpers shared by the test programs: the source tree and CLI paths from
 * argv, temporary directories, running the CLI and capturing its output,
 * reading reports, and reading views back through the Gmsh API. */
#ifndef DTM_TESTUTIL_H
#define DTM_TESTUTIL_H

#include <stddef.h>

struct cJSON;

/* Record argv[1] (source dir) and argv[2] (dtmap CLI). */
void tu_init(int argc, char **argv);
const char *tu_src(void);
const char *tu_cli(void);
/* A fresh temporary directory (owned by the library, removed at exit).
 * At exit every *.json in it, the reports the program wrote, is validated
 * against schema/dtmap-report.schema.json (tests/common/report_schema.py);
 * a report that does not follow it makes the program fail. */
const char *tu_tmpdir(void);
/* Write text to path (aborts the test program on failure). */
void tu_write(const char *path, const char *text);
/* The whole file at path (malloc'ed, NUL-terminated), its size in *n
 * (aborts the test program when it cannot be read). */
char *tu_slurp(const char *path, size_t *n);
int tu_exists(const char *path);
/* Remove a directory tree (files and subdirectories; links not followed). */
void tu_remove_tree(const char *path);
/* Run a shell command; its stdout+stderr go to *out (malloc'ed, may be
 * NULL); returns the exit status, or -1 when it did not exit normally. */
int tu_run(char **out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Parse a JSON file; NULL on failure. Free with cJSON_Delete. */
struct cJSON *tu_json_load(const char *path);
/* Number at a dotted path ("dt.min") of a JSON object; NaN if absent. */
double tu_json_number(const struct cJSON *root, const char *dotted);

struct dtm_scene;
struct dtm_analysis;
/* Load <tmpdir>/<name>.xml into *s and run its analysis (Gmsh started);
 * aborts the test program with dtmap's message when either fails. */
struct dtm_analysis *tu_analyse(const char *name, struct dtm_scene **s);
/* Write <tmpdir>/<name>.xml: the source element (<geometry .../> or
 * <mesh .../>), <meshing ATTRS/> with the given attributes, one steel
 * material on group "block", the elastic effect, then tail (e.g. an
 * <output .../>; "" for none). */
void tu_steel_scene(const char *name, const char *source, const char *meshing, const char *tail);
/* The OpenCASCADE unit cube with its volume in physical group "block", as
 * <tmpdir>/<file>, followed by extra lines (e.g. options; "" for none). */
void tu_cube_geo(const char *file, const char *extra);

/* Start Gmsh quietly in the test process (General.AbortOnError=0), and
 * stop it. */
void tu_gmsh_begin(void);
void tu_gmsh_end(void);

/* A view read back from a .msh through Gmsh (gmsh must be initialised and
 * the file opened). */
typedef struct {
  char type[32];  /* "ElementData" or "NodeData" */
  size_t n;       /* number of values */
  size_t *tags;   /* [n] */
  double *values; /* [n] */
} tu_view;
/* Find the view with that exact name; returns 0 on success. */
int tu_view_read(const char *name, tu_view *v);
/* The same for the last view with that name (the latest result's). */
int tu_view_read_last(const char *name, tu_view *v);
void tu_view_free(tu_view *v);
/* Number of views loaded. */
int tu_view_count(void);

#endif
