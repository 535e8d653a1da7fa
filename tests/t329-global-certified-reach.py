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
tolerance)."""

import json
import os
import subprocess
import sys
import unittest

import gmsh
import numpy as np

import testutil as tu

REF = os.path.join(tu.SRC, "tests", "reference", "mass_ref.py")
SIZE = 0.12
SCALE = 1 + 1.5e-4
ROUNDING = 1e-10
OLD_REACH = 30000  # unknowns: the hand-written factorisation refused every operator above


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
