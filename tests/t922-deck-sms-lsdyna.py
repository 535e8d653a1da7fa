"""`dtmap deck --solver lsdyna --target T --selective-mass` (issue 44): LS-DYNA's
selective mass scaling on a part set (src/deck/sms.c, lsdyna.c).

The cards, field by field (each field within its 10 fixed columns, read by
tests/common/deckread.py's reader, which refuses a longer one):
- *CONTROL_TIMESTEP's first card: DTINIT 0, TSSFAC <= 0.9 (the report's),
  ISDO 0, TSLIMT 0, DT2MS negative (the report's), LCTM 1, and TSSFAC x
  |DT2MS| the deck's step (1e-15 relative), at most the target and within
  1e-7 of it (TSSFAC's 8 digits);
- its second card: DT2MSF 0, DT2MSLC 0, IMSCL minus the ID of the part set
  DTMAP_SMS_PARTS, two unused fields 0, RMSCL 0 (translations only);
- DTMAP_SMS_PARTS lists every *PART of the deck;
- no *ELEMENT_MASS: LS-DYNA's own scaling reaches the target;
- everything else is the deck without --selective-mass, card for card
  (that deck has no second card and no DTMAP_SMS_PARTS).
The prediction: on t377's bar of two cell sizes (16 cells 0.01 x 0.02 x
0.02 m, 16 cubes of 0.02 m, steel) with a target between their steps,
the report's selective_mass.added_mass is the conventional DT2MS figure
16 rho V_small ((|DT2MS| c_d / 0.01)^2 - 1) within 1e-9 (sums of 32 doubles
of corners Gmsh writes at 17 digits), at 16 elements, the header states it
with the model's mass and says the selective form leaves the translational
mass unchanged. A step within 0.9 x LS-DYNA's estimate needs no scaling
(the Brazilian disc): no DT2MS, no second card, and the header says so.
Fails on the code before: it has no --selective-mass (exit 2)."""

import os
import unittest

import deckread
from barmodel import BAR, C_D, E, NU, RHO, SCENE
import testutil as tu

BOX = os.path.join(tu.SRC, "geometries", "box.xml")


def deck(scene, name, *extra):
    out, rep = tu.path(name + ".k"), tu.path(name + ".json")
    code, text = tu.run("deck", scene, "--solver", "lsdyna", "-o", out, "--report", rep, *extra)
    if code:
        raise AssertionError("dtmap deck: exit %d\n%s" % (code, text))
    return out, tu.report(rep)["deck"], text


def control(path):
    """The *CONTROL_TIMESTEP cards, fields as strings (10 columns each)."""
    for key, cs in deckread._cards(path):
        if key == "CONTROL_TIMESTEP":
            return [deckread._fields(cs[0], [10] * 8)] + [deckread._fields(c, [10] * 6) for c in cs[1:]]
    raise AssertionError("no *CONTROL_TIMESTEP")


class LsdynaSelective(unittest.TestCase):
    def test_box_cards(self):
        out, r, text = deck(BOX, "box_sms", "--target", "6e-7", "--selective-mass")
        plain, _, _ = deck(BOX, "box", "--target", "6e-7")
        c = control(out)
        self.assertEqual(len(c), 2)
        one, two = c
        self.assertEqual(float(one[0]), 0.0)
        self.assertEqual(float(one[1]), r["tssfac"])
        self.assertLessEqual(r["tssfac"], 0.9)
        self.assertEqual((one[2], float(one[3])), ("0", 0.0))
        self.assertEqual(float(one[4]), r["dt2ms"])
        self.assertLess(r["dt2ms"], 0)
        self.assertEqual(int(one[5]), 1)
        self.assertLess(abs(r["tssfac"] * -r["dt2ms"] / r["step"] - 1), 1e-15)
        self.assertLessEqual(r["step"], 6e-7)
        self.assertLess(1 - r["step"] / 6e-7, 1e-7)
        d = deckread.read_k(out)
        kind, ids = d.elsets["DTMAP_SMS_PARTS"]
        self.assertEqual(kind, "parts")
        self.assertEqual(ids, set(d.sections["parts"]))
        set_id = [int(deckread._fields(cs[1], [10])[0]) for k, cs in deckread._cards(out)
                  if k == "SET_PART_LIST_TITLE" and cs[0].strip() == "DTMAP_SMS_PARTS"]
        self.assertEqual(len(set_id), 1)
        self.assertEqual([float(two[0]), int(two[1]), int(two[2]), two[3], two[4], float(two[5])],
                         [0.0, 0, -set_id[0], "0", "0", 0.0])
        self.assertEqual(d.masses, {})
        sm = r["selective_mass"]
        self.assertTrue(sm["solver_scales"])
        self.assertEqual(sm["added_mass"], r["solver_added_mass"])
        self.assertEqual(sm["elements"], r["solver_added_elements"])
        self.assertIn("selective", sm["note"])
        self.assertIn("LS-DYNA scales every part selectively", text)
        # the rest is the deck without --selective-mass
        a = [(k, cs) for k, cs in deckread._cards(out) if k != "CONTROL_TIMESTEP" and
             not (k == "SET_PART_LIST_TITLE" and cs[0].strip() == "DTMAP_SMS_PARTS")]
        b = [(k, cs) for k, cs in deckread._cards(plain) if k != "CONTROL_TIMESTEP"]
        self.assertEqual(a, b)
        self.assertEqual(control(plain), [one])

    def test_bar_prediction(self):
        tu.write("bar.geo", BAR)
        scene = tu.write("bar.xml", SCENE % (E, NU, RHO))
        t_small = 0.01 / C_D
        out, r, _ = deck(scene, "bar", "--target", "%.12e" % (0.9 * 1.5 * t_small), "--selective-mass")
        d = -r["dt2ms"]
        self.assertTrue(t_small < d < 2 * t_small)
        want = 16 * RHO * 0.01 * 0.02 * 0.02 * ((d / t_small) ** 2 - 1)
        sm = r["selective_mass"]
        self.assertEqual(sm["elements"], 16)
        self.assertLess(abs(sm["added_mass"] / want - 1), 1e-9)
        with open(out) as f:
            head = f.read(6000)
        self.assertIn("IMSCL", head)
        self.assertIn("leaves its translational", head)
        self.assertIn("%.10g kg at 16 elements" % sm["added_mass"], head)
        self.assertIn("%.10g kg" % r["model_mass"], head)
        self.assertIn("(0 kg)", head)

    def test_no_scaling_needed(self):
        """The Brazilian disc's step is 0.835 x LS-DYNA's estimate: a target
        below it leaves the deck's step dtmap's, with no scaling."""
        disc = os.path.join(tu.SRC, "geometries", "brazilian_disc.xml")
        out, r, _ = deck(disc, "disc", "--target", "1e-9", "--selective-mass")
        self.assertLessEqual(r["step"], 0.9 * r["own_estimate"])
        self.assertNotIn("dt2ms", r)
        self.assertEqual(len(control(out)), 1)
        self.assertEqual(r["selective_mass"]["elements"], 0)
        with open(out) as f:
            self.assertIn("no mass scaling, selective or not; IMSCL is not written", f.read(6000))


if __name__ == "__main__":
    tu.main()
