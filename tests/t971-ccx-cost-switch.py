"""CalculiX's cost per element-step follows the mesh's size (issue 43, item 5).

Debian's ccx 2.20 costs about twice as much per element-step on a mesh
beyond a switch of about 25,000 elements as on a smaller one (the arrays it
allocates every increment pass glibc's mmap threshold: docs/accuracy.md;
bench/ccx_cost.py measures both
figures per CalculiX element and the switch on C3D4; src/cost/ccx_cost.inc
holds them, read here). Checked on two bundled examples meshed by the real
Gmsh: the box (10,161 C3D4, below the switch) takes the small figure and the
notched beam (31,313 C3D4, beyond it) the large one, in both places a
CalculiX figure is used, the deck's solvers[] (deck --solver calculix) and
run's per-element-step cost (the report's cost block); the source line names
the switch. The figures are the same doubles (1e-15: ns x 1e-9 either way).
Fails on the code before: one figure per element, so the notched beam took
C3D4's small figure (its ccx runs measured 2.2 - 2.4x that prediction).

Each figure is measured on a deck of its element alone, and ccx sizes the
per-element arrays it copies every increment by the deck's bound of
integration points per element, which the deck's elements set together
(CalculiX 2.20's allocation.f, restated in POINTS below from reading it):
C3D4 alone gives 27, the reinforced block's C3D4 with M3D3 and SPRINGA 9,
and that block ran at 0.61 - 0.68 of the old prediction. Checked on the
reinforced block (bound 9) and the stiffened panel (S3 with B31: 27, where
S3 alone gives 9): the figure of each deck element is the table's plus
CCX_POINT_NS (the .inc) per point of the difference between the deck's
bound and the element's own deck's, an element not measured taking CPE3's
figure (M3D3, SPRINGA, B31: dtmap's tri3 and line2 stand as CPE3), weighted
by the element counts of the deck file; run's cost block gives the same
figure for the block (for the panel it takes dtmap's types, 2D as plane
strain: docs/accuracy.md). Fails on the code before: no bound, the block
took 1261 ns where this takes about 860 (the .inc had no CCX_POINT_NS)."""

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


def point_ns():
    """CCX_POINT_NS of src/cost/ccx_cost.inc, ns per point of the bound and element-step."""
    with open(os.path.join(tu.SRC, "src", "cost", "ccx_cost.inc")) as f:
        return float(re.search(r"#define CCX_POINT_NS ([0-9.e+-]+)", f.read()).group(1))


# Integration points per element of CalculiX 2.20's elements (its
# allocation.f); *DYNAMIC then raises the deck's largest: 1, 8 -> 27, 4 -> 15, 2 -> 9.
POINTS = {"C3D4": 1, "C3D10": 4, "C3D8": 8, "CPE3": 2, "CPS3": 2, "M3D3": 2, "S3": 2, "CPE4": 8, "S4": 8,
          "CPE6": 9, "B31": 8, "SPRINGA": 1, "MASS": 0}
DYNAMIC = {1: 27, 8: 27, 4: 15, 2: 9}
STANDS = {"M3D3": "CPE3", "SPRINGA": "CPE3", "B31": "CPE3", "CPS3": "CPE3"}


def deck_elements(path):
    """{CalculiX element: count} of a deck's *ELEMENT blocks."""
    counts, elem = {}, None
    with open(path) as f:
        for line in f:
            if line.startswith("*"):
                m = re.match(r"\*ELEMENT, TYPE=(\w+)", line)
                elem = m.group(1) if m else None
            elif elem and line.strip():
                counts[elem] = counts.get(elem, 0) + 1
    return counts


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

    def bound(self, name, want_points, run_too=True):
        t, k = table(), point_ns()
        deck, run = self.figures(name)
        counts = deck_elements(tu.path(name + ".inp"))
        counts.pop("MASS", None)  # point masses: no element-steps of dtmap's
        points = DYNAMIC.get(max(POINTS[e] for e in counts), max(POINTS[e] for e in counts))
        self.assertEqual(points, want_points, counts)
        n = deck["deck"]["elements"]
        self.assertEqual(sum(counts.values()), n, counts)
        self.assertLess(n, t["C3D4"][2])  # below the switch: the first figures
        ns = 0.0
        for e, c in counts.items():
            stand = STANDS.get(e, e)
            alone = DYNAMIC.get(POINTS[stand], POINTS[stand])
            ns += c * (t[stand][0] + k * (points - alone))
        want = ns / n * 1e-9
        s = deck["solvers"][0]
        # the same sum in another order: 1e-12 of the figure
        self.assertLess(abs(s["cost_per_element_step"] / want - 1), 1e-12, (s, want))
        self.assertIn("bound of %d integration points" % points, s["cost_source"])
        if run_too:
            cost = run["cost"]
            self.assertLess(abs(cost["per_element_step"] / want - 1), 1e-12, (cost, want))
            self.assertIn("bound of %d integration points" % points, cost["per_element_step_source"])
        return want

    def test_reinforced_block_bound_9(self):
        want = self.bound("reinforced_block", 9)
        t = table()
        self.assertLess(want, 0.8 * t["C3D4"][0] * 1e-9)  # below C3D4 alone's, as ccx ran it

    def test_stiffened_panel_bound_27(self):
        # run's cost knows dtmap's types only (2D as plane strain CPE3: bound 9), not the deck's S3 and B31
        self.bound("stiffened_panel", 27, run_too=False)

    def test_box_below(self):
        self.check("box", False)

    def test_notched_beam_beyond(self):
        self.check("notched_beam", True)


if __name__ == "__main__":
    tu.main()
