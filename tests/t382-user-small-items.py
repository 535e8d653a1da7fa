"""The smaller things a user hits (issue 43, item 8), each failing on the
dtmap before it:
- an error lands after the summary it follows, on a line of its own, with
  stdout and stderr in one file (`> log 2>&1`): stdout was block-buffered
  and the error came first or mid-word;
- `refine -o X.msh` (and `run -o X.msh`) writes the report the scene's
  <output report> asks for as X.json, so two meshes keep a report each;
- `--solver ls-dyna` (deck) and `--solver-rule LS-DYNA` (run) say did you
  mean lsdyna;
- `<material unit="MPa">` names <dtmap-scene units="mm-t-s"> as the way,
  not "not a number";
- `snapshot nosuch.msh` says the file does not exist;
- refine's `applied` column names every --optimise pass a remesh ran
  (gmsh's was shown nowhere), and a pass that ran in no remesh (netgen,
  which Debian's Gmsh is built without) is said to have changed nothing;
- a 2.2 um CAD sliver (two boxes stacked 2.2 um apart in x, fused) that
  caps the step about 1000x below the bulk gets a WARNING naming the worst
  element and its model entities; a plain box gets none;
- the worst element is marked in PREFIX_worst.png: a red ring (about 400
  pixels of pure red, in a box of at most 45 x 45 pixels: a ring of 16
  pixels' radius, 4 wide) on the bundled plate with a hole (2D) and on the
  sliver (3D); the pictures held no red before (viridis and a faint dt)."""

import os
import re
import shutil
import struct
import zlib

import testutil as tu

GEO = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.1, 0.1};
Physical Volume("block") = {1};
"""


def scene(name, material='E="210e9" nu="0.3" rho="7850"', extra=""):
    tu.write("box.geo", GEO)
    return tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="box.geo"/>
  <meshing size="0.04"/>
  <material name="steel" groups="block" %s/>
  <effects><elastic/></effects>
  %s
</dtmap-scene>
""" % (material, extra))


def png_rgb(path):
    """(width, height, rows of bytes, bytes per pixel) of an 8-bit RGB(A) PNG (Gmsh's), decoded here."""
    with open(path, "rb") as f:
        d = f.read()
    pos, idat = 8, b""
    while pos < len(d):
        n, t = struct.unpack(">I4s", d[pos:pos + 8])
        c = d[pos + 8:pos + 8 + n]
        pos += 12 + n
        if t == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", c[:10])
        elif t == b"IDAT":
            idat += c
    assert depth == 8 and ctype in (2, 6)
    raw, bpp = zlib.decompress(idat), 3 if ctype == 2 else 4
    stride, rows, prev, i = w * bpp, [], bytearray(w * bpp), 0
    for _ in range(h):
        kind, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a, b, c = line[x - bpp] if x >= bpp else 0, prev[x], prev[x - bpp] if x >= bpp else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, rows, bpp


def red_pixels(path):
    w, h, rows, bpp = png_rgb(path)
    return [(x, y) for y in range(h) for x in range(w)
            if rows[y][bpp * x] > 180 and rows[y][bpp * x + 1] < 110 and rows[y][bpp * x + 2] < 80]


def gmsh_build_options():
    import gmsh
    gmsh.initialize(["t382", "-v", "0"])
    try:
        return gmsh.option.getString("General.BuildOptions")
    finally:
        gmsh.finalize()


def recommended(name):
    code, log = tu.run("run", name + ".xml", "-q", "-o", name + "_probe.msh", "--report", name + "_probe.json")
    assert code == 0, log
    return tu.report(name + "_probe.json")["dt"]["recommended"]


class Small(tu.unittest.TestCase):
    def test_error_after_the_summary(self):
        scene("flush")
        target = 50 * recommended("flush")  # no remesh reaches it in one round
        code, log = tu.run("refine", "flush.xml", "--target", "%.6e" % target, "--max-iter", "1", "-o", "flush_r.msh")
        self.assertEqual(code, 1, log)
        lines = log.splitlines()
        errors = [i for i, l in enumerate(lines) if "dtmap: error:" in l]
        self.assertEqual(len(errors), 1, log)
        self.assertTrue(lines[errors[0]].startswith("dtmap: error: refine: the target"), lines[errors[0]])
        self.assertTrue(any(l.startswith("round") for l in lines[:errors[0]]), log)  # the table came first
        self.assertTrue(any(l.startswith("wrote ") for l in lines[:errors[0]]), log)

    def test_report_named_after_o(self):
        scene("rep", extra='<output report="rep_out.json"/>')
        target = 0.5 * recommended("rep")  # met by the input: no remesh
        for out in ("a", "b"):
            code, log = tu.run("refine", "rep.xml", "--target", "%.6e" % target, "-q", "-o", out + ".msh")
            self.assertEqual(code, 0, log)
            self.assertTrue(os.path.exists(tu.path(out + ".json")), log)
        self.assertFalse(os.path.exists(tu.path("rep_out_refined.json")))
        self.assertEqual(tu.report("a.json")["mesh"]["elements"], tu.report("b.json")["mesh"]["elements"])

    def test_solver_did_you_mean(self):
        scene("solver")
        code, log = tu.run("deck", "solver.xml", "--solver", "ls-dyna")
        self.assertEqual(code, 2, log)
        self.assertIn("unknown solver 'ls-dyna': did you mean lsdyna?", log)
        code, log = tu.run("run", "solver.xml", "--solver-rule", "calculix,LS-DYNA")
        self.assertEqual(code, 2, log)
        self.assertIn("'LS-DYNA' is not a solver (did you mean lsdyna?)", log)
        code, log = tu.run("deck", "solver.xml", "--solver", "nastran")
        self.assertEqual(code, 2, log)
        self.assertNotIn("did you mean", log)

    def test_material_unit_attribute(self):
        scene("unit", 'E="210000" nu="0.3" rho="7.85e-9" unit="MPa"')
        code, log = tu.run("run", "unit.xml", "-q")
        self.assertEqual(code, 2, log)
        self.assertIn("unit.xml:5: material 'steel': unit=\"MPa\" is no attribute of <material>", log)
        self.assertIn('<dtmap-scene units="mm-t-s">', log)
        self.assertNotIn("not a number", log)

    def test_optimise_shown(self):
        scene("opt")
        target = 1.3 * recommended("opt")
        code, log = tu.run("refine", "opt.xml", "--target", "%.6e" % target, "--max-iter", "2", "--optimise",
                           "gmsh,netgen", "-o", "opt_r.msh", "--report", "opt_r.json")
        self.assertIn(code, (0, 1), log)
        rounds = [l for l in log.splitlines() if l.strip().startswith(("1 ", "2 ")) and ("nodal" in l or "elem." in l)]
        self.assertTrue(rounds, log)
        for l in rounds:
            self.assertTrue(l.rstrip().split("  target met")[0].split("  (kept)")[0].endswith(", gmsh"), l)
        rep = tu.report("opt_r.json")["refine"]["rounds"]
        self.assertTrue(all(r["optimisers"] == ["gmsh"] for r in rep if r["kind"] == "mesh"), rep)
        gmsh_has_netgen = "Netgen" in gmsh_build_options()
        if not gmsh_has_netgen:
            self.assertIn("--optimise netgen: changed nothing, it ran in no remesh (Netgen is not built into this "
                          "Gmsh", log)

    def test_sliver_warning(self):
        tu.write("sliver.geo", """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.1, 0.05};
Box(2) = {2.2e-6, 0, 0.05, 0.1, 0.1, 0.05};
BooleanUnion(3) = {Volume{1}; Delete;}{Volume{2}; Delete;};
Physical Volume("block") = {3};
""")
        with open(scene("sliver")) as f:
            tu.write("sliver.xml", f.read().replace("box.geo", "sliver.geo").replace('size="0.04"', 'size="0.008"'))
        code, log = tu.run("run", "sliver.xml", "-o", "sliver_dt.msh", "--report", "sliver_dt.json")
        self.assertEqual(code, 0, log)
        w = [x for x in tu.report("sliver_dt.json")["warnings"] if "caps the step" in x]
        self.assertEqual(len(w), 1, log)
        self.assertRegex(w[0], r"^element \d+ \(tet4\) in group 'block' at \(.*\) m caps the step: ")
        ratio = float(re.search(r"s, ([0-9.e+]+)x below the 1 % quantile", w[0]).group(1))
        self.assertGreater(ratio, 100)  # the sliver's tets are micrometres thick, the bulk's millimetres
        self.assertIn("in model volume 3", w[0])
        self.assertIn("surface", w[0])
        self.assertIn("WARNING: " + w[0][:60], log)
        code, log = tu.run("run", scene("plain"), "-o", "plain_dt.msh")
        self.assertEqual(code, 0, log)
        self.assertNotIn("caps the step", log)

    def test_worst_element_ringed(self):
        for f in ("plate_with_hole.xml", "plate_with_hole.geo"):
            shutil.copy(os.path.join(tu.SRC, "geometries", f), tu.path(f))
        code, log = tu.run("run", "plate_with_hole.xml", "-q", "-o", "ph.msh", "--png", "ph")
        self.assertEqual(code, 0, log)
        pictures = [tu.path("ph_worst.png")]
        if os.path.exists(tu.path("sliver_dt.msh")):  # the 3D sliver of test_sliver_warning, when it ran first
            code, log = tu.run("snapshot", "sliver_dt.msh", "-q", "--png", "sl")
            self.assertEqual(code, 0, log)
            pictures.append(tu.path("sl_worst.png"))
        for png in pictures:
            red = red_pixels(png)
            self.assertGreater(len(red), 150, png)
            xs, ys = [p[0] for p in red], [p[1] for p in red]
            self.assertLessEqual(max(xs) - min(xs), 45, png)
            self.assertLessEqual(max(ys) - min(ys), 45, png)
        self.assertLess(len(red_pixels(tu.path("ph_dt.png"))), 20)  # the dt picture stays unmarked

    def test_snapshot_of_a_missing_file(self):
        code, log = tu.run("snapshot", "nosuch.msh")
        self.assertEqual(code, 2, log)
        self.assertIn("nosuch.msh: no such file", log)


if __name__ == "__main__":
    tu.main()
