/* The ONELAB client's entry point: connect to the Gmsh that launched dtmap,
 * read the action Gmsh asks for (NAME/Action), keep Gmsh from meshing and
 * saving the model itself (dtmap meshes with the scene's options), declare
 * the panel on "check", and on "compute" (or when Gmsh names no action, as
 * gmsh.onelab.run does) analyse with the panel's values, stopping between
 * stages, with nothing written, when the user presses Gmsh's Stop (which
 * sets NAME/Action to "stop"; compute.c). Progress goes to
 * Gmsh's status bar; any error goes to Gmsh as a ONELAB error with dtmap's
 * own message (which names the file and line, or the group and element).
 * The dtmap command connects in its supervisor and serves in its worker
 * (src/cli/supervise.c): the supervisor also sends the worker's stages
 * while they run, and the crash message when the worker dies by a signal. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "onelab-impl.h"
#include "onelab.h"

/* Gmsh skips its own meshing and model reload before running a client
 * when IsMetamodel is set (as Gmsh's own example clients do). */
static int no_gmsh_meshing(ol_conn *c) {
  ol_param p;
  dtm_ol_number(&p, "IsMetamodel", 1, "");
  p.visible = 0;
  p.never_changed = 1;
  return dtm_ol_set(c, &p);
}

static int act(ol_conn *c, const dtm_onelab_opts *o, const char *action) {
  ol_model m;
  ol_panel pn = {0};
  DTM_CHECK(no_gmsh_meshing(c));
  if (!strcmp(action, "initialize")) return DTM_OK;
  DTM_CHECK(dtm_gmsh_start(o->verbosity > 1 ? 2 : 0));
  int r = dtm_ol_model_load(c, o->scene, &m);
  if (r == DTM_OK) r = dtm_ol_panel_declare(c, &m, &pn);
  if (r == DTM_OK && (!strcmp(action, "compute") || !action[0])) r = dtm_ol_compute(c, &m, &pn, 0);
  if (r == DTM_OK) r = dtm_ol_send_text(c, OL_PROGRESS, "done");
  dtm_ol_panel_free(&pn);
  dtm_ol_model_free(&m);
  dtm_gmsh_stop();
  return r;
}

static void report(ol_conn *c, int r, int verbosity) {
  char msg[4400];
  snprintf(msg, sizeof msg, "%s", dtm_error_message());
  if (c->fd >= 0) dtm_ol_send_text(c, OL_ERROR, msg);
  fprintf(stderr, "dtmap: error: %s\n", msg);
  if (verbosity > 1) fprintf(stderr, "traceback:\n%s", dtm_error_traceback());
  (void)r;
}

/* The client: its connection, opened by the supervisor and shared with
 * the worker (src/cli/supervise.c). */
struct dtm_onelab_client {
  ol_conn c;                /* the connection to Gmsh */
  const dtm_onelab_opts *o; /* the command line's options */
};

int dtm_onelab_open(const dtm_onelab_opts *o, dtm_onelab_client **out) {
  dtm_onelab_client *cl = calloc(1, sizeof *cl);
  *out = cl;
  if (!cl) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  cl->c.fd = -1, cl->o = o;
  int r = dtm_ol_connect(&cl->c, o->name, o->address);
  if (r) report(&cl->c, r, o->verbosity);
  return r;
}

int dtm_onelab_serve(dtm_onelab_client *cl) {
  char action[64] = "";
  if (cl->o->threads > 0) omp_set_num_threads(cl->o->threads);
  int r = dtm_ol_action(&cl->c, action, sizeof action);
  if (r == DTM_OK) r = act(&cl->c, cl->o, action);
  if (r) report(&cl->c, r, cl->o->verbosity);
  return r;
}

void dtm_onelab_progress(dtm_onelab_client *cl, const char *stages, double seconds) {
  char line[600];
  snprintf(line, sizeof line, "dtmap: %s, %.0f s", stages, seconds);
  dtm_ol_send_text(&cl->c, OL_PROGRESS, line);
  dtm_error_clear(); /* a lost connection is the worker's to report */
}

void dtm_onelab_crashed(dtm_onelab_client *cl, const char *message) {
  dtm_ol_send_text(&cl->c, OL_ERROR, message);
  dtm_error_clear();
}

void dtm_onelab_close(dtm_onelab_client **cl) {
  if (!*cl) return;
  dtm_ol_close(&(*cl)->c);
  free(*cl);
  *cl = NULL;
}
