/* The spectral module's interface to the rest of libdtmap and its
 * white-box tests (internal, hidden): the node count up to which the
 * operator keeps its connectivity in 32 bits (UINT32_MAX; a test lowers it
 * to exercise the 64-bit loops on a small mesh). */
#ifndef DTMAP_SPECTRAL_H
#define DTMAP_SPECTRAL_H

#include <stddef.h>

#include "dtmap/mesh.h"

extern size_t dtm_operator_narrow_max;

/* A part of a mesh block whose elements share one integration rule
 * (parts.c). */
typedef struct {
  dtm_block blk; /* its elements: the mesh block itself when orig is NULL
                    (arrays not owned), else owned copies of tags, conn,
                    mat and section (group, gmask, entity NULL) */
  int level;     /* 0: the full rule; else the levelled rule's level (DTM_K_RULE_C3D10: CalculiX's C3D10 rule) */
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
 * was affordable, the safe side). 0 for shells and beams. */
size_t dtm_operator_node_graph_floor(const struct dtm_operator *op);

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
