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
/* Work in a Gmsh session the caller opened (a script that called
 * gmsh.initialize() through Gmsh's Python module, in the same process and
 * on the same libgmsh): DTM_ERR_INPUT when Gmsh is not initialised. dtmap's
 * loops get threads OpenMP threads (0: all cores), since Gmsh sets OpenMP's
 * count to its General.NumThreads when it starts and when it meshes. The
 * caller's Gmsh options are left as they are. */
DTM_EXPORT int dtm_gmsh_attach(int threads);
/* The Gmsh libdtmap runs on: its version at run time (General.Version,
 * e.g. "4.8.4") into buf[len], and in *api (may be NULL) the Gmsh API
 * version of the headers libdtmap was built with (owned by the library).
 * Starts and stops Gmsh when no session is open. */
DTM_EXPORT int dtm_gmsh_version(char *buf, size_t len, const char **api);
/* Where Gmsh meshes a scene (src/gmsh/contain.c). contained = 1 (the
 * default, for a script's process): in a forked child, so that a crash in
 * Gmsh is an error with its signal and Gmsh's last messages. contained = 0:
 * the caller contains this whole process (the dtmap command's supervisor
 * forks it as its worker and reports its crash), so the first mesh is made
 * here, nothing handed back; while Gmsh reads or meshes, its messages go to
 * log_fd (unless the terminal shows them, verbosity 2), -1 for none.
 * Remeshes and probes (refine) stay in a child either way: a crash there
 * ends a round, not the run. */
DTM_EXPORT void dtm_gmsh_contain(int contained, int log_fd);
/* Gmsh's last messages in the log at fd (up to four lines, "; "-separated;
 * "" when it holds none) into buf[len]. */
DTM_EXPORT void dtm_gmsh_log_tail(int fd, char *buf, size_t len);
/* Give dtmap's loops back the thread count in force at dtm_gmsh_start
 * (Gmsh resets it to its own General.NumThreads when it meshes). */
DTM_EXPORT void dtm_gmsh_restore_threads(void);
/* Mesh on one thread: the same scene then always gives the same mesh. */
DTM_EXPORT void dtm_gmsh_serial(void);
/* Before meshing: the scene's <meshing algorithm threads> where it names
 * them (s may be NULL: keep what is set), else what the geometry file set;
 * records them for dtm_gmsh_mesher. */
DTM_EXPORT void dtm_gmsh_mesher_apply(const dtm_scene *s);
/* The current model was read from a .msh. */
DTM_EXPORT void dtm_gmsh_mesher_read(void);
/* Back to Gmsh's default mesher (Delaunay, one thread) before a geometry is
 * opened, so that a previous scene's choice does not carry over. */
DTM_EXPORT void dtm_gmsh_mesher_defaults(void);

/* How the current model's mesh was made. */
typedef struct {
  int algorithm;    /* Gmsh's Mesh.Algorithm3D (1 Delaunay, 10 HXT, ...); 0: read from a .msh */
  int threads;      /* threads Gmsh meshed with; 0: read from a .msh */
  int reproducible; /* 1: read, or meshed on one thread by a mesher other
                       than HXT (the same scene gives the same numbering);
                       0: a parallel mesher or HXT, whose numbering and
                       even element count may vary between runs */
} dtm_mesher_info;

/* The mesher of the current model (after dtm_gmsh_load or dtm_gmsh_remesh). */
DTM_EXPORT void dtm_gmsh_mesher(dtm_mesher_info *out);

/* The length unit of the current model's file and the factor dtmap applied
 * to its coordinates (src/gmsh/units.c). */
typedef struct {
  int active;     /* 1: a STEP, IGES or BREP was imported, or a .msh with <mesh unit> (else 0) */
  char found[8];  /* the unit the file declares (STEP, IGES: "mm", "in", "m", ...), "" when none */
  double found_m; /* metres per that unit; 0 when none */
  char given[8];  /* the scene's <geometry unit> or <mesh unit>, "" when unset */
  char system[4]; /* the scene's length unit, "m" or "mm" */
  double factor;  /* the coordinates of the file were multiplied by it into the scene's unit */
} dtm_import_units;
DTM_EXPORT void dtm_gmsh_import_units(dtm_import_units *out);
/* Before the scene's source at path is opened: read a STEP's or IGES's
 * unit, set Gmsh's OpenCASCADE options that convert it (or apply
 * <geometry unit>). After: set them back and scale a .msh's nodes by
 * <mesh unit>. None: the current model is a script's (<model/>). */
DTM_EXPORT int dtm_gmsh_units_before(const dtm_scene *s, const char *path);
DTM_EXPORT int dtm_gmsh_units_after(const char *path);
DTM_EXPORT void dtm_gmsh_units_none(void);

/* Open the scene's source: mesh its geometry with the <meshing> options, or
 * open its .msh. *dim receives the dimension to analyse. Errors name the
 * file; a geometry that yields no element of that dimension is an error. */
DTM_EXPORT int dtm_gmsh_load(const dtm_scene *s, int *dim);

/* Open a geometry or a .msh (no meshing) as the only model; *dim receives
 * its highest dimension. DTM_ERR_INPUT naming the file when Gmsh cannot. */
DTM_EXPORT int dtm_gmsh_open(const char *path, int *dim);

/* The dimension to analyse in the current model (for a model a program
 * built): the scene's <meshing dim>, else the model's dimension.
 * DTM_ERR_INPUT when the model has no element of that dimension (not
 * meshed, or Gmsh not initialised). */
DTM_EXPORT int dtm_gmsh_model_dim(const dtm_scene *s, int *dim);

/* Physical groups of dimension dim in the current model. */
DTM_EXPORT int dtm_gmsh_groups(int dim, dtm_group **groups, int *ngroups);
/* The Gmsh tags of the nodes of physical group (dim, tag) of the current
 * model, *n of them into *tags (malloc'ed, the caller frees). */
DTM_EXPORT int dtm_gmsh_group_nodes(int dim, int tag, size_t **tags, size_t *n);

/* Extract the nodes and the elements of dimension dim of the current model
 * into m (m->groups must be set). group_mat[g] is the material of group g or
 * -1; default_mat is used for elements whose groups have no material (-1:
 * none, an error naming the element tag and group). Types dtmap does not
 * handle are an error naming the element tag and type. */
DTM_EXPORT int dtm_gmsh_extract(int dim, const int *group_mat, int default_mat, const dtm_scene *s, dtm_mesh *m);

/* The groups of an extraction: material and section of each group of
 * m->groups (-1: none) and the defaults (-1: none). */
typedef struct {
  const int *group_mat; /* [ngroups] material index, or -1 */
  int default_mat;      /* material of elements whose groups have none, or -1 */
  const int *group_sec; /* [ngroups] section index, or -1; NULL: the scene has no section */
  int default_sec;      /* section of elements of dimension dim in no sectioned group, or -1 */
} dtm_group_map;
/* dtm_gmsh_extract with sections: the elements of dimension dim get the
 * section of their first sectioned group (else the default section), and
 * the elements of lower dimension whose entity is in a group of m->groups
 * with a section (curves and surfaces in or on the volumes: trusses,
 * membranes) are extracted too, with that group, its material and section;
 * their nodes are the ones they share with the rest of the mesh. */
DTM_EXPORT int dtm_gmsh_extract_map(int dim, const dtm_group_map *map, const dtm_scene *s, dtm_mesh *m);
/* The point masses of the session's DTM_VIEW_NODE_MASS view (loaded with
 * the .msh src), by node tag, into m->node_mass; nothing when there is no
 * such view. DTM_ERR_INPUT for a negative or non-finite mass, or one on a
 * node of no analysed element, naming it in mass_unit (the scene's:
 * dtm_scene_mass_unit) (src/gmsh/node_mass.c). */
DTM_EXPORT int dtm_gmsh_node_masses(dtm_mesh *m, const char *src, const char *mass_unit);
/* After extraction, from the current model: m->nodes_used, and in
 * m->left the groups of dimension below m->dim without a section whose
 * elements reach nodes no extracted element uses (parts of the model left
 * out; src/gmsh/left_out.c). */
DTM_EXPORT int dtm_gmsh_left_out(dtm_mesh *m);
/* Append to *groups the physical groups of dimension below dim that one of
 * the scene's sections names (by name, or by number when unnamed) and that
 * no group of *groups already answers to. */
DTM_EXPORT int dtm_gmsh_groups_sectioned(int dim, const dtm_scene *s, dtm_group **groups, int *ngroups);

/* Clear the current model's mesh and mesh it again (dimension dim, then
 * order) with the size scale * size[v] (m) at node v of m, the current mesh
 * (NaN: no value there), interpolated over its elements, as the only size
 * source; then Gmsh's optimiser passes optimise asks for (DTM_OPTIMISE_*
 * bits, those of the mesh's dimension: dtm_gmsh_optimisers). Meshes with
 * the mesher of the scene's load (dtm_gmsh_mesher_apply), in a child
 * process (round, the last round made before it, names it in messages:
 * "remeshing after round <round>"; a remesh Gmsh refuses makes no round).
 * DTM_ERR_INPUT with Gmsh's reason when Gmsh refuses the remesh,
 * DTM_ERR_INTERNAL with the signal and Gmsh's last messages when it
 * crashes; the model's mesh is then cleared. */
DTM_EXPORT int dtm_gmsh_remesh(const dtm_mesh *m, const double *size, double scale, int dim, int order, int round,
                               unsigned optimise);
/* A time limit on each remesh's child (seconds; 0: none, the default):
 * past it the child ends and the remesh fails as refused (refine sets it
 * while it searches: on a swept pipe one remesh ran for minutes). */
DTM_EXPORT void dtm_gmsh_remesh_limit(unsigned seconds);
/* Gmsh's own size options a remesh may keep beside the field (refine's
 * strategies, src/study/refine.c): a floor on every size (Mesh.MeshSizeMin,
 * m; 0: none), sizes from the curvature (Mesh.MeshSizeFromCurvature,
 * elements per 2 pi; 0: off) and a cap on every size (Mesh.MeshSizeMax, m;
 * 0: none: where the new mesh leaves the old one, on curved faces, the
 * field has no value and the cap then sets the size). {0, 0, 0} is
 * dtm_gmsh_remesh. */
typedef struct {
  double min_size;
  double curvature;
  double max_size;
} dtm_remesh_sizes;
DTM_EXPORT int dtm_gmsh_remesh_sized(const dtm_mesh *m, const double *size, double scale, int dim, int order, int round,
                                     unsigned optimise, const dtm_remesh_sizes *sizes);
/* Gmsh's optimiser passes a remesh can run (bits). */
enum {
  DTM_OPTIMISE_GMSH = 1,      /* Gmsh's default tetrahedral optimiser (3D) */
  DTM_OPTIMISE_NETGEN = 2,    /* Netgen's (3D; not built into Debian's Gmsh: it does nothing there) */
  DTM_OPTIMISE_RELOCATE = 4,  /* Relocate3D / Relocate2D: nodes moved to improve the worst elements */
  DTM_OPTIMISE_LAPLACE2D = 8, /* Laplace smoothing of surface meshes (2D) */
  DTM_OPTIMISE_NONE = 16      /* none (a set of its own, so that 0 can mean the default) */
};
/* The passes of asked that apply to a mesh of dimension dim and that this
 * Gmsh has (Netgen is not in every build: General.BuildOptions). */
DTM_EXPORT unsigned dtm_gmsh_optimisers(int dim, unsigned asked);

/* The gap between model entities a and b ({dim, tag}, curves or surfaces)
 * of the current Gmsh model near x0: the distance of their closest points
 * pa, pb (alternating projections from x0, on the untrimmed geometry), m;
 * NaN when Gmsh cannot project (no model, a point, a discrete entity it
 * cannot project onto). src/gmsh/gap.c */
DTM_EXPORT double dtm_gmsh_gap(const int a[2], const int b[2], const double x0[3], double pa[3], double pb[3]);

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

/* One reason a size field cannot set the sizes (or why refine stopped),
 * with the model entities it concerns and what to change. */
#define DTM_CAUSE_ENTITIES 64
typedef struct {
  char kind[32];               /* "size-options", "fixed-node-count", "recombined", "periodic",
                                  "embedded", "gmsh-refused", "gmsh-crash", "shape-limited",
                                  "thickness", "accuracy", "budget", "stalled" */
  char text[640];              /* what holds the sizes, in a sentence or two */
  char fix[2048];              /* lines to paste into the .geo, "" when none */
  int nent;                    /* entities named (the first DTM_CAUSE_ENTITIES) */
  int dim[DTM_CAUSE_ENTITIES]; /* their dimensions */
  int tag[DTM_CAUSE_ENTITIES]; /* their Gmsh tags */
} dtm_cause;

/* The node counts the current model fixes (src/gmsh/counts.c): its
 * transfinite curves (their count, law and coefficient, and the classes of
 * curves a transfinite surface ties together), and the curves whose count
 * it fixes otherwise, the layers of an extrusion, found on its mesh g with
 * size[] the size that reaches the target at each node and cur[] the
 * current size (g->nnodes each). NULL *out when g is NULL. */
typedef struct dtm_structure dtm_structure;
DTM_EXPORT int dtm_gmsh_structure(const dtm_geo *g, const double *size, const double *cur, dtm_structure **out);
DTM_EXPORT void dtm_gmsh_structure_destroy(dtm_structure **s);
/* 1 when a node of an entity an extrusion's layer curve bounds (or, with
 * keep_counts, a transfinite curve, whose count refine then keeps) needs a
 * size above that curve's smallest segment: no remesh reaches the target
 * there. */
DTM_EXPORT int dtm_gmsh_counts_cap(const dtm_structure *s, int keep_counts);
/* A curve whose node count the model fixes. */
typedef struct {
  int tag;       /* the curve */
  double length; /* its length, m */
  int nodes;     /* its node count */
  double need;   /* layer curves: the largest size a node of the entities it bounds needs, m (0: none) */
} dtm_fixed_curve;
/* The transfinite curves (transfinite = 1) or the layer curves (0), into
 * out[max]; returns how many there are. */
DTM_EXPORT int dtm_gmsh_fixed_curves(const dtm_structure *s, int transfinite, dtm_fixed_curve *out, int max);
/* Plan the transfinite counts for a size field: each curve's segments
 * divided by the largest growth size/cur asks at its nodes, the smallest
 * over the curves a surface ties to it, never more than the model's. */
DTM_EXPORT int dtm_gmsh_counts_plan(dtm_structure *s, const dtm_geo *g, const double *size, const double *cur);
/* Set the planned counts on the model (its law and coefficient kept);
 * *changed: how many curves differ from the model's own count. */
DTM_EXPORT int dtm_gmsh_counts_apply(dtm_structure *s, int *changed);
/* A transfinite curve whose node count refine set. */
typedef struct {
  int tag;      /* the curve */
  int from, to; /* node counts, the model's and refine's */
} dtm_count_change;
/* The curves whose count differs from the model's, into *out (malloc'd). */
DTM_EXPORT int dtm_gmsh_counts_list(const dtm_structure *s, dtm_count_change **out, int *n);

/* What the current model holds that decides sizes a size field cannot:
 * Gmsh's size options (Mesh.MeshSizeMin/Max/Factor, which the remesh lifts),
 * curves whose node count the model fixes (st, from dtm_gmsh_structure:
 * the layers of an extrusion, with the Layers{} counts the target needs;
 * and the transfinite curves when refine keeps their counts, keep_counts,
 * with "Transfinite Curve{t} = n;" lines), recombined surfaces and
 * structured volumes, periodic and embedded entities.
 * s: the scene (size options that are its own <meshing size min-size> are
 * not named; may be NULL); m, g: a mesh of the model and its
 * classification; size[m->nnodes]: the suggested size at its nodes (m).
 * Appends to out[*n] up to max causes. */
DTM_EXPORT int dtm_gmsh_size_causes(const dtm_scene *s, const dtm_mesh *m, const dtm_geo *g, const double *size,
                                    const dtm_structure *st, int keep_counts, dtm_cause *out, int max, int *n);

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
  const double *values; /* [n] (ignored when ivalues is set) */
  size_t n;             /* number of tags and values */
  const int *ivalues;   /* [n] integer values (written as numbers), or NULL */
  int finite_only;      /* 1: leave out the tags whose value is not finite */
} dtm_view;

/* How dtm_gmsh_write encodes the file. */
typedef struct {
  int binary;     /* 1: binary .msh 4.1 (mesh and views), 0: ASCII */
  int views_only; /* 1: only the format header and the views, no mesh: a
                     file Gmsh merges on top of the mesh it has open
                     (`gmsh input.msh views.msh`) */
  int partition;  /* part number (1 ...) of one part of a partitioned result: the
                     views carry it, so Gmsh merges the parts' views into one
                     view each; 0: a whole mesh */
} dtm_msh_format;

/* Write the current mesh (Gmsh's writer, Mesh.SaveAll=1) and then the views
 * to path (a .msh), or only the views (fmt->views_only). Views are written
 * directly, without creating Gmsh views; tags must be at most INT_MAX
 * (Gmsh's view format). fmt NULL: ASCII with the mesh. The caller makes
 * the write atomic. */
DTM_EXPORT int dtm_gmsh_write(const char *path, const dtm_view *views, int nviews, const dtm_msh_format *fmt);
/* The two halves of dtm_gmsh_write: the current mesh alone (path created),
 * and the views (appended after the mesh, or, with fmt->views_only, in a
 * new file with the format header). */
DTM_EXPORT int dtm_gmsh_write_mesh(const char *path, int binary);
/* dtm_gmsh_write_mesh for a model read from a .msh and changed by no
 * dtmap call since (a program that changes it through Gmsh's own API calls
 * dtm_gmsh_write_mesh): the file's own mesh sections are copied
 * (src/gmsh/msh_copy.c says when that is the mesh Gmsh would write), else
 * Gmsh writes it. With release, the model is released (dtm_gmsh_release)
 * as soon as it is no longer needed: before the copy, or after Gmsh's
 * write. */
DTM_EXPORT int dtm_gmsh_write_mesh_as_read(const char *path, int binary, int release);
DTM_EXPORT int dtm_gmsh_write_views(const char *path, const dtm_view *views, int nviews, const dtm_msh_format *fmt);
/* Drop the current model and give its memory back (once its mesh is
 * extracted and, where wanted, written): a run from a 1e6-tet .msh then
 * holds one copy of the mesh, not two. */
DTM_EXPORT void dtm_gmsh_release(void);
/* Gmsh's library is not thread-safe, and one thread calls it beside the
 * main one: run's background writer (src/output/mesh.c), which holds this
 * lock while it writes the mesh and releases the model. A call into Gmsh
 * that the analysis makes while that writer may run (the layers' gap,
 * dtm_gmsh_gap) takes it too. */
DTM_EXPORT void dtm_gmsh_lock(void);
DTM_EXPORT void dtm_gmsh_unlock(void);
/* On from the start of run's background writer until its output is
 * finished: the model is the writer's, released once written, and
 * dtm_gmsh_gap answers NaN at once (the layers keep the mesh's thickness)
 * instead of asking a model the writer may be releasing. */
DTM_EXPORT void dtm_gmsh_model_given(int on);

/* The view of a 3D result with trusses or membranes that draws the solid
 * elements' faint skin: dt over its solid elements alone, an ElementData
 * view of the .msh (src/output/mesh.c). */
#define DTM_VIEW_DT_SKIN "dt skin"

/* One picture of a result: which views it shows. */
typedef struct {
  const char *png;  /* output file (.png), written atomically */
  const char *only; /* show only the view of this name (and its skin, DTM_VIEW_DT_SKIN,
                       for "dt"), opaque, plus dtmap's text annotation; NULL: the
                       views as the .opt leaves them */
  int worst;        /* 1: a flat model framed on its worst elements (the view "below
                       target [s]" or "smallest 1% [s]", shown opaque over a faint dt);
                       else the whole model */
} dtm_snapshot_shot;

/* Pictures of a result through Gmsh's own renderer: open msh (Gmsh merges
 * msh.opt), then for each shot set the views, draw and write a PNG of width
 * x height pixels, dtmap's figures (the .opt's Printf lines) at the top. Needs an X display (DISPLAY); the CLI starts a
 * virtual one when there is none. Leaves Gmsh finalized. DTM_ERR_INPUT naming the file when Gmsh cannot open it, it has
 * no dt view (not a result of dtmap) or a picture cannot be written. */
DTM_EXPORT int dtm_gmsh_snapshot(const char *msh, const dtm_snapshot_shot *shots, int nshots, int width, int height);

/* Add the views to the current model of the open session, where they stay
 * (nothing is written); tags[nviews] receives their Gmsh view tags (tags
 * may be NULL). On failure the views added so far are removed. */
DTM_EXPORT int dtm_gmsh_add_views(const dtm_view *views, int nviews, int *tags);

/* A display option of a view, View[i].<name>: a number, or a string when
 * text is not NULL. */
typedef struct {
  const char *name; /* option name after "View[i].", e.g. "ScaleType" */
  double number;    /* its value when text is NULL */
  const char *text; /* its value for a string option, or NULL */
} dtm_view_option;

/* Set option o of the view with Gmsh tag tag in the open session. */
DTM_EXPORT int dtm_gmsh_view_option(int tag, const dtm_view_option *o);

/* Partition the current model's mesh into nparts with METIS and write the
 * parts as Gmsh names them: path "dir/x.msh" gives dir/x_1.msh ...
 * dir/x_<nparts>.msh (binary MSH 4.1: coordinates exact). The model stays
 * partitioned. DTM_ERR_INPUT naming path when Gmsh fails. */
DTM_EXPORT int dtm_gmsh_partition_write(int nparts, const char *path);
/* What the current model says about its partitions: *part is the partition
 * every entity of dimension dim that holds elements belongs to (0: they are
 * not partition entities, -1: they belong to different or several
 * partitions), *maxpart the highest partition number any entity names. */
DTM_EXPORT int dtm_gmsh_partition_info(int dim, int *part, int *maxpart);

#endif
