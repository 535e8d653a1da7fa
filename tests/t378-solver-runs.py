"""The step and the hours each solver will take (issue 43, item 5).

`run --solver-rule calculix,lsdyna,abaqus` and `deck --solver S` give, per
solver, the step it takes with dtmap's deck and the hours of the scene's
duration, in the summary (one line each) and in the report's solvers[]:
- CalculiX: the smaller of its own estimate (the deck header's, report
  deck.own_estimate) and the deck's increment; its cost per element-step is
  the figure bench/ccx_cost.py measured for the deck's element
  (src/cost/ccx_cost.inc, read here: C3D4 on the box), so hours =
  elements x ceil(duration / step) x that figure / 3600 (to 1e-12: the same
  doubles);
- LS-DYNA and Abaqus: the deck's step; no binary here, so without the
  scene's <time cost-per-element-step> the hours are null, said "not
  known", and never CalculiX's figure; with it (2e-7 s) every solver's
  hours use the scene's figure, whose file and line are named.
Fails on the code before issue 43: no solvers[] and no such lines."""

import math
import os
import re
import unittest

import testutil as tu

BOX = os.path.join(tu.SRC, "geometries", "box.xml")


def ccx_figure(elem):
    with open(os.path.join(tu.SRC, "src", "cost", "ccx_cost.inc")) as f:
        return float(re.search(r'\{"%s", ([0-9.e+]+),' % elem, f.read()).group(1)) * 1e-9


class Runs(unittest.TestCase):
    def run_box(self, scene, name):
        code, out = tu.run("run", scene, "--solver-rule", "calculix,lsdyna,abaqus", "-o", tu.path(name + ".msh"),
                           "--report", tu.path(name + ".json"))
        self.assertEqual(code, 0, out)
        return out, {s["solver"]: s for s in tu.report(name + ".json")["solvers"]}

    def test_box(self):
        out, runs = self.run_box(BOX, "box")
        self.assertEqual(list(runs), ["calculix", "lsdyna", "abaqus"])
        code, text = tu.run("deck", BOX, "--solver", "calculix", "-o", tu.path("box.inp"), "--report",
                            tu.path("box_deck.json"))
        self.assertEqual(code, 0, text)
        rep = tu.report("box_deck.json")
        d, n, duration = rep["deck"], rep["mesh"]["elements"], 1e-4  # box.xml's <time duration>
        c = runs["calculix"]
        self.assertEqual(rep["solvers"][0]["step"], c["step"])
        self.assertEqual(c["step"], min(d["own_estimate"], d["step"]))
        self.assertLess(d["own_estimate"], d["step"])  # ccx runs at its own estimate here (12.95x below)
        self.assertEqual(c["element_steps"], n * math.ceil(duration / c["step"]))
        self.assertLess(abs(c["cost_per_element_step"] / ccx_figure("C3D4") - 1), 1e-15)  # ns x 1e-9 either way
        self.assertLess(abs(c["hours"] / (c["element_steps"] * ccx_figure("C3D4") / 3600) - 1), 1e-12)
        self.assertIn("bench/ccx_cost.py", c["cost_source"])
        for s in ("lsdyna", "abaqus"):
            self.assertIsNone(runs[s]["hours"])
            self.assertIsNone(runs[s]["cost_per_element_step"])
            self.assertIn("not known", runs[s]["cost_source"])
            self.assertEqual(runs[s]["element_steps"], n * math.ceil(duration / runs[s]["step"]))
        self.assertIn("hours not known", out)
        lines = [l for l in out.split("\n") if re.match(r"  (calculix|lsdyna|abaqus) +step ", l)]
        self.assertEqual(len(lines), 3, out)
        self.assertIn("%.4g h" % c["hours"], lines[0])

    def test_scene_figure(self):
        with open(BOX) as f:
            text = f.read().replace('<geometry file="box.geo"/>',
                                    '<geometry file="%s"/>' % os.path.join(tu.SRC, "geometries", "box.geo"))
        scene = tu.write("box_cost.xml", text.replace('duration="1e-4"', 'duration="1e-4" cost-per-element-step="2e-7"'))
        _, runs = self.run_box(scene, "box_cost")
        for s, r in runs.items():
            self.assertEqual(r["cost_per_element_step"], 2e-7, s)
            self.assertLess(abs(r["hours"] / (r["element_steps"] * 2e-7 / 3600) - 1), 1e-12)
            self.assertIn("box_cost.xml", r["cost_source"])
            self.assertIn("<time cost-per-element-step>", r["cost_source"])


if __name__ == "__main__":
    tu.main()
