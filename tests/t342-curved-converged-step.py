"""The global step on a curved tet10 mesh holds for the converged
integration (issue 45, item 2), against an independent assembly
(tests/reference/tet10_exact.py: numpy/scipy, its own shape functions,
Gauss-Jacobi collapsed rules, HRZ lumping as dtmap's tet10, eigsh at
tolerance 0).

- Straight tet10 (a box meshed at order 2 with Gmsh's mid-edge nodes put on
  the straight edges): dtmap's full rule and the reference's degree-16 rule
  are both exact there, so every element step agrees to 1e-10 (rounding of
  two 30 x 30 eigenproblems, measured 1e-13) and the global step is at or
  below the exact one. This checks that the reference assembles dtmap's
  model (stiffness and lumped masses).
- Gmsh's demos/simple_geo/cone.geo (gmsh-doc) meshed here with Gmsh's
  Python API as `gmsh cone.geo -3 -order 2 -optimize_ho` does (2,462 tet10,
  4,185 nodes, 12,555 unknowns; its tip elements have a Jacobian ratio of
  0.09). dtmap integrates those elements at rule level 8, where their
  stiffness is still 2e-5 off (relative Frobenius), and before this test its
  global step was 1.0000061x the exact step of the converged integration.
  The reference raises each element's degree from 16 by 8 until its
  matrices change by at most 1e-12; the assembled step from the degrees
  before the last agrees with it to 1e-10 (measured 1e-13). dtmap's global
  step must be at or below the converged exact step with no tolerance: the
  defect was 6.1e-6 and the two assemblies' rounding is about 1e-13 relative,
  far inside the quadrature margin dtmap now takes off (7e-5 of the step
  here); and within 1e-3 of it, so that the margin stays a margin.
Both run through the same .msh files: dtmap and the reference read the mesh
this run wrote.
"""

import json
import os
import shutil
import subprocess
import sys
import unittest

import testutil as tu

REF = os.path.join(tu.SRC, "tests", "reference", "tet10_exact.py")
CONE = "/usr/share/doc/gmsh-doc/doc/gmsh/demos/simple_geo/cone.geo"
E, NU, RHO = 210e9, 0.3, 7850.0


def mesh(name, build):
    """NAME.msh (version 4.1) from build(gmsh), run in the test's folder."""
    import gmsh
    gmsh.initialize(["t342", "-v", "0"])
    try:
        build(gmsh)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(tu.path(name + ".msh"))
    finally:
        gmsh.finalize()


def box(gmsh):
    gmsh.model.add("box")
    gmsh.model.occ.addBox(0, 0, 0, 1, 0.6, 0.4)
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
    gmsh.option.setNumber("Mesh.ElementOrder", 2)
    gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)  # mid-edge nodes on the straight edges
    gmsh.model.mesh.generate(3)


def cone(gmsh):
    gmsh.open(tu.path("cone.geo"))
    gmsh.option.setNumber("Mesh.ElementOrder", 2)  # -order 2
    gmsh.option.setNumber("Mesh.HighOrderOptimize", 2)  # -optimize_ho (the CLI's value: same mesh)
    gmsh.model.mesh.generate(3)


def run(name):
    tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<mesh file="%s.msh"/>
<material name="steel" default="true" E="%g" nu="%g" rho="%g"/>
<effects><elastic formulation="3d"/></effects>
</dtmap-scene>
""" % (name, E, NU, RHO))
    code, log = tu.run("run", name + ".xml", "-q", "--posterior", "-o", name + "_dt.msh", "--report", name + ".json")
    assert code == 0, log
    rep = tu.report(name + ".json")
    return rep, tu.view_values(tu.path(name + "_dt.msh"), "dt")


def reference(name, *args):
    out = subprocess.run([sys.executable, REF, tu.path(name + ".msh"), repr(E), repr(NU), repr(RHO)] + list(args),
                         stdout=subprocess.PIPE, universal_newlines=True, env=tu.plain_env(), check=True).stdout
    return json.loads(out)


class Converged(unittest.TestCase):
    def test_straight_same_model(self):
        mesh("box", box)
        rep, dt = run("box")
        ref = reference("box", "16")["degrees"][0]
        self.assertEqual(rep["curvature"]["curved"], 0)
        worst = max(abs(dt[t] / s - 1) for t, s in ((int(t), s) for t, s in ref["element_steps"].items()))
        self.assertLessEqual(worst, 1e-10)
        g, lz = rep["dt"]["global"], rep["effect_minima"][0]["lanczos"]
        self.assertEqual(lz["quadrature_margin"], 0)
        self.assertLessEqual(g, ref["exact_step"])
        self.assertGreaterEqual(g, ref["exact_step"] * (1 - 1e-4))

    # 119 s under the sanitizers (47 s optimised), most of it the sanitized run --posterior; the curved
    # margin's code runs under them in the straight case here and in t340/t341
    @unittest.skipIf(tu.SANITIZED, "the cone runs in the optimised build")
    def test_cone_below_converged(self):
        self.assertTrue(os.path.exists(CONE), "%s: install gmsh-doc (scripts/setup.sh does)" % CONE)
        shutil.copy(CONE, tu.path("cone.geo"))
        mesh("cone", cone)
        rep, _ = run("cone")
        ref = reference("cone", "converged")
        self.assertEqual((ref["elements"], ref["nodes"]), (2462, 4185))  # the demo as the issue measured it
        self.assertAlmostEqual(ref["previous_step"] / ref["exact_step"], 1, delta=1e-10)
        g, lz = rep["dt"]["global"], rep["effect_minima"][0]["lanczos"]
        self.assertTrue(lz["converged"])
        self.assertGreater(lz["quadrature_margin"], 0)
        exact = ref["exact_step"]
        self.assertLessEqual(g, exact, "global %.12e s, converged exact %.12e s (%.9f)" % (g, exact, g / exact))
        self.assertGreaterEqual(g, exact * (1 - 1e-3))


if __name__ == "__main__":
    tu.main()
