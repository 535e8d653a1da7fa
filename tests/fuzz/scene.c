/* libFuzzer target for the scene reader: the input bytes are a scene file,
 * read from memory with dtm_scene_load_memory. Loading must either succeed
 * with a scene that keeps the reader's promises (one source, materials with
 * admissible properties, at least one effect, options in range) or fail
 * with DTM_ERR_INPUT and a message that starts with the scene's name; any
 * other outcome, a crash, a leak or a sanitizer report is a finding. The
 * scene is named <dir>/fuzz.xml, where dir is a private directory holding
 * empty files with the names the corpus uses (disc.geo, m.msh, ...), so
 * inputs get past the existence check of <geometry> and <mesh>. The same
 * code runs under `scripts/fuzz.sh` (built with -fsanitize=fuzzer) and in
 * ctest, where tests/fuzz/replay.c feeds it the corpus in
 * tests/data/fuzz/scene/. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/registry.h"
#include "dtmap/scene.h"

static char scene_name[256]; /* <dir>/fuzz.xml */

static const char *const present[] = {"disc.geo",
                                      "box.geo",
                                      "brazilian_disc.geo",
                                      "notched_beam.geo",
                                      "plate_with_hole.geo",
                                      "x.geo",
                                      "a.geo",
                                      "x.step",
                                      "x.stp",
                                      "x.brep",
                                      "m.msh",
                                      "x.msh",
                                      "a.msh"};

static char dir[64]; /* the private directory */

static void remove_dir(void) {
  for (size_t i = 0; i < sizeof present / sizeof *present; i++) {
    char path[300];
    snprintf(path, sizeof path, "%s/%s", dir, present[i]);
    unlink(path);
  }
  rmdir(dir);
}

static void make_dir(void) {
  snprintf(dir, sizeof dir, "/tmp/dtm-fuzz-scene-XXXXXX");
  if (!mkdtemp(dir)) abort();
  atexit(remove_dir);
  for (size_t i = 0; i < sizeof present / sizeof *present; i++) {
    char path[300];
    snprintf(path, sizeof path, "%s/%s", dir, present[i]);
    FILE *f = fopen(path, "w");
    if (!f) abort();
    fclose(f);
  }
  snprintf(scene_name, sizeof scene_name, "%s/fuzz.xml", dir);
}

/* Abort with a note: libFuzzer saves the input as a crash. */
static void broken(const char *what) {
  fprintf(stderr, "scene fuzz: broken promise: %s (message: %s)\n", what, dtm_error_message());
  abort();
}

/* Every property a material gives is finite and, when a built-in effect
 * declares it, within the declared range. */
static void check_material(const dtm_scene *s, const dtm_scene_material *sm) {
  const dtm_material *m = &sm->m;
  if (!m->name || !m->name[0] || m->line <= 0) broken("a material without name or line");
  if (m->nprops != s->nprops) broken("a material outside the scene's property catalogue");
  for (int i = 0; i < m->nprops; i++) {
    if (!dtm_material_has(m, i)) continue;
    const dtm_property *p = dtm_registry_property(m->prop_names[i], NULL);
    if (!isfinite(m->prop[i]) || (p && dtm_property_check(p, m, m->prop[i]) != DTM_OK))
      broken("an inadmissible property");
  }
  for (int g = 0; g < sm->ngroups; g++)
    if (!sm->groups[g] || !sm->groups[g][0]) broken("an empty group reference");
}

static void check_scene(const dtm_scene *s) {
  if (!s) broken("success without a scene");
  if (!s->geometry == !s->mesh) broken("not exactly one source");
  if (s->nmaterials < 1 || s->neffects < 1) broken("no material or no effect");
  int defaults = 0;
  for (int i = 0; i < s->nmaterials; i++) {
    check_material(s, &s->materials[i]);
    defaults += s->materials[i].is_default;
    for (int j = 0; j < i; j++)
      if (!strcmp(s->materials[i].m.name, s->materials[j].m.name)) broken("two materials with one name");
  }
  if (defaults > 1) broken("two default materials");
  for (int i = 0; i < s->neffects; i++)
    if (!s->effects[i].name || s->effects[i].line <= 0) broken("an effect without name or line");
  if (!(s->safety > 0 && s->safety <= 1)) broken("safety outside (0, 1]");
  if (!(s->target >= 0 && s->duration >= 0 && s->mesh_size >= 0 && s->mesh_min_size >= 0) || !isfinite(s->target) ||
      !isfinite(s->duration) || !isfinite(s->mesh_size) || !isfinite(s->mesh_min_size))
    broken("a negative or infinite option");
  if (s->mesh_order < 1 || s->mesh_order > 2 || s->mesh_dim < 0 || s->mesh_dim > 3) broken("order or dim outside");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (!scene_name[0]) make_dir();
  dtm_scene *s = NULL;
  dtm_error_clear();
  int r = dtm_scene_load_memory((const char *)data, size, scene_name, &s);
  if (r == DTM_OK) check_scene(s);
  if (r != DTM_OK && r != DTM_ERR_INPUT) broken("a code other than 0 or 2");
  if (r != DTM_OK && (s || strncmp(dtm_error_message(), scene_name, strlen(scene_name))))
    broken("an error that does not start with the scene's name");
  dtm_scene_destroy(&s);
  dtm_error_clear();
  return 0;
}
