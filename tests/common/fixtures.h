/* In-memory fixtures for effect tests: a scene effect element with given
 * attributes, a one-group mesh, effect args bound to them, and a batch of
 * one element built from coordinates. No Gmsh, no files. */
#ifndef DTM_FIXTURES_H
#define DTM_FIXTURES_H

#include "dtmap/effect.h"
#include "dtmap/mesh.h"
#include "dtmap/scene.h"
#include "effect-impl.h"

typedef struct {
  dtm_scene scene;     /* path "fixture.xml" */
  dtm_scene_effect se; /* the effect element */
  char *keys[8], *values[8];
  dtm_mesh mesh; /* dim only, one group named "rock" */
  dtm_group group;
  dtm_effect_args args;
} tu_effect_fixture;

/* attrs: NULL-terminated key, value, key, value, ... */
void tu_fixture_init(tu_effect_fixture *f, const char *name, int dim, const char *const *attrs);

/* Give scene s the built-in property catalogue (nprops, prop_names, nknown). */
void tu_scene_catalogue(dtm_scene *s);
/* A material on the built-in catalogue with the given properties:
 * NULL-terminated name, value pairs ("E", 1e9, "rho", 2700.0, NULL; values
 * are doubles). Its values live in a static pool (no free). */
void tu_material(dtm_material *m, const char *name, ...);

/* A batch of one element of type with coordinates x[nn][3], material m,
 * group 0, tag 1. */
dtm_batch tu_batch1(int type, const double *x, const dtm_material **m);

/* A heap-allocated 1D mesh of n line2 elements along x with lengths len[n]
 * (m), element e joining nodes e and e+1, tags e+1; group[e] and mat[e]
 * per element (NULL: no group, material 0). Owned by the caller (or by an
 * analysis it is handed to): dtm_mesh_destroy frees it. */
dtm_mesh *tu_bar_mesh(int n, const double *len, const int *group, const int *mat);

/* A steel bar scene in s (path "mem.xml", material steel: E 200 GPa,
 * rho 8000 kg/m^3, the default; one elastic effect in the bar formulation;
 * safety 0.9; target in s), with se and sm its effect and material (all
 * caller-owned, they must outlive any analysis of s). */
void tu_bar_scene(dtm_scene *s, dtm_scene_effect *se, dtm_scene_material *sm, double target);
/* The analysis of scene s on the bar chain of lengths len[n] (m), groups
 * group[n] (NULL: none) among ngroups groups named "a", "b", ... */
struct dtm_analysis *tu_bar_analysis(const dtm_scene *s, int n, const double *len, const int *group, int ngroups);

/* A random element of type in x[3 nn]: the regular element's corners moved
 * by up to 15 % (not out of the xy plane for a 2D type), the other nodes
 * where the parent's map puts them, then moved by up to curve (0:
 * straight-sided), urand() uniform in [-1, 1). DTM_OK, or
 * dtm_elem_regular's error. (t521, t951) */
int tu_random_element(int type, double curve, double (*urand)(void), double *x);

struct dtm_operator;
/* The operator as a dense matrix of dtm_operator_ndof(op)^2 doubles, column
 * j its product with the unit vector e_j: the symmetric M^-1/2 K M^-1/2
 * when sym, else K (owned: free). (t501, t503, t504, t925, t941) */
double *tu_operator_dense(const struct dtm_operator *op, int sym);

#endif
