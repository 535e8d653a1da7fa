/* libFuzzer target for the .msh path: the input bytes are written as a
 * .msh file and a fixed scene (one default material, the elastic effect)
 * is run on it through everything a `dtmap run` does before writing:
 * dtmap's header scan and kill switches, Gmsh's reader (with its logged
 * errors caught), extraction, the mesh check (shapes, flagged elements),
 * the element kernels, the nodal bound and the recommendation. The run
 * must succeed with a finite, positive recommended step, or fail with
 * DTM_ERR_INPUT and a message; anything else (another code, a crash, a
 * sanitizer report in dtmap's code) is a finding. Gmsh itself is not
 * instrumented, so coverage guides only dtmap's side; Gmsh's own leaks are
 * suppressed (tests/lsan.supp). Replayed in ctest by tests/fuzz/replay.c
 * over tests/data/fuzz/msh/. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/analysis.h"
#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/scene.h"

static char dir[64];     /* private directory */
static char msh[128];    /* dir/m.msh */
static dtm_scene *scene; /* the fixed scene, loaded once */

static const char scene_text[] = "<dtmap-scene version=\"1\">\n"
                                 "  <mesh file=\"m.msh\"/>\n"
                                 "  <material name=\"rock\" default=\"true\" E=\"1e9\" nu=\"0.3\" rho=\"2000\"/>\n"
                                 "  <effects><elastic/></effects>\n"
                                 "</dtmap-scene>\n";

static void cleanup(void) {
  dtm_scene_destroy(&scene);
  dtm_gmsh_stop();
  unlink(msh);
  rmdir(dir);
}

static void setup(void) {
  char name[160];
  snprintf(dir, sizeof dir, "/tmp/dtm-fuzz-msh-XXXXXX");
  if (!mkdtemp(dir)) abort();
  snprintf(msh, sizeof msh, "%s/m.msh", dir);
  FILE *f = fopen(msh, "w");
  if (!f) abort();
  fclose(f);
  snprintf(name, sizeof name, "%s/fuzz.xml", dir);
  if (dtm_scene_load_memory(scene_text, sizeof scene_text - 1, name, &scene)) abort();
  if (dtm_gmsh_start(0)) abort();
  atexit(cleanup);
}

static void broken(const char *what) {
  fprintf(stderr, "msh fuzz: broken promise: %s (message: %s)\n", what, dtm_error_message());
  abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (!scene) setup();
  FILE *f = fopen(msh, "wb");
  if (!f || fwrite(data, 1, size, f) != size || fclose(f)) abort();
  dtm_analysis *a = NULL;
  dtm_error_clear();
  int r = dtm_analysis_run(scene, &a);
  if (r == DTM_OK) {
    double dt = dtm_analysis_recommended(a);
    if (!(dt > 0) || !isfinite(dt)) broken("a recommended step that is not finite and positive");
  } else if (r != DTM_ERR_INPUT || !dtm_error_message()[0]) {
    broken("a code other than 0 or 2, or no message");
  }
  dtm_analysis_destroy(&a);
  dtm_error_clear();
  return 0;
}
