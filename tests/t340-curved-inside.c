/* An element inverted between its sampling points, end to end through the
 * CLI: a tet10 (tag 7, group "part") whose det J is positive at its nodes
 * and at the 14 points of its rule but negative inside (the element of
 * t116) is refused with exit 2, naming its tag, group and centroid and
 * the Bezier bound, and nothing is written; the same tet with its
 * mid-edge nodes moved only a little (curved, valid) is analysed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* One tet10; node 5 (edge 0-1) at (a, b, c), node 7 (edge 2-0) at (0, e, f). */
static void write_mesh(const char *path, const double *n5, const double *n7) {
  char text[2048];
  snprintf(text, sizeof text,
           "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"part\"\n$EndPhysicalNames\n"
           "$Nodes\n10\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 %.17g %.17g %.17g\n6 0.5 0.5 0\n"
           "7 %.17g %.17g %.17g\n8 0 0 0.5\n9 0 0.5 0.5\n10 0.5 0 0.5\n$EndNodes\n"
           "$Elements\n1\n7 11 2 1 1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n",
           n5[0], n5[1], n5[2], n7[0], n7[1], n7[2]);
  tu_write(path, text);
}

static int run(const double *n5, const double *n7, char **log, char *out) {
  char msh[512], scene[512];
  snprintf(msh, sizeof msh, "%s/curved.msh", tu_tmpdir());
  snprintf(scene, sizeof scene, "%s/curved.xml", tu_tmpdir());
  snprintf(out, 512, "%s/curved-out.msh", tu_tmpdir());
  write_mesh(msh, n5, n7);
  tu_write(scene, "<dtmap-scene version=\"1\">\n  <mesh file=\"curved.msh\"/>\n"
                  "  <material name=\"steel\" groups=\"part\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                  "  <effects><elastic/></effects>\n</dtmap-scene>\n");
  remove(out);
  return tu_run(log, "%s run %s -q -o %s", tu_cli(), scene, out);
}

static void test_refused(void **state) {
  (void)state;
  const double n5[3] = {0.27, 0.13, 0.17}, n7[3] = {0, 0.28, -0.1};
  char *log = NULL, out[512];
  assert_int_equal(run(n5, n7, &log, out), 2);
  if (!strstr(log, "element 7 (tet10) in group 'part' at (") || !strstr(log, "inverted inside") ||
      !strstr(log, "curved.msh: 1 element cannot be analysed"))
    fail_msg("unexpected message:\n%s", log);
  assert_false(tu_exists(out));
  free(log);
}

static void test_mildly_curved_analysed(void **state) {
  (void)state;
  const double n5[3] = {0.5, 0.04, -0.03}, n7[3] = {0.02, 0.5, -0.04};
  char *log = NULL, out[512];
  int code = run(n5, n7, &log, out);
  if (code) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, 0);
  assert_true(tu_exists(out));
  free(log);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_refused),
      cmocka_unit_test(test_mildly_curved_analysed),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
