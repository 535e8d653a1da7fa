"""Units (docs/units.md): a STEP file in millimetres (tests/data/units/, a
10 x 20 x 30 mm box that Gmsh wrote; part_m.step is the same box in metres,
part_in.step the mm file's numbers declared in inches) is converted to
metres on import and gives the same step as the same part in metres; the
summary and the report say which unit was found and the factor applied.
unit="mm" on a .msh scales its nodes; units="mm-t-s" gives the same step as
SI for steel; E in MPa beside rho in kg/m^3, said to be meant
(plausible="no-check"), is warned about, naming the material (t381 has the
refusal without it); a scene unit that contradicts a STEP's is exit 2; the mass of a unit steel cube is 7850 kg (closed form, rho V)
with its bounding box; bad unit values are exit 2 naming the file and line;
a BREP in mm with a size in metres is refused for memory with the unit
that makes it sensible.

Tolerances: the converted and the metre geometry are the same to rounding
(x 0.001 in OpenCASCADE), Gmsh meshes both into the same element count and
the steps agree to 1e-9 (rounding of coordinates near 1e-16 relative moves
a step by about that much; 1e-9 leaves room for the eigen solver's
convergence tolerance on slightly different numbers). The .msh scaled by
dtmap or written in metres differ by one rounding per coordinate: steps
agree to 1e-12. The mass of the 6 Kuhn tetrahedra (1/6 m^3 each) is exact
but for rounding: 1e-12."""

import gzip
import itertools
import os
import shutil

import testutil as tu

DATA = os.path.join(tu.SRC, "tests", "data", "units")


def step_scene(name, part, extra="", size="0.004"):
    return tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="%s"%s/>
  <meshing size="%s"/>
  <material name="steel" E="210e9" nu="0.3" rho="7850" default="true"/>
  <effects><elastic/></effects>
</dtmap-scene>
""" % (os.path.join(DATA, part), extra, size))


def cube_msh(name, scale):
    """The unit cube as 6 Kuhn tetrahedra (positive volume), coordinates x
    scale; tetrahedra 1-3 in group 'a', 4-6 in 'b'."""
    corner = [(i & 1, (i >> 1) & 1, (i >> 2) & 1) for i in range(8)]
    tets = []
    for p in itertools.permutations(range(3)):
        path = [0, 1 << p[0], (1 << p[0]) | (1 << p[1]), 7]
        x = [corner[i] for i in path]
        d = [[x[k][c] - x[0][c] for c in range(3)] for k in (1, 2, 3)]
        det = (d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
               + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]))
        if det < 0:
            path[1], path[2] = path[2], path[1]
        tets.append(path)
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "2", '3 1 "a"', '3 2 "b"',
             "$EndPhysicalNames", "$Nodes", "8"]
    lines += ["%d %.17g %.17g %.17g" % (i + 1, scale * c[0], scale * c[1], scale * c[2]) for i, c in enumerate(corner)]
    lines += ["$EndNodes", "$Elements", "6"]
    lines += ["%d 4 2 %d %d %s" % (k + 1, 1 + k // 3, 1 + k // 3, " ".join(str(v + 1) for v in t))
              for k, t in enumerate(tets)]
    lines += ["$EndElements", ""]
    return tu.write(name + ".msh", "\n".join(lines))


def cube_scene(name, msh, unit="", units="", E="210e9", rho="7850"):
    return tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1"%s>
  <mesh file="%s"%s/>
  <material name="steel" groups="a b" E="%s" nu="0.3" rho="%s"/>
  <effects><elastic/></effects>
</dtmap-scene>
""" % (units, msh, unit, E, rho))


def run(name):
    code, log = tu.run("run", name + ".xml", "-o", name + "_dt.msh", "--report", name + "_dt.json")
    return code, log, (tu.report(name + "_dt.json") if code == 0 else None)


class Units(tu.unittest.TestCase):
    def test_step_in_mm_runs_as_metres(self):
        step_scene("mm", "part_mm.step")
        step_scene("m", "part_m.step")
        code, log, mm = run("mm")
        self.assertEqual(code, 0, log)
        code, _, m = run("m")
        self.assertEqual(code, 0)
        self.assertIn("unit mm found in the file: coordinates x 0.001 into m", log)
        self.assertEqual(mm["mesh"]["elements"], m["mesh"]["elements"])
        self.assertAlmostEqual(mm["dt"]["recommended"] / m["dt"]["recommended"], 1.0, delta=1e-9)
        self.assertAlmostEqual(mm["dt"]["min"] / m["dt"]["min"], 1.0, delta=1e-9)
        self.assertEqual(mm["model"]["import"], {"unit_found": "mm", "factor": 0.001})
        self.assertEqual(m["model"]["import"]["unit_found"], "m")
        for got, want in zip(mm["model"]["bbox"]["extent"], (0.01, 0.02, 0.03)):
            self.assertAlmostEqual(got, want, delta=1e-12)
        self.assertAlmostEqual(mm["model"]["mass"], 7850 * 6e-6, delta=1e-12)  # rho V of the box

    def test_step_in_inches_and_override(self):
        step_scene("in", "part_in.step", size="0.05")
        code, log, r = run("in")
        self.assertEqual(code, 0, log)
        self.assertEqual(r["model"]["import"]["unit_found"], "in")
        for got, want in zip(r["model"]["bbox"]["extent"], (0.254, 0.508, 0.762)):
            self.assertAlmostEqual(got, want, delta=1e-12)
        step_scene("over", "part_in.step", ' unit="mm"')  # a scene unit that contradicts the file's: refused
        code, log = tu.run("run", "over.xml", "-q", "-o", "over_dt.msh")
        self.assertEqual(code, 2, log)
        self.assertIn('over.xml:3: <geometry unit="mm"> contradicts the unit the file declares, in', log)
        self.assertIn('remove unit="mm"', log)
        self.assertFalse(os.path.exists(tu.path("over_dt.msh")))
        step_scene("same", "part_in.step", ' unit="in"', size="0.05")  # the same unit: allowed
        code, log, r = run("same")
        self.assertEqual(code, 0, log)
        self.assertEqual(r["model"]["import"]["unit_given"], "in")

    def test_iges(self):
        """A 10-unit line in IGES files whose global section says mm (flag
        2) and inches (flag 1), a steel truss of 1 cm^2 meshed at 1 mm:
        mass rho A L (closed form), and the same step, one segment's h/c
        (the nodal bound of a uniform bar with lumped mass; Gmsh's
        segments are equal to rounding, so 1e-6 is loose)."""
        for part, length, unit in (("line_mm.igs", 0.01, "mm"), ("line_in.igs", 0.254, "in")):
            tu.write(unit + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="%s"/>
  <meshing size="0.001"/>
  <material name="steel" E="210e9" nu="0.3" rho="7850" default="true"/>
  <section kind="truss" area="1e-4" default="true"/>
  <effects><elastic/></effects>
</dtmap-scene>
""" % os.path.join(DATA, part))
            code, log, r = run(unit)
            self.assertEqual(code, 0, log)
            self.assertEqual(r["model"]["import"]["unit_found"], unit)
            self.assertAlmostEqual(r["model"]["bbox"]["extent"][0], length, delta=1e-12)
            self.assertAlmostEqual(r["model"]["mass"], 7850 * 1e-4 * length, delta=1e-12)
            self.assertEqual(r["mesh"]["elements"], round(length / 0.001))
            c = (210e9 / 7850) ** 0.5  # the bar's wave speed
            self.assertAlmostEqual(r["dt"]["basis_step"] / (0.001 / c), 1.0, delta=1e-6)

    def test_msh_unit_mm(self):
        cube_scene("cm_mm", cube_msh("cube_mm", 1000.0), ' unit="mm"')
        cube_scene("cm_m", cube_msh("cube_m", 1.0))
        cube_scene("cm_raw", tu.path("cube_mm.msh"))
        _, log, a = run("cm_mm")
        self.assertIsNotNone(a, log)
        _, _, b = run("cm_m")
        _, _, raw = run("cm_raw")
        self.assertAlmostEqual(a["dt"]["recommended"] / b["dt"]["recommended"], 1.0, delta=1e-12)
        self.assertAlmostEqual(raw["dt"]["recommended"] / b["dt"]["recommended"], 1000.0, delta=1e-9)
        self.assertEqual(a["model"]["import"], {"unit_given": "mm", "factor": 0.001})
        self.assertEqual(a["model"]["bbox"]["max"], [1.0, 1.0, 1.0])
        self.assertEqual(raw["warnings"], [])  # 1 km across: not larger than 1 km
        cube_scene("big", cube_msh("big", 2000.0))  # a mesh in mm read as metres
        _, _, big = run("big")
        self.assertTrue(any("the model is 2000 m across, larger than 1 km" in w for w in big["warnings"]),
                        big["warnings"])

    def test_mm_t_s_same_step_as_si(self):
        cube_scene("si", cube_msh("c_si", 1.0))
        cube_scene("mts", cube_msh("c_mm", 1000.0), units=' units="mm-t-s"', E="210000", rho="7.85e-9")
        _, _, si = run("si")
        code, log, mts = run("mts")
        self.assertEqual(code, 0, log)
        self.assertAlmostEqual(mts["dt"]["recommended"] / si["dt"]["recommended"], 1.0, delta=1e-12)
        self.assertEqual(mts["model"]["units"], "mm-t-s")
        self.assertAlmostEqual(mts["model"]["mass"], 7.85, delta=7.85e-12)  # tonnes
        self.assertEqual(mts["warnings"], [])
        self.assertIn("units        mm-t-s", log)
        # a mesh in metres in an mm-t-s scene: unit="m" scales it by 1000
        cube_scene("mts_m", tu.path("c_si.msh"), ' unit="m"', ' units="mm-t-s"', "210000", "7.85e-9")
        _, _, mm = run("mts_m")
        self.assertAlmostEqual(mm["dt"]["recommended"] / si["dt"]["recommended"], 1.0, delta=1e-12)

    def test_modulus_in_mpa_is_flagged(self):
        cube_scene("mpa", cube_msh("c1", 1.0), E='210e3" plausible="no-check')  # meant: a warning, not a refusal
        code, log, r = run("mpa")
        self.assertEqual(code, 0, log)
        w = [x for x in r["warnings"] if "material 'steel'" in x and "wave speed" in x]
        self.assertEqual(len(w), 1, r["warnings"])
        self.assertIn("6.001 m/s", w[0])  # sqrt(210e3 (0.7/(1.3 x 0.4)) / 7850)
        self.assertIn("WARNING: material 'steel'", log)
        code, log = tu.run("run", "mpa.xml", "-q", "-o", "mpa_q.msh")  # quiet: on stderr all the same
        self.assertEqual(code, 0, log)
        self.assertIn("dtmap: warning: material 'steel' (line 4): dilatational wave speed 6.001 m/s", log)
        cube_scene("rho", cube_msh("c2", 1.0), rho="7.85e-3")  # g/mm^3 taken as kg/m^3: rho too low (and c high)
        _, _, r = run("rho")
        self.assertTrue(any("material 'steel' (line 4): density rho = 0.00785 kg/m^3" in x for x in r["warnings"]),
                        r["warnings"])

    def test_unit_cube_mass_and_bbox(self):
        cube_scene("cube", cube_msh("cube", 1.0))
        code, log, r = run("cube")
        self.assertEqual(code, 0, log)
        self.assertAlmostEqual(r["model"]["mass"], 7850.0, delta=7850e-12)
        groups = {g["group"]: g["mass"] for g in r["model"]["groups"]}
        self.assertEqual(sorted(groups), ["a", "b"])
        for g in groups.values():
            self.assertAlmostEqual(g, 3925.0, delta=3925e-12)
        self.assertEqual(r["model"]["bbox"], {"min": [0, 0, 0], "max": [1, 1, 1], "extent": [1, 1, 1]})
        self.assertIn("model        mass 7850 kg", log)
        self.assertEqual(r["warnings"], [])

    def test_bad_values(self):
        msh = cube_msh("cb", 1.0)
        for name, units, unit, line in (("b1", ' units="cgs"', "", 2), ("b2", "", ' unit="ft"', 3)):
            cube_scene(name, msh, unit, units)
            code, log = tu.run("run", name + ".xml", "-q")
            self.assertEqual(code, 2, log)
            self.assertIn("%s.xml:%d:" % (name, line), log)
        geo = tu.write("g.geo", "Point(1) = {0, 0, 0};\n")
        tu.write("b3.xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="%s" unit="mm"/>
  <material name="steel" E="210e9" nu="0.3" rho="7850" default="true"/>
  <effects><elastic/></effects>
</dtmap-scene>
""" % geo)
        code, log = tu.run("run", "b3.xml", "-q")
        self.assertEqual(code, 2, log)
        self.assertIn("b3.xml:3: <geometry> unit=\"mm\" on the .geo file", log)

    def test_size_in_another_unit(self):
        step_scene("s4", "part_mm.step", size="4")  # 4 mm meant, 4 m read, on a 3 cm part
        code, log, r = run("s4")
        self.assertEqual(code, 0, log)
        self.assertTrue(any('<meshing size="4"> (line 4) is 133 times the model\'s extent, 0.03 m: sizes are in m' in w
                            and 'size="0.004"' in w for w in r["warnings"]), r["warnings"])

    def test_gmsh_component8(self):
        """Gmsh's demos/boolean/component8.step (gmsh-doc), in mm: meshed at 3 mm."""
        src = "/usr/share/doc/gmsh-doc/doc/gmsh/demos/boolean/component8.step"
        if os.path.exists(src):
            shutil.copy(src, tu.path("component8.step"))
        else:
            with gzip.open(src + ".gz", "rb") as z, open(tu.path("component8.step"), "wb") as out:
                shutil.copyfileobj(z, out)
        step_scene("c8", "", size="0.003")
        with open(tu.path("c8.xml")) as f:
            tu.write("c8.xml", f.read().replace(os.path.join(DATA, ""), tu.path("component8.step")))
        code, log, r = run("c8")
        self.assertEqual(code, 0, log)
        self.assertEqual(r["model"]["import"], {"unit_found": "mm", "factor": 0.001})
        for got, want in zip(r["model"]["bbox"]["extent"], (0.03695, 0.03263, 0.032)):
            self.assertAlmostEqual(got, want, delta=1e-5)  # the part is 36.95 x 32.63 x 32 mm
        self.assertEqual(r["warnings"], [])

    def test_memory_refusal_names_the_unit(self):
        step_scene("brep", "part_mm.brep")
        code, log = tu.run("run", "brep.xml", "-q")
        self.assertEqual(code, 2, log)
        self.assertIn("looks like mm taken as metres: with <geometry unit=\"mm\">", log)
        step_scene("brep_mm", "part_mm.brep", ' unit="mm"')
        code, log, r = run("brep_mm")
        self.assertEqual(code, 0, log)
        self.assertAlmostEqual(r["model"]["bbox"]["extent"][2], 0.03, delta=1e-12)


if __name__ == "__main__":
    tu.main()
