"""Beams that cross or corner on shell nodes give a CalculiX deck Debian's
ccx 2.20 runs (issue 43 item 7: with one beam node per shell node, the two
beams met at an angle on it, CalculiX joined them by a KNOT, a nonlinear
MPC, on a node the deck's linear *EQUATION ties to the shell, and ccx
refused at once: "nonlinear MPCs depend on each other").

Gmsh (the real library, OpenCASCADE) meshes a 0.2 m square plate of
quadrangles (4 mm steel shell) with two stiffeners (5 x 20 mm beams)
embedded in it: a cross through its middle, and an L-frame whose two legs
meet at (0.05, 0.05). `dtmap deck --solver calculix` gives each beam its
own node at every shell node it touches, tied to the shell node by
*EQUATION on the translations; at the crossing and at the corner there are
two, one per beam (a straight beam through a node keeps one). ccx runs each
deck for 200 of its increments under random unit loads at every node and
ends with finite displacements below 1e-3 m (the loads move it by about
1e-8 m; a diverging explicit run reaches inf or NaN long before), at its
own estimate, which is the header's within 2e-6 (ccx's 7 digits).
"""

import math
import shutil
import unittest

import deckutil as du
import testutil as tu

CCX = shutil.which("ccx") or "ccx"
SCENE = """<dtmap-scene version="1">
  <mesh file="%s.msh"/>
  <material name="steel" groups="skin stiffener" E="200e9" nu="0.3" rho="7850"/>
  <section groups="skin" kind="shell" thickness="0.004"/>
  <section groups="stiffener" kind="beam" width="0.005" height="0.02" orientation="0 0 1"/>
  <effects><elastic/></effects>
  <time safety="0.9" duration="1e-4"/>
</dtmap-scene>
"""


def stiffened_plate(name, legs):
    """name.msh: the plate [0, 0.2]^2 (group "skin", quadrangles of 0.02 m)
    with the segments legs [((x0, y0), (x1, y1)), ...] embedded as group
    "stiffener"."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        plate = occ.addRectangle(0, 0, 0, 0.2, 0.2)
        lines = [occ.addLine(occ.addPoint(a[0], a[1], 0), occ.addPoint(b[0], b[1], 0)) for a, b in legs]
        occ.fragment([(2, plate)], [(1, t) for t in lines])
        occ.synchronize()
        inner = []
        for _, c in gmsh.model.getEntities(1):
            b = gmsh.model.getBoundingBox(1, c)
            mid = ((b[0] + b[3]) / 2, (b[1] + b[4]) / 2)
            if min(mid[0], mid[1], 0.2 - mid[0], 0.2 - mid[1]) > 1e-6:  # not on the plate's edge
                inner.append(c)
        gmsh.model.addPhysicalGroup(2, [t for _, t in gmsh.model.getEntities(2)], 1)
        gmsh.model.setPhysicalName(2, 1, "skin")
        gmsh.model.addPhysicalGroup(1, inner, 2)
        gmsh.model.setPhysicalName(1, 2, "stiffener")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.02)
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.model.mesh.generate(2)
        gmsh.write(tu.path(name + ".msh"))
        return len(inner)
    finally:
        gmsh.finalize()


class BeamCrossing(unittest.TestCase):
    def case(self, name, legs, joint):
        self.assertGreaterEqual(stiffened_plate(name, legs), 2)
        scene = tu.write(name + ".xml", SCENE % name)
        out, rep = tu.path(name + ".inp"), tu.path(name + ".json")
        code, text = tu.run("deck", scene, "--solver", "calculix", "-o", out, "--report", rep, "-q")
        self.assertEqual(code, 0, text)
        rep = tu.report(name + ".json")
        with open(out) as f:
            deck = f.read()
        nodes = du.inp_nodes(deck.split("\n"))
        beams = [line for line in deck.split("*ELEMENT, TYPE=B31")[1].split("\n*")[0].split("\n")[1:] if line]
        used = {int(x) for line in beams for x in line.split(",")[1:]}
        tied = {int(line.split("\n")[0].split(",")[0]) for line in deck.split("*EQUATION\n2\n")[1:]}
        self.assertEqual(used, tied)  # every beam node is one of its own, tied to the shell
        at_joint = [n for n in used if math.dist(nodes[n], joint) < 1e-9]
        self.assertEqual(len(at_joint), 2, at_joint)  # one node per beam at the joint
        run, _ = du.prepare(out, 200 * rep["deck"]["own_estimate"])
        code, log, u, est, sel = du.run(CCX, run)
        self.assertEqual(code, 0, "%s: ccx exit %d\n%s" % (name, code, log[-2000:]))
        self.assertIn("Job finished", log)
        self.assertTrue(0 < u < 1e-3, "%s: largest |u| %g m" % (name, u))
        self.assertLess(abs(est / rep["deck"]["own_estimate"] - 1), 2e-6, (est, rep["deck"]["own_estimate"]))
        print("%s: %d beam nodes of their own, ccx's estimate %.7g s, largest |u| %.3g m after 200 increments"
              % (name, len(used), est, u))

    def test_cross(self):
        self.case("cross", [((0, 0.1), (0.2, 0.1)), ((0.1, 0), (0.1, 0.2))], (0.1, 0.1, 0))

    def test_l_frame(self):
        self.case("lframe", [((0.05, 0.05), (0.15, 0.05)), ((0.05, 0.05), (0.05, 0.15))], (0.05, 0.05, 0))


if __name__ == "__main__":
    tu.main()
