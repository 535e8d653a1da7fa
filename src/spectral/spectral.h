/* The spectral module's interface to the rest of libdtmap and its
 * white-box tests (internal, hidden): the node count up to which the
 * operator keeps its connectivity in 32 bits (UINT32_MAX; a test lowers it
 * to exercise the 64-bit loops on a small mesh). */
#ifndef DTMAP_SPECTRAL_H
#define DTMAP_SPECTRAL_H

#include <stddef.h>

#include "dtmap/mesh.h"
#include "dtmap/operator.h"

extern size_t dtm_operator_narrow_max;
/* Which blocks of solid 3D elements the operator keeps as element matrices
 * instead of points (operator.c): 1 (default) where the packed matrix is
 * smaller than the points (curved elements at a high level), 0 none, 2
 * every one that is not a linear simplex (tests compare the two ways). */
extern int dtm_operator_store;
/* How many elements op keeps as element matrices. */
size_t dtm_operator_stored(const struct dtm_operator *op);
/* How many rule points op keeps for the elements it does not keep as
 * matrices (shells and beams aside). */
size_t dtm_operator_points(const struct dtm_operator *op);

/* The part of the tet10 whose map is affine (dtm_elem_affine) among those
 * the full rule integrates: the operator integrates their stiffness with a
 * rule of degree 2 (the 4 points of CalculiX's C3D10 rule), which is exact
 * for them, instead of the full rule's 14 points; their masses stay the
 * full rule's. */
#define DTM_RULE_AFFINE (DTM_K_RULE_C3D10 + 1)

/* A part of a mesh block whose elements share one integration rule
 * (parts.c). */
typedef struct {
  dtm_block blk; /* its elements: the mesh block itself when orig is NULL
                    (arrays not owned), else owned copies of tags, conn,
                    mat and section (group, gmask, entity NULL) */
  int level;     /* 0: the full rule; else the levelled rule's level (DTM_K_RULE_C3D10: CalculiX's C3D10 rule;
                    DTM_RULE_AFFINE: affine tet10) */
  int block;     /* index of the mesh block */
  size_t *orig;  /* [blk.n] element index in the mesh block (owned), or NULL */
} dtm_rule_part;

/* The parts of every block of m for the integration model
 * (DTM_INTEGRATION_*) into *parts[*nparts] (owned: dtm_rule_parts_free,
 * also after an error); kept[block][element] (or NULL, or a NULL row) the
 * elements' converged levels an analysis found (then not searched again). */
int dtm_rule_parts(const dtm_mesh *m, int model, const unsigned char *const *kept, dtm_rule_part **parts, int *nparts);
void dtm_rule_parts_free(dtm_rule_part *parts, int n);

struct dtm_operator;
/* The nodes that share an element with each node (itself included):
 * adj[xadj[v] .. xadj[v + 1]) for the *nnodes = ndof / ncomp nodes (owned:
 * free). An error for shells and beams (their rotations are not nodes'
 * translations). */
int dtm_operator_node_graph(const struct dtm_operator *op, size_t *nnodes, size_t **xadj, size_t **adj);
/* A lower bound of that graph's entries without building it (one pass over
 * the connectivity): every node of an element of nn nodes shares it with
 * nn nodes (itself included), so the entries are at least the nodes in
 * some element times the fewest nodes per element of any block (an element
 * that repeats a node could only make the bound refuse a certificate that
 * was affordable, the safe side). A mesh of linear tets alone does better:
 * by Euler's formula V - E + F - T = b0 - b1 + b2, with F = (4T + Fb) / 2
 * (a face in at most two tets), E = V + T + Fb / 2 - (b0 - b1 + b2) >= V + T,
 * since every part and every cavity is bounded by at least 4 faces of the
 * Fb on the boundary; the entries V + 2E are then at least 3V + 2T (3.8x
 * the first bound at 1.2e6 tets, where the graph took 2 % of the run's CPU
 * to be refused). 0 for shells and beams. */
size_t dtm_operator_node_graph_floor(const struct dtm_operator *op);

/* The stiffness K of the operator assembled by coloured products (as the
 * certificate assembles A, certify.c), in node blocks over its node graph:
 * blk[(p * nc + i) * nc + j] = K(adj[p] nc + i, v nc + j) for p in
 * [xadj[v], xadj[v + 1]), nc = dtm_operator_ncomp (all owned: free). An
 * error for shells and beams, as dtm_operator_node_graph. */
int dtm_operator_assemble(const struct dtm_operator *op, size_t *nnodes, size_t **xadj, size_t **adj, double **blk);

/* csr.c: x . y summed in order (the mass solves and the modes' Lanczos:
 * one rounding for every caller). */
double dtm_vec_dot(size_t n, const double *x, const double *y);

/* lzvec.c: the global Lanczos run's vector work, chunk by chunk of
 * DTM_VCHUNK unknowns with the chunks' sums added in order (the same bits
 * on any thread count), on OpenMP's threads for long vectors. part is
 * workspace of dtm_vchunks(n) * max(2, nv) doubles. A basis vector j is
 * sc[j] V[j]. */
#define DTM_VCHUNK 4096
size_t dtm_vchunks(size_t n);
/* w = s w - t x, then d[0] = w . y and d[1] = w . w (x and y not NULL;
 * t = 0 leaves s w exactly). */
void dtm_vstep(size_t n, double *w, double s, double t, const double *x, const double *y, double *part, double d[2]);
/* c[j] = w . (sc[j] V[j]), j < nv. */
void dtm_vproject(size_t n, const double *w, double *const *V, const double *sc, int nv, double *part, double *c);
/* w -= sum_j c[j] sc[j] V[j]; returns w . w. */
double dtm_vsubtract(size_t n, double *w, double *const *V, const double *sc, const double *c, int nv, double *part);
/* y = sum_j c[j] sc[j] V[j]. */
void dtm_vcombine(size_t n, double *y, double *const *V, const double *sc, const double *c, int nv);

/* integrate.c: one energy sample of a verify run, the energy norm q at
 * step n over its value at rest: the growth kept over n >= steps / 2 (or
 * at once when q passes 1e6 or is not finite: unstable); 1 when the run
 * stops there (unstable, or n == steps). */
int dtm_verify_sample(int n, int steps, double q, dtm_verify_result *r);

/* The certificate of certify.c: sigma I - A = L L^T for A = M^-1/2 K M^-1/2
 * assembled from the operator's product. */
typedef struct dtm_certifier dtm_certifier;
/* Order (CHOLMOD's analysis), predict the factor's flops and bytes and,
 * within budget flops and the memory cap, assemble; *status
 * DTM_CERT_PROVEN (ready: *out set), DTM_CERT_TOO_DEAR (more than budget
 * flops or more memory than the cap: not assembled) or
 * DTM_CERT_UNAVAILABLE (shells or beams, or an assembly that does not
 * reproduce the product); *out NULL then. */
int dtm_certifier_create(const struct dtm_operator *op, double budget, dtm_certifier **out, int *status);
/* The same, with predicted[0] the predicted flops and predicted[1] the
 * predicted bytes of the factorisation (NaN where not predicted: a node
 * graph too large to order within the budget, shells or beams). */
int dtm_certifier_create_costed(const struct dtm_operator *op, double budget, dtm_certifier **out, int *status,
                                double predicted[2]);
void dtm_certifier_destroy(dtm_certifier **c);
/* The factorisation's flops (CHOLMOD's prediction). */
double dtm_certifier_flops(const dtm_certifier *c);
/* 1 when sigma I - A factors with positive pivots, so that every
 * eigenvalue of A is below sigma + *margin (the rounding of the
 * factorisation); 0 when a pivot is not positive (an eigenvalue lies at or
 * above sigma, up to that rounding), or when CHOLMOD ran out of memory
 * (nothing proven: the caller takes it as refuted, the safe side). */
int dtm_certifier_below(dtm_certifier *c, double sigma, double *margin);

/* Each element of op's blocks (in their order) with its mesh block, its
 * index in that block, its nn node indices and its lumped node masses
 * w[nn] (kg: what it adds to dtm_operator_mass at each of its nodes'
 * translational unknowns); fn returning non-zero stops the walk and is
 * returned. DTM_ERR_INPUT for an operator with shells or beams. mesh is
 * the operator's; level the converged rule levels its creation was given
 * (dtm_operator_kept.level), or NULL: searched again, the same weights
 * (the operator keeps no pointer to what its creation was given). */
typedef int (*dtm_operator_elem_fn)(void *user, int block, size_t local, int nn, const size_t *nodes, const double *w);
int dtm_operator_each_element(const struct dtm_operator *op, const dtm_mesh *mesh, const unsigned char *const *level,
                              dtm_operator_elem_fn fn, void *user);

/* The largest eigenvalue of the symmetric tridiagonal matrix of diagonal
 * a[k] and off-diagonal b[k - 1] (lanczos.c: bisection), with its unit
 * eigenvector in s[k] (inverse iteration; w: [4k] workspace). */
double dtm_tridiag_top(int k, const double *a, const double *b, double *s, double *w);

/* certify.c for a pencil: 1 when sigma D - A factors with positive pivots
 * for D = I + dx (dx symmetric, both triangles, its pattern within the
 * certifier's node graph: a scaled added mass M^-1/2 M_add M^-1/2), so
 * that every eigenvalue of the pencil (A, D) is below sigma + *margin
 * (the factorisation's rounding and that of forming sigma dx - A; D >= I
 * turns an absolute perturbation into one of the pencil's eigenvalues); 0
 * as dtm_certifier_below. */
int dtm_certifier_below_pencil(dtm_certifier *c, const dtm_csr *dx, double sigma, double *margin);

/* sms.c: G^T g for a factor G of M_s = G^T G (G stacks M^1/2 and each
 * scaled element's sqrt(beta) W^1/2 (I - 1 w^T / m) per component) and g
 * standard normal drawn from seed (per node tag and component for M^1/2):
 * M_s^-1 G^T g then has an M_s^1/2 image that is standard normal. */
struct dtm_sms;
void dtm_sms_factor_draw(const struct dtm_sms *s, const struct dtm_operator *op, unsigned long long seed, double *rhs);
/* Lanczos's reorthogonalisation (lanczos.c): partial (Simon's omega
 * recurrence: what dtmap runs), full at every step, or none. */
enum { DTM_REORTH_PARTIAL, DTM_REORTH_FULL, DTM_REORTH_NONE };
/* White-box (tests/t931): steps Lanczos steps from seed (fewer where T_k
 * becomes invariant) with the reorthogonalisation mode (DTM_REORTH_*);
 * *theta the top Ritz value, *deviation the largest |v_i . v_j -
 * delta_ij| over the stored basis, *nreorth the steps that
 * reorthogonalised. */
int dtm_lanczos_basis_check(const struct dtm_operator *op, int steps, unsigned seed, int mode, double *theta,
                            double *deviation, int *nreorth);

#endif
