/* --verified and --calibrate of run, sweep and refine: close the loop with
 * `dtmap verify --accuracy`. Each report given (V.json, comma-separated)
 * holds a wave's measured and predicted phase-speed errors; the command
 * says whether the measurement agrees with the prediction (within the 20 %
 * band verify judges by) and gives the measures the ratio measured /
 * predicted of each branch (the mean over its reports), which they name in
 * their note and, with --calibrate, multiply their errors of that branch
 * by (dtm_scene.phase_ratio, src/cost/accuracy.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/output.h"

/* One report's line on the terminal. */
static void print_check(const char *path, const dtm_wave_check *c, double ratio, int calibrate) {
  printf("verified     %s: %s along (%.3g, %.3g, %.3g) at %.4g Hz: measured %+.4g %%, predicted %+.4g %%: %s\n", path,
         c->mode ? "S" : "P", c->dir[0], c->dir[1], c->dir[2], c->f, 100 * c->measured, 100 * c->predicted,
         fabs(ratio - 1) <= 0.2 ? "agrees" : "DISAGREES");
  if (fabs(ratio - 1) > 0.2 || calibrate)
    printf("             the measures %s the measured %s error (%.3g x the prediction)\n",
           calibrate ? "use" : "keep the prediction; --calibrate uses", c->mode ? "S" : "P", ratio);
}

int dtm_cli_verified(dtm_scene *s, const cli_opts *o) {
  if (o->calibrate && !o->verified) return DTM_ERR(DTM_ERR_INPUT, "--calibrate needs --verified V.json");
  double sum[2] = {0, 0};
  int n[2] = {0, 0};
  char list[4096];
  snprintf(list, sizeof list, "%s", o->verified ? o->verified : "");
  for (char *save = NULL, *path = strtok_r(list, ",", &save); path; path = strtok_r(NULL, ",", &save)) {
    dtm_wave_check c;
    DTM_CHECK(dtm_verify_wave_report_read(path, &c));
    if (!(c.predicted != 0)) return DTM_ERR(DTM_ERR_INPUT, "%s: the predicted error is zero: no ratio", path);
    double ratio = c.measured / c.predicted;
    if (o->verbosity) print_check(path, &c, ratio, o->calibrate);
    sum[c.mode] += ratio, n[c.mode]++;
  }
  for (int b = 0; b < 2; b++) s->phase_ratio[b] = n[b] ? sum[b] / n[b] : 0;
  s->phase_calibrate = o->calibrate;
  return DTM_OK;
}
