/* Private to src/kernel/: an element prepared for the generic quadrature
 * path (local frame, rule, validity checked) and the dense element matrices
 * built on it by assemble.c. */
#ifndef DTMAP_KERNEL_ASSEMBLE_H
#define DTMAP_KERNEL_ASSEMBLE_H

#include "kernel-impl.h"

typedef struct {
  int type;                  /* Gmsh type code */
  int d;                     /* dimension of the element's own frame */
  int nn;                    /* node count */
  double xl[DTM_K_NODES][3]; /* nodes in the element frame, m */
  dtm_qrule q;               /* the rule: full, or levelled for a curved
                                element (curved.c) */
  int level;                 /* 0 for the full rule, else the level of q */
  int settled;               /* 0 when the levels stopped before settling */
  int bad;                   /* after a failed setup: first bad rule point
                                (see dtm_map_first_bad), or -1 when the
                                nodes span no frame */
  double bad_det;            /* det J at that point */
} dtm_elem_geom;

/* Fill eg for the element with coordinates x[nn][3], integrated as the
 * model (DTM_INTEGRATION_*) says. Returns 0, or -1
 * (recording nothing) for an unsupported type or a degenerate or inverted
 * element; then eg->bad says where. */
int dtm_elem_setup(int type, const double *x, int model, dtm_elem_geom *eg);
/* dtm_elem_setup, raising DTM_ERR_INPUT with a message when it fails. */
int dtm_elem_prepare(int type, const double *x, int model, dtm_elem_geom *eg);
/* m[nn]: lumped mass per unit density (m^d): integral of N_a for linear
 * types, HRZ for second-order ones (dtm_lumped_mass). */
void dtm_elem_mass(const dtm_elem_geom *eg, double *m);
/* K[nn][nn]: integral of grad N_a . grad N_b (m^(d-2)). */
void dtm_elem_laplace(const dtm_elem_geom *eg, double *K);
/* K[nn d][nn d], unknown (a, i) at a d + i: elastic stiffness (N/m). The
 * bar (d = 1) uses modulus E axially. */
void dtm_elem_stiffness(const dtm_elem_geom *eg, const dtm_elastic_moduli *m, double *K);
#define DTM_GRAM_W 32 /* the blocked Gram's padded width and points per block (tet10: nd = 30) */
/* U += sum_p dv[p] gl[p] gl[p]^T over np (<= 4) rule points, on the upper
 * triangle (x <= y) of the nd x nd U, gl[p] point p's gradients flattened
 * (gl[p][a d + i] = g[a][i]): the Gram tensor's sum of the second-order
 * stiffness and of curved.c's level search. Each entry of U is loaded and
 * stored once for the np points and still takes their products one rounded
 * addition after the other (p = 0, 1, ...), so U is bitwise what the points
 * one at a time give. AVX where the processor has it (DTM_KERNEL_AVX: the
 * same bits). */
void dtm_elem_gram_add_points(int nd, int np, const double (*gl)[DTM_K_DOF], const double *dv, double *U);
/* The same sum over np <= DTM_GRAM_W points for nd <= DTM_GRAM_W, on a
 * padded Ul (row x, column y of U at Ul[x][y]; the rows and columns from nd
 * on are scratch, and gb's columns from nd on must be finite): each entry
 * of a tile of 4 x 8 stays in a register through all the points, so U is
 * loaded and stored once per block instead of once per four points, and
 * still takes the points' products one rounded addition after the other
 * in their order, so the same bits. */
void dtm_elem_gram_block(int nd, int np, const double (*gb)[DTM_GRAM_W], const double *dv, double (*Ul)[DTM_GRAM_W]);
/* A walk over the points of a rule's table t in their order, for an
 * element in its frame xl, that the element assembly and curved.c's level
 * search share: the map (dtm_map_eval_valid4) at four points side by side
 * where a full group of four opens (d = 3), else at one point
 * (dtm_map_eval_valid); and the points' gradients gathered for the Gram
 * tensor, a whole group straight from the map's rows. */
typedef struct {
  const dtm_ref_table *t;
  int d, nn;
  const double (*xl)[3];
  double g4[4][DTM_K_NODES][3], dv4[4], dj4[4]; /* the current group of four */
  double *rows[4];                              /* where its gradients are: g4, or the block's rows */
  int bad4;                                     /* its first lane where det J is not safely positive, or -1 */
  double g[DTM_K_NODES][3];                     /* a point outside the groups */
  double gl[4][DTM_K_DOF], dvl[4];              /* such points, flattened, waiting for the Gram update */
  int held;
  /* 3D types with nd <= DTM_GRAM_W (tet10): the Gram tensor summed in
   * register tiles (dtm_elem_gram_block) over blocks of points, into Ul,
   * and added to U at the end; bl: points in the block, ul: Ul zeroed */
  int blocked, bl, ul;
  _Alignas(32) double Ul[DTM_GRAM_W][DTM_GRAM_W];
  _Alignas(32) double gb[DTM_GRAM_W][DTM_GRAM_W];
  double dvb[DTM_GRAM_W];
} dtm_point_walk;
void dtm_point_walk_start(dtm_point_walk *w, const dtm_ref_table *t, int d, int nn, const double (*xl)[3]);
/* Point k (each k in turn from 0): its gradients g[nn][3], dv and det J
 * (*dj). *valid is 0 where det J is not safely positive (the gradients are
 * computed all the same); in a group of four only its first such lane says
 * so, the later lanes are not tested (the callers stop, or have marked the
 * element, at the first). */
const double (*dtm_point_walk_at(dtm_point_walk *w, int k, double *dv, double *dj, int *valid))[3];
/* U += dv g g^T of point k (its gradients g, just returned), as
 * dtm_elem_gram_add_points four points at a time, or dtm_elem_gram_block
 * DTM_GRAM_W at a time into the walk's Ul; _end adds the points still held
 * (and Ul to U). U must be zero at the walk's start (both callers clear
 * it): the blocked sums start from zero, and 0 + s is s, so U's bits are
 * those of the points added to U one after the other. */
void dtm_point_walk_gram(dtm_point_walk *w, int k, const double (*g)[3], double dv, double *U);
void dtm_point_walk_gram_end(dtm_point_walk *w, double *U);
/* The whole walk: every point's gradients into U (cleared by the caller,
 * as above) and its dv into dv[k]; returns the first point where det J is
 * not safely positive (its det J into *dj), or -1. Every point is
 * integrated, valid or not. The same bits as the calls above, point after
 * point; a 3D walk hands the map's groups of four to the block directly. */
int dtm_point_walk_gram_all(dtm_point_walk *w, double *U, double *dv, double *dj);
/* The element bound's matrices in one pass over the points of table t
 * (dtm_ref_rule_table) for the element in its frame xl: the elastic
 * stiffness K[nn d][nn d] of moduli m (NULL: the Laplacian K[nn][nn]) and
 * the lumped masses per unit density mass[nn]: the masses, the Laplacian
 * and the stiffness of linear types bitwise what dtm_elem_mass,
 * dtm_elem_laplace and dtm_elem_stiffness give on the same rule; the
 * stiffness of second-order types from the Gram tensor integral g_ai g_bj
 * (half the products per point), which rounds differently in the last
 * bits. Returns -1, or the first point where det J (into *dj) is not
 * safely positive, as dtm_elem_setup checks it. */
int dtm_elem_assemble(int type, int d, int nn, const double (*xl)[3], const dtm_ref_table *t,
                      const dtm_elastic_moduli *m, double *K, double *mass, double *dj);
/* The lumped masses per unit density m[nn] (HRZ's N_a^2 dv where hrz,
 * else N_a dv) and the measure *vol from every point's dv over table t:
 * the sums dtm_lumped_mass_table makes, point after point, before
 * dtm_lumped_finish. */
void dtm_elem_masses(const dtm_ref_table *t, int nn, int hrz, const double *dv, double *m, double *vol);
/* The Gram tensor U (its upper triangle, row-major nn d x nn d) and the
 * lumped masses per unit density of a second-order element, from the memo
 * (memo.c) or integrated over table t as dtm_elem_assemble does: returns
 * -1, or the first point where det J (into *dj) is not safely positive. */
int dtm_elem_gram(int type, int d, int nn, const double (*xl)[3], const dtm_ref_table *t, double *U, double *mass,
                  double *dj);
/* Lane l of the packed lower triangle A (dtm_eig_sym_max_tridiag_packed)
 * from the Gram tensor U of a 3D element of nn nodes: the elastic stiffness of moduli lam, mu that
 * dtm_elem_assemble forms from it, each entry K_xy times r_x r_y (r the
 * masses' m^-1/2 per unknown), bitwise what dtm_eig_sym_max_tridiag_lanes
 * packs from that matrix scaled by generic.c before its division by the
 * largest |entry|, which is returned (NaN if an entry is not finite). */
double dtm_elem_gram_lane(int nn, double lam, double mu, const double *U, const double *r, int l, dtm_v4d *A);
/* dtm_affine_matrices' check and frame: 1 with det J in *dj and J^-1 in Ji
 * when its shortcut applies to the element, else 0. */
int dtm_affine_frame(int type, int d, int nn, const double (*xl)[3], double *dj, double Ji[3][3]);
/* dtm_affine_matrices of count (1 .. 4) elastic tet10 whose frames
 * dtm_affine_frame gave (dj[l], Ji[l]), side by side in vector lanes: K[l]
 * (30 x 30) and mass[l] (10) bitwise the one-element call's. */
void dtm_affine_elastic_lanes(int count, const double *dj, const double (*Ji)[3][3], const dtm_elastic_moduli *const *m,
                              double *const *K, double *const *mass);
/* dtm_affine_elastic_lanes' matrices of the tet10 in the lanes l with
 * use[l] (their own dj, Ji and moduli m, density included, at index l),
 * scaled by their masses, straight into lane l of A, packed for
 * dtm_eig_sym_max_tridiag_packed (the other lanes are written too, with a
 * used lane's values), and their largest |entry| (NaN if one is not
 * finite) into top[l]: bitwise what dtm_eig_sym_max_tridiag_lanes would
 * pack from those matrices before its division by the largest entry
 * (dtm_packed_divide). 0 (A unusable) where a mass is not positive. */
int dtm_affine_elastic_pack(const int *use, const double *dj, const double (*Ji)[3][3],
                            const dtm_elastic_moduli *const *m, dtm_v4d *A, double *top);
/* The end of the packing: each lane l < count of A divided by s[l] (its
 * largest |entry|), a lane whose s is not positive (or NaN), and every
 * lane from count on, set to +0 (s[l] = 0 there), as
 * dtm_eig_sym_max_tridiag_lanes packs them. */
void dtm_packed_divide(int count, dtm_v4d *A, double *s);
/* The matrices of a straight-sided tri6 or tet10 from the type's
 * reference tensors (affine.c), to 1e-12 of dtm_elem_assemble's: returns
 * 1 with K and mass filled, or 0 (nothing written) for another type, a
 * curved element or one near the validity threshold. */
int dtm_affine_matrices(int type, int d, int nn, const double (*xl)[3], const dtm_elastic_moduli *m, double *K,
                        double *mass);
/* The lumped masses per unit density (m[nn]) and the measure (*vol) of a
 * straight-sided tri6 or tet10 from the reference fractions, as
 * dtm_affine_matrices gives its masses: 1, or 0 (nothing written) where
 * its shortcut does not apply. To 1e-12 of the full rule's sums
 * (dtm_lumped_mass_table), which they replace in measure.c. */
int dtm_affine_lumped(int type, int d, int nn, const double (*xl)[3], double *m, double *vol);
/* For a straight-sided tri6 or tet10 (affine.c's test): 1, with the
 * scaled Jacobian det J / (product of J's column lengths) of its constant
 * Jacobian in *scaled; else 0. */
int dtm_affine_scaled(int type, int d, int nn, const double (*xl)[3], double *scaled);
/* Largest eigenvalue of diag(m)^-1/2 K diag(m)^-1/2 for K[n][n] of an
 * element of the given type, where unknown k belongs to node k / per (per
 * unknowns per node); K destroyed. Jacobi for linear types,
 * tridiagonalization for second-order ones. DTM_ERR_INPUT if a mass is not
 * positive. */
int dtm_lumped_eig_max(int type, int n, int per, double *K, const double *m, double *lambda);

#endif
