/* The progress hook behind include/dtmap/progress.h: a stack of open stage
 * names (nesting at most DTM_PROGRESS_DEPTH deep; deeper stages are counted
 * but not reported) and the caller's function, called on every event. */
#include <stdio.h>

#include "dtmap/progress.h"

#define DTM_PROGRESS_DEPTH 8

static dtm_progress_fn hook;
static void *hook_user;
static char names[DTM_PROGRESS_DEPTH][96]; /* open stages, outermost first */
static int depth;                          /* open stages */

void dtm_progress_set(dtm_progress_fn fn, void *user) {
  hook = fn, hook_user = user;
  depth = 0;
}

void dtm_progress_begin(const char *stage) {
  if (depth < DTM_PROGRESS_DEPTH) snprintf(names[depth], sizeof names[depth], "%s", stage ? stage : "");
  if (hook && depth < DTM_PROGRESS_DEPTH) hook(hook_user, DTM_PROGRESS_BEGIN, names[depth], -1, depth);
  depth++;
}

void dtm_progress_update(double fraction) {
  if (hook && depth > 0 && depth <= DTM_PROGRESS_DEPTH)
    hook(hook_user, DTM_PROGRESS_UPDATE, names[depth - 1], fraction, depth - 1);
}

void dtm_progress_end(void) {
  if (depth <= 0) return;
  depth--;
  if (hook && depth < DTM_PROGRESS_DEPTH) hook(hook_user, DTM_PROGRESS_END, names[depth], 1, depth);
}
