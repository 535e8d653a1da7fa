"""Structured tetrahedral meshes are recognised and predicted by their own
lattice (src/cost/structured.c), leading waves included, against an
independent Bloch analysis (tests/common/wavecheck.py: the reference's own
plane-wave matrix of the mesh's elements, numpy, no dtmap code, itself
checked here against the periodic-box simulation of
tests/reference/periodic_wave.py).

- The cube lattice (each cube cut into six tetrahedra around its main
  diagonal, all cells alike) and Gmsh's transfinite box (six tetrahedra per
  cube, cut differently from cell to cell), 12^3 cells of 10 mm, at the
  frequency of one S wavelength along a body diagonal (6.9 cells per
  wavelength): dtmap reports the model "structured lattice" and a worst
  within 10 % of the Bloch worst over 113 directions (P and S, at dtmap's
  step) that the reference finds; both lead (the S wave runs ahead off the
  axes: +14 % and +28 %).
- The reference's plane-wave prediction matches the simulation of the S
  waves along the four body diagonals within 1e-3 of the error (the
  simulation reproduces a Bloch mode exactly on a lattice, and on Gmsh's
  mixed cells very nearly).
"""

import unittest

import testutil as tu
import wavecheck as wc


class Structured(unittest.TestCase):
    def test_lattices(self):
        for name, kuhn in (("cube_lattice", True), ("transfinite", False)):
            phase, worst, where, gap, per_wl = wc.structured_case(name, 12, kuhn)
            text = ("%s: %.2f cells per S wavelength, dtmap %+.4f %% (%s along %s, %s), Bloch worst %+.4f %% (%s along "
                    "%s), simulation gap %.1e" % (name, per_wl, 100 * phase["worst"], phase["wave"], phase["direction"],
                                                  phase["model"], 100 * worst, where[0], where[1], gap))
            print(text)
            self.assertEqual(phase["model"], "structured lattice", text)
            self.assertGreater(worst, 0.1, text)  # the S wave leads off the axes
            self.assertLessEqual(abs(phase["worst"] / worst - 1), 0.1, text)
            self.assertLess(gap, 1e-3, text)


if __name__ == "__main__":
    tu.main()
