"""LS-DYNA decks keep TSSFAC at or below 0.9 (issue 43, item 6).

- The default LS-DYNA deck of every bundled example (geometries/*.xml, the
  scenes scripts/example.sh and the tests use) has TSSFAC <= 0.9, read back
  from its *CONTROL_TIMESTEP card; where it carries a DT2MS, that is negative
  and TSSFAC x |DT2MS| is the report's step (to TSSFAC's 8 digits: 1e-7).
  An example LS-DYNA lacks an element for (exit 2 naming it) is passed over
  and must not be all of them.
- The mass LS-DYNA adds by its DT2MS rule (an element whose step by its rule
  dt_e is below |DT2MS| gets mass m_e ((|DT2MS| / dt_e)^2 - 1)) on a
  structured hexahedral bar of two cell sizes, 0.01 x 0.02 x 0.02 m (16
  cells: dt_e = 0.01 m / c_d) and 0.02 m cubes (16 cells: 0.02 m / c_d),
  with a target between the two: only the small cells gain, and the
  predicted mass is 16 rho V_small ((|DT2MS| c_d / 0.01)^2 - 1), within
  1e-9 (sums of 32 doubles and the cells' corners written by Gmsh at 17
  digits).
- --lsdyna-step proven writes the deck of before: TSSFAC the step over
  LS-DYNA's estimate (above 1 on the box), no DT2MS, the header's warning.

Fails on the code before issue 43: its TSSFAC was 1.128 on the box and it
wrote no DT2MS."""

import glob
import os
import unittest

import deckread
from barmodel import BAR, C_D, E, NU, RHO, SCENE
import testutil as tu


def deck(scene, name, *extra):
    out, rep = tu.path(name + ".k"), tu.path(name + ".json")
    code, text = tu.run("deck", scene, "--solver", "lsdyna", "-o", out, "--report", rep, "-q", *extra)
    return code, text, out, rep


def dt2ms(path):
    """DT2MS, the fifth field of *CONTROL_TIMESTEP's first card (0: none)."""
    with open(path) as f:
        lines = f.read().split("\n")
    i = lines.index("*CONTROL_TIMESTEP") + 1
    while lines[i].startswith("$"):
        i += 1
    return float(lines[i].split(",")[4])


class LsdynaStep(unittest.TestCase):
    def test_bundled_examples(self):
        scenes = sorted(glob.glob(os.path.join(tu.SRC, "geometries", "*.xml")))
        self.assertGreaterEqual(len(scenes), 7)
        written = 0
        for scene in scenes:
            name = os.path.basename(scene)[:-4]
            with self.subTest(example=name):
                code, text, out, rep = deck(scene, name)
                if code == 2 and "LS-DYNA" in text:
                    continue  # an element LS-DYNA lacks, said so
                self.assertEqual(code, 0, text)
                written += 1
                d, r = deckread.read_k(out), tu.report(rep)["deck"]
                self.assertLessEqual(d.controls["tssfac"], 0.9)
                self.assertEqual(d.controls["tssfac"], r["tssfac"])
                self.assertEqual(r["lsdyna_step"], "conventional")
                self.assertLessEqual(r["step"], r["recommended"])
                if "dt2ms" in r:
                    self.assertEqual(dt2ms(out), r["dt2ms"])
                    self.assertLess(r["dt2ms"], 0)
                    self.assertLess(abs(r["tssfac"] * -r["dt2ms"] / r["step"] - 1), 1e-15)
                    self.assertLess(1 - r["step"] / r["recommended"], 1e-7)
                    self.assertGreater(r["solver_added_elements"], 0)
                else:
                    self.assertEqual(dt2ms(out), 0.0)
        self.assertGreaterEqual(written, 5)

    def test_dt2ms_mass_closed_form(self):
        tu.write("bar.geo", BAR)
        scene = tu.write("bar.xml", SCENE % (E, NU, RHO))
        t_small = 0.01 / C_D
        code, text, out, rep = deck(scene, "bar", "--target", "%.12e" % (0.9 * 1.5 * t_small))
        self.assertEqual(code, 0, text)
        r = tu.report(rep)["deck"]
        self.assertEqual(r["elements"], 32)
        # LS-DYNA's estimate of a box cell is V / A_max / c_d: the small cells'
        self.assertLess(abs(r["own_estimate"] / t_small - 1), 1e-12)
        d = -dt2ms(out)
        self.assertEqual(-d, r["dt2ms"])
        self.assertTrue(t_small < d < 2 * t_small)
        self.assertLessEqual(r["tssfac"], 0.9)
        m_small = 16 * RHO * 0.01 * 0.02 * 0.02
        want = m_small * ((d / t_small) ** 2 - 1)
        self.assertEqual(r["solver_added_elements"], 16)
        self.assertLess(abs(r["solver_added_mass"] / want - 1), 1e-9)
        self.assertLess(abs(r["model_mass"] / (RHO * 0.12 * 0.04 * 0.04) - 1), 1e-12)
        self.assertEqual(r["added_mass"], 0.0)  # no nodal masses: LS-DYNA's scaling reaches the target
        self.assertEqual(deckread.read_k(out).masses, {})
        with open(out) as f:
            head = f.read(4000)
        self.assertIn("DT2MS %.10g s" % r["dt2ms"], head)
        self.assertIn("%.10g kg" % r["solver_added_mass"], head)

    def test_proven(self):
        scene = os.path.join(tu.SRC, "geometries", "box.xml")
        code, text, out, rep = deck(scene, "box_proven", "--lsdyna-step", "proven")
        self.assertEqual(code, 0, text)
        r = tu.report(rep)["deck"]
        self.assertEqual(r["lsdyna_step"], "proven")
        self.assertGreater(r["tssfac"], 1)
        self.assertNotIn("dt2ms", r)
        self.assertEqual(dt2ms(out), 0.0)
        self.assertLess(abs(r["tssfac"] * r["own_estimate"] / r["step"] - 1), 1e-15)
        with open(out) as f:
            self.assertIn("WARNING: TSSFAC is above the 0.9", f.read(4000))
        code, text, _, _ = deck(scene, "box_bad", "--lsdyna-step", "safe")
        self.assertEqual(code, 2)
        self.assertIn("--lsdyna-step 'safe' is neither conventional nor proven", text)
        code, text = tu.run("deck", scene, "--solver", "abaqus", "--lsdyna-step", "proven", "-o", tu.path("b.inp"))
        self.assertEqual(code, 2)
        self.assertIn("--lsdyna-step is for --solver lsdyna", text)


if __name__ == "__main__":
    tu.main()
