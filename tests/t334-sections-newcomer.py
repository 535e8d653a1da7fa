"""What a new user meets with sections, on small models built here (Gmsh's
built-in kernel, meshed by `dtmap run`):

1. A model whose every element is a shell has no dispersion model, so no
   default frequency: the summary and the report say so and why, and never
   print or write NaN.
2. A curve group without a section that reaches beyond the analysed
   elements (a rod standing on a shell plate) is left out with a warning
   naming the group, its element count (counted here in the written .msh
   with Gmsh's API) and the truss or beam section that includes it; a
   boundary curve group on the plate's own nodes is not named; the summary
   and the report count the analysed nodes beside all nodes. With a truss
   section on the rod, nothing is left out.
3. Plane surfaces that share one normal but lie at two heights are a plane
   problem, each in its own plane: the element steps and the nodal bound
   equal those of the same mesh moved into one plane (1e-12 relative: the
   element kernels and the nodal bound work in each element's own frame),
   the global estimate agrees to 2e-4 (each is within its Lanczos tolerance
   1e-4 of the exact step, on its safe side). A folded pair (two planes at
   right angles) is refused, with the remedy that keeps the formulation
   (plane strain: mesh the volume; plane stress: a membrane).
4. formulation="3d" on a shell model is refused saying that a section sets
   its groups' formulation and the attribute applies only to elements
   without one, never that the model is "analysed in 2D".
5. A 10 mm shell on 0.25 m elements scales rotary inertia above 100: a
   warning gives the step with physical inertia (the report's figure) and
   the bending wavelength the scaling slows, 2 pi (t/sqrt 12) sqrt(scale)
   from the report's scale (3 significant digits, as printed); a 0.1 m shell
   (scale about 4) gets none. The summary says which step is the eigenvalue
   bound and which the length rule.
6. A thickness or truss area larger than the model is warned about.
7. (issue item 10) A 3D block with a truss: Gmsh's view list, after opening
   the result with its .opt, holds no name twice; the alias that draws the
   solid's skin is "dt skin".
"""

import json
import math
import os
import re
import unittest

import testutil as tu

STEEL = '<material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>'

PLATE = """lc = 0.25;
Point(1) = {0, 0, 0, lc}; Point(2) = {1, 0, 0, lc}; Point(3) = {1, 1, 0, lc}; Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Point(5) = {1, 1, 1, lc}; Line(5) = {3, 5};
Physical Surface("plate") = {1};
Physical Curve("rod") = {5};
Physical Curve("edge") = {1};
"""

SLICES = """lc = 0.2;
Point(1) = {0, 0, 0, lc}; Point(2) = {1, 0, 0, lc}; Point(3) = {1, 1, 0, lc}; Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Point(11) = {2, 0, %s, lc}; Point(12) = {3, 0, %s, lc}; Point(13) = {3, 1, %s, lc}; Point(14) = {2, 1, %s, lc};
Line(11) = {11, 12}; Line(12) = {12, 13}; Line(13) = {13, 14}; Line(14) = {14, 11};
Curve Loop(2) = {11, 12, 13, 14}; Plane Surface(2) = {2};
Physical Surface("low") = {1}; Physical Surface("high") = {2};
"""

FOLDED = """lc = 0.25;
Point(1) = {0, 0, 0, lc}; Point(2) = {1, 0, 0, lc}; Point(3) = {1, 1, 0, lc}; Point(4) = {0, 1, 0, lc};
Point(5) = {1, 0, 1, lc}; Point(6) = {1, 1, 1, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {2, 5}; Line(6) = {5, 6}; Line(7) = {6, 3};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Physical Surface("folded") = {1, 2};
"""

BLOCK = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Point(100) = {0.5, 0.5, 0.2}; Point(101) = {0.5, 0.5, 0.8}; Line(100) = {100, 101};
Curve{100} In Volume{1};
Physical Volume("block") = {1};
Physical Curve("bar") = {100};
"""


def scene(name, geo, body, meshing='<meshing size="0.25" dim="2"/>', effects="<elastic/>"):
    tu.write(name + ".geo", geo)
    tu.write(name + ".xml", '<dtmap-scene version="1">\n  <geometry file="%s.geo"/>\n  %s\n  %s\n  %s\n'
             '  <effects>%s</effects>\n  <output mesh="%s.msh" report="%s.json"/>\n</dtmap-scene>\n'
             % (name, meshing, STEEL, body, effects, name, name))
    return name + ".xml"


def run(name, geo, body, *args, **kw):
    code, out = tu.run("run", scene(name, geo, body, **kw), *args)
    return code, out


def ok(test, name, geo, body, *args, **kw):
    code, out = run(name, geo, body, *args, **kw)
    test.assertEqual(code, 0, out)
    return out, tu.report(name + ".json")


def warnings(out):
    return [l[len("WARNING: "):] for l in out.splitlines() if l.startswith("WARNING: ")]


def group_counts(msh, dim, name):
    """(elements of physical group name of dimension dim, nodes of the elements of every other group)
    in the .msh at msh, read with Gmsh's API."""
    import gmsh
    gmsh.initialize(["t334", "-v", "0"])
    try:
        gmsh.open(msh)
        elems, nodes_other = 0, set()
        for d, t in gmsh.model.getPhysicalGroups():
            mine = d == dim and gmsh.model.getPhysicalName(d, t) == name
            for e in gmsh.model.getEntitiesForPhysicalGroup(d, t):
                _, etags, ntags = gmsh.model.mesh.getElements(d, e)
                if mine:
                    elems += sum(len(x) for x in etags)
                elif d == 2:  # the analysed elements' nodes: the plate's
                    for x in ntags:
                        nodes_other.update(int(n) for n in x)
        return elems, len(nodes_other)
    finally:
        gmsh.finalize()


class NoDefaultFrequency(unittest.TestCase):
    def test_shells_have_no_nan(self):
        out, rep = ok(self, "nofreq", PLATE, '<section groups="plate" kind="shell" thickness="0.01"/>')
        with open(tu.path("nofreq.json")) as f:
            text = f.read()
        for what, t in (("summary", out), ("report", text)):
            self.assertIsNone(re.search(r"\bnan\b", t, re.I), "%s prints NaN:\n%s" % (what, t))
        phase = [m for m in rep["accuracy_measures"] if m["measure"] == "phase-speed error"][0]
        self.assertNotIn("frequency", phase)
        self.assertIn("no default frequency", phase["note"])
        self.assertIn("in sections", phase["note"])
        self.assertIn("no default frequency", out)


class LeftOut(unittest.TestCase):
    def test_rod_without_section(self):
        out, rep = ok(self, "rod", PLATE, '<section groups="plate" kind="shell" thickness="0.01"/>')
        rod, plate_nodes = group_counts(tu.path("rod.msh"), 1, "rod")
        self.assertGreater(rod, 0)
        w = [x for x in warnings(out) if "left out" in x]
        self.assertEqual(len(w), 1, out)
        self.assertIn("%d line elements left out" % rod, w[0])
        self.assertIn("rod (%d)" % rod, w[0])
        self.assertNotIn("edge", w[0])  # on the plate's own nodes
        self.assertIn('<section groups="rod" kind="truss"', w[0])
        self.assertIn("truss or beam", w[0])
        self.assertEqual(rep["mesh"]["left_out"], [{"group": "rod", "dim": 1, "elements": rod}])
        self.assertEqual(rep["mesh"]["nodes_analysed"], plate_nodes)
        self.assertGreater(rep["mesh"]["nodes"], plate_nodes)
        self.assertIn("%d nodes (%d in analysed elements)" % (rep["mesh"]["nodes"], plate_nodes), out)
        self.assertTrue(any("left out" in x for x in rep["warnings"]))

    def test_rod_as_truss(self):
        out, rep = ok(self, "truss", PLATE, '<section groups="plate" kind="shell" thickness="0.01"/>\n'
                      '  <section groups="rod" kind="truss" area="1e-4"/>')
        self.assertFalse([x for x in warnings(out) if "left out" in x], out)
        self.assertEqual(rep["mesh"]["left_out"], [])
        self.assertEqual(rep["mesh"]["nodes_analysed"], rep["mesh"]["nodes"])


def write_msh(geo, path, flatten):
    """Mesh geo (2D, Gmsh's API, one thread) and write it in binary to path,
    with every node moved to z = 0 when flatten."""
    import gmsh
    gmsh.initialize(["t334", "-v", "0"])
    try:
        gmsh.open(geo)
        gmsh.model.mesh.generate(2)
        if flatten:
            tags, xyz, _ = gmsh.model.mesh.getNodes()
            for i, t in enumerate(tags):
                gmsh.model.mesh.setNode(int(t), [xyz[3 * i], xyz[3 * i + 1], 0.0], [])
        gmsh.option.setNumber("Mesh.Binary", 1)
        gmsh.write(path)
    finally:
        gmsh.finalize()


class ParallelPlanes(unittest.TestCase):
    def mesh_run(self, name, msh):
        tu.write(name + ".xml", '<dtmap-scene version="1">\n  <mesh file="%s"/>\n  %s\n'
                 '  <effects><elastic formulation="plane-strain"/></effects>\n</dtmap-scene>\n' % (msh, STEEL))
        code, out = tu.run("run", name + ".xml", "--posterior", "-o", name + "_dt.msh", "--report", name + ".json")
        self.assertEqual(code, 0, out)
        return out, tu.report(name + ".json"), tu.view_values(tu.path(name + "_dt.msh"), "dt")

    def test_each_in_its_own_plane(self):
        tu.write("slices.geo", SLICES % (("0.5",) * 4))
        write_msh(tu.path("slices.geo"), tu.path("apart.msh"), False)
        write_msh(tu.path("slices.geo"), tu.path("flat.msh"), True)
        out, apart, dt_apart = self.mesh_run("apart", "apart.msh")
        _, flat, dt_flat = self.mesh_run("flat", "flat.msh")
        self.assertIn("analysed in 2 parallel planes", out)
        self.assertEqual(sorted(dt_apart), sorted(dt_flat))
        for t, v in dt_flat.items():
            self.assertLessEqual(abs(dt_apart[t] - v), 1e-12 * v, "element %d" % t)
        self.assertLessEqual(abs(apart["dt"]["nodal"] / flat["dt"]["nodal"] - 1), 1e-12)
        self.assertLessEqual(abs(apart["dt"]["global"] / flat["dt"]["global"] - 1), 2e-4)

    def test_folded_is_refused_with_the_formulations_remedy(self):
        for form, want in (("plane-strain", "mesh it as a volume"), ("plane-stress", "Keep plane stress")):
            code, out = run("folded_" + form, FOLDED, "", effects='<elastic formulation="%s"/>' % form)
            self.assertEqual(code, 2, out)
            self.assertIn("not plane and parallel", out)
            self.assertIn("no %s problem" % form, out)
            self.assertIn(want, out)


class SectionFormulation(unittest.TestCase):
    def test_3d_on_shells(self):
        code, out = run("form3d", PLATE, '<section default="true" kind="shell" thickness="0.01"/>',
                        effects='<elastic formulation="3d"/>')
        self.assertEqual(code, 2, out)
        self.assertNotIn("analysed in 2D", out)
        self.assertIn("applies only to elements without a <section>", out)
        self.assertIn("a section sets the formulation of its groups' elements", out)


class RotaryInertia(unittest.TestCase):
    def test_large_scale_is_warned(self):
        out, rep = ok(self, "thin", PLATE, '<section groups="plate" kind="shell" thickness="0.01"/>')
        ri = rep["sections"][0]["rotary_inertia"]
        self.assertGreater(ri["scale_max"], 100)
        w = [x for x in warnings(out) if "rotary inertia scaled" in x]
        self.assertEqual(len(w), 1, out)
        self.assertIn("%.4e s" % ri["dt_physical_min"], w[0])
        got = float(re.search(r"Bending waves shorter than ([0-9.e+-]+) m", w[0]).group(1))
        want = 2 * math.pi * 0.01 / math.sqrt(12) * math.sqrt(ri["scale_max"])
        self.assertLessEqual(abs(got - want), 5e-3 * want)  # printed to 3 significant digits
        self.assertIn("an eigenvalue bound", out)
        self.assertIn("length rule", out)

    def test_small_scale_is_not(self):
        out, rep = ok(self, "thick", PLATE, '<section groups="plate" kind="shell" thickness="0.1"/>')
        self.assertLess(rep["sections"][0]["rotary_inertia"]["scale_max"], 100)
        self.assertFalse([x for x in warnings(out) if "rotary inertia scaled" in x], out)


class AbsurdSizes(unittest.TestCase):
    def test_thickness_and_area(self):
        out, _ = ok(self, "huge", PLATE, '<section groups="plate" kind="shell" thickness="1e30"/>\n'
                    '  <section groups="rod" kind="truss" area="1e30"/>')
        w = [x for x in warnings(out) if "exceeds the model's own extent" in x]
        self.assertEqual(len(w), 2, out)
        self.assertIn("thickness 1e+30 m", w[0])
        self.assertIn("area 1e+30 m^2", w[1])
        out, _ = ok(self, "sane", PLATE, '<section groups="plate" kind="shell" thickness="0.01"/>\n'
                    '  <section groups="rod" kind="truss" area="1e-4"/>')
        self.assertNotIn("exceeds the model's own extent", out)


class ViewNames(unittest.TestCase):
    def test_no_two_views_share_a_name(self):
        ok(self, "block", BLOCK, '<section groups="bar" kind="truss" area="1e-4"/>',
           meshing='<meshing size="0.25" dim="3"/>')
        import gmsh
        gmsh.initialize(["t334", "-v", "0"])
        try:
            gmsh.open(tu.path("block.msh"))  # merges block.msh.opt
            names = [gmsh.option.getString("View[%d].Name" % i) for i in range(len(gmsh.view.getTags()))]
        finally:
            gmsh.finalize()
        self.assertEqual(len(names), len(set(names)), names)
        self.assertIn("dt", names)
        self.assertIn("dt skin", names)


if __name__ == "__main__":
    tu.main()
