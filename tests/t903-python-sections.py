"""Sections from Python: the bundled reinforced block (geometries/reinforced_block.geo:
a concrete box with four embedded rebars and an embedded plate) built here with
Gmsh's OpenCASCADE API, step for step as the .geo builds it, and meshed with the
scene's size on one thread:

- without sections, dtmap.analyse refuses the material on the rebar group, and
  the message gives the sections= entry a Python caller writes (not only the XML
  element);
- with sections=[{"groups": "rebar", "kind": "truss", "area": 3.1e-4},
  {"groups": "plate", "kind": "membrane", "thickness": 0.01}] (the scene's
  keys), the result is `dtmap run geometries/reinforced_block.xml`'s: the same
  elements, the same element steps and recommended step. The meshes are the
  same (Gmsh's Delaunay on one thread from the same entities), so the numbers
  are the same doubles: the element steps are compared with the run's dt view,
  whose ASCII values keep 17 digits (exact), the recommended step and element
  bound with the report, which cJSON prints to 15 digits when they read back
  within DBL_EPSILON (one unit in the last place);
- its report lists the two sections as the scene file's run does.
"""

import os
import shutil
import sys

import gmsh

import dtmap
import testutil as tu

EPS = sys.float_info.epsilon
MATERIALS = {"concrete": {"groups": "concrete", "E": 30e9, "nu": 0.2, "rho": 2400},
             "steel": {"groups": "rebar plate", "E": 200e9, "nu": 0.3, "rho": 7850}}
SECTIONS = [{"groups": "rebar", "kind": "truss", "area": 3.1e-4},
            {"groups": "plate", "kind": "membrane", "thickness": 0.01}]
TIME = {"safety": 0.9, "duration": 1e-3}


def build_block():
    """reinforced_block.geo through the API: W = 0.4, H = 1, cover 0.05, plate at z = 0.5."""
    occ = gmsh.model.occ
    w, h, c, zp, a = 0.4, 1.0, 0.05, 0.5, 0.1
    occ.addBox(0, 0, 0, w, w, h, 1)
    bars = []
    for x, y in ((c, c), (w - c, c), (w - c, w - c), (c, w - c)):
        bars.append(occ.addLine(occ.addPoint(x, y, c), occ.addPoint(x, y, h - c)))
    plate = occ.addRectangle(a, a, zp, w - 2 * a, w - 2 * a)
    occ.synchronize()
    gmsh.model.mesh.embed(1, bars, 3, 1)
    gmsh.model.mesh.embed(2, [plate], 3, 1)
    gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [1]), "concrete")
    gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, bars), "rebar")
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [plate]), "plate")
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.05)  # the scene's <meshing size>
    gmsh.model.mesh.generate(3)


class Sections(tu.unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for ext in ("geo", "xml"):
            shutil.copy(os.path.join(tu.SRC, "geometries", "reinforced_block." + ext), tu.tmpdir())
        code, out = tu.run("run", "reinforced_block.xml", "-q", "-o", "cli.msh", "--report", "cli.json")
        assert code == 0, out
        cls.cli = tu.report("cli.json")
        cls.cli_dt = tu.view_values(tu.path("cli.msh"), "dt")
        gmsh.initialize(["t903", "-v", "0"])
        build_block()

    @classmethod
    def tearDownClass(cls):
        gmsh.finalize()

    def test_without_sections_the_message_speaks_python(self):
        with self.assertRaises(dtmap.Error) as e:
            dtmap.analyse(materials=MATERIALS, effects=["elastic"], time=TIME, views=False)
        self.assertEqual(e.exception.code, 2)
        self.assertIn("sections=[{'groups': 'rebar', 'kind': 'truss', 'area': ...}]", str(e.exception))

    def test_with_sections_as_the_scene_file(self):
        r = dtmap.analyse(materials=MATERIALS, sections=SECTIONS, effects=["elastic"], time=TIME, views=False)
        self.assertEqual(len(r.dt), self.cli["mesh"]["elements"])
        self.assertEqual(sorted(int(t) for t in r.element_tags), sorted(self.cli_dt))
        for t, v in zip(r.element_tags, r.dt):
            self.assertEqual(v, self.cli_dt[int(t)], "element %d" % t)
        for mine, theirs in ((r.recommended, self.cli["dt"]["recommended"]), (r.dt_min, self.cli["dt"]["min"])):
            self.assertLessEqual(abs(mine - theirs), EPS * theirs)
        self.assertEqual(r.basis, self.cli["dt"]["basis"])
        r.write_report(tu.path("py.json"))
        kinds = lambda rep: [(s["kind"], s["groups"], s["elements"]) for s in rep["sections"]]
        self.assertEqual(kinds(tu.report("py.json")), kinds(self.cli))
        r.close()


if __name__ == "__main__":
    tu.main()
