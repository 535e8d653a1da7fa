"""Sections as a user meets them: real Gmsh models built here, scenes
written for them, `dtmap run` on each.

- A folded plate (two rectangles meeting at a right angle, a surface model
  in 3D) is no plane problem: with the default plane-strain formulation,
  and with a plane-stress section, the run exits 2 and names the
  out-of-plane extent (the fold's 0.3 m leg, to 1e-6 relative: the
  reference plane is the larger leg's, so the farthest node is the other
  leg's free edge) and the membrane section; with a membrane section it
  runs, --posterior included, and its element, nodal and global steps are
  ordered as the bounds promise (element <= nodal <= global).
- The same surface model meshed in the plane z = 0 (unfolded) runs with
  the default formulation (nothing changes for plane models), and a
  membrane section there gives the plane-stress element steps exactly
  (1e-12: the same kernel, the thickness cancels).
- A block with an embedded curve: a material that names the curve's group
  without a section is refused with the section to add; a section of the
  wrong kind for the group's dimension, on a group that does not exist,
  on a group twice, without its area, with a zero or infinite thickness,
  and a plane section in a 3D model are each exit 2 naming the scene file
  and line, and no output is written.
"""

import os
import re
import unittest

import gmsh

import testutil as tu


def folded_plate(name, fold=True):
    """Two 1 x 0.5 and 1 x 0.3 m rectangles sharing an edge along x; the
    second stands up (fold) or lies in z = 0; physical surface 'skin'."""
    gmsh.initialize(["t331", "-v", "0"])
    gmsh.model.add(name)
    occ = gmsh.model.occ
    a = occ.addRectangle(0, 0, 0, 1, 0.5)
    b = occ.addRectangle(0, 0, 0, 1, 0.3)
    if fold:
        occ.rotate([(2, b)], 0, 0, 0, 1, 0, 0, 1.5707963267948966)  # into the plane y = 0
    else:
        occ.translate([(2, b)], 0, -0.3, 0)
    occ.fragment([(2, a)], [(2, b)])
    occ.synchronize()
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [s for _, s in gmsh.model.getEntities(2)]), "skin")
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.1)
    gmsh.model.mesh.generate(2)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(tu.path(name + ".msh"))
    gmsh.finalize()


def block_with_bar():
    """A 1 m cube ('block') with an embedded line from (0.5, 0.5, 0.1) to
    (0.5, 0.5, 0.9) ('bar')."""
    gmsh.initialize(["t331", "-v", "0"])
    gmsh.model.add("bar")
    occ = gmsh.model.occ
    occ.addBox(0, 0, 0, 1, 1, 1)
    p, q = occ.addPoint(0.5, 0.5, 0.1), occ.addPoint(0.5, 0.5, 0.9)
    line = occ.addLine(p, q)
    occ.synchronize()
    gmsh.model.mesh.embed(1, [line], 3, 1)
    gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [1]), "block")
    gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [line]), "bar")
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
    gmsh.model.mesh.generate(3)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(tu.path("bar.msh"))
    gmsh.finalize()


STEEL = 'name="steel" E="210e9" nu="0.3" rho="7850"'


def scene(name, mesh, body, effects="<elastic/>"):
    text = ('<?xml version="1.0"?>\n<dtmap-scene version="1">\n  <mesh file="%s"/>\n%s\n'
            "  <effects>%s</effects>\n</dtmap-scene>\n" % (mesh, body, effects))
    return tu.write(name, text)


def line_of(path, needle):
    with open(path) as f:
        for i, text in enumerate(f, 1):
            if needle in text:
                return i
    raise AssertionError("%s not in %s" % (needle, path))


class FoldedPlate(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        folded_plate("fold")
        folded_plate("flat", fold=False)

    def refused(self, body):
        scene("f.xml", "fold.msh", body)
        code, out = tu.run("run", "f.xml", "-o", "f_out.msh")
        self.assertEqual(code, 2, out)
        self.assertIn("not plane", out)
        self.assertIn('kind="membrane"', out)
        m = re.search(r"up to ([0-9.e+-]+) m out of one plane", out)
        self.assertIsNotNone(m, out)
        self.assertLessEqual(abs(float(m.group(1)) - 0.3), 0.3e-6, out)
        self.assertFalse(os.path.exists(tu.path("f_out.msh")))

    def test_plane_strain_refused(self):
        self.refused('  <material %s default="true"/>' % STEEL)

    def test_plane_stress_section_refused(self):
        self.refused('  <material %s default="true"/>\n  <section default="true" kind="plane-stress"/>' % STEEL)

    def test_membrane_runs(self):
        scene("m.xml", "fold.msh",
              '  <material %s default="true"/>\n  <section groups="skin" kind="membrane" thickness="0.004"/>' % STEEL)
        code, out = tu.run("run", "m.xml", "-o", "m_out.msh", "--report", "m.json", "--posterior")
        self.assertEqual(code, 0, out)
        dt = tu.report("m.json")["dt"]
        self.assertLessEqual(dt["min"], dt["nodal"])
        self.assertLessEqual(dt["nodal"], dt["global"])

    def test_flat_unchanged_and_membrane_is_plane_stress(self):
        mat = '  <material %s default="true"/>' % STEEL
        scene("p.xml", "flat.msh", mat, '<elastic formulation="plane-stress"/>')
        scene("q.xml", "flat.msh", mat + '\n  <section default="true" kind="membrane" thickness="0.004"/>')
        self.assertEqual(tu.run("run", "p.xml", "--report", "p.json", "-o", "p.msh")[0], 0)
        self.assertEqual(tu.run("run", "q.xml", "--report", "q.json", "-o", "q.msh")[0], 0)
        p, q = tu.report("p.json")["dt"], tu.report("q.json")["dt"]
        for key in ("min", "nodal"):
            self.assertLessEqual(abs(p[key] - q[key]), 1e-12 * p[key], key)


class BadSections(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        block_with_bar()

    def refused(self, body, *needles, line_needle=None):
        path = scene("b.xml", "bar.msh", body)
        code, out = tu.run("run", "b.xml", "-o", "b_out.msh")
        self.assertEqual(code, 2, out)
        for n in needles:
            self.assertIn(n, out)
        if line_needle:
            self.assertIn("b.xml:%d" % line_of(path, line_needle), out)
        self.assertFalse(os.path.exists(tu.path("b_out.msh")))

    def test_runs_with_truss(self):
        scene("ok.xml", "bar.msh", '  <material %s groups="block bar"/>\n  <section groups="bar" kind="truss" area="1e-4"/>'
              % STEEL)
        code, out = tu.run("run", "ok.xml", "-o", "ok.msh", "--report", "ok.json")
        self.assertEqual(code, 0, out)
        self.assertIn("line2", out)

    def test_material_on_curve_needs_section(self):
        self.refused('  <material %s groups="block bar"/>' % STEEL, "'bar' holds curves", 'kind="truss"',
                     line_needle="<material")

    def test_wrong_kind(self):
        self.refused('  <material %s groups="block bar"/>\n  <section groups="bar" kind="membrane" thickness="1e-3"/>'
                     % STEEL, "needs surfaces", line_needle="<section")

    def test_missing_group(self):
        self.refused('  <material %s default="true"/>\n  <section groups="rebar" kind="truss" area="1e-4"/>' % STEEL,
                     "'rebar' does not exist", line_needle="<section")

    def test_group_twice(self):
        self.refused('  <material %s groups="block bar"/>\n  <section groups="bar" kind="truss" area="1e-4"/>\n'
                     '  <section groups="bar" kind="truss" area="2e-4"/>' % STEEL, "already has a section",
                     line_needle='area="2e-4"')

    def test_truss_without_area(self):
        self.refused('  <material %s groups="block bar"/>\n  <section groups="bar" kind="truss"/>' % STEEL,
                     "needs area", line_needle="<section")

    def test_bad_thickness(self):
        for value in ("0", "-1", "INF", "abc"):
            self.refused('  <material %s default="true"/>\n  <section default="true" kind="membrane" thickness="%s"/>'
                         % (STEEL, value), "thickness", line_needle="<section")

    def test_runs_with_beam(self):
        """a beam in a block: the element, nodal and global steps in order."""
        scene("bm.xml", "bar.msh", '  <material %s groups="block bar"/>\n'
              '  <section groups="bar" kind="beam" radius="0.01"/>' % STEEL)
        code, out = tu.run("run", "bm.xml", "--posterior", "-o", "bm.msh", "--report", "bm.json")
        self.assertEqual(code, 0, out)
        dt = tu.report("bm.json")["dt"]
        self.assertLessEqual(dt["min"], dt["nodal"])
        self.assertLessEqual(dt["nodal"], dt["global"] * (1 + 1e-12))

    def test_bad_beam_profiles(self):
        beam = '  <material %s groups="block bar"/>\n  <section groups="bar" kind="beam" %s/>'
        for attrs, needle in (("", "needs one profile"), ('area="1e-4"', "go together"),
                              ('radius="0.01" width="0.01" height="0.02"', "needs one profile"),
                              ('width="0.01"', "width and height go together"),
                              ('radius="0.01" orientation="1 0"', "orientation"),
                              ('radius="0.01" orientation="0 0 0"', "orientation"),
                              ('radius="0.01" orientation="1 0 nan"', "orientation"),
                              ('radius="0.01" rotary="lumped"', "rotary"),
                              ('radius="0.01" thickness="0.1"', "takes no thickness"),
                              ('radius="-1"', "radius")):
            with self.subTest(attrs=attrs):
                self.refused(beam % (STEEL, attrs), needle, line_needle="<section")

    def test_beam_orientation_along_its_axis(self):
        """the bar runs along z: an orientation along z leaves no section plane;
        the error names the element."""
        self.refused('  <material %s groups="block bar"/>\n  <section groups="bar" kind="beam" radius="0.01" '
                     'orientation="0 0 2"/>' % STEEL, "parallel to the beam", "(line2)")

    def test_bad_shells(self):
        for body, needle in (('<section groups="bar" kind="shell" thickness="0.01"/>', "needs surfaces"),
                             ('<section groups="bar" kind="shell"/>', "needs thickness"),
                             ('<section groups="bar" kind="truss" area="1e-4" rotary="scaled"/>', "takes no rotary"),
                             ('<section groups="bar" kind="truss" area="1e-4" iy="1e-8"/>', "takes no iy"),
                             ('<section groups="bar" kind="beam" radius="0.01" shear-factor="0"/>', "shear-factor")):
            with self.subTest(body=body):
                self.refused('  <material %s groups="block bar"/>\n  %s' % (STEEL, body), needle,
                             line_needle="<section")

    def test_plane_section_in_3d(self):
        self.refused('  <material %s default="true"/>\n  <section default="true" kind="plane-stress"/>' % STEEL,
                     "a plane-stress section needs surfaces", line_needle="<section")


if __name__ == "__main__":
    tu.main()
