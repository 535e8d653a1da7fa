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

#endif
