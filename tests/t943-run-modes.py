"""`dtmap run --modes N [--target DT]` on a real Gmsh mesh: a free steel
plate 0.1 x 0.05 x 0.005 m of linear tetrahedra.

Checks and tolerances:
- the report's modes object: 6 rigid modes counted, N elastic frequencies,
  converged, each within 1e-8 relative of the independent reference
  (tests/reference/modes_ref.py: numpy assembly of the mesh the run wrote,
  scipy's eigh; the reasons for 1e-8 are t942's: Lanczos's test, the
  shift's conditioning, the .msh's 16 digits);
- --target above the recommended step: the conventional variant added point
  masses (kg > 0, at some nodes), and by Courant-Fischer each of its
  eigenvalues lies at or below the model's of the same index (added
  positive semi-definite mass can only lower them), allowing 1e-9 relative
  for the two eigen-solves; every matched shift is then <= 1e-7 %, and the
  MAC of a match at least 0.8;
- the analysis is put back after the search: dt.recommended and the
  smallest element step are the same doubles with and without --modes
  --target;
- a target the model already meets adds no mass and shifts every mode by
  at most 1e-9 % (the same pencil factored twice);
- the summary names the rigid modes and prints one column per variant.
"""

import math
import os
import sys
import unittest

import gmsh

import testutil as tu

sys.path.insert(0, os.path.join(tu.SRC, "tests", "reference"))
from modes_ref import Reference, elastic  # noqa: E402

E, NU, RHO = 210e9, 0.3, 7850.0
N = 8

GEO = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.05, 0.005};
Physical Volume("block") = {1};
Mesh.MeshSizeMax = 0.008;
"""


def run(*extra, quiet=True):
    name = "p%d" % run.count
    run.count += 1
    code, out = tu.run("run", "plate.xml", *(("-q",) if quiet else ()), "-o", name + ".msh", "--report",
                       name + ".json", *extra)
    assert code == 0, out
    return tu.report(name + ".json"), out, tu.path(name + ".msh")


run.count = 0


class RunModes(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        tu.write("plate.geo", GEO)
        tu.elastic_scene("plate", "plate.geo", 3)
        cls.plain, _, _ = run()
        cls.rep, _, msh = run("--modes", str(N))
        gmsh.initialize(["t943", "-v", "0"])
        try:
            gmsh.open(msh)
            cls.ref = Reference(E, NU, RHO)
        finally:
            gmsh.finalize()

    def test_frequencies(self):
        m = self.rep["modes"]
        self.assertEqual((m["rigid"], m["asked"], len(m["frequencies"])), (6, N, N))
        self.assertTrue(m["converged"])
        self.assertEqual(m["variants"], [])
        want = elastic(self.ref.eig()[0])[0][:N]
        for i, f in enumerate(m["frequencies"]):
            lam = (2 * math.pi * f) ** 2
            self.assertLessEqual(abs(lam - want[i]) / want[i], 1e-8, "mode %d: %.10g Hz" % (i + 1, f))
            self.assertLessEqual(m["residuals"][i], 1e-6)

    def test_conventional(self):
        target = 1.5 * self.plain["dt"]["recommended"]
        rep, out, _ = run("--modes", str(N), "--target", "%.9e" % target, quiet=False)
        for key in ("recommended", "min"):
            self.assertEqual(rep["dt"][key], self.plain["dt"][key], "the analysis put back: dt." + key)
        m = rep["modes"]
        self.assertEqual(m["target"], float("%.9e" % target))
        v = m["variants"][0]
        self.assertEqual(v["name"], "conventional mass")
        self.assertTrue(v["computed"])
        self.assertGreater(v["added_mass"], 0)
        self.assertGreater(v["nodes"], 0)
        self.assertEqual(v["rigid"], 6)
        for i in range(N):
            self.assertLessEqual(v["frequencies"][i], m["frequencies"][i] * (1 + 1e-9), "Courant-Fischer, mode %d" % i)
            if v["match"][i] is not None:
                self.assertGreaterEqual(v["mac"][i], 0.8)
                self.assertLessEqual(v["shifts"][i], 1e-7)
        self.assertIn("6 rigid-body mode(s)", out)
        self.assertIn("conventional mass", out)
        print("target %.4e s: %.4g kg at %d nodes (%.3g %%), shifts %s %%" % (
            target, v["added_mass"], v["nodes"], v["added_percent"],
            ", ".join("%.3f" % s if s is not None else "none" for s in v["shifts"])))

    def test_target_met(self):
        rep, _, _ = run("--modes", "3", "--target", "%.9e" % (0.5 * self.plain["dt"]["recommended"]))
        v = rep["modes"]["variants"][0]
        self.assertTrue(v["computed"])
        self.assertEqual((v["added_mass"], v["nodes"]), (0, 0))
        self.assertEqual(v["match"], [1, 2, 3])
        for s in v["shifts"]:
            self.assertLessEqual(abs(s), 1e-9)


if __name__ == "__main__":
    tu.main()
