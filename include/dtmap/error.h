/* dtmap error handling: every function returns an int code; DTM_ERR records
 * the code with a formatted message and the file, line and function where it
 * was raised, and DTM_CHECK propagates a failed call while adding a traceback
 * line. Messages about user input name the input file and line, or the Gmsh
 * element tag and physical group, in the message itself. */
#ifndef DTMAP_ERROR_H
#define DTMAP_ERROR_H

#include "dtmap/export.h"

/* Return codes; they double as the CLI's exit codes. */
enum {
  DTM_OK = 0,          /* success */
  DTM_ERR_TARGET = 1,  /* a target or a verification was not met */
  DTM_ERR_INPUT = 2,   /* bad input or usage */
  DTM_ERR_INTERNAL = 3 /* a bug or a failed library call */
};

/* Record an error; returns code so it can be used as `return DTM_ERR(...)`.
 * The first error raised since the last dtm_error_clear() keeps its message;
 * later calls on the way up only add traceback lines. */
DTM_EXPORT int dtm_error_raise(int code, const char *file, int line, const char *func, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
/* Add one traceback line (file:line func) and return code unchanged. */
DTM_EXPORT int dtm_error_trace(int code, const char *file, int line, const char *func);
/* The message of the pending error ("" if none). Owned by the library. */
DTM_EXPORT const char *dtm_error_message(void);
/* The traceback, one "file:line in func" per line. Owned by the library. */
DTM_EXPORT const char *dtm_error_traceback(void);
/* The code of the pending error (DTM_OK if none). */
DTM_EXPORT int dtm_error_code(void);
DTM_EXPORT void dtm_error_clear(void);

/* Comma form (as libCEED's CeedError): the expression's value is `code`
 * itself, so static analysers follow the error path. code is evaluated
 * twice: pass a constant or a variable. */
#define DTM_ERR(code, ...) (dtm_error_raise((code), __FILE__, __LINE__, __func__, __VA_ARGS__), (code))
#define DTM_CHECK(call)                                                                                                \
  do {                                                                                                                 \
    int dtm_ierr_ = (call);                                                                                            \
    if (dtm_ierr_) return dtm_error_trace(dtm_ierr_, __FILE__, __LINE__, __func__);                                    \
  } while (0)

#endif
