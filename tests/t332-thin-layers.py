"""Thin layers: the bundled tunnel (geometries/tunnel_lining.xml, a 0.3 m
concrete lining in rock, 2D plane strain, real Gmsh meshing) with a target
1.3 times its recommended step.

- `dtmap run` names the lining as thickness-limited: its thickness (0.3 m:
  the nodes of the two faces are radially aligned at r = 3 and 3.3, so the
  smallest gap is 0.3 to rounding; 1e-9 relative), every element below the
  target is among them and lies in the lining, the view 'thickness
  limited' holds exactly those elements with their local thickness, the
  best step a fresh mesh of the layer reaches is below the target, and the
  remedies carry their costs: mass at their nodes (+% of the group's
  mass), the subcycling speed-up, and LS-DYNA's rule for the layer as a
  beam, size / sqrt(E/(rho(1 - nu^2))) with the concrete's moduli (1e-12:
  a few roundings).
- `dtmap refine` does not take `run`'s layer figure as a fact: it remeshes
  before it names a cause (issue 35), and a remesh of the tunnel whose
  lining has coarser elements meets the target (Gmsh meshes this 2D model
  the same way each time: the scaled input sizes, x1.97, give a nodal step
  of 5.55e-5 s against 5.2e-5). So exit 0, the kept round is a remesh whose
  recommended step is at least the target, and nothing is said of a stop
  or of the lining's thickness as a cause. (`run`'s reach figure for the
  layer, below the target, is the element-step rule's estimate, which this
  remesh beats.)
- With a target 1.05 times the step, which a fresh mesh of the lining can
  reach, nothing is called thickness-limited.
- Without a target, the smallest steps are said to lie across the lining
  (at_minimum, thickness 0.3 m to 1e-9, no remedies), and the bundled box,
  whose smallest steps lie in no thin part, has no such entry. With
  --posterior the recommended step (global) beats that reach, and the line
  says the reach is an estimate, not a bound (issue 43).
"""

import math
import os
import shutil
import unittest


import testutil as tu

E, NU, RHO = 30e9, 0.2, 2400.0


class TunnelLining(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for ext in ("geo", "xml"):
            shutil.copy(os.path.join(tu.SRC, "geometries", "tunnel_lining." + ext), tu.tmpdir())
        code, cls.out = tu.run("run", "tunnel_lining.xml", "-o", "t.msh", "--report", "t.json")
        if code:
            raise AssertionError(cls.out)
        cls.rep = tu.report("t.json")

    def test_lining_named(self):
        layers = self.rep["thickness_limited"]
        self.assertEqual([l["group"] for l in layers], ["lining"])
        l = layers[0]
        self.assertLessEqual(abs(l["thickness"] - 0.3), 0.3e-9)
        self.assertEqual(l["elements"], self.rep["below_target"])
        self.assertLess(l["reach"], 5.2e-5)
        self.assertIn("'lining'", self.out)
        self.assertIn("thickness limited", self.out)

    def test_view(self):
        v = tu.view_values(tu.path("t.msh"), "thickness limited")
        self.assertEqual(len(v), self.rep["thickness_limited"][0]["elements"])
        for t in v.values():
            self.assertTrue(0.3 * (1 - 1e-9) <= t < 0.35, t)
        groups = {s["element"]: s for s in self.rep["shape_limited"]}
        for tag in v:
            self.assertEqual(groups[tag]["group"], "lining")

    def test_remedies(self):
        l = self.rep["thickness_limited"][0]
        r = l["remedies"]
        self.assertGreater(r["mass_percent"], 0)
        self.assertGreaterEqual(r["subcycling_speedup"], 1)
        want = l["size"] / math.sqrt(E / (RHO * (1 - NU * NU)))
        self.assertLessEqual(abs(r["shell_rule_step"] - want), 1e-12 * want)

    def test_refine_remeshes_before_a_cause(self):
        code, out = tu.run("refine", "tunnel_lining.xml", "-o", "r.msh", "--report", "r.json")
        self.assertEqual(code, 0, out)
        ref = tu.report("r.json")["refine"]
        self.assertGreater(len(ref["rounds"]), 1)
        kept = ref["rounds"][ref["best"]]
        self.assertEqual(kept["kind"], "mesh")
        self.assertGreaterEqual(kept["recommended"], ref["target"])
        self.assertTrue(ref["met"])
        self.assertEqual(ref["causes"], [])
        self.assertNotIn("stopped", out.split("met:")[0].lower())
        self.assertTrue(os.path.exists(tu.path("r.msh")))

    def test_reachable_target_is_not_thickness_limited(self):
        code, out = tu.run("run", "tunnel_lining.xml", "-o", "u.msh", "--report", "u.json", "-q")
        self.assertEqual(code, 0, out)
        rec = tu.report("u.json")["dt"]["recommended"]
        with open(tu.path("tunnel_lining.xml")) as f:
            text = f.read().replace('target="5.2e-5"', 'target="%.6e"' % (1.05 * rec))
        tu.write("near.xml", text)
        code, out = tu.run("run", "near.xml", "-o", "n.msh", "--report", "n.json", "-q")
        self.assertEqual(code, 0, out)
        self.assertEqual(tu.report("n.json")["thickness_limited"], [])

    def test_without_target_at_minimum(self):
        with open(tu.path("tunnel_lining.xml")) as f:
            tu.write("free.xml", f.read().replace(' target="5.2e-5"', ""))
        code, out = tu.run("run", "free.xml", "-o", "f.msh", "--report", "f.json")
        self.assertEqual(code, 0, out)
        layers = tu.report("f.json")["thickness_limited"]
        self.assertEqual([(l["group"], l["at_minimum"]) for l in layers], [("lining", True)])
        self.assertLessEqual(abs(layers[0]["thickness"] - 0.3), 0.3e-9)
        self.assertEqual(layers[0]["remedies"], {})
        self.assertIn("smallest steps lie where 'lining' is 0.3 m thin", out)

    def test_reach_not_a_bound_on_the_global_basis(self):
        # issue 43: with --posterior the recommended step (the global estimate, 4.904e-5 s with
        # Gmsh 4.8.4) lies above the reach a fresh mesh of the lining gets by the element rule
        # (4.887e-5 s); the line then says the estimate is not a bound, and only then.
        with open(tu.path("tunnel_lining.xml")) as f:
            tu.write("free_g.xml", f.read().replace(' target="5.2e-5"', ""))
        code, out = tu.run("run", "free_g.xml", "--posterior", "-o", "g.msh", "--report", "g.json")
        self.assertEqual(code, 0, out)
        rep = tu.report("g.json")
        line = [l for l in out.splitlines() if l.startswith("thickness ")][0]
        beaten = rep["thickness_limited"][0]["reach"] < rep["dt"]["recommended"]
        self.assertEqual("already beats: not a bound" in line, beaten, line)
        self.assertTrue(beaten, (rep["thickness_limited"][0]["reach"], rep["dt"]["recommended"]))

    def test_box_has_no_thin_part(self):
        shutil.copy(os.path.join(tu.SRC, "geometries", "box.geo"), tu.tmpdir())
        with open(os.path.join(tu.SRC, "geometries", "box.xml")) as f:
            tu.write("box_free.xml", f.read().replace(' target="4e-7"', ""))
        code, out = tu.run("run", "box_free.xml", "-o", "box_out.msh", "--report", "box_out.json", "-q")
        self.assertEqual(code, 0, out)
        self.assertEqual(tu.report("box_out.json")["thickness_limited"], [])


if __name__ == "__main__":
    tu.main()
