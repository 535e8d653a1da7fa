/* Helpers for the tests of the distributed run (t9xx, built with DTM_MPI):
 * starting the CLI under a real mpirun, meshing a bundled geometry and
 * splitting it into part files with Gmsh's own API, and comparing a view
 * of a whole-mesh output with the same view of the parts merged by Gmsh. */
#ifndef DTM_TEST_PARTS_H
#define DTM_TEST_PARTS_H

#include <stddef.h>

#include "testutil.h"

/* Run "mpirun -n np <command>" (command formatted like tu_run's): the
 * mpirun the build found (DTM_TEST_MPIRUN); its environment (root,
 * oversubscription) comes from the test's ctest properties. */
int tu_mpirun(char **out, int np, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* In dir: `dtmap run scene_serial --posterior --tol 1e-10` into
 * tag_ser.msh and tag_ser.json, then under mpirun -n np `dtmap run
 * scene_parts --posterior --tol 1e-9` into tag_par.msh (one file per part)
 * and tag_par.json; prints the output of a run that fails. Returns 0 when
 * both succeed. */
int tu_run_pair(const char *dir, int np, const char *scene_serial, const char *scene_parts, const char *tag);

/* Mesh geometries/<geo> (dimension dim, Mesh.MeshSizeMax h) with Gmsh in
 * this process, write it to dir/<name>.msh and its split into nparts
 * (METIS) to dir/<name>_parts_1.msh ... (Gmsh's own naming). */
void tu_mesh_and_split(const char *geo, int dim, double h, const char *dir, const char *name, int nparts);

/* Open the whole-mesh file `whole` and read view `name` into *a; then open
 * part 1 of `parts` (a dtmap output name, OUT.msh -> OUT_1.msh ...) and
 * merge the others, as a user opening the parts in Gmsh, and read the
 * merged view into *b. Returns 0 when both exist. */
int tu_view_pair(const char *whole, const char *parts, int nparts, const char *name, tu_view *a, tu_view *b);

/* Names of the views in the .msh at path (at most max), in file order;
 * returns how many. */
int tu_view_list(const char *path, char (*names)[96], int max);

/* b against a, value by tag: *missing tags of a absent from b (and
 * counts that differ count too), *bitequal values identical, and the
 * largest relative difference. */
typedef struct {
  size_t missing;  /* tags of a not in b, plus |n_a - n_b| */
  size_t bitequal; /* values identical to the bit */
  double worst;    /* max |b - a| / |a| */
  double scaled;   /* max |b - a| / max |a|: against the view's largest value */
} tu_view_diff;
void tu_view_compare(const tu_view *a, const tu_view *b, tu_view_diff *d);

#endif
