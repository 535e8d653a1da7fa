"""`dtmap verify --selective-mass` (issue 44 item 6; src/spectral/sms_verify.c):
central differences on (K, M_s) with a PCG mass solve every step.

Three Gmsh-meshed models, the bundled steel box (coarsened to 20 mm), a
block with a 0.8 mm layer fused on its top (the geometry of t926) and the
bundled aluminium plate with a hole in plane stress (2D: two components
per node; coarsened to 10 mm, 3 mm at the hole, about 1,500 triangles),
each at a target 3x the input's recommended step (the layer's elements get
beta up to about 10):

- at the target the run is bounded (growth below 10 over 1000 steps: a
  stable run's discrete energy wanders by a few units at most, an
  unstable one passes 1e6 within a few dozen steps), exit 0;
- at 1.05x the scaled model's proven global step it grows past 1e6
  (UNSTABLE, exit 1): the proven step is within 1e-4 of the exact one
  (t926), so 1.05x lies above the exact critical step;
- the summary names the step as a multiple of the proven global step.
"""

import re
import shutil
import os

import testutil as tu
from slab import GEO

SLAB = """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="slab.geo"/>
<meshing dim="3" size="5e-3"/>
<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
<effects><elastic formulation="3d"/></effects>
<time duration="1e-4"/>
</dtmap-scene>
"""

STEPS = 1000


def models():
    tu.write("slab.geo", GEO)
    tu.write("slab.xml", SLAB)
    for ext in ("geo", "xml"):
        shutil.copy(os.path.join(tu.SRC, "geometries", "box." + ext), tu.tmpdir())
    with open(tu.path("box.xml")) as f:
        text = f.read().replace('size="8e-3"', 'size="2e-2"')
    tu.write("box.xml", text)
    for ext in ("geo", "xml"):
        shutil.copy(os.path.join(tu.SRC, "geometries", "plate_with_hole." + ext), tu.tmpdir())
    with open(tu.path("plate_with_hole.xml")) as f:
        text = f.read()
    coarse = text.replace('size="5e-3" min-size="1e-3"', 'size="1e-2" min-size="3e-3"')
    assert coarse != text, "geometries/plate_with_hole.xml: its <meshing> changed; update t927"
    tu.write("plate_with_hole.xml", coarse)
    return ["slab", "box", "plate_with_hole"]


class Verify(tu.unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.names = models()

    def verify(self, name, target, *extra):
        return tu.run("verify", name + ".xml", "--selective-mass", "--target", "%.9e" % target, "--steps", STEPS,
                      *extra)

    def test_bounded_then_growing(self):
        for name in self.names:
            step = tu.run_dt(name)["recommended"]
            code, log = self.verify(name, 3 * step)
            self.assertEqual(code, 0, log)
            growth = float(re.search(r"growth \(largest .*?\) ([0-9.e+-]+): stable", log).group(1))
            factor = float(re.search(r"= ([0-9.]+)x the scaled model's global step .*\(proven", log).group(1))
            print("%s at the target 3x = %.4e s: %.3fx the proven step, growth %.3g" % (name, 3 * step, factor, growth))
            self.assertLess(growth, 10)
            self.assertLess(factor, 1)
            code, log = self.verify(name, 3 * step, "--factor", "1.05")
            self.assertEqual(code, 1, log)
            self.assertIn("UNSTABLE", log)
            self.assertIn("1.0500x the scaled model's global step", log)

    def test_usage(self):
        for extra in (("--accuracy",), ("--report", "v.json"), ("--posterior",)):
            code, log = tu.run("verify", "slab.xml", "--selective-mass", "--target", "1e-7", *extra)
            self.assertEqual(code, 2, log)
            self.assertIn("--selective-mass checks the scaled model's stability alone", log)


if __name__ == "__main__":
    tu.main()
