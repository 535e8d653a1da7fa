/* Reading a .msh beside Gmsh: while Gmsh reads the file into its model
 * (dtm_gmsh_open, on this thread), a thread of dtmap's own reads its
 * nodes and elements (msh_read.c) on the core Gmsh's serial reader leaves
 * idle; extraction then takes them (dtm_gmsh_parsed_take) instead of
 * listing the model through the C API. The thread lives only while Gmsh
 * reads: it is joined before dtm_gmsh_open returns, so no fork or other
 * Gmsh call ever meets it.
 *
 * What is taken must be what Gmsh holds: the model must still be the file
 * as read (dtm_gmsh_source_unchanged, the same path), and Gmsh's own
 * statistics must give the same number of nodes and of triangles,
 * quadrangles, tetrahedra, hexahedra, prisms and pyramids. Extraction
 * still walks Gmsh's entities and their element types and takes only the
 * blocks that match one; a pair without a block is listed by Gmsh. */
#include <gmshc.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "gmsh-impl.h"

static struct {
  pthread_t thread;
  int running;        /* the thread was started and not yet joined */
  char path[4096];    /* the file */
  dtm_msh_parsed got; /* what it read */
  int ok;             /* it read the file (set by the thread) */
  int have;           /* got is kept for extraction */
} side;
static int enabled = 1, taken;

static void *read_main(void *arg) {
  (void)arg;
  side.ok = dtm_msh_parse(side.path, &side.got) == 0;
  return NULL;
}

void dtm_msh_beside_start(const char *path) {
  dtm_msh_beside_drop();
  if (!enabled || strlen(path) >= sizeof side.path) return;
  snprintf(side.path, sizeof side.path, "%s", path);
  side.ok = 0;
  side.running = !pthread_create(&side.thread, NULL, read_main, NULL);
}

void dtm_msh_beside_finish(int keep) {
  if (!side.running) return;
  pthread_join(side.thread, NULL);
  side.running = 0;
  side.have = side.ok;
  if (!keep) dtm_msh_beside_drop();
}

void dtm_msh_beside_drop(void) {
  if (side.have) dtm_msh_parsed_free(&side.got);
  side.have = 0;
}

/* Gmsh's statistics of the current model against p's counts. */
static int counts_agree(const dtm_msh_parsed *p) {
  static const char *const names[8] = {NULL,
                                       NULL,
                                       "Mesh.NbTriangles",
                                       "Mesh.NbQuadrangles",
                                       "Mesh.NbTetrahedra",
                                       "Mesh.NbHexahedra",
                                       "Mesh.NbPrisms",
                                       "Mesh.NbPyramids"};
  double v = -1;
  int ierr = 0;
  gmshOptionGetNumber("Mesh.NbNodes", &v, &ierr);
  if (ierr || v != (double)p->nnodes) return 0;
  for (int f = 2; f < 8; f++) {
    gmshOptionGetNumber(names[f], &v, &ierr);
    if (ierr || v != (double)p->family[f]) return 0;
  }
  return 1;
}

int dtm_gmsh_parsed_take(dtm_msh_parsed *p) {
  const char *src = dtm_gmsh_source_unchanged();
  memset(p, 0, sizeof *p);
  if (!side.have) return 0;
  *p = side.got, side.have = 0;
  memset(&side.got, 0, sizeof side.got);
  if (!src || strcmp(src, side.path) || !counts_agree(p)) {
    dtm_msh_parsed_free(p);
    return 0;
  }
  taken++;
  return 1;
}

int dtm_gmsh_parsed_enable(int on) {
  enabled = on;
  return taken;
}
