/* The mesh as dtmap computes on it: nodes as a dense coordinate array and
 * the elements of the analysed dimension (and those of lower dimension in a
 * physical group the scene gives a section: trusses, membranes) as one block
 * per element type, a structure of arrays. Filled from the current Gmsh model by dtm_gmsh_extract
 * (src/gmsh/extract.c); kernels and effects never see Gmsh itself. */
#ifndef DTMAP_MESH_H
#define DTMAP_MESH_H

#include "dtmap/export.h"

#include <stddef.h>

#define DTM_MAX_MASK_GROUPS 64 /* groups representable in dtm_block.gmask */

/* The NodeData view of point masses added at the nodes (kg; per unit
 * thickness in a plane model), as refine writes them and a mesh read back
 * carries them into every estimate (dtm_mesh.node_mass). */
#define DTM_VIEW_NODE_MASS "added mass at nodes"

typedef struct {
  int dim;    /* dimension of the physical group (below the mesh's only for
                 groups a <section> names: curves and surfaces in or on it) */
  int tag;    /* Gmsh physical tag */
  char *name; /* its name, or "" when it has none (owned) */
} dtm_group;

typedef struct {
  int type;                  /* Gmsh element type code (DTM_TET4, ...) */
  int dim;                   /* topological dimension */
  int nn;                    /* nodes per element */
  size_t n;                  /* number of elements */
  size_t *tags;              /* [n] Gmsh element tags */
  size_t *conn;              /* [n][nn] 0-based indices into the mesh's node arrays */
  int *group;                /* [n] index into dtm_mesh.groups, -1 when in no group
                                (the group that gave the element its material) */
  int *mat;                  /* [n] index into the scene's materials, -1 until assigned */
  unsigned long long *gmask; /* [n] bit g set when the element is in group g
                   (every physical group of its entity, g < 64); may be NULL */
  int *entity;               /* [n] tag of the model entity (of dimension dim) the
                                element is classified on; may be NULL */
  int *section;              /* [n] index into the scene's sections, -1 for none (the
                                effects' own formulation); NULL when the scene has none */
} dtm_block;

/* An element dtmap analyses although its Jacobian is not safely positive at
 * one of its nodes: it is at every integration point, so its element
 * matrices are well defined (see dtm_kernel_shape). dtmap flags it: the view
 * "invalid elements", the report's list and a warning. */
typedef struct {
  int block;           /* index into dtm_mesh.blocks */
  size_t index;        /* element index in that block */
  double min_jacobian; /* smallest scaled Jacobian over its integration
                          points and nodes (negative: inverted there) */
  int node;            /* local node where it occurs (-1: a rule point) */
} dtm_flagged;

/* A physical group of dimension below the mesh's, without a section, whose
 * elements extraction left out although they reach nodes no analysed
 * element has (a tower's bars, a plate beside a solid): a part of the
 * model that is not analysed (dtm_gmsh_left_out). */
typedef struct {
  int dim;         /* dimension of the group (1: curves, 2: surfaces) */
  int tag;         /* Gmsh physical tag, -1: the entities in no physical group */
  char name[64];   /* its name, "" when it has none */
  size_t elements; /* its elements left out */
} dtm_left_out;

typedef struct dtm_mesh {
  int dim;           /* dimension of the analysed elements */
  size_t nnodes;     /* number of nodes */
  size_t *node_tags; /* [nnodes] Gmsh node tags */
  double *xyz;       /* [nnodes][3] coordinates, in length_unit (the scene's: m, or mm) */
  int nblocks;
  dtm_block *blocks; /* [nblocks], one per element type present */
  int ngroups;
  dtm_group *groups;       /* [ngroups] physical groups of dimension dim, then
                              the lower-dimensional groups sections name */
  size_t nflagged;         /* elements analysed although inverted at a node */
  dtm_flagged *flagged;    /* [nflagged] in block order (owned; dtm_mesh_check) */
  int space_dim;           /* the dimension of the space the nodes span, once known (a
                              distributed run agrees on it over the parts); 0: not yet */
  double *node_mass;       /* [nnodes] point masses added at the nodes, kg (per unit thickness
                              in a plane model): in the lumped mass of every wave effect's
                              nodal bound, global estimate and simulation, not in the element
                              steps; NULL: none (owned) */
  size_t nodes_used;       /* nodes of the extracted elements (0: not counted) */
  size_t nleft_dim[3];     /* [d] elements of dimension d left out, each once (groups may share some) */
  int nleft;               /* groups with elements left out */
  dtm_left_out *left;      /* [nleft] those groups (owned; dtm_gmsh_left_out) */
  const char *length_unit; /* the unit of xyz ("m", "mm": the scene's; static), printed after
                              the places of elements in messages; NULL: not printed */
} dtm_mesh;

/* Extent of the nodes the elements use along x, y and z, m, into ext[3];
 * DTM_ERR_INTERNAL for a node index beyond the mesh. */
DTM_EXPORT int dtm_mesh_extent(const dtm_mesh *m, double ext[3]);
/* Total number of elements over all blocks. */
DTM_EXPORT size_t dtm_mesh_nelements(const dtm_mesh *m);
/* Name of a group for messages: its name, or its number when unnamed. */
DTM_EXPORT const char *dtm_mesh_group_label(const dtm_mesh *m, int g, char *buf, size_t len);
/* Find a group by name, or by number written as text; -1 when absent. */
DTM_EXPORT int dtm_mesh_group_find(const dtm_mesh *m, const char *ref);
/* used[i] = 1 for every material index i some element has (the
 * blocks' mat), 0 for the others; used has nmat entries. */
DTM_EXPORT void dtm_mesh_materials_used(const dtm_mesh *m, int nmat, char *used);
/* Gather the coordinates of block b: x[n][nn][3]. x is caller-owned. */
DTM_EXPORT void dtm_mesh_gather(const dtm_mesh *m, const dtm_block *b, double *x);
/* The node coordinates x[nn][3] of element e of block b alone. */
DTM_EXPORT void dtm_mesh_gather_one(const dtm_mesh *m, const dtm_block *b, size_t e, double *x);
/* Renumber for locality (src/mesh/order.c): the elements of each block
 * along a Hilbert curve through their centroids, the nodes in the order
 * those elements first use them. Tags and every per-element and per-node
 * array move with their element or node, so results reported by tag are
 * unchanged. O(n). */
DTM_EXPORT int dtm_mesh_reorder(dtm_mesh *m);
/* "element T (type) in group 'G' at (x, y, z) m" for element e of block b
 * (the centroid of its nodes, followed by m->length_unit when it is set;
 * "in no physical group" when it has none), into buf; returns buf. */
DTM_EXPORT const char *dtm_mesh_element_place(const dtm_mesh *m, int b, size_t e, char *buf, size_t len);
/* Check the mesh before anything is computed on it: every node's
 * coordinates are finite, every element's nodes exist, and every element
 * has a shape dtmap can analyse (dtm_kernel_shape). Elements inverted,
 * folded or flat at an integration point are DTM_ERR_INPUT, naming src (the
 * mesh's file) and, for the first 20, the element's tag, type, group and
 * centroid, how it fails and its scaled Jacobian, then how many there are
 * in all. Elements valid at every integration point but not at a node are
 * recorded in m->flagged (replacing an earlier list). Then two elements of
 * one type on the same set of nodes (a file holding the mesh twice) are
 * DTM_ERR_INPUT naming src, the first pair, the cause and the remedy. */
DTM_EXPORT int dtm_mesh_check(dtm_mesh *m, const char *src);
/* The dimension of the space the elements' nodes span, *d: m->space_dim
 * when set; else the mesh's
 * dimension for a 2D mesh in a plane z = const or a 1D mesh along x (within
 * 1e-9 of the mesh's size), else the smallest that holds them (a 1D mesh in
 * a plane z = const: 2; anything else: 3). Elements of lower dimension than
 * *d (trusses, membranes, curved surfaces) act in their tangent line or
 * plane. DTM_ERR_INPUT for non-finite coordinates, DTM_ERR_INTERNAL for a
 * node index beyond the mesh. */
DTM_EXPORT int dtm_mesh_space_dim(const dtm_mesh *m, int *d);

/* The nodes split into parts for a scatter in parallel that adds each
 * node's contributions in the serial order (src/mesh/node_parts.c): part p
 * owns the nodes [lo, hi) (dtm_mesh_node_part) and, in block b, walks first
 * the list of elements from below that reach into it, then its core run
 * [e0, e1) (dtm_mesh_node_part_elements), adding only into its own nodes:
 * every element with a node in [lo, hi), in ascending order. A mesh not in
 * locality order (dtm_mesh_reorder) gets one part, every element its core. */
#define DTM_NODE_PARTS_MAX 256
typedef struct {
  int n;         /* parts */
  int nblocks;   /* blocks of the mesh */
  size_t nnodes; /* nodes of the mesh */
  size_t *core;  /* [nblocks][n + 1]: part p's core run in block b, [core[p], core[p + 1]) */
  size_t *at;    /* [nblocks][n + 1]: part p's listed elements, list[b][at[p] .. at[p + 1]) */
  size_t **list; /* [nblocks]: the listed elements, each part's ascending */
} dtm_node_parts;
/* Split m's nodes into np parts (at most DTM_NODE_PARTS_MAX and the node
 * count, at least 1); free with dtm_mesh_node_parts_free. */
DTM_EXPORT int dtm_mesh_node_parts(const dtm_mesh *m, int np, dtm_node_parts *out);
/* The nodes [lo, hi) of part p (hi = SIZE_MAX with one part). */
DTM_EXPORT void dtm_mesh_node_part(const dtm_node_parts *parts, int p, size_t *lo, size_t *hi);
/* The elements of block b part p walks: list[nlist], then [e0, e1). */
DTM_EXPORT void dtm_mesh_node_part_elements(const dtm_node_parts *parts, int p, int b, const size_t **list,
                                            size_t *nlist, size_t *e0, size_t *e1);
DTM_EXPORT void dtm_mesh_node_parts_free(dtm_node_parts *parts);
DTM_EXPORT void dtm_mesh_destroy(dtm_mesh **m);

#endif
