"""One "below the target" count (issue 43, item 4), on the bundled
Brazilian disc (geometries/brazilian_disc.xml, the README's first command,
target 8e-8 s above its recommended step of about 4.1e-8 s).

- The summary's "below target" line, the histogram's title and the bins
  of the histogram under 1, the mass line's "below the target among them"
  and the report's below_target give one number (before: 501 below, 433 in
  the histogram's bins under 1, "on 574 elements" for the mass).
- That number is the count of elements whose own safe step, safety x the
  larger of the element step (the 'dt' view) and the smallest nodal bound at
  its nodes (the 'nodal dt' view), lies below the target, computed here from
  the views with Gmsh's API (tests/common/ownstep.py): exact, both sides
  compare the same doubles.
- The lines that print a count name its definition, and the view 'below
  target [s]' holds exactly those elements with those steps.
- After a met refine, the histogram has nothing under 1 and below_target
  is 0.
"""

import math
import os
import re
import shutil
import unittest

import testutil as tu
from ownstep import own_safe_steps

TARGET = 8e-8


class Disc(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for ext in ("geo", "xml"):
            shutil.copy(os.path.join(tu.SRC, "geometries", "brazilian_disc." + ext), tu.tmpdir())
        code, cls.out = tu.run("run", "brazilian_disc.xml", "-o", "d.msh", "--report", "d.json")
        assert code == 0, cls.out
        cls.rep = tu.report("d.json")

    def test_one_count(self):
        n = self.rep["below_target"]
        self.assertGreater(n, 0)
        m = re.search(r"^below target (\d+) element\(s\) \(own safe step below the target: safety x the larger of "
                      r"its element step and the smallest nodal bound at its nodes; view 'below target \[s\]'\)",
                      self.out, re.M)
        self.assertTrue(m, self.out)
        self.assertEqual(int(m.group(1)), n)
        title, rows = tu.histogram(self.out)
        self.assertIn("each element's own safe step / it", title)
        self.assertIn("below 1: the %d element(s) below the target" % n, title)
        self.assertEqual(sum(c for lo, hi, c in rows if hi <= 1), n)
        self.assertEqual(sum(c for _, _, c in rows), self.rep["mesh"]["elements"])
        m = re.search(r"the (\d+) below the target among them", self.out)
        self.assertTrue(m, self.out)
        self.assertEqual(int(m.group(1)), n)

    def test_count_from_the_views(self):
        own = own_safe_steps(tu.path("d.msh"), self.rep["dt"]["safety"])
        self.assertEqual(sum(1 for v in own.values() if v < TARGET), self.rep["below_target"])
        view = tu.view_values(tu.path("d.msh"), "below target [s]")
        self.assertEqual(view, {t: v for t, v in own.items() if v < TARGET})
        want = {}
        for v in own.values():
            k = min(math.floor(math.log2(v / TARGET)), -1) if v < TARGET else math.floor(math.log2(v / TARGET))
            want[k] = want.get(k, 0) + 1
        _, rows = tu.histogram(self.out)
        got = {round(math.log2(lo)): c for lo, hi, c in rows if c}
        self.assertEqual(got, want)

    def test_met_refine_has_none_below(self):
        code, log, rep = tu.refine("brazilian_disc", TARGET)
        self.assertEqual(code, 0, log)
        self.assertTrue(rep["refine"]["met"], log)
        self.assertEqual(rep["below_target"], 0)
        _, rows = tu.histogram(log)
        self.assertEqual(sum(c for lo, hi, c in rows if hi <= 1), 0, rows)


if __name__ == "__main__":
    tu.main()
