/* dtmap's Gmsh API client: start and stop Gmsh, open a geometry and mesh it
 * or open a .msh, read the physical groups and extract element blocks, and
 * write views. All Gmsh calls of the project live behind this header. */
#ifndef DTMAP_GMSH_H
#define DTMAP_GMSH_H

#include "dtmap/export.h"

#include <stddef.h>

#include "dtmap/mesh.h"
#include "dtmap/scene.h"

/* Start Gmsh with General.AbortOnError=0. verbosity: 0 quiet (errors only
 * through dtmap's messages), 1 warnings, 2 Gmsh's info messages. */
DTM_EXPORT int dtm_gmsh_start(int verbosity);
DTM_EXPORT void dtm_gmsh_stop(void);
/* Give dtmap's loops back the thread count in force at dtm_gmsh_start
 * (Gmsh resets it to its own General.NumThreads when it meshes). */
DTM_EXPORT void dtm_gmsh_restore_threads(void);
/* Mesh on one thread: the same scene then always gives the same mesh. */
DTM_EXPORT void dtm_gmsh_serial(void);

/* Open the scene's source: mesh its geometry with the <meshing> options, or
 * open its .msh. *dim receives the dimension to analyse. Errors name the
 * file; a geometry that yields no element of that dimension is an error. */
DTM_EXPORT int dtm_gmsh_load(const dtm_scene *s, int *dim);

/* Open a geometry or a .msh (no meshing) as the only model; *dim receives
 * its highest dimension. DTM_ERR_INPUT naming the file when Gmsh cannot. */
DTM_EXPORT int dtm_gmsh_open(const char *path, int *dim);

/* Physical groups of dimension dim in the current model. */
DTM_EXPORT int dtm_gmsh_groups(int dim, dtm_group **groups, int *ngroups);

/* Extract the nodes and the elements of dimension dim of the current model
 * into m (m->groups must be set). group_mat[g] is the material of group g or
 * -1; default_mat is used for elements whose groups have no material (-1:
 * none, an error naming the element tag and group). Types dtmap does not
 * handle are an error naming the element tag and type. */
DTM_EXPORT int dtm_gmsh_extract(int dim, const int *group_mat, int default_mat, const dtm_scene *s, dtm_mesh *m);

/* Clear the current model's mesh and mesh it again (dimension dim, then
 * order) with the size scale * size[v] (m) at node v of m, the current mesh
 * (NaN: no value there), interpolated over its elements, as the only size
 * source; in 3D the default and Netgen optimisers run after. Meshes on one
 * thread (reproducible numbering). DTM_ERR_INPUT when Gmsh fails. */
DTM_EXPORT int dtm_gmsh_remesh(const dtm_mesh *m, const double *size, double scale, int dim, int order);

/* Where the mesh sits on the model, for the advice on shape-limited
 * elements. Filled from the current Gmsh model after dtm_gmsh_extract. */
typedef struct {
  int dim;     /* 0 point, 1 curve, 2 surface */
  int tag;     /* Gmsh entity tag */
  double size; /* curves: length of the curve's mesh (sum of the chords of
                  its line elements), m; 0 for the others */
  int npoints; /* model points in its closure (its end points for a curve) */
  int *points; /* [npoints] their tags (owned) */
} dtm_geo_entity;

typedef struct dtm_geo {
  size_t nnodes;       /* nodes of the mesh it was built for */
  int *node_dim;       /* [nnodes] dimension of the model entity each node is
                          classified on (the mesh's dimension for interior
                          nodes and nodes Gmsh does not classify) */
  int *node_tag;       /* [nnodes] that entity's tag (-1 when not known) */
  size_t nel;          /* elements of the mesh */
  int *elem_entity;    /* [nel] model entity (of the mesh's dimension) of each
                          element, in the mesh's block order (-1: not found) */
  int nent;            /* entities of dimension below the mesh's */
  dtm_geo_entity *ent; /* [nent] sorted by (dim, tag) */
} dtm_geo;

/* Classify mesh m (just extracted from the current model) on the model's
 * entities. *out is owned by the caller (dtm_gmsh_geo_destroy). */
DTM_EXPORT int dtm_gmsh_geo(const dtm_mesh *m, dtm_geo **out);
DTM_EXPORT void dtm_gmsh_geo_destroy(dtm_geo **g);
/* The entity (dim, tag) of g, or NULL. */
DTM_EXPORT const dtm_geo_entity *dtm_geo_find(const dtm_geo *g, int dim, int tag);
/* 1 when node v lies in the closure of entity e (on it, or on one of its
 * points). */
DTM_EXPORT int dtm_geo_node_on(const dtm_geo *g, size_t v, const dtm_geo_entity *e);
/* 1 when the entities of nodes v and w touch: the same entity, one in the
 * other's closure, or a model point in common. */
DTM_EXPORT int dtm_geo_touch(const dtm_geo *g, size_t v, size_t w);

/* Save the current model's mesh (every element) to path, and replace the
 * current model by the mesh read back from path: the refine loop keeps its
 * best mesh this way while it remeshes on. */
DTM_EXPORT int dtm_gmsh_save_mesh(const char *path);
DTM_EXPORT int dtm_gmsh_restore_mesh(const char *path);

/* A view to write: name, ElementData or NodeData, one value per tag. */
typedef struct {
  const char *name;     /* exact view name */
  int node_data;        /* 1: NodeData over node tags; 0: ElementData */
  const size_t *tags;   /* [n] element or node tags */
  const double *values; /* [n] */
  size_t n;
} dtm_view;

/* Write the current mesh and the views to path (a .msh), appending views
 * with PostProcessing.SaveMesh=0. The caller makes the write atomic. */
DTM_EXPORT int dtm_gmsh_write(const char *path, const dtm_view *views, int nviews);

/* One picture of a result: which views it shows. */
typedef struct {
  const char *png;  /* output file (.png), written atomically */
  const char *only; /* show only the view of this name, opaque, plus dtmap's text
                       annotation; NULL: the views as the .opt leaves them */
} dtm_snapshot_shot;

/* Pictures of a result through Gmsh's own renderer: open msh (Gmsh merges
 * msh.opt), then for each shot set the views, draw and write a PNG of width
 * x height pixels. Needs an X display (DISPLAY); the CLI starts a virtual one
 * when there is none. Leaves Gmsh finalized. DTM_ERR_INPUT naming the file
 * when Gmsh cannot open it or write a picture. */
DTM_EXPORT int dtm_gmsh_snapshot(const char *msh, const dtm_snapshot_shot *shots, int nshots, int width, int height);

#endif
