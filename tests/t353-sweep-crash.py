"""A Gmsh crash at one size of a sweep fails that size's row only (issue 43
item 7: the crash ended the sweep with exit 3 and every other size's row
lost). `dtmap sweep` meshes each size in a child process
(src/gmsh/contain.c), so a crash there is that row's reason.

The bundled plate with a hole at three sizes; DTMAP_TEST_GMSH_CRASH =
"meshing#2" makes Gmsh's second meshing job raise a real SIGSEGV (the
test hook of src/gmsh/contain.c). The sweep exits 1 (some size gave no
figures, the others written), its CSV and the table keep all three rows:
the second FAILED with "Gmsh crashed" and the signal, the first and third
with the same element counts and steps as a sweep without the crash (the
contained meshing is the same meshing).
"""

import csv
import os
import subprocess
import unittest

import testutil as tu

SIZES = "0.01,0.005,0.004"


def sweep(name, crash=None):
    env = dict(os.environ)
    env.pop("DTMAP_TEST_GMSH_CRASH", None)
    if crash:
        env["DTMAP_TEST_GMSH_CRASH"] = crash
    scene = os.path.join(tu.SRC, "geometries", "plate_with_hole.xml")
    p = subprocess.run([tu.CLI, "sweep", scene, "--sizes", SIZES, "--csv", name + ".csv", "--plot", name + ".png"],
                       cwd=tu.tmpdir(), env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       universal_newlines=True)
    rows = []
    if os.path.exists(tu.path(name + ".csv")):
        with open(tu.path(name + ".csv")) as f:
            rows = [r for r in csv.DictReader(f)]
    return p.returncode, p.stdout, rows


class SweepCrash(unittest.TestCase):
    def test_crash_at_one_size(self):
        code, out, rows = sweep("plain")
        self.assertEqual(code, 0, out)
        self.assertEqual(len(rows), 3, out)
        code, out, crashed = sweep("crashed", "meshing#2")
        self.assertEqual(code, 1, out)
        self.assertEqual(len(crashed), 3, out)
        self.assertIn("sweep at size 0.005 m: meshing: Gmsh crashed (signal 11", out)
        self.assertIn("1 of 3 sizes FAILED", out)
        failed = crashed[1]
        self.assertEqual(failed["elements"], "", failed)
        self.assertIn("Gmsh crashed (signal 11", failed["failed"])
        for i in (0, 2):
            self.assertEqual(crashed[i]["elements"], rows[i]["elements"], (crashed[i], rows[i]))
            self.assertEqual(crashed[i]["dt_recommended_s"], rows[i]["dt_recommended_s"])
        print(out.splitlines()[-1])


if __name__ == "__main__":
    tu.main()
