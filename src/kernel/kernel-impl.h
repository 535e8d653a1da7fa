/* Private interface shared by the files of src/kernel/: element topology
 * tables, reference shape functions and quadrature rules, the map from the
 * reference element (Jacobian, physical gradients), the barycentric metric
 * of simplices and the small dense eigenvalue helpers. Nothing here is part
 * of the public API in include/dtmap/kernel.h, nor of the kernel's interface
 * to the library (reference.h); the kernel's own tests reach them too. */
#ifndef DTMAP_KERNEL_IMPL_H
#define DTMAP_KERNEL_IMPL_H

#include "dtmap/kernel.h"
#include "reference.h"

/* Four doubles in one vector (GCC's vector extension): lane l belongs to
 * matrix l (or rule point l) of a group. */
typedef double dtm_v4d __attribute__((vector_size(32)));

/* Boundary facets and edges of a type, in Gmsh's node numbering. A
 * second-order type has those of its linear parent, on its corner nodes
 * (Gmsh numbers the corners first, as in the parent). */
typedef struct {
  int nfacet;                 /* number of facets (points in 1D) */
  int facet_nn[DTM_K_FACETS]; /* node count of each facet */
  int facet[DTM_K_FACETS][4]; /* facet nodes, ordered around the facet */
  int nedge;                  /* number of edges */
  int edge[DTM_K_EDGES][2];   /* edge end nodes */
} dtm_topology;

/* Topology of a supported type; NULL for any other. Static storage. */
const dtm_topology *dtm_elem_topology(int type);
/* 1 for the serendipity types (quad8, hex20, prism15, pyr13), whose nodes
 * stop after the mid-edge ones; 0 otherwise. */
int dtm_elem_serendipity(int type);

/* Rule coordinates of node a (used to check the Jacobian at the nodes).
 * Second-order nodes follow Gmsh: corners, one node at the middle of each
 * edge of the parent (in the parent's edge order), then for quad9, hex27,
 * prism18 and pyr14 one at the centre of each quadrilateral face (in the
 * parent's facet order) and for quad9 and hex27 one at the centre. */
void dtm_ref_node(int type, int a, double p[3]);
/* Reference coordinates (u, v, w) of node a (Gmsh's, not collapsed). */
void dtm_ref_node_uvw(int type, int a, double p[3]);
/* The same for every node of type, as a static table [nn][3]; NULL for an
 * unsupported type. */
const double (*dtm_ref_nodes(int type))[3];
/* Shape functions of the second-order types (ref_quadratic.c, and
 * ref_pyramid.c for pyr13 and pyr14), same contract as dtm_ref_eval; dN
 * is already zeroed. */
void dtm_ref_eval_quadratic(int type, const double p[3], double *N, double (*dN)[3]);
void dtm_ref_eval_pyramid2(int type, const double p[3], double *N, double (*dN)[3]);

/* The frame of a plane element from its first nc corners x[nc][3]: axes[2]
 * the unit (Newell) normal, axes[0] the edge 0-1 projected on the plane,
 * axes[1] = axes[2] x axes[0]. Returns 0, or -1 when the corners span no
 * plane. */
int dtm_elem_plane_axes(int nc, const double *x, double axes[3][3]);
/* Coordinates xl[nn][3] of the nodes in the element's own frame: 3D
 * elements are copied, 2D elements are projected onto the mean plane of
 * their corner nodes (Newell normal), 1D elements onto their line; unused
 * components are 0.
 * Returns 0, or -1 when no frame exists (coincident nodes, collinear 2D). */
int dtm_elem_local(int type, const double *x, double (*xl)[3]);

/* A levelled rule with its shape functions evaluated at its points
 * (ref_table.c), shared by every element of the type. */
typedef struct {
  dtm_qrule q;                         /* the rule (dtm_ref_rule_level) */
  double N[DTM_K_QP][DTM_K_NODES];     /* shape functions at its points */
  double dN[DTM_K_QP][DTM_K_NODES][3]; /* their reference gradients */
  /* the same gradients of points 4 g .. 4 g + 3 lane by lane, for the map
   * at four points side by side (dtm_map_eval_valid4); full groups only */
  dtm_v4d dN4[DTM_K_QP / 4][DTM_K_NODES][3];
} dtm_ref_table;
/* The table of type's levelled rule at level (1 .. DTM_K_LEVEL_MAX), built
 * on first use (thread-safe); NULL for a type without levelled rules or
 * another level. Read only; it lives until the process ends. */
const dtm_ref_table *dtm_ref_level_table(int type, int level);
/* The table of the rule id (dtm_ref_rule_id: 0 the full rule, a level, or
 * DTM_K_RULE_C3D10 on tet10), same contract; NULL for an unsupported type
 * or id, or without memory. */
const dtm_ref_table *dtm_ref_rule_table(int type, int id);
/* The same at the nodes of type (dtm_ref_node's rule coordinates, weights
 * 0), for the node checks of shape.c. */
const dtm_ref_table *dtm_ref_node_table(int type);

/* The isoparametric map at one rule point, in the local frame of dimension
 * d: N[nn], physical gradients g[nn][3] (first d components) and the
 * volume factor dv = det J * rule weight. Returns det J. */
double dtm_map_eval(int type, int d, int nn, const double (*xl)[3], const double p[3], double wq, double *N,
                    double (*g)[3], double *dv);
/* The same from the reference gradients dN[nn][3] at the point (a table's:
 * dtm_ref_level_table), without N. */
double dtm_map_eval_dn(int d, int nn, const double (*xl)[3], const double (*dN)[3], double wq, double (*g)[3],
                       double *dv);
/* dtm_map_eval_valid (d = 3) at four points, their reference gradients
 * lane by lane D[nn][3] (a table's dN4) and weights wq[l], side by side in
 * vector lanes (map.c): the first of the four (0..3) whose det J (all four
 * in dj[4]) is not safely positive, or -1; point l's gradients, flattened
 * (g[l][3 a + i]), and dv[l] bitwise dtm_map_eval_valid's where it passes. */
int dtm_map_eval_valid4(int nn, const double (*xl)[3], const dtm_v4d (*D)[3], const double *wq, double *const g[4],
                        double *dv, double *dj);
/* dtm_map_eval_dn's det J and dv alone (no inverse, no gradients): bitwise
 * the same two numbers, for the sums that need only the volume factor
 * (the lumped masses). */
double dtm_map_dv_dn(int d, int nn, const double (*xl)[3], const double (*dN)[3], double wq, double *dv);
/* dtm_map_dv_dn at four points of a table side by side (3D), as
 * dtm_map_eval_valid4: dv[4] bitwise those four calls give. */
void dtm_map_dv_dn4(int nn, const double (*xl)[3], const dtm_v4d (*D)[3], const double *wq, double *dv);
/* dtm_map_det_dn (d = 3) at four points, reference gradients lane by lane
 * D[nn][3]: det J into det[4] and the Hadamard bounds into hadamard[4],
 * bitwise those four calls give. */
void dtm_map_det_dn4(int nn, const double (*xl)[3], const dtm_v4d (*D)[3], double *det, double *hadamard);
/* dtm_map_eval_dn with the validity test of dtm_map_first_bad on the same
 * Jacobian: returns -1 when det J (into *dj) is not safely positive (g and
 * dv are computed all the same, not finite where det J is 0), else 0.
 * Bitwise the values of the two calls. */
int dtm_map_eval_valid(int d, int nn, const double (*xl)[3], const double (*dN)[3], double wq, double (*g)[3],
                       double *dv, double *dj);
/* dtm_map_det from the reference gradients dN[nn][3] at the point. */
double dtm_map_det_dn(int d, int nn, const double (*xl)[3], const double (*dN)[3], double *hadamard);
/* det J of the map at rule coordinates p, and the product of the column
 * lengths of J in *hadamard (|det J| <= hadamard). */
double dtm_map_det(int type, int d, int nn, const double (*xl)[3], const double p[3], double *hadamard);
/* Index of the first rule point k < q->n where det J is not safely
 * positive (see map.c), det J there in *dj; -1 when the map is valid at
 * every rule point. Nodes are not checked (dtm_kernel_shape does). Raises
 * nothing. */
int dtm_map_first_bad(int type, int d, int nn, const double (*xl)[3], const dtm_qrule *q, double *dj);
/* The same over the points of a levelled rule's table. */
int dtm_map_first_bad_table(int d, int nn, const double (*xl)[3], const dtm_ref_table *t, double *dj);

/* n Gauss-Legendre points x[n] (ascending) and weights w[n] on [-1, 1]. */
void dtm_gauss_legendre(int n, double *x, double *w);
/* Largest offset of a second-order node of the element with coordinates
 * x[nn][3] from where its linear parent's map puts it, relative to its
 * edge (face and centre nodes: to the longest edge); 0 for linear types
 * and pyramids. */
double dtm_elem_node_offset(int type, const double (*x)[3]);
/* The rule of the element in its frame (xl) for the model (see curved.c):
 * returns 0 with the full rule, or the level of the levelled rule put in
 * q (q may be NULL: the level only); *settled (may be NULL) is 0 when the levels stopped at
 * DTM_K_LEVEL_MAX before the element settled. */
int dtm_elem_rule_choose(int type, int d, int nn, const double (*xl)[3], int model, dtm_qrule *q, int *settled);

/* Bernstein bound of det J over a tri6 or tet10 in its frame (bezier.c):
 * 1 when det J is proved positive everywhere, -1 when some point has det J
 * not safely positive (its scaled Jacobian into *scaled, may be NULL), 0
 * when neither is proved at the depth allowed, -2 for another type.
 * *ratio: a lower bound of min det J / max det J over the element (the
 * scaled Jacobian found when -1). */
int dtm_elem_jacobian_bound(int type, int d, int nn, const double (*xl)[3], double *ratio, double *scaled);

/* Barycentric metric of a simplex: S = sum_a g_a g_a^T (d x d, symmetric)
 * as scale * s, with s packed as s[0]=S11 s[1]=S22 s[2]=S33 s[3]=S12
 * s[4]=S13 s[5]=S23 (unused entries 0; scale > 0, 1/m^2), and the measure.
 * DTM_ERR_INPUT for a degenerate or inverted simplex. */
int dtm_simplex_metric(int type, const double *x, int *d, double s[6], double *scale, double *measure);

/* Eigenvalues e[0] >= e[1] >= e[2] of the symmetric 3x3 matrix packed as
 * above, each within a few ulps of the largest magnitude (trigonometric
 * solution, refined by deflation where two eigenvalues are close). */
void dtm_eig3_sym(const double s[6], double e[3]);
/* What the simplex kernels need of S's spectrum s1 >= s2 >= s3, each
 * part to a few eps of |S| (absolute; rho to eps |S|^2) even when s2 and
 * s3 are too close to split: the largest eigenvalue and the sum and
 * product of the gaps e_i = s1 - s_i, i = 2, 3. Any symmetric function of
 * (s2, s3) follows: s2 + s3 = 2 s1 - tau, s2 s3 = s1^2 - s1 tau + rho. */
typedef struct {
  double s1;  /* largest eigenvalue */
  double tau; /* e2 + e3 = 3 s1 - tr S >= 0 */
  double rho; /* e2 e3 >= 0 */
} dtm_top3;
void dtm_eig3_top(const double s[6], dtm_top3 *top);
/* Eigenvalues e[0] >= e[1] of the symmetric 2x2 [[a, b], [b, c]]. */
void dtm_eig2_sym(double a, double b, double c, double e[2]);

/* Largest eigenvalue of the symmetric n x n matrix a (row-major, 1 <= n <=
 * DTM_K_DOF, destroyed; its lower triangle is read) by Householder
 * tridiagonalization and Laguerre's iteration (tridiag.c): within a small multiple of n eps |A|, like
 * dtm_eig_sym_max, and far faster for n > 24. NaN if an entry is not
 * finite. */
double dtm_eig_sym_max_tridiag(int n, double *a);
/* The same with the tridiagonal's top found by plain bisection (what
 * dtm_eig_sym_max_tridiag did before its Laguerre iteration): the
 * reference of tests/t521. */
double dtm_eig_sym_max_tridiag_bisect(int n, double *a);
/* The Householder reduction both take (tridiag.c): a (n x n, lower
 * triangle read, destroyed) divided by its largest entry s and reduced to
 * the tridiagonal (d, e) (n and n - 1 entries); returns s, 0 for the zero
 * matrix (d, e untouched), NaN with a non-finite entry. Shared with the
 * shell and beam eigensolver (shell_eig.c). */
double dtm_eig_sym_tridiagonalize(int n, double *a, double *d, double *e);
/* dtm_eig_sym_max_tridiag of count <= 4 matrices a[l] (n x n, lower
 * triangles read, not written) at once, one per lane of a vector of four
 * doubles (tridiag.c): lambda[l] is bitwise what dtm_eig_sym_max_tridiag
 * returns for a[l] alone, whatever the other lanes hold. */
void dtm_eig_sym_max_tridiag_lanes(int n, double *const a[], int count, double *lambda);
/* dtm_eig_sym_max_tridiag_lanes' second half, for callers that build the
 * packed lanes themselves: A holds the lower triangles packed by rows (row
 * r starts at r (r + 1) / 2), lane l already divided by its largest
 * |entry| s[l]; a lane whose s[l] is 0 or NaN holds zeros and its lambda
 * is s[l]. A is overwritten. lambda[l] for l < count. */
void dtm_eig_sym_max_tridiag_packed(int n, dtm_v4d *A, const double s[4], int count, double *lambda);

/* Generic (quadrature + eigenvalue) paths, any supported type; linear
 * simplices go through them too, which is how the closed forms are
 * cross-checked. */
int dtm_elastic_lambda_generic(int type, const dtm_elastic_moduli *m, const double *x, double *lambda);
int dtm_diffusion_lambda_generic(int type, double alpha, const double *x, double *lambda);
/* The same with the rule of the element's kept level (level >= 0: the
 * level dtm_ref_rule_elem returns under DTM_INTEGRATION_CONVERGED; the
 * model's rule follows from it, dtm_ref_rule_id), or searched (level -1). */
int dtm_elastic_lambda_at(int type, const dtm_elastic_moduli *m, const double *x, int level, double *lambda);
/* Tests only: nonzero sends every element of dtm_kernel_elastic_lambda_lanes
 * through the one-element path (elastic.c), the reference the lanes are
 * compared with. Set it before an analysis, never during one. */
extern int dtm_kernel_lanes_off;
#define DTM_K_LANE_DOF 30 /* most unknowns the lanes take: tet10 (29 kB per four matrices) */
/* dtm_elastic_lambda_at of count <= DTM_KERNEL_LANES elements of one type
 * (moduli m[k], coordinates x[k], kept level level[k]) whose element
 * problems go to the tridiagonal path with at most DTM_K_LANE_DOF
 * unknowns, their eigenvalue problems solved side by side in vector lanes
 * (dtm_eig_sym_max_tridiag_lanes): each lambda[k] bitwise the scalar
 * path's. On an error, *failed is the element's index and the lambdas
 * before it are set. */
int dtm_elastic_lambda_lanes(int type, int count, const dtm_elastic_moduli *const *m, const double *const *x,
                             const int *level, double *lambda, int *failed);
/* The generic path as it was before the fast one (generic.c): separate
 * passes, the rule searched, bisection on the tridiagonal. For tests. */
int dtm_elastic_lambda_reference(int type, const dtm_elastic_moduli *m, const double *x, double *lambda);
int dtm_diffusion_lambda_reference(int type, double alpha, const double *x, double *lambda);
/* Closed form on simplices (line2, tri3, tet4). */
int dtm_elastic_lambda_simplex(int type, const dtm_elastic_moduli *m, const double *x, double *lambda);

/* Lumped nodal masses per unit density m[nn] (m^d) of the element in its
 * frame, integrated with rule q; returns the measure (integral of det J).
 * Linear types: row sums m_a = integral N_a. Second-order types: HRZ,
 * m_a = integral N_a^2 scaled so that sum_a m_a = measure (see lump.c). */
double dtm_lumped_mass(int type, int d, int nn, const double (*xl)[3], const dtm_qrule *q, double *m);
/* The same at the points of a levelled rule's table (its shape functions
 * evaluated once). */
double dtm_lumped_mass_table(int type, int d, int nn, const double (*xl)[3], const dtm_ref_table *t, double *m);
/* The last step of both: m[nn] holds the integrals of N_a (linear types:
 * left as they are) or N_a^2 (second-order types: scaled to the measure
 * vol, or CalculiX's C3D10 lumping when a tet10's rule has 4 points). */
void dtm_lumped_finish(int type, int nn, int npoints, double vol, double *m);

/* The per-thread memo of a curved element's integration at its kept level
 * (memo.c): the Gram tensor U (row-major nd x nd, upper triangle read or
 * written), the masses per unit density m[nn] and the measure, keyed by
 * type, rule table and the coordinates xl[nn] in the element's frame,
 * compared exactly. dtm_memo_fits: whether elements of nn nodes and nd
 * unknowns are kept at all. A put may drop the oldest entry or, without
 * memory, do nothing; a get returns 1 and the values (U may be NULL), or 0. */
int dtm_memo_fits(int nn, int nd);
void dtm_memo_put(int type, const dtm_ref_table *t, int nn, int nd, const double (*xl)[3], const double *U,
                  const double *m, double vol);
int dtm_memo_get(int type, const dtm_ref_table *t, int nn, int nd, const double (*xl)[3], double *U, double *m,
                 double *vol);
/* For tests: forget every entry of this thread's memo; how many gets it
 * has answered. */
void dtm_memo_clear(void);
long dtm_memo_hits(void);

/* On x86-64 with GCC, a hot loop marked DTM_KERNEL_AVX is compiled three
 * times, for the build's baseline (SSE2), for AVX and for x86-64-v4
 * (AVX-512: twice the vector registers, so the map at four points and the
 * Gram tiles keep more in them; about 5 % off a curved tet10's level
 * search), and the processor's version is chosen when the library loads
 * (an ifunc). Only for loops whose lanes are independent: C11 mode does
 * not contract a multiplication and an addition into a fused one (AVX has
 * none; x86-64-v4 has, and GCC emits none here), so every version gives the
 * same bits. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define DTM_KERNEL_AVX __attribute__((target_clones("arch=x86-64-v4", "avx", "default")))
#else
#define DTM_KERNEL_AVX
#endif

/* Three-component vectors: difference, dot and cross products. */
static inline void dtm_v3_sub(const double *a, const double *b, double *c) {
  for (int i = 0; i < 3; i++) c[i] = a[i] - b[i];
}

static inline double dtm_v3_dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static inline void dtm_v3_cross(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

#endif
