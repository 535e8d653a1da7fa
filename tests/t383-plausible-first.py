"""Plausibility first (issue 43, item 2; docs/units.md):
- material values no solid has (src/scene/plausible.c) are refused when the
  scene is read, before any output: E in MPa beside rho in kg/m^3 in an SI
  scene (a steel's wave speed 6.001 m/s), rho = 2700 in an mm-t-s scene
  (2.7e15 kg/m^3), each naming the scene's line, the likely slip and the
  values it means; a wave speed 1000x outside what solids have, whatever the
  cause; plausible="no-check" on the <material> or on <dtmap-scene> lets
  them through as warnings;
- those warnings stand right under the summary's model line, before any
  result, and in the report's warnings[];
- Python's dtmap.analyse raises on the same errors and returns the same
  warnings in Result.warnings;
- a <geometry unit> that contradicts the unit a STEP file declares is exit 2
  naming both; a STEP whose unit is a named multiple of the millimetre
  ('TEN MM' = 10 mm) is said to be so, with the factor applied (x 0.01).
Each check fails on the dtmap before issue 43's item 2.

Figures: c = sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu)) / rho); for E = 210e3,
nu = 0.3, rho = 7850: 6.001 m/s (4 digits printed). The 10 mm box is the
10 x 20 x 30 box of tests/data/units/ in units of 10 mm: 0.1 x 0.2 x 0.3 m,
to OpenCASCADE's rounding (1e-12 m)."""

import os

import gmsh

import dtmap
import testutil as tu

DATA = os.path.join(tu.SRC, "tests", "data", "units")
GEO = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.1, 0.1};
Physical Volume("block") = {1};
"""


def scene(name, material, units="", geometry=None):
    tu.write("box.geo", GEO)
    return tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1"%s>
  <geometry file="%s"/>
  <meshing size="%s"/>
  <material name="steel" groups="block" nu="0.3" %s/>
  <effects><elastic/></effects>
</dtmap-scene>
""" % (units, geometry or "box.geo", "50" if "mm-t-s" in units else "0.05", material))


def run(name):
    code, log = tu.run("run", name + ".xml", "-o", name + "_dt.msh", "--report", name + "_dt.json")
    return code, log


class Refused(tu.unittest.TestCase):
    def refused(self, name, *says):
        code, log = run(name)
        self.assertEqual(code, 2, log)
        for s in says:
            self.assertIn(s, log)
        self.assertIn('add plausible="no-check" to the <material>', log)
        for f in (name + "_dt.msh", name + "_dt.msh.opt", name + "_dt.json"):
            self.assertFalse(os.path.exists(tu.path(f)), f)  # before any output
        return log

    def test_modulus_in_mpa(self):
        scene("mpa", 'E="210e3" rho="7850"')
        self.refused("mpa", "mpa.xml:5: material 'steel': rho = 7850 kg/m^3 and E = 210000 Pa give a dilatational "
                     "wave speed of 6.001 m/s, which no solid has", "E looks like MPa", 'write E="2.1e+11"')

    def test_density_in_kg_per_m3_under_mm_t_s(self):
        scene("rho", 'E="70000" rho="2700"', ' units="mm-t-s"')
        self.refused("rho", "rho.xml:5: material 'steel': rho = 2700 t/mm^3 (2.7e+15 kg/m^3)",
                     "rho looks like kg/m^3, and this mm-t-s scene takes rho in t/mm^3", 'write rho="2.7e-09"')

    def test_whole_material_in_mm_t_s_in_an_si_scene(self):
        scene("mts", 'E="210000" rho="7.85e-9"')
        self.refused("mts", 'E and rho look like mm-t-s values (MPa, t/mm^3): declare the scene\'s system, '
                     '<dtmap-scene units="mm-t-s">', 'write E="2.1e+11" rho="7850"')

    def test_far_outside_whatever_the_cause(self):
        scene("far", 'E="1e20" rho="7850"')  # c = 1.3e8 m/s, 6500x diamond's
        self.refused("far", "1000 times or more outside what solids have")

    def test_bad_word(self):
        scene("word", 'E="210e9" rho="7850" plausible="maybe"')
        code, log = run("word")
        self.assertEqual(code, 2, log)
        self.assertIn("word.xml:5:", log)


class Meant(tu.unittest.TestCase):
    def test_warning_under_the_model_line(self):
        for name, material, units in (("m1", 'E="210e3" rho="7850" plausible="no-check"', ""),
                                      ("m2", 'E="210e3" rho="7850"', ' plausible="no-check"')):
            scene(name, material, units)
            code, log = run(name)
            self.assertEqual(code, 0, log)
            lines = log.splitlines()
            model = next(i for i, l in enumerate(lines) if l.startswith("model "))
            self.assertTrue(lines[model + 1].startswith("WARNING: material 'steel' (line 5): dilatational wave "
                                                        "speed 6.001 m/s"), lines[model:model + 3])
            first_result = next(i for i, l in enumerate(lines) if l.startswith("recommended"))
            self.assertGreater(first_result, model + 1)
            self.assertEqual(log.count("dilatational wave speed 6.001 m/s"), 1, log)  # once: not again at the end
            w = tu.report(name + "_dt.json")["warnings"]
            self.assertTrue(any("dilatational wave speed 6.001 m/s" in x for x in w), w)

    def test_plausible_steel_has_no_warning(self):
        scene("ok", 'E="210e9" rho="7850"')
        code, log = run("ok")
        self.assertEqual(code, 0, log)
        self.assertNotIn("WARNING", log)


class Python(tu.unittest.TestCase):
    def setUp(self):
        gmsh.initialize(["t381", "-v", "0"])
        gmsh.model.add("box")
        gmsh.model.occ.addBox(0, 0, 0, 0.1, 0.1, 0.1)
        gmsh.model.occ.synchronize()
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [1]), "block")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.05)
        gmsh.model.mesh.generate(3)

    def tearDown(self):
        gmsh.finalize()

    def material(self, **extra):
        m = {"groups": "block", "E": 210e3, "nu": 0.3, "rho": 7850}
        m.update(extra)
        return {"steel": m}

    def test_raises_on_the_same_error(self):
        with self.assertRaises(dtmap.Error) as e:
            dtmap.analyse(materials=self.material(), effects=["elastic"], views=False)
        self.assertEqual(e.exception.code, 2)
        self.assertIn("E looks like MPa", str(e.exception))

    def test_returns_the_same_warnings(self):
        r = dtmap.analyse(materials=self.material(plausible="no-check"), effects=["elastic"], views=False)
        self.assertTrue(any("dilatational wave speed 6.001 m/s" in w for w in r.warnings), r.warnings)
        self.assertTrue(r.warnings[0].startswith("material 'steel'"), r.warnings)
        ok = dtmap.analyse(materials=self.material(E=210e9), effects=["elastic"], views=False)
        self.assertEqual(ok.warnings, [])


class FileUnits(tu.unittest.TestCase):
    def test_scene_unit_contradicts_the_step(self):
        for part, unit, declared in (("part_m.step", "mm", "m"), ("part_mm.step", "m", "mm")):
            name = "c_" + declared
            scene(name, 'E="210e9" rho="7850"', geometry='%s" unit="%s' % (os.path.join(DATA, part), unit))
            code, log = run(name)
            self.assertEqual(code, 2, log)
            self.assertIn('%s.xml:3: <geometry unit="%s"> contradicts the unit the file declares, %s:'
                          % (name, unit, declared), log)
            self.assertIn('remove unit="%s"' % unit, log)
            self.assertFalse(os.path.exists(tu.path(name + "_dt.msh")))

    def test_named_multiple_of_the_millimetre(self):
        with open(os.path.join(DATA, "part_in.step")) as f:
            text = f.read()
        text = text.replace("CONVERSION_BASED_UNIT('INCH',#900)", "CONVERSION_BASED_UNIT('TEN MM',#900)")
        text = text.replace("LENGTH_MEASURE(25.4)", "LENGTH_MEASURE(10.)")
        self.assertIn("'TEN MM'", text)
        tu.write("part_10mm.step", text)
        scene("ten", 'E="210e9" rho="7850"', geometry=tu.path("part_10mm.step"))
        with open(tu.path("ten.xml")) as f:
            tu.write("ten.xml", f.read().replace('groups="block"', 'default="true"').replace("0.05", "0.02"))
        code, log = run("ten")
        self.assertEqual(code, 0, log)
        self.assertIn("import       unit 10 mm found in the file: coordinates x 0.01 into m", log)
        r = tu.report("ten_dt.json")
        self.assertAlmostEqual(r["model"]["import"]["factor"], 0.01, delta=1e-15)
        for got, want in zip(r["model"]["bbox"]["extent"], (0.1, 0.2, 0.3)):
            self.assertAlmostEqual(got, want, delta=1e-12)


if __name__ == "__main__":
    tu.main()
