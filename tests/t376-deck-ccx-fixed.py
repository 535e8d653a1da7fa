"""The CalculiX deck's step for shells in a CalculiX that runs at the
increment it is given (bench/ccx_fixed_inc.sh builds it from Debian's
calculix-ccx 2.20 source package; the test runs only when DTM_CCX_FIXED names that binary,
and is skipped otherwise, exit 77 for ctest). On three small flat plates,
h = 20 mm, t = 4 mm, of S4 quadrangles (90), of S3 triangles (156) and of
both (45 S4 beside 78 S3), the same meshes as bench/ccx_shell_caps.py's,
from a seeded random force at every node (tests/common/deckutil.py), 400
increments:
- at the deck's step the run is bounded: its largest displacement is below
  1e3 x that of a run at half the step, scaled by the square of the step
  (a free plate under a constant force drifts as t^2);
- at 1.05 x the upper end of the limit bench/ccx_shell_caps.py measured for
  that mesh (S4 and mixed: 0.3406 x the smallest element bound of the
  layer's solids, S3: 0.8406) it diverges: the test can tell the two
  apart. Under the old cap (0.8 x the bound, safety 0.9) the S4 deck's
  step was 2.1x its limit."""

import os
import re
import sys
import unittest

import deckutil as du
import testutil as tu

CCX = os.environ.get("DTM_CCX_FIXED", "")

PLATE = """L = 0.16; W = 0.10;
Point(1) = {0, 0, 0}; Point(2) = {L/2, 0, 0.3*L/2}; Point(3) = {L, 0, 0.3*L};
Point(4) = {0, W, 0}; Point(5) = {L/2, W, 0.3*L/2}; Point(6) = {L, W, 0.3*L};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {4, 5}; Line(4) = {5, 6};
Line(5) = {1, 4}; Line(6) = {2, 5}; Line(7) = {3, 6};
Curve Loop(1) = {1, 6, -3, -5}; Plane Surface(1) = {1};
Curve Loop(2) = {2, 7, -4, -6}; Plane Surface(2) = {2};
Physical Surface("part") = {1, 2};
"""
STEPS = 400


def plate(name, mesh):
    tu.write(name + ".geo", PLATE + mesh)
    scene = tu.write(name + ".xml", '<dtmap-scene version="1">\n  <geometry file="%s.geo"/>\n'
                     '  <meshing size="0.02" dim="2"/>\n'
                     '  <material name="steel" groups="part" E="200e9" nu="0.3" rho="7850"/>\n'
                     '  <section groups="part" kind="shell" thickness="0.004"/>\n'
                     '  <effects><elastic/></effects>\n  <time safety="0.9"/>\n</dtmap-scene>\n' % name)
    out, rep = tu.path(name + ".inp"), tu.path(name + ".json")
    code, text = tu.run("deck", scene, "--solver", "calculix", "-o", out, "--report", rep, "-q")
    if code:
        raise AssertionError("dtmap deck: exit %d\n%s" % (code, text))
    with open(out) as f:
        bound = float(re.search(r"^\*\* layer \S+ \(\w+\): element bound of its solids (\S+) s", f.read(), re.M).group(1))
    return out, tu.report(rep)["deck"]["step"], bound


def displacement(path, dt):
    name, _ = du.prepare(path, STEPS * dt, increment=dt)
    code, log, u, est, sel = du.run(CCX, name, fixed=dt, timeout=1800)
    if code or sel is None or abs(sel / dt - 1) > 1e-6:
        raise AssertionError("ccx did not run at the fixed increment %g (exit %d):\n%s" % (dt, code, log[-1500:]))
    return u


class Fixed(unittest.TestCase):
    def check(self, name, mesh, limit):
        path, step, bound = plate(name, mesh)
        ref = displacement(path, step / 2)
        self.assertTrue(0 < ref < float("inf"))
        at_step = displacement(path, step)
        self.assertLess(at_step, 1e3 * ref * 4, "%s: diverges at the deck's step %g" % (name, step))
        above = 1.05 * limit * bound
        u = displacement(path, above)
        self.assertFalse(u < 1e3 * ref * (above / (step / 2)) ** 2,
                         "%s: bounded at %g (%.3f x the deck's step)" % (name, above, above / step))

    def test_quads(self):
        self.check("quads", "Mesh.RecombineAll = 1;\n", 0.3406)

    def test_triangles(self):
        self.check("tris", "", 0.8406)

    def test_mixed(self):  # 45 S4 beside 78 S3: the S4 cap governs
        self.check("mixed", "Recombine Surface{1};\n", 0.3406)


if __name__ == "__main__":
    if not (CCX and os.access(CCX, os.X_OK)):
        print("skipped: DTM_CCX_FIXED does not name a fixed-increment ccx (bench/ccx_fixed_inc.sh builds one)")
        sys.exit(77)
    tu.main()
