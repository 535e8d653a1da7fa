"""The section report's physical step under the scaled convention, found
with the screen of dtm_analysis_rotary (issue 38: every 64th element of a
block solved whole first, the others' physical eigenproblem skipped where
a factorisation proves it below the largest of those), is the exact
minimum over the section, on the same element.

The bundled stiffened panel's geometry (geometries/stiffened_panel.geo) is
meshed at 2 cm (about 4e3 tri3 and 60 line2: the beams have one seed, the
shells dozens) and at 3 cm with quadrangles (Mesh.RecombineAll), and run
twice each: with the default scaled rotary inertia, and with
rotary="physical", where every element's step is its physical one, each
computed (the step needs it: no screen). For both sections the scaled
run's dt_physical_min must be the physical run's dt_min to 1e-12 (the
bound the issue puts on the map; both come from the same eigenproblems
by the same code, so they agree to rounding), and its physical_element the
physical run's element.
"""

import os
import shutil
import unittest

import testutil as tu

SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="%s"/>
  <meshing size="%s" order="1" dim="2"/>
  <material name="steel" groups="skin stiffener" E="200e9" nu="0.3" rho="7850"/>
  <section groups="skin" kind="shell" thickness="0.005" %s/>
  <section groups="stiffener" kind="beam" width="0.01" height="0.04" orientation="1 0 0" %s/>
  <effects><elastic/></effects>
  <output mesh="%s.msh" report="%s.json"/>
</dtmap-scene>
"""
MESHES = (("stiffened_panel.geo", "0.02"), ("quads.geo", "0.03"))


def run(geo, size, rotary):
    name = "%s_%s" % (geo.split(".")[0], rotary)
    attr = 'rotary="%s"' % rotary
    tu.write(name + ".xml", SCENE % (geo, size, attr, attr, name, name))
    code, out = tu.run("run", name + ".xml", "-q")
    if code:
        raise AssertionError("dtmap run %s: exit %d\n%s" % (name, code, out))
    return {s["kind"]: s for s in tu.report(name + ".json")["sections"]}


class Screen(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        panel = os.path.join(tu.tmpdir(), "stiffened_panel.geo")
        shutil.copy(os.path.join(tu.SRC, "geometries", "stiffened_panel.geo"), panel)
        with open(panel) as f, open(os.path.join(tu.tmpdir(), "quads.geo"), "w") as g:
            g.write(f.read() + "\nMesh.RecombineAll = 1;\n")
        cls.runs = {(geo, r): run(geo, size, r) for geo, size in MESHES for r in ("scaled", "physical")}

    def test_physical_minimum_is_exact(self):
        for geo, _ in MESHES:
            s, p = self.runs[(geo, "scaled")], self.runs[(geo, "physical")]
            self.assertGreater(s["shell"]["elements"], 20 * 64, geo + ": too few shells for the screen to act")
            for kind in ("shell", "beam"):
                ri = s[kind]["rotary_inertia"]
                got, want = ri["dt_physical_min"], p[kind]["dt_min"]
                self.assertLessEqual(abs(got - want), 1e-12 * want,
                                     "%s %s: %.17g against %.17g" % (geo, kind, got, want))
                self.assertEqual(ri["physical_element"], p[kind]["element"], "%s %s" % (geo, kind))


if __name__ == "__main__":
    tu.main()
