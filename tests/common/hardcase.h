/* Helpers for the hard-case stability corpus (t7xx): single-type meshes
 * placed by hand and written through the Gmsh C API as discrete entities
 * with named physical groups, structured builders (Kuhn-split boxes,
 * split rectangles, bars), writing the current Gmsh model, and the common
 * check of one case: `dtmap run --posterior` (Lanczos converged, element
 * and nodal bounds below the global estimate), `dtmap verify` bounded at
 * the recommended step and unbounded at 1.05 x the global estimate's
 * unsafe side. Gmsh must be initialised by the test program. */
#ifndef DTM_HARDCASE_H
#define DTM_HARDCASE_H

#include <stddef.h>

#define HC_MAX_GROUPS 4

/* Gmsh element type codes used by the builders. */
enum { HC_LINE2 = 1, HC_TRI3 = 2, HC_TET4 = 4 };

/* A single-type mesh under construction: node tags are 1..nn, element
 * tags 1..ne, each element in one of the named groups. */
typedef struct {
  int dim, type, npe; /* Gmsh element type, nodes per element */
  size_t nn, ne, cap_n, cap_e;
  double *xyz;  /* [3 nn] */
  size_t *conn; /* [npe ne], node tags */
  int *group;   /* [ne] */
  const char *groups[HC_MAX_GROUPS];
  int ngroups;
} hc_mesh;

/* An empty mesh with one group named group0. */
void hc_mesh_init(hc_mesh *m, int dim, int type, int npe, const char *group0);
void hc_mesh_free(hc_mesh *m);
/* Add a node; returns its tag. */
size_t hc_node(hc_mesh *m, double x, double y, double z);
/* Add an element as given (nodes: npe tags). */
void hc_elem(hc_mesh *m, const size_t *nodes, int group);
/* Add a simplex (tri3 or tet4) with positive orientation; fails the test
 * when it is degenerate. */
void hc_simplex(hc_mesh *m, const size_t *nodes, int group);
/* Signed measure of a simplex of m (area for tri3, volume for tet4). */
double hc_simplex_measure(const hc_mesh *m, const size_t *nodes);

/* Nodes of a rectilinear grid with coordinates x[0..nx], y[0..ny],
 * z[0..nz] (nz = 0: a plane grid); the tag of node (i, j, k) is
 * hc_grid_tag(first, nx, ny, i, j, k). */
size_t hc_grid_nodes(hc_mesh *m, const double *x, int nx, const double *y, int ny, const double *z, int nz);
size_t hc_grid_tag(size_t first, int nx, int ny, int i, int j, int k);
/* Kuhn split of grid cell (i, j, k) into 6 tets along its main diagonal
 * (conforming: every face is cut along its min-max diagonal). */
void hc_kuhn_cell(hc_mesh *m, size_t first, int nx, int ny, int i, int j, int k, int group);
/* A box grid, every cell Kuhn-split. */
void hc_box(hc_mesh *m, const double *x, int nx, const double *y, int ny, const double *z, int nz);
/* A rectangle grid in the plane z = 0, every cell cut along (0,0)-(1,1). */
void hc_rect(hc_mesh *m, const double *x, int nx, const double *y, int ny);
/* A bar along x with nodes x[0..n]. */
void hc_bar(hc_mesh *m, const double *x, int n);

/* Split every element holding edge a-b at the new node p (on the
 * segment): each becomes two, one with b replaced by p (in place), one
 * with a replaced by p (appended). Returns the number split. */
size_t hc_split_edge(hc_mesh *m, size_t a, size_t b, size_t p);
/* Split simplex e at the new node p (inside it) into npe simplices, vertex
 * k replaced by p: k = 0 in place, k = 1.. appended in order. */
void hc_split_simplex(hc_mesh *m, size_t e, size_t p);
/* Longest over shortest edge of element e. */
double hc_aspect(const hc_mesh *m, size_t e);

/* Write m as one discrete entity per group (physical groups named) to
 * tu_tmpdir()/name.msh; replaces the current Gmsh model. */
void hc_mesh_write(const hc_mesh *m, const char *name);
/* Write the current Gmsh model to tu_tmpdir()/name.msh, node coordinates
 * multiplied by scale (Mesh.ScalingFactor). */
void hc_model_write(const char *name, double scale);
/* Elements of dimension dim in the current Gmsh model, by type name
 * ("tet4 812, pyr5 40"), into buf. */
size_t hc_model_census(int dim, char *buf, size_t len);

/* One case's figures. */
typedef struct {
  size_t elements;
  double dt_min, dt_nodal, dt_global, recommended;
  double unsafe;     /* smallest dt_bracket[1] over the effects */
  double theta;      /* Ritz value of that effect */
  char effect[32];   /* that effect's name */
  char basis[32];    /* dt.basis */
  int iterations;    /* largest Lanczos iteration count */
  double growth_ok;  /* verify growth at the recommended step */
  double growth_bad; /* verify growth at 1.05 x unsafe */
  double seconds;    /* wall time of the three CLI runs */
} hc_result;

/* Write tu_tmpdir()/name.xml reading name.msh, with the given material
 * lines and effects (the inside of <effects>). */
void hc_scene_write(const char *name, const char *materials, const char *effects);
/* `dtmap run` on that scene (with --posterior if posterior); returns the
 * number at a dotted report path. */
double hc_run_number(const char *name, int posterior, const char *dotted);
/* The full check of a case (scene already written); prints a table row. */
void hc_check(const char *name, hc_result *r);
/* Header of the table rows hc_check prints. */
void hc_table_header(void);
/* cmocka group setup that prints the table header. */
int hc_group_setup(void **state);

#endif
