/* The mesh module's own interface between its files (internal to the
 * module): the duplicate-element check dtm_mesh_check runs
 * (src/mesh/duplicates.c). */
#ifndef DTM_MESH_IMPL_H
#define DTM_MESH_IMPL_H

#include "dtmap/mesh.h"

/* DTM_ERR_INPUT when two elements of one block (one element type) have the
 * same set of nodes: a .msh that holds the mesh twice (Gmsh writes one when
 * a view is appended to a file with the mesh saved again), whose elements
 * would each be counted twice. The message names src, how many elements
 * repeat, the first pair by tag, the likely cause and the remedy. */
int dtm_mesh_check_duplicates(const dtm_mesh *m, const char *src);

#endif
