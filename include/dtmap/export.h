/* Symbol visibility of libdtmap: the library is built with hidden
 * visibility, so only declarations marked DTM_EXPORT (the public API in
 * include/dtmap/) are exported from the shared object; everything else,
 * module interfaces included, stays internal. */
#ifndef DTMAP_EXPORT_H
#define DTMAP_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define DTM_EXPORT __attribute__((visibility("default")))
#else
#define DTM_EXPORT
#endif

#endif
