/* Local topology of the element types, in Gmsh's node ordering: edges and
 * facets, with the measures effects need (mean edge length as the element
 * "size" a Gmsh size field means; facet measures for interface springs).
 * Second-order types have the edges and facets of their linear parent, on
 * their corner nodes (the first nodes in Gmsh's order): only corner nodes
 * appear in the tables, lengths are chords between corners and facets are
 * measured flat. Coordinates are x[nn][3], m (all nn nodes of the element;
 * only the corners are read). */
#ifndef DTMAP_TOPOLOGY_H
#define DTMAP_TOPOLOGY_H

#include "dtmap/export.h"

#define DTM_MAX_FACETS 6      /* hex8 (and hex20, hex27) */
#define DTM_MAX_FACET_NODES 4 /* quadrilateral face, corner nodes only */

/* Number of edges of type, and *edges pointing at [count][2] local nodes. */
DTM_EXPORT int dtm_elem_edges(int type, const int (**edges)[2]);
/* Mean edge length (m) of one element. */
DTM_EXPORT double dtm_elem_mean_edge(int type, const double *x);

/* Number of facets (points of a line, edges of a 2D element, faces of a 3D
 * one); facet f has nodes[f][0..count[f]-1]. */
DTM_EXPORT int dtm_elem_facets(int type, const int (**nodes)[DTM_MAX_FACET_NODES], const int **count);
/* Measure of facet f: 1 for a point (unit cross-section), length of an edge
 * (per unit thickness in 2D), area of a face (m^2). */
DTM_EXPORT double dtm_elem_facet_measure(int type, int f, const double *x);

#endif
