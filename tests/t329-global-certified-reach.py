"""The certificate of the global bound past the hand-written factorisation's
reach (src/spectral/certify.c, CHOLMOD since issue 45; the old one refused
every operator above 30,000 unknowns as "too dear"). The mesh: a Gmsh tet4
mesh of an 8 x 1 x 1 bar (OpenCASCADE box, size 0.12) and, not connected
to it, the same mesh scaled by 1 + 1.5e-4, steel, 3D elasticity: 31,668
unknowns. Scaling a 3D mesh by s divides every eigenvalue of M^-1 K by s^2,
so the top two eigenvalues of the whole are 3e-4 apart relative, the
clustered top Lanczos alone cannot tell apart (tests/t504). A bar orders
into small separators, so its factorisation is cheap (2.8e9 predicted
flops) and within src/analysis/global.c's smallest budget whatever the
machine's speed: the test does not depend on timing.
The exact step comes from an independent assembly
(tests/reference/mass_ref.py: numpy/scipy eigsh, no dtmap code). run
--posterior must say "proven", and its global step must not exceed the
exact step beyond 1e-10 relative (the two assemblies' rounding, far below
the 3e-4 of the cluster) and stay within 1e-4 of it (Lanczos's
tolerance).

The budget's rule (src/analysis/global.c): the factorisation is tried
when CHOLMOD predicts at most max(CERT_FLOOR, CERT_RATE x the run before
it) flops, the run before being the report's timings mesh + extract +
effects + nodal. Two Gmsh tet4 boxes (the unit box of
bench/certify_reach.py) check it: at 22,026 unknowns CHOLMOD predicts
6.9e9 flops, below the floor whatever the machine's speed, so it is
proven (the floor of 4e9 flops before OpenBLAS refused it); at 36,813
unknowns AMD predicts 6.8e10 (METIS 2.1e10), and the summary's allowed
flops must be the rule's, to its 3 printed digits, and the outcome the
comparison's ("too dear" unless the run before took seconds)."""

import json
import os
import re
import subprocess
import sys
import unittest

import gmsh
import numpy as np

import testutil as tu

sys.path.insert(0, os.path.join(tu.SRC, "bench"))
import certify_reach  # noqa: E402  (bench/certify_reach.py: the reach table's boxes)

REF = os.path.join(tu.SRC, "tests", "reference", "mass_ref.py")
SIZE = 0.12
SCALE = 1 + 1.5e-4
ROUNDING = 1e-10
OLD_REACH = 30000  # unknowns: the hand-written factorisation refused every operator above
CERT_RATE = 8e9  # flop/s, src/analysis/global.c
CERT_FLOOR = 8e9  # flops, src/analysis/global.c
OLD_FLOOR = 4e9  # flops: the floor with the reference BLAS under CHOLMOD
PRINTED = 5e-3  # the summary prints flops to 3 significant digits


def two_bars(path):
    """The bar's mesh and its scaled copy 3 m away, as two discrete volumes."""
    gmsh.initialize(["t329", "-v", "0"])
    try:
        gmsh.model.add("bar")
        gmsh.model.occ.addBox(0, 0, 0, 8, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMin", SIZE)
        gmsh.option.setNumber("Mesh.MeshSizeMax", SIZE)
        gmsh.model.mesh.generate(3)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        _, _, conn = gmsh.model.mesh.getElements(3)
        tags, xyz, conn = np.array(tags, dtype=np.int64), np.array(xyz).reshape(-1, 3), np.array(conn[0], np.int64)
        ne, top = len(conn) // 4, int(tags.max())
        gmsh.model.add("two bars")
        for k, s in enumerate((1.0, SCALE)):
            e = gmsh.model.addDiscreteEntity(3)
            x = xyz * s
            x[:, 1] += 3.0 * k
            gmsh.model.mesh.addNodes(3, e, list(tags + k * top), list(x.ravel()))
            gmsh.model.mesh.addElementsByType(e, 4, list(np.arange(1, ne + 1) + k * ne), list(conn + k * top))
        gmsh.write(path)
    finally:
        gmsh.finalize()


def box(name, unknowns):
    """bench/certify_reach.py's Delaunay tet4 unit box with about unknowns / 3 nodes, and its scene."""
    certify_reach.box_mesh(tu.path(name + ".msh"), unknowns)
    tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<mesh file="%s.msh"/>
<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
<effects><elastic formulation="3d"/></effects>
</dtmap-scene>
""" % name)


def budget_run(name):
    """run --posterior of name.xml: (report, summary, the flops the rule allows from the report's timings)."""
    code, log = tu.run("run", name + ".xml", "-o", name + "_out.msh", "--report", name + ".json", "--posterior")
    if code != 0:
        raise AssertionError(log)
    rep = tu.report(name + ".json")
    tm = rep["timings"]
    before = tm["mesh"] + tm["extract"] + tm["effects"] + tm["nodal"]
    return rep, log, max(CERT_FLOOR, CERT_RATE * before)


class Budget(unittest.TestCase):
    def test_proven_between_old_and_new_floor(self):
        box("small", 1.8e4)
        rep, log, allowed = budget_run("small")
        self.assertEqual(3 * rep["mesh"]["nodes"], 22026, "the mesh changed: the predicted flops below do not hold")
        m = re.search(r"factorisation of ([0-9.e+]+) flops", log)
        self.assertIsNotNone(m, log)
        predicted = float(m.group(1))
        self.assertGreater(predicted, OLD_FLOOR, log)
        self.assertLessEqual(predicted, CERT_FLOOR, log)
        self.assertLessEqual(predicted, allowed * (1 + PRINTED), log)
        self.assertEqual(rep["effect_minima"][0]["lanczos"].get("deterministic"), "proven", log)

    def test_allowed_flops_are_the_rule(self):
        box("large", 3e4)
        rep, log, allowed = budget_run("large")
        self.assertEqual(3 * rep["mesh"]["nodes"], 36813, "the mesh changed: the predicted flops below do not hold")
        lz = rep["effect_minima"][0]["lanczos"]
        dear = re.search(r"too dear: ([0-9.e+]+) flops and [0-9.e+]+ MB predicted, ([0-9.e+]+) flops allowed", log)
        if dear:
            predicted, printed = float(dear.group(1)), float(dear.group(2))
            self.assertAlmostEqual(printed / allowed, 1, delta=PRINTED, msg=log)
            self.assertGreater(predicted, allowed * (1 - PRINTED), log)
            self.assertEqual(lz.get("deterministic"), "too dear", log)
        else:  # a run before of seconds (a loaded machine, the sanitizers): allowed, so proven
            m = re.search(r"factorisation of ([0-9.e+]+) flops", log)
            self.assertIsNotNone(m, log)
            self.assertLessEqual(float(m.group(1)), allowed * (1 + PRINTED), log)
            self.assertEqual(lz.get("deterministic"), "proven", log)


class Reach(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        two_bars(tu.path("bars.msh"))
        tu.write("bars.xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<mesh file="bars.msh"/>
<material name="steel" E="210e9" nu="0.3" rho="7850" default="true"/>
<effects><elastic formulation="3d"/></effects>
</dtmap-scene>
""")
        out = subprocess.run([sys.executable, REF, tu.path("bars.msh"), "210e9", "0.3", "7850", "3d"],
                             stdout=subprocess.PIPE, universal_newlines=True, env=tu.plain_env(), check=True).stdout
        cls.ref = json.loads(out)

    def test_proven_above_old_reach(self):
        code, log = tu.run("run", "bars.xml", "-o", "out.msh", "--report", "out.json", "--posterior")
        self.assertEqual(code, 0, log)
        rep = tu.report("out.json")
        self.assertGreater(3 * rep["mesh"]["nodes"], OLD_REACH)
        self.assertEqual(rep["mesh"]["nodes"], self.ref["nodes"])
        lz = rep["effect_minima"][0]["lanczos"]
        self.assertTrue(lz["converged"])
        self.assertEqual(lz.get("certificate"), "proven", log)
        self.assertIn("bound proven: the factorisation shows no eigenvalue above theta + residual", log)
        self.assertIn("factorisation of ", log)
        g, exact = rep["dt"]["global"], self.ref["exact_step"]
        self.assertLessEqual(g, exact * (1 + ROUNDING), "global %.9e s, exact %.9e s" % (g, exact))
        self.assertGreaterEqual(g, exact * (1 - 1e-4))


if __name__ == "__main__":
    tu.main()
