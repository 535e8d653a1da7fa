/* Element type catalogue: the Gmsh type codes dtmap handles (first-order
 * line, triangle, quadrangle, tetrahedron, hexahedron, prism, pyramid, and
 * the second-order triangle, quadrangle, tetrahedron, hexahedron, prism and
 * pyramid, complete and serendipity), their dimension, node count, name
 * and linear parent, and the parent's facets and edges in Gmsh's node
 * numbering: a second-order element's geometry (lengths, facets) is that
 * of its corner nodes. Anything else (line3, third order, ...) is rejected
 * here with a message naming the Gmsh type code. */
#include <stddef.h>

#include "dtmap/error.h"
#include "kernel-impl.h"

typedef struct {
  int type;          /* Gmsh type code */
  int dim;           /* topological dimension */
  int nn;            /* node count */
  const char *name;  /* short name used in messages */
  int parent;        /* linear parent type (the type itself if linear) */
  int serendipity;   /* 1: nodes stop after the mid-edge ones */
  dtm_topology topo; /* facets and edges (linear types only) */
} elem_entry;

/* Facets are ordered so that their Newell normal points out of a
 * positively oriented element (only their measure and plane are used). */
static const elem_entry table[] = {
    {DTM_LINE2, 1, 2, "line2", DTM_LINE2, 0, {2, {1, 1}, {{0}, {1}}, 1, {{0, 1}}}},
    {DTM_TRI3, 2, 3, "tri3", DTM_TRI3, 0, {3, {2, 2, 2}, {{0, 1}, {1, 2}, {2, 0}}, 3, {{0, 1}, {1, 2}, {2, 0}}}},
    {DTM_QUAD4,
     2,
     4,
     "quad4",
     DTM_QUAD4,
     0,
     {4, {2, 2, 2, 2}, {{0, 1}, {1, 2}, {2, 3}, {3, 0}}, 4, {{0, 1}, {1, 2}, {2, 3}, {3, 0}}}},
    {DTM_TET4,
     3,
     4,
     "tet4",
     DTM_TET4,
     0,
     {4,
      {3, 3, 3, 3},
      {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}},
      6,
      {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}}}},
    {DTM_HEX8,
     3,
     8,
     "hex8",
     DTM_HEX8,
     0,
     {6,
      {4, 4, 4, 4, 4, 4},
      {{0, 3, 2, 1}, {0, 1, 5, 4}, {0, 4, 7, 3}, {1, 2, 6, 5}, {2, 3, 7, 6}, {4, 5, 6, 7}},
      12,
      {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3}, {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}}}},
    {DTM_PRISM6,
     3,
     6,
     "prism6",
     DTM_PRISM6,
     0,
     {5,
      {3, 3, 4, 4, 4},
      {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {0, 3, 5, 2}, {1, 2, 5, 4}},
      9,
      {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 4}, {2, 5}, {3, 4}, {3, 5}, {4, 5}}}},
    {DTM_PYR5,
     3,
     5,
     "pyr5",
     DTM_PYR5,
     0,
     {5,
      {4, 3, 3, 3, 3},
      {{0, 3, 2, 1}, {0, 1, 4}, {3, 0, 4}, {1, 2, 4}, {2, 3, 4}},
      8,
      {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 4}, {2, 3}, {2, 4}, {3, 4}}}},
    /* Second order: the topology is taken from the parent's entry. */
    {DTM_TRI6, 2, 6, "tri6", DTM_TRI3, 0, {0}},
    {DTM_QUAD9, 2, 9, "quad9", DTM_QUAD4, 0, {0}},
    {DTM_TET10, 3, 10, "tet10", DTM_TET4, 0, {0}},
    {DTM_HEX27, 3, 27, "hex27", DTM_HEX8, 0, {0}},
    {DTM_PRISM18, 3, 18, "prism18", DTM_PRISM6, 0, {0}},
    {DTM_PYR14, 3, 14, "pyr14", DTM_PYR5, 0, {0}},
    {DTM_QUAD8, 2, 8, "quad8", DTM_QUAD4, 1, {0}},
    {DTM_HEX20, 3, 20, "hex20", DTM_HEX8, 1, {0}},
    {DTM_PRISM15, 3, 15, "prism15", DTM_PRISM6, 1, {0}},
    {DTM_PYR13, 3, 13, "pyr13", DTM_PYR5, 1, {0}},
};

static const elem_entry *find(int type) {
  for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
    if (table[i].type == type) return &table[i];
  return NULL;
}

int dtm_elem_info(int type, int *dim, int *nn) {
  const elem_entry *e = find(type);
  if (!e)
    return DTM_ERR(DTM_ERR_INPUT,
                   "Gmsh element type %d is not supported: dtmap handles the "
                   "first-order types line2 (1), tri3 (2), quad4 (3), tet4 (4), "
                   "hex8 (5), prism6 (6) and pyr5 (7) and the second-order "
                   "types tri6 (9), quad9 (10), tet10 (11), hex27 (12), "
                   "prism18 (13), pyr14 (14), quad8 (16), hex20 (17), "
                   "prism15 (18) and pyr13 (19); line3 and third- and "
                   "higher-order elements are not supported",
                   type);
  if (dim) *dim = e->dim;
  if (nn) *nn = e->nn;
  return DTM_OK;
}

const char *dtm_elem_name(int type) {
  const elem_entry *e = find(type);
  return e ? e->name : "unknown";
}

/* The closed forms hold for linear simplices only: tri6 and tet10 are not
 * "simplices" here. */
int dtm_elem_is_simplex(int type) { return type == DTM_LINE2 || type == DTM_TRI3 || type == DTM_TET4; }

int dtm_elem_parent(int type) {
  const elem_entry *e = find(type);
  return e ? e->parent : 0;
}

int dtm_elem_serendipity(int type) {
  const elem_entry *e = find(type);
  return e ? e->serendipity : 0;
}

const dtm_topology *dtm_elem_topology(int type) {
  const elem_entry *e = find(type);
  if (e && e->parent != type) e = find(e->parent);
  return e ? &e->topo : NULL;
}
