"""Debian's CalculiX 2.20 (ccx) runs the deck `dtmap deck --solver calculix`
writes for every bundled example (geometries/*.xml) to its end: the deck's
two include slots are opened, with a seeded random force at every node from
the start (tests/common/deckutil.py) and a duration of 20 of CalculiX's own
increments, so that the run does real work. For each deck:
- ccx exits 0 and says "Job finished", and the displacements it prints at
  the end are finite and not all zero;
- the estimate ccx prints (its "Volumetric COURANT initial stable time
  increment") is the deck's own_estimate, computed by dtmap from CalculiX's
  rule (src/deck/rules.c), within 2e-6 relative (ccx prints 7 digits);
- ccx selects its own estimate (the packaged 2.20 takes the smaller of its
  estimate and the deck's maximum increment, the step), which is below the
  deck's step.
A plane surface meshed clockwise runs (its elements turned); a bar of
springs alone, which CalculiX's estimate passes over, runs at the deck's step. A ball of curved tet10 (C3D10; CalculiX's estimate takes det J at the
centroid and the 6-node faces) runs too, its estimate the deck's. And the
deck of the box with --target (mass elements at 1391 nodes) runs to
its end too, its mass elements adding up to the report's added mass (and to
mass_scaling.total_added: the same nodal form) within 1e-12.

Shells, membranes and beams (CalculiX builds them as layers of solids):
- on a curved panel (radius 0.5 m, 8 mm) of quadrangles and triangles, of
  triangles alone, and as membranes, the estimate ccx prints is the
  header's within 1e-6 (ccx's 7 digits: 5e-7 at most): the header builds
  the layer along the corner normals CalculiX averages at each node
  (gen3dnor.f); the flat extrusion it took before was 0.99 % high on the
  mixed panel (its triangles' estimate is in-plane there: 2.5e-5);
- a beam on the free edge of that panel (quadrangles) runs to its end with
  finite displacements: its nodes are its own, tied to the shell's by
  *EQUATION on the translations (with the beam on the shell's nodes,
  CalculiX's KNOT went to NaN within 20 increments), and the header says so;
- each layer's cap is in the header: the deck's step is safety x the
  element's share x the smallest element bound of the layer's solids, the
  shares from what bench/ccx_shell_caps.py measured (S3 0.76, S4
  0.30, B31 0.31), and the
  warning names the measured range."""

import glob
import os
import shutil
import unittest

import deckutil as du
import testutil as tu

CCX = shutil.which("ccx") or "ccx"


def deck(scene, name, *extra):
    out, rep = tu.path(name + ".inp"), tu.path(name + ".json")
    code, text = tu.run("deck", scene, "--solver", "calculix", "-o", out, "--report", rep, "-q", *extra)
    if code:
        raise AssertionError("dtmap deck %s: exit %d\n%s" % (scene, code, text))
    return out, tu.report(rep)


def masses(path):
    """The *MASS values of a deck."""
    with open(path) as f:
        lines, total = f.read().split("\n"), 0.0
    for i, line in enumerate(lines):
        if line.startswith("*MASS,"):
            total += float(lines[i + 1])
    return total


class Examples(unittest.TestCase):
    def run_deck(self, path, rep):
        own = rep["deck"].get("own_estimate")
        run, step = du.prepare(path, 20 * (own or rep["deck"]["step"]))
        code, log, u, est, sel = du.run(CCX, run)
        name = os.path.basename(path)
        self.assertEqual(code, 0, "%s: ccx exit %d\n%s" % (name, code, log[-2000:]))
        self.assertIn("Job finished", log, name)
        self.assertTrue(0 < u < float("inf"), "%s: largest |u| %g" % (name, u))
        if own is None:  # its rule covers none of the elements: it takes the deck's maximum increment
            self.assertLess(abs(sel / step - 1), 2e-6, name)
            return
        self.assertLess(abs(est / own - 1), 2e-6, "%s: ccx's estimate %g, the deck's %g" % (name, est, own))
        self.assertLessEqual(sel, step * (1 + 1e-6), name)

    def test_springs_alone(self):
        """A bar model (1D, formulation bar): springs and masses only, which
        CalculiX's estimate passes over; it runs at the deck's step."""
        tu.write("bar.geo", "Point(1) = {0, 0, 0, 0.01}; Point(2) = {0.2, 0, 0, 0.01}; Line(1) = {1, 2};\n"
                 "Physical Curve(\"bar\") = {1};\n")
        scene = tu.write("bar.xml", '<dtmap-scene version="1">\n  <geometry file="bar.geo"/>\n'
                         '  <meshing dim="1"/>\n  <material name="steel" groups="bar" E="210e9" rho="7850"/>\n'
                         '  <effects><elastic formulation="bar"/></effects>\n</dtmap-scene>\n')
        path, rep = deck(scene, "bar")
        self.assertNotIn("own_estimate", rep["deck"])
        self.run_deck(path, rep)

    def test_every_example(self):
        scenes = sorted(glob.glob(os.path.join(tu.SRC, "geometries", "*.xml")))
        self.assertGreaterEqual(len(scenes), 7)
        for scene in scenes:
            with self.subTest(scene=os.path.basename(scene)):
                path, rep = deck(scene, os.path.basename(scene)[:-4])
                self.run_deck(path, rep)

    def test_curved_tet10(self):
        tu.write("ball.geo", 'SetFactory("OpenCASCADE");\nSphere(1) = {0, 0, 0, 0.05};\nPhysical Volume("ball") = {1};\n')
        scene = tu.write("ball.xml", '<dtmap-scene version="1">\n  <geometry file="ball.geo"/>\n'
                         '  <meshing size="0.02" order="2" dim="3"/>\n'
                         '  <material name="steel" groups="ball" E="210e9" nu="0.3" rho="7850"/>\n'
                         '  <effects><elastic/></effects>\n  <time duration="1e-4"/>\n</dtmap-scene>\n')
        path, rep = deck(scene, "ball")
        self.assertGreater(rep["curvature"]["curved"], 0)
        self.assertEqual(rep["curvature"]["integration"], "calculix")
        self.run_deck(path, rep)

    def test_clockwise_plane(self):
        """A plane surface meshed clockwise (its curve loop reversed): the deck
        turns its elements counter-clockwise, else CalculiX's extrusion would
        invert them."""
        tu.write("cw.geo", "Point(1) = {0, 0, 0}; Point(2) = {0.1, 0, 0}; Point(3) = {0.1, 0.05, 0};\n"
                 "Point(4) = {0, 0.05, 0}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4};\n"
                 "Line(4) = {4, 1}; Curve Loop(1) = {-4, -3, -2, -1}; Plane Surface(1) = {1};\n"
                 "Physical Surface(\"slab\") = {1};\n")
        scene = tu.write("cw.xml", '<dtmap-scene version="1">\n  <geometry file="cw.geo"/>\n'
                         '  <meshing size="0.01" dim="2"/>\n'
                         '  <material name="steel" groups="slab" E="210e9" nu="0.3" rho="7850"/>\n'
                         '  <effects><elastic formulation="plane-strain"/></effects>\n</dtmap-scene>\n')
        path, rep = deck(scene, "cw")
        self.run_deck(path, rep)

    def test_added_mass(self):
        path, rep = deck(os.path.join(tu.SRC, "geometries", "box.xml"), "box_mass", "--target", "6e-7")
        d = rep["deck"]
        self.assertEqual(d["step"], 6e-7)
        self.assertGreater(d["added_nodes"], 0)
        self.assertLess(abs(masses(path) - d["added_mass"]), 1e-12 * d["added_mass"])
        self.assertLess(abs(d["added_mass"] - rep["mass_scaling"]["total_added"]), 1e-12 * d["added_mass"])
        self.run_deck(path, rep)


PANEL = """R = 0.5; a = 20 * Pi / 180; W = 0.16;
Point(1) = {0, 0, 0}; Point(2) = {-R*Sin(a), 0, R*Cos(a)}; Point(3) = {0, 0, R}; Point(4) = {R*Sin(a), 0, R*Cos(a)};
Circle(1) = {2, 1, 3}; Circle(2) = {3, 1, 4};
s1[] = Extrude {0, W, 0} { Curve{1}; }; s2[] = Extrude {0, W, 0} { Curve{2}; };
Physical Surface("skin") = {s1[1], s2[1]};
Physical Curve("stiffener") = {s1[2]};
"""


def panel(name, kind="shell", mesh="", beam=False):
    """A curved panel (radius 0.5 m, 40 degrees, 0.16 m long, size 0.02 m,
    8 mm thick); mesh: extra Gmsh lines ("Mesh.RecombineAll = 1;" for
    quadrangles); beam: a 10 x 30 mm ring beam on its free straight edge."""
    tu.write(name + ".geo", PANEL + mesh + "\n")
    beam_lines = ('  <section groups="stiffener" kind="beam" width="0.01" height="0.03" orientation="1 0 0"/>\n'
                  if beam else "")
    return tu.write(name + ".xml", '<dtmap-scene version="1">\n  <geometry file="%s.geo"/>\n'
                    '  <meshing size="0.02" dim="2"/>\n'
                    '  <material name="steel" groups="skin%s" E="200e9" nu="0.3" rho="7850"/>\n'
                    '  <section groups="skin" kind="%s" thickness="0.008"/>\n%s'
                    '  <effects><elastic/></effects>\n  <time safety="0.9" duration="1e-4"/>\n</dtmap-scene>\n'
                    % (name, " stiffener" if beam else "", kind, beam_lines))


def header(path):
    with open(path) as f:
        return [line for line in f.read().split("\n") if line.startswith("**")]


class Layers(unittest.TestCase):
    def estimate(self, scene, name, want):
        path, rep = deck(scene, name)
        with open(path) as f:
            types = {line.split("TYPE=")[1].split(",")[0] for line in f if line.startswith("*ELEMENT")}
        self.assertEqual(types, want)
        run, _ = du.prepare(path, 20 * rep["deck"]["own_estimate"])
        code, log, u, est, sel = du.run(CCX, run)
        self.assertEqual(code, 0, log[-2000:])
        self.assertTrue(0 < u < float("inf"), "largest |u| %g" % u)
        self.assertLess(abs(est / rep["deck"]["own_estimate"] - 1), 1e-6,
                        "ccx's estimate %.7g, the header's %.10g" % (est, rep["deck"]["own_estimate"]))
        return path, rep

    def test_curved_shell_estimates(self):
        self.estimate(panel("mixed", mesh="Recombine Surface{s1[1]};"), "mixed", {"S3", "S4"})
        self.estimate(panel("tris"), "tris", {"S3"})
        self.estimate(panel("membrane", kind="membrane", mesh="Recombine Surface{s1[1]};"), "membrane",
                      {"M3D3", "M3D4"})

    def test_beam_on_shell(self):
        path, rep = self.estimate(panel("beam", mesh="Mesh.RecombineAll = 1;", beam=True), "beam", {"S4", "B31"})
        with open(path) as f:
            text = f.read()
        beams = [line for line in text.split("*ELEMENT, TYPE=B31")[1].split("\n*")[0].split("\n")[1:] if line]
        nodes = du.inp_nodes(text.split("\n"))
        twins = {int(x) for line in beams for x in line.split(",")[1:]}
        self.assertTrue(twins and min(twins) > max(n for n in nodes if n not in twins))
        self.assertEqual(text.split("\n").count("*EQUATION"), 3 * len(twins))
        self.assertTrue(any("beam nodes are shell or membrane nodes" in w for w in rep["deck"]["warnings"]))
        # each beam node sits where its shell node is, and the equations tie them
        for line in text.split("*EQUATION\n2\n")[1:]:
            v = line.split("\n")[0].split(",")
            self.assertEqual(nodes[int(v[0])], nodes[int(v[3])])
            self.assertIn(int(v[0]), twins)

    def test_caps_in_header(self):
        shares = {"S3": 0.76, "S4": 0.30, "M3D3": 0.76, "M3D4": 0.76, "B31": 0.31}
        path, rep = deck(panel("capped", mesh="Recombine Surface{s1[1]};", beam=True), "capped")
        lines = header(path)
        caps = []
        for line in lines:
            if line.startswith("** layer "):
                elem = line.split("(")[1].split(")")[0]
                bound = float(line.split("solids ")[1].split(" s;")[0])
                self.assertIn("cap %.2f x it" % shares[elem], line)
                caps.append(shares[elem] * bound)
        self.assertEqual(len(caps), 3)
        self.assertEqual(rep["deck"]["basis"], "capped by the solver's elements")
        self.assertLess(abs(rep["deck"]["step"] / (0.9 * min(caps)) - 1), 1e-9)
        # plane stress: a 2 mm layer is capped (CPS3 0.94); the 1 m plate with a hole is left to the factor
        tu.write("thin.geo", "Point(1) = {0, 0, 0}; Point(2) = {0.1, 0, 0}; Point(3) = {0.1, 0.05, 0};\n"
                 "Point(4) = {0, 0.05, 0}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4};\n"
                 "Line(4) = {4, 1}; Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
                 "Physical Surface(\"slab\") = {1};\n")
        thin = tu.write("thin.xml", '<dtmap-scene version="1">\n  <geometry file="thin.geo"/>\n'
                        '  <meshing size="0.01" dim="2"/>\n'
                        '  <material name="steel" groups="slab" E="210e9" nu="0.3" rho="7850"/>\n'
                        '  <section groups="slab" kind="plane-stress" thickness="0.002"/>\n'
                        '  <effects><elastic formulation="plane-stress"/></effects>\n'
                        '  <time safety="0.9"/>\n</dtmap-scene>\n')
        tpath, trep = deck(thin, "thin")
        layers = [line for line in header(tpath) if line.startswith("** layer ")]
        self.assertEqual(len(layers), 1)
        self.assertIn("(CPS3)", layers[0])
        self.assertIn("cap 0.94 x it", layers[0])
        bound = float(layers[0].split("solids ")[1].split(" s;")[0])
        self.assertLess(abs(trep["deck"]["step"] / (0.9 * 0.94 * bound) - 1), 1e-9)
        ppath, _ = deck(os.path.join(tu.SRC, "geometries", "plate_with_hole.xml"), "plate")
        self.assertFalse([line for line in header(ppath) if line.startswith("** layer ")])
        for elem in ("S3", "S4", "B31"):
            self.assertTrue(any("%s into a layer" % elem in w and "at %.2f x their element bound" % shares[elem] in w
                                and "was measured at" in w and "bench/ccx_shell_caps.py" in w
                                for w in rep["deck"]["warnings"]), elem)


if __name__ == "__main__":
    tu.main()
