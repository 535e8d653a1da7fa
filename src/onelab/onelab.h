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

/* Run one ONELAB action (Gmsh's NAME/Action: initialize, check, compute;
 * none = check then compute). Returns the exit code; errors are also sent
 * to Gmsh as ONELAB errors. */
int dtm_onelab_main(const dtm_onelab_opts *o);

#endif
