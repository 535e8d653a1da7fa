/* CHOLMOD, loaded when first needed instead of at every start: the library
 * and what it pulls in (BLAS, LAPACK, the Fortran runtime) took 21 ms of
 * dynamic linking from every dtmap command (dtmap --version: 125 ms
 * against 103 ms; about 4 % of a run on a 1e5-element mesh), while only
 * the certificate and --modes factorise. cholmod.h still gives the types
 * and prototypes; every call of the functions below goes through the table
 * dtm_cholmod_load fills, by the macros at the end of this header (so the
 * callers read as plain CHOLMOD code). Include this header instead of
 * cholmod.h. */
#ifndef DTM_SPECTRAL_CHOLMOD_DL_H
#define DTM_SPECTRAL_CHOLMOD_DL_H

#include <cholmod.h>

#define DTM_CHOLMOD_FUNCTIONS(X)                                                                                       \
  X(cholmod_l_add)                                                                                                     \
  X(cholmod_l_allocate_sparse)                                                                                         \
  X(cholmod_l_allocate_triplet)                                                                                        \
  X(cholmod_l_analyze)                                                                                                 \
  X(cholmod_l_analyze_p)                                                                                               \
  X(cholmod_l_factorize)                                                                                               \
  X(cholmod_l_factorize_p)                                                                                             \
  X(cholmod_l_finish)                                                                                                  \
  X(cholmod_l_free_dense)                                                                                              \
  X(cholmod_l_free_factor)                                                                                             \
  X(cholmod_l_free_sparse)                                                                                             \
  X(cholmod_l_free_triplet)                                                                                            \
  X(cholmod_l_solve)                                                                                                   \
  X(cholmod_l_sort)                                                                                                    \
  X(cholmod_l_start)                                                                                                   \
  X(cholmod_l_triplet_to_sparse)                                                                                       \
  X(cholmod_l_zeros)

#define DTM_CHOLMOD_POINTER(f) __typeof__(f) *f;
typedef struct {
  DTM_CHOLMOD_FUNCTIONS(DTM_CHOLMOD_POINTER)
} dtm_cholmod_table;
#undef DTM_CHOLMOD_POINTER

/* The table, filled by dtm_cholmod_load (thread-safe, once). */
extern dtm_cholmod_table dtm_cholmod_fns;

/* Load CHOLMOD (DTM_CHOLMOD_SONAME, the library the build found): DTM_OK,
 * or DTM_ERR_INTERNAL naming the library and the loader's reason. Call it
 * before the first CHOLMOD call of an entry point. */
int dtm_cholmod_load(void);

#ifndef DTM_CHOLMOD_DL_IMPL
#define cholmod_l_add dtm_cholmod_fns.cholmod_l_add
#define cholmod_l_allocate_sparse dtm_cholmod_fns.cholmod_l_allocate_sparse
#define cholmod_l_allocate_triplet dtm_cholmod_fns.cholmod_l_allocate_triplet
#define cholmod_l_analyze dtm_cholmod_fns.cholmod_l_analyze
#define cholmod_l_analyze_p dtm_cholmod_fns.cholmod_l_analyze_p
#define cholmod_l_factorize dtm_cholmod_fns.cholmod_l_factorize
#define cholmod_l_factorize_p dtm_cholmod_fns.cholmod_l_factorize_p
#define cholmod_l_finish dtm_cholmod_fns.cholmod_l_finish
#define cholmod_l_free_dense dtm_cholmod_fns.cholmod_l_free_dense
#define cholmod_l_free_factor dtm_cholmod_fns.cholmod_l_free_factor
#define cholmod_l_free_sparse dtm_cholmod_fns.cholmod_l_free_sparse
#define cholmod_l_free_triplet dtm_cholmod_fns.cholmod_l_free_triplet
#define cholmod_l_solve dtm_cholmod_fns.cholmod_l_solve
#define cholmod_l_sort dtm_cholmod_fns.cholmod_l_sort
#define cholmod_l_start dtm_cholmod_fns.cholmod_l_start
#define cholmod_l_triplet_to_sparse dtm_cholmod_fns.cholmod_l_triplet_to_sparse
#define cholmod_l_zeros dtm_cholmod_fns.cholmod_l_zeros
#endif

#endif
