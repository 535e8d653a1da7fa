/* The ONELAB client's interface to the dtmap command line: when Gmsh runs
 * dtmap as a solver (`dtmap [run] [SCENE.xml] [options] -onelab NAME
 * ADDRESS`), the CLI hands over here. The client declares dtmap's
 * parameters in Gmsh's panel, and on "compute" analyses the model open in
 * Gmsh (or SCENE.xml) with the panel's values and sends the result back for
 * Gmsh to merge. */
#ifndef DTM_ONELAB_H
#define DTM_ONELAB_H

/* What the command line passes on. */
typedef struct {
  const char *name;    /* client name Gmsh gave (-onelab NAME ...) */
  const char *address; /* Gmsh's socket: a Unix socket path or host:port */
  const char *scene;   /* SCENE.xml given on the command line, or NULL (MODEL.xml beside the model) */
  int verbosity;       /* 0 quiet, 1 normal, 2 verbose */
  int threads;         /* -j N, 0 = all cores */
} dtm_onelab_opts;

/* The client (opaque). open connects to Gmsh (o is kept, not copied);
 * serve runs one ONELAB action (Gmsh's NAME/Action: initialize, check,
 * compute; none = check then compute) and returns the exit code; errors are
 * also sent to Gmsh as ONELAB errors, and printed. progress shows the open
 * stages and their time (s) in Gmsh's status bar; crashed sends message as
 * an error; close says goodbye and frees. open and close belong to the
 * supervisor, serve to its worker (the connection is shared by fork). */
typedef struct dtm_onelab_client dtm_onelab_client;
int dtm_onelab_open(const dtm_onelab_opts *o, dtm_onelab_client **out);
int dtm_onelab_serve(dtm_onelab_client *cl);
void dtm_onelab_progress(dtm_onelab_client *cl, const char *stages, double seconds);
void dtm_onelab_crashed(dtm_onelab_client *cl, const char *message);
void dtm_onelab_close(dtm_onelab_client **cl);

#endif
