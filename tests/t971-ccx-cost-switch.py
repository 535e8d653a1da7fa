"""CalculiX's cost per element-step follows the mesh's size (issue 43, item 5).

Debian's ccx 2.20 costs about twice as much per element-step on a mesh
beyond a switch of about 25,000 elements as on a smaller one (its arrays no
longer stay in the processor's cache: bench/ccx_cost.py measures both
figures per CalculiX element and the switch on C3D4; src/cost/ccx_cost.inc
holds them, read here). Checked on two bundled examples meshed by the real
Gmsh: the box (10,161 C3D4, below the switch) takes the small figure and the
notched beam (31,313 C3D4, beyond it) the large one, in both places a
CalculiX figure is used, the deck's solvers[] (deck --solver calculix) and
run's per-element-step cost (the report's cost block); the source line names
the switch. The figures are the same doubles (1e-15: ns x 1e-9 either way).
Fails on the code before: one figure per element, so the notched beam took
C3D4's small figure (its ccx runs measured 2.2 - 2.4x that prediction)."""

import os
import re
import unittest

import testutil as tu

GEO = os.path.join(tu.SRC, "geometries")


def table():
    """{element: (ns below, ns beyond, switch)} of src/cost/ccx_cost.inc."""
    with open(os.path.join(tu.SRC, "src", "cost", "ccx_cost.inc")) as f:
        rows = re.findall(r'\{"(\w+)", ([0-9.e+]+), ([0-9.e+]+), ([0-9.e+]+)\}', f.read())
    return {r[0]: tuple(float(x) for x in r[1:]) for r in rows}


class Switch(unittest.TestCase):
    def figures(self, name):
        scene = os.path.join(GEO, name + ".xml")
        code, out = tu.run("deck", scene, "--solver", "calculix", "-o", tu.path(name + ".inp"), "--report",
                           tu.path(name + "_deck.json"), "-q")
        self.assertEqual(code, 0, out)
        deck = tu.report(name + "_deck.json")
        code, out = tu.run("run", scene, "-o", tu.path(name + ".msh"), "--report", tu.path(name + ".json"), "-q")
        self.assertEqual(code, 0, out)
        return deck, tu.report(name + ".json")

    def check(self, name, beyond):
        t = table()
        self.assertIn("C3D4", t)
        small, large, switch = t["C3D4"]
        self.assertGreater(large, 1.5 * small)  # the measured jump the model is for
        deck, run = self.figures(name)
        n = deck["deck"]["elements"]
        self.assertEqual(n > switch, beyond, "%s: %d elements, switch %g" % (name, n, switch))
        want = (large if beyond else small) * 1e-9
        s = deck["solvers"][0]
        self.assertLess(abs(s["cost_per_element_step"] / want - 1), 1e-15, s)
        self.assertIn("beyond the switch" if beyond else "below the switch", s["cost_source"])
        cost = run["cost"]
        self.assertLess(abs(cost["per_element_step"] / want - 1), 1e-15, cost)
        self.assertIn("beyond the switch" if beyond else "below the switch", cost["per_element_step_source"])

    def test_box_below(self):
        self.check("box", False)

    def test_notched_beam_beyond(self):
        self.check("notched_beam", True)


if __name__ == "__main__":
    tu.main()
