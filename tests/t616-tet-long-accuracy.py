"""dtmap's phase-speed error on Gmsh's unstructured linear tetrahedra on
periodic boxes long along the wave, against the independent simulation of
tests/reference/periodic_wave.py (numpy/scipy, no dtmap code) through
tests/common/wavecheck.py (issue 37: the S wave lags less along the axes on
such boxes than in the cubes the measured table came from, and dtmap's
worst was 1.56 times the simulation's at 4 elements per S wavelength and
2.37 times on a box graded 2x along the wave).

- A box of 0.8 x 0.16 x 0.16 m (68 cells along x) at 4 elements per S
  wavelength: dtmap's reported worst is within 0.7 to 1.5 times the worst
  the simulation measures at dtmap's step among P and S along x and along
  the box's diagonal (the issue's band), and `verify --accuracy --wave S`
  along x (a periodic sample, 12 periods) agrees with the prediction within
  its 20 % band.
- The same box graded 2x along x (fine ends, coarse middle; 0.12 m across,
  which changes nothing along x), 4 elements per S wavelength in the coarse
  middle: the worst is an element's, so it is compared with its local
  elements (the simulation of the uniform box above, whose elements are
  the coarse middle's size, scaled by (k h)^2 to the same elements per
  wavelength): within 0.7 to 1.5; and against the whole graded box's mode
  (the simulation's mean over the path from fine to coarse), at least 1
  (an element's worst is never under the mean of the errors along the
  wave) and at most 2: with errors quadratic in a size that doubles
  linearly along the wave, an exact local prediction is 12/7 = 1.71 times
  the mean, so this comparison cannot reach the issue's 1.5.
- Under the sanitizers the uniform box alone, without verify.
"""

import unittest

import testutil as tu
import wavecheck as wc

H4 = 0.8 / 68


class Long(unittest.TestCase):
    def test_uniform_and_graded(self):
        phase, res, worst, per = wc.long_case("long4", [0.8, 0.16, 0.16], H4, 4)
        phase = phase[0]
        text = wc.describe(phase, res, worst, per)
        print("long4", text)
        self.assertLess(abs(per - 4) / 4, 0.05, text)
        self.assertEqual(phase["model"], "measured", text)
        self.assertTrue(0.7 <= phase["worst"] / worst <= 1.5, text)
        if tu.SANITIZED:
            return
        code, out = tu.run("verify", "long4.xml", "--accuracy", "--wave", "S", "--report", "long4_S.json")
        acc = tu.report("long4_S.json")["accuracy"]
        self.assertEqual(code, 0, out)
        self.assertTrue(acc["periodic"], out)
        self.assertLessEqual(abs(acc["agreement"]), 0.2, out)
        gphase, gres, gworst, gper = wc.long_case("graded2", [0.8, 0.12, 0.12], H4 / 2, 4, grading=2.0)
        gphase = gphase[0]
        text = wc.describe(gphase, gres, gworst, gper)
        local = worst * (per / gper) ** 2  # the uniform box's worst at the graded box's coarse elements per wavelength
        print("graded2", text, "; against the uniform box at the coarse size (%+.4f %%): %.2f" % (
            100 * local, gphase["worst"] / local))
        self.assertLess(abs(gper - 4) / 4, 0.1, text)
        self.assertTrue(0.7 <= gphase["worst"] / local <= 1.5, text)
        self.assertTrue(1.0 <= gphase["worst"] / gworst <= 2.0, text)


if __name__ == "__main__":
    tu.main()
