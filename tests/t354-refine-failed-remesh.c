/* A remesh whose mesh cannot be analysed ends as a failed mesh, not the
 * refine (issue 43 item 7: `refine --posterior` on a STEP part exited 2 with
 * no report and no mesh when one of Gmsh's size-field remeshes came back
 * with 2 flat tetrahedra). Gmsh does not make such a mesh on demand, so the
 * classification of a remesh's outcome (dtm_refine_remesh_failed,
 * src/study/refine.c) is checked on the real error: a Gmsh model holding a
 * flat tetrahedron (four coplanar nodes, zero volume) beside a valid one is
 * analysed as refine analyses each remesh (dtm_analysis_current), which
 * refuses it with DTM_ERR_INPUT naming the element; that outcome of a
 * remesh is a failed mesh (its strategy ends, the refine goes on), as are
 * Gmsh's refusals and crashes; out of memory (DTM_ERR_INTERNAL in the
 * analysis) still ends the refine, and a clean remesh is no failure. (The
 * input's own flat element stays the user's error: `run` refuses it,
 * t314 and t315; refine analyses its input before any remesh.) */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/analysis.h"
#include "dtmap/error.h"
#include "dtmap/scene.h"
#include "study-impl.h"
#include "testutil.h"

static void write_flat(const char *dir) {
  char path[600];
  snprintf(path, sizeof path, "%s/flat.msh", dir);
  tu_write(path, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"block\"\n$EndPhysicalNames\n"
                 "$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 0\n6 0.5 0.5 0\n$EndNodes\n"
                 "$Elements\n2\n1 4 2 1 1 1 2 3 4\n2 4 2 1 1 2 5 3 6\n$EndElements\n");
  snprintf(path, sizeof path, "%s/flat.xml", dir);
  tu_write(path, "<dtmap-scene version=\"1\">\n  <mesh file=\"flat.msh\"/>\n"
                 "  <material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                 "  <effects><elastic/></effects>\n  <time duration=\"1e-4\"/>\n</dtmap-scene>\n");
}

static void flat_remesh_is_a_failed_mesh(void **state) {
  (void)state;
  const char *dir = tu_tmpdir();
  char path[600];
  write_flat(dir);
  snprintf(path, sizeof path, "%s/flat.xml", dir);
  dtm_scene *s = NULL;
  assert_int_equal(dtm_scene_load(path, &s), DTM_OK);
  tu_gmsh_begin();
  int ierr = 0;
  snprintf(path, sizeof path, "%s/flat.msh", dir);
  gmshOpen(path, &ierr);
  assert_int_equal(ierr, 0);
  dtm_analysis *a = NULL;
  int analysed = dtm_analysis_current(s, 3, &a);
  assert_int_equal(analysed, DTM_ERR_INPUT);
  assert_null(a);
  const char *msg = dtm_error_message();
  if (!strstr(msg, "element 2 (tet4)") || !strstr(msg, "cannot be analysed")) fail_msg("message: %s", msg);
  dtm_error_clear();
  tu_gmsh_end();
  dtm_scene_destroy(&s);
  assert_true(dtm_refine_remesh_failed(DTM_OK, analysed));          /* Gmsh's flat elements: a failed mesh */
  assert_true(dtm_refine_remesh_failed(DTM_ERR_INPUT, DTM_OK));     /* Gmsh refused the remesh */
  assert_true(dtm_refine_remesh_failed(DTM_ERR_INTERNAL, DTM_OK));  /* Gmsh crashed in it */
  assert_false(dtm_refine_remesh_failed(DTM_OK, DTM_OK));           /* a clean remesh */
  assert_false(dtm_refine_remesh_failed(DTM_OK, DTM_ERR_INTERNAL)); /* out of memory ends the refine */
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(flat_remesh_is_a_failed_mesh)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
