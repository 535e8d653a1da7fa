/* Private to the operator (src/spectral/operator.c, structural.c): the
 * stored shell and beam elements of a global operator and their rotation
 * unknowns, appended after the nodes' translations. */
#ifndef DTMAP_SPECTRAL_STRUCTURAL_IMPL_H
#define DTMAP_SPECTRAL_STRUCTURAL_IMPL_H

#include <stddef.h>

#include "dtmap/mesh.h"
#include "dtmap/problem.h"
#include "dtmap/section.h"

typedef struct {
  size_t n;                              /* shell and beam elements */
  int *ndof;                             /* [n] 6 nn */
  size_t *idx;                           /* [n][DTM_STRUCT_DOF] the global dof of each element unknown */
  double *K;                             /* stiffness in global axes: of element i the rows of its upper
                                            triangle, (6 nn)(6 nn + 1)/2 numbers from koff[i] */
  size_t *koff;                          /* [n] where element i's stiffness starts in K */
  double *m;                             /* [n][DTM_STRUCT_DOF] lumped masses (diagonal in any frame) */
  int *slot;                             /* [n] coefficient slot */
  size_t base;                           /* first rotation dof: nnodes * 3 */
  size_t nrot;                           /* nodes with rotations */
  size_t *rot_of;                        /* [nnodes] rank of each node's rotations, SIZE_MAX for none */
  size_t *rot_node;                      /* [nrot] node of each rank */
  double *fe;                            /* [n][DTM_STRUCT_DOF] element forces of a product (work, owned) */
  const dtm_section_bounds *const *kept; /* [nblocks][n] an analysis's kept bounds (setup only), or NULL */
} dtm_op_struct;

/* Whether slot coefficients c are a shell or beam section's (elastic). */
int dtm_op_struct_is(const dtm_operator_coeffs *c);
/* Collect the structural elements of m (coefficients c per slot, nmat the
 * mesh's materials: slot = mat + nmat (section + 1)); s->n = 0 when none.
 * A shell's rotary scale comes from kept (dtm_operator_create_kept) when
 * it holds one. DTM_ERR_INPUT names the element for a bad one. */
int dtm_op_struct_setup(dtm_op_struct *s, const dtm_mesh *m, const dtm_operator_coeffs *c, int nmat,
                        const dtm_section_bounds *const *kept);
/* mass[k] += the elements' lumped masses; mass_alpha (or NULL) += alpha times them. */
void dtm_op_struct_masses(const dtm_op_struct *s, const double *alpha_of_slot, double *mass, double *mass_alpha);
/* y += sum_e f_e K_e u over the elements, f_e = beta_of_slot[slot] (NULL:
 * 1): the element products in parallel, the scatter serial, in element
 * order (the same sum whatever the threads). */
void dtm_op_struct_apply(const dtm_op_struct *s, const double *u, const double *beta_of_slot, double *y);
void dtm_op_struct_free(dtm_op_struct *s);

#endif
