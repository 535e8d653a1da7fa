/* The error record behind DTM_ERR and DTM_CHECK: one pending message (the
 * first raised) plus a traceback that grows as the error propagates. The
 * record is thread-local so OpenMP loops cannot garble it. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "dtmap/error.h"

#define DTM_MSG_MAX 8192 /* room for a list of 20 elements with their places */
#define DTM_TRACE_MAX 4096

static _Thread_local int err_code;
static _Thread_local char err_msg[DTM_MSG_MAX];
static _Thread_local char err_trace[DTM_TRACE_MAX];

static void trace_append(const char *file, int line, const char *func) {
  size_t used = strlen(err_trace);
  if (used + 1 >= sizeof err_trace) return;
  snprintf(err_trace + used, sizeof err_trace - used, "%s:%d in %s\n", file, line, func);
}

int dtm_error_raise(int code, const char *file, int line, const char *func, const char *fmt, ...) {
  if (err_code == DTM_OK) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err_msg, sizeof err_msg, fmt, ap);
    va_end(ap);
    err_code = code;
    err_trace[0] = '\0';
  }
  trace_append(file, line, func);
  return code;
}

int dtm_error_trace(int code, const char *file, int line, const char *func) {
  trace_append(file, line, func);
  return code;
}

const char *dtm_error_message(void) { return err_msg; }
const char *dtm_error_traceback(void) { return err_trace; }
int dtm_error_code(void) { return err_code; }

void dtm_error_clear(void) {
  err_code = DTM_OK;
  err_msg[0] = '\0';
  err_trace[0] = '\0';
}
