"""`dtmap deck --solver abaqus --target T --selective-mass` (issue 44):
Abaqus/Explicit has no selective mass scaling, so the deck falls back to
dtmap's conventional mass at the nodes and says so with its price.

On the bundled box with T = 6e-7 s:
- the deck's data lines (comments out) are those of the deck `--target
  6e-7` without --selective-mass, line for line: the same *MASS elements,
  the same increment;
- the header says Abaqus/Explicit has no selective scaling and gives the
  mass at the nodes (the report's added_mass, 10 digits), its nodes and its
  share of the model's mass (4 digits), and that it changes the
  translational mass;
- the summary says it too, with the same figures (6 digits, 3 for the
  share), and the report's deck.selective_mass has solver_scales false;
- --max-added-mass below that share still exits 1 and writes nothing (the
  fallback is the conventional mass the limit is for).
Fails on the code before: it has no --selective-mass (exit 2)."""

import os
import unittest

import testutil as tu

BOX = os.path.join(tu.SRC, "geometries", "box.xml")


def deck(name, *extra):
    out, rep = tu.path(name + ".inp"), tu.path(name + ".json")
    code, text = tu.run("deck", BOX, "--solver", "abaqus", "--target", "6e-7", "-o", out, "--report", rep, *extra)
    return code, text, out, rep


def data_lines(path):
    with open(path) as f:
        return [line for line in f.read().split("\n") if not line.startswith("**")]


class AbaqusSelective(unittest.TestCase):
    def test_fallback(self):
        code, text, out, rep = deck("box_sms", "--selective-mass")
        self.assertEqual(code, 0, text)
        code, text0, plain, _ = deck("box")
        self.assertEqual(code, 0, text0)
        self.assertEqual(data_lines(out), data_lines(plain))
        d = tu.report(rep)["deck"]
        self.assertGreater(d["added_mass"], 0)
        sm = d["selective_mass"]
        self.assertFalse(sm["solver_scales"])
        self.assertNotIn("added_mass", sm)
        share = 100 * d["added_mass"] / d["model_mass"]
        with open(out) as f:
            head = f.read(6000)
        self.assertIn("Abaqus/Explicit has none", head)
        self.assertIn("%.10g kg at %d nodes, %.4g %% of the model's %.10g kg" %
                      (d["added_mass"], d["added_nodes"], share, d["model_mass"]), head)
        self.assertIn("changes the model's\n** translational mass", head)
        self.assertIn("Abaqus/Explicit has no selective mass scaling: conventional mass at the nodes instead, "
                      "%.6g kg at %d nodes (%.3g %% of the model's %.6g kg)" %
                      (d["added_mass"], d["added_nodes"], share, d["model_mass"]), text)

    def test_limit(self):
        code, text, out, _ = deck("box_limit", "--selective-mass", "--max-added-mass", "1")
        self.assertEqual(code, 1, text)
        self.assertIn("above --max-added-mass 1 %", text)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    tu.main()
