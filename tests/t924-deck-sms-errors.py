"""Bad uses of `dtmap deck --selective-mass` (issue 44) are usage errors:
exit 2, a message that names the option and what to do, and no deck or
report written.
- --selective-mass without --target, for each solver;
- --selective-mass with --lsdyna-step proven (the two ask for different
  masses: LS-DYNA's own scaling against dtmap's masses at the nodes).
On the code before, the option itself was unknown: exit 2 too, but with
"unknown option" and not these messages."""

import os
import unittest

import testutil as tu

BOX = os.path.join(tu.SRC, "geometries", "box.xml")


class SelectiveErrors(unittest.TestCase):
    def refused(self, name, message, *args):
        out, rep = tu.path(name), tu.path(name + ".json")
        code, text = tu.run("deck", BOX, "-o", out, "--report", rep, *args)
        self.assertEqual(code, 2, text)
        self.assertIn(message, text)
        self.assertFalse(os.path.exists(out))
        self.assertFalse(os.path.exists(rep))

    def test_no_target(self):
        for solver in ("calculix", "abaqus", "lsdyna"):
            with self.subTest(solver=solver):
                self.refused("no_target_" + solver,
                             "--selective-mass scales the mass to reach a step: give --target DT", "--solver", solver,
                             "--selective-mass")

    def test_lsdyna_proven(self):
        self.refused("proven.k", "--selective-mass takes LS-DYNA's own scaling", "--solver", "lsdyna", "--target",
                     "6e-7", "--selective-mass", "--lsdyna-step", "proven")


if __name__ == "__main__":
    tu.main()
