/* `dtmap snapshot RESULT.msh` and `dtmap run --png PREFIX`: pictures of a
 * result drawn by Gmsh's renderer (dtm_gmsh_snapshot), under a virtual
 * display when there is none: PREFIX_worst.png shows the views as the .opt
 * leaves them on opening (in 3D the faint model with the below-target
 * elements; the text view with the recommended step), PREFIX_dt.png the dt
 * map alone. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli-impl.h"
#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "dtmap/util.h"

typedef struct {
  const char *msh;          /* the result */
  char worst[DTM_PATH_MAX]; /* PREFIX_worst.png */
  char dt[DTM_PATH_MAX];    /* PREFIX_dt.png */
  int width, height;        /* pixels */
} pictures;

static int draw(void *arg) {
  pictures *p = arg;
  dtm_snapshot_shot shots[2] = {{p->worst, NULL}, {p->dt, "dt"}};
  return dtm_gmsh_snapshot(p->msh, shots, 2, p->width, p->height);
}

int dtm_cli_pictures(const char *msh, const char *prefix, int width, int height, int verbosity) {
  pictures p = {msh, "", "", width, height};
  snprintf(p.worst, sizeof p.worst, "%.4000s_worst.png", prefix);
  snprintf(p.dt, sizeof p.dt, "%.4000s_dt.png", prefix);
  DTM_CHECK(dtm_cli_with_display(draw, &p));
  if (verbosity) printf("wrote        %s, %s (%d x %d)\n", p.worst, p.dt, width, height);
  return DTM_OK;
}

/* The pictures can be written (dtm_output_path_check), before Xvfb starts. */
static int check_pictures(const char *prefix, const char *origin) {
  char path[DTM_PATH_MAX];
  static const char *const suffix[2] = {"_worst.png", "_dt.png"};
  for (int i = 0; i < 2; i++) {
    snprintf(path, sizeof path, "%.4000s%s", prefix, suffix[i]);
    DTM_CHECK(dtm_output_path_check(NULL, path, NULL, origin));
  }
  return DTM_OK;
}

int dtm_cli_snapshot(const cli_opts *o) {
  char prefix[DTM_PATH_MAX];
  size_t n = strlen(o->scene);
  if (n < 5 || strcmp(o->scene + n - 4, ".msh"))
    return dtm_cli_fail(DTM_ERR(DTM_ERR_INPUT, "%s: not a .msh result of dtmap run", o->scene), o->verbosity);
  if (access(o->scene, R_OK)) return dtm_cli_fail(DTM_ERR(DTM_ERR_INPUT, "%s: cannot read it", o->scene), o->verbosity);
  snprintf(prefix, sizeof prefix, "%.*s", (int)(n - 4), o->scene);
  int r = check_pictures(o->png ? o->png : prefix, o->png ? "--png" : "default picture");
  if (r == DTM_OK) r = dtm_cli_pictures(o->scene, o->png ? o->png : prefix, o->width, o->height, o->verbosity);
  return r ? dtm_cli_fail(r, o->verbosity) : 0;
}
