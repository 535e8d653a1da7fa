"""The global estimate where the top of the spectrum is clustered: a refined
demos/boolean/fillet3.geo mesh carrying 0.229 % point masses from refine's
mass round (tests/data/mass/fillet3_point_masses.msh, its NodeData view
'added mass at nodes'; steel, 3D, 201 nodes, 484 tet4). The masses equalise
the limiting modes: its top two eigenvalues are 7.7e-4 apart, and plain
Lanczos converged on the second (1.067038e-05 s against the exact
1.066652e-05 s). The exact step comes from an independent assembly
(tests/reference/mass_ref.py: numpy/scipy, no dtmap code). dtmap's global
step (run --posterior, at the default tolerance and at 1e-6, where plain
Lanczos was still above it) must not exceed it, beyond 1e-10 relative (the
two assemblies' rounding, far below the 3.6e-4 of the defect), and stay
within 1e-4 of it; its report must say the bound was proven. verify
--posterior checks the step run --posterior reports, which must then be
at most the safety factor times the exact step."""

import json
import os
import shutil
import subprocess
import sys
import unittest

import testutil as tu

MESH = os.path.join(tu.SRC, "tests", "data", "mass", "fillet3_point_masses.msh")
REF = os.path.join(tu.SRC, "tests", "reference", "mass_ref.py")
SAFETY = 0.9
ROUNDING = 1e-10


class Clustered(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.copy(MESH, tu.path("fillet3.msh"))
        tu.write("fillet3.xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<mesh file="fillet3.msh"/>
<material name="steel" E="210e9" nu="0.3" rho="7850" default="true"/>
<effects><elastic formulation="3d"/></effects>
<time safety="%g"/>
</dtmap-scene>
""" % SAFETY)
        out = subprocess.run([sys.executable, REF, tu.path("fillet3.msh"), "210e9", "0.3", "7850", "3d"],
                             stdout=subprocess.PIPE, universal_newlines=True, env=tu.plain_env(), check=True).stdout
        cls.ref = json.loads(out)

    def posterior(self, *extra):
        code, log = tu.run("run", "fillet3.xml", "-q", "-o", "out.msh", "--report", "out.json", "--posterior", *extra)
        self.assertEqual(code, 0, log)
        rep = tu.report("out.json")
        return rep["dt"]["global"], rep["effect_minima"][0]["lanczos"]

    def test_reference(self):
        self.assertAlmostEqual(self.ref["exact_step"], 1.066652e-05, delta=1e-11)  # the case's own figure
        self.assertGreater(self.ref["point_mass"], 0)

    def test_global_at_most_exact(self):
        for extra in ([], ["--tol", "1e-6"]):
            g, lz = self.posterior(*extra)
            exact = self.ref["exact_step"]
            self.assertLessEqual(g, exact * (1 + ROUNDING), "%s: global %.9e s, exact %.9e s" % (extra, g, exact))
            self.assertGreaterEqual(g, exact * (1 - 1e-4), extra)
            self.assertTrue(lz["converged"])
            self.assertEqual(lz.get("certificate"), "proven")

    def test_verify_checks_that_step(self):
        code, log = tu.run("verify", "fillet3.xml", "-q", "--posterior", "--report", "verify.json")
        self.assertEqual(code, 0, log)
        rep = tu.report("verify.json")
        self.assertEqual(rep["basis"], "global estimate")
        self.assertLessEqual(rep["step"], SAFETY * self.ref["exact_step"] * (1 + ROUNDING))
        self.assertEqual(rep["verdict"], "stable")


if __name__ == "__main__":
    tu.main()
