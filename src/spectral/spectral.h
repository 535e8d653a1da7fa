/* The spectral module's interface to the rest of libdtmap and its
 * white-box tests (internal, hidden): the node count up to which the
 * operator keeps its connectivity in 32 bits (UINT32_MAX; a test lowers it
 * to exercise the 64-bit loops on a small mesh). */
#ifndef DTMAP_SPECTRAL_H
#define DTMAP_SPECTRAL_H

#include <stddef.h>

extern size_t dtm_operator_narrow_max;

#endif
