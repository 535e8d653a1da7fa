/* The base layer's interface to the rest of libdtmap (internal, hidden):
 * the seeded random generator, carrying the first error out of an OpenMP
 * region, building "'a', 'b', 'c'" lists for messages, why a write failed, and the memory limit of
 * the kill switches. The public part
 * of the base layer is include/dtmap/error.h and include/dtmap/util.h. */
#ifndef DTMAP_BASE_H
#define DTMAP_BASE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "dtmap/error.h"
#include "dtmap/util.h"

/* splitmix64: the next 64 random bits from *state (advanced). */
uint64_t dtm_rng_next(uint64_t *state);
/* Uniform in [lo, hi) with 53 random bits: lo + (hi - lo) (bits >> 11) 2^-53. */
double dtm_rng_uniform(uint64_t *state, double lo, double hi);
/* Uniform in [lo, hi) for one key of a seeded field, independent of any
 * other draw (order-free: the same key always gives the same value). */
double dtm_rng_uniform_at(uint64_t seed, uint64_t key, double lo, double hi);
/* A standard normal value of key (Box-Muller), drawn like dtm_rng_uniform_at. */
double dtm_rng_normal_at(uint64_t seed, uint64_t key);

/* The first error raised inside an OpenMP parallel region. The error record
 * is thread-local, so a worker's message would otherwise be lost (and stay
 * pending on that thread). */
typedef struct {
  int code;       /* DTM_OK until an error is kept */
  char msg[2048]; /* its message */
} dtm_par_error;

/* In a worker: keep code r and this thread's pending message if nothing is
 * kept yet, then clear this thread's record. Thread-safe. */
void dtm_par_error_keep(dtm_par_error *pe, int r);
/* After the region, on the caller's thread: raise the kept error there
 * (returns its code), or DTM_OK when none was kept. */
int dtm_par_error_raise(const dtm_par_error *pe);

/* Append item to the list in buf, quoted as 'item' when quote is set, after
 * ", " when buf is not empty; truncates silently at len. */
void dtm_strlist_add(char *buf, size_t len, const char *item, int quote);

/* Why writes to f failed (f's error flag is set): the errno of flushing it
 * again, else of writing 64 KiB more; DTM_WRITE_CAUSE_UNKNOWN when both
 * succeed now (src/base/atomic.c). */
#define DTM_WRITE_CAUSE_UNKNOWN (-1)
int dtm_write_errno(FILE *f);
/* The reason for a message, into buf: strerror(e), with the size limit
 * behind EFBIG (ulimit -f); returns buf. */
const char *dtm_write_reason(int e, char *buf, size_t len);

/* Bytes this process may use at most: the smallest of the machine's
 * physical memory, the cgroup limit and the rlimits (memory.c). */
double dtm_memory_limit(void);
/* bytes as "1.5 GB" (powers of 1000) in buf; returns buf. */
const char *dtm_bytes_text(double bytes, char *buf, size_t len);

#endif
