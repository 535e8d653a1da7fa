"""`dtmap run` from a geometry gives the views and figures the same mesh
gives read from a .msh (issue 46, the geometry path: nothing the path from
a geometry adds or skips may change what is analysed).

- A block with a hole (OpenCASCADE), HXT on 2 threads (whose mesh differs
  from run to run: the comparison is with the mesh that run wrote): the
  .msh dtmap wrote, read back by a second `dtmap run`, gives the same
  views: every view of the first run is in the second, on the same tags,
  every value equal to 1e-12 relative (the integer views exactly); and the
  report's figures (the smallest step, its element and effect, the nodal
  and recommended steps and their basis) agree to 1e-12 relative. The
  file is ASCII at this size, where Gmsh writes a coordinate to 16
  significant digits: that moves a step by about 1e-14 relative (measured
  8.6e-15), 100 times below the tolerance; a node moved by 1e-9 m fails it.
- The mesh in that .msh is the one analysed: the element and node counts
  of the report are Gmsh's counts of the file.
"""

import math
import unittest

import testutil as tu

GEO = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.06, 0.04};
Cylinder(2) = {0.05, 0.03, -0.01, 0, 0, 0.06, 0.012};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Physical Volume("block") = {3};
"""

SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
%s
<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
<effects><elastic/></effects>
<time duration="1e-4"/>
</dtmap-scene>
"""

REL = 1e-12  # the same arithmetic on the same mesh, its coordinates through 16 digits of ASCII


def counts(path):
    """(elements of dimension 3, nodes) of the .msh at path."""
    import gmsh
    gmsh.initialize(["t961", "-v", "0"])
    try:
        gmsh.open(path)
        n = sum(len(t) for t in gmsh.model.mesh.getElements(3)[1])
        return n, len(gmsh.model.mesh.getNodes()[0])
    finally:
        gmsh.finalize()


def close(a, b):
    return a == b or abs(a - b) <= REL * max(abs(a), abs(b))


class GeometryPath(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        tu.write("holed.geo", GEO)
        tu.write("geo.xml", SCENE % '<geometry file="holed.geo"/>\n'
                 '<meshing size="0.004" algorithm="hxt" threads="2"/>')
        code, log = tu.run("run", "geo.xml", "-q", "-o", "geo_dt.msh", "--report", "geo_dt.json")
        assert code == 0, log
        tu.write("msh.xml", SCENE % '<mesh file="geo_dt.msh"/>')
        code, log = tu.run("run", "msh.xml", "-q", "-o", "msh_dt.msh", "--report", "msh_dt.json")
        assert code == 0, log
        cls.geo, cls.msh = tu.report("geo_dt.json"), tu.report("msh_dt.json")
        cls.vgeo, cls.vmsh = tu.views(tu.path("geo_dt.msh")), tu.views(tu.path("msh_dt.msh"))

    def test_mesh_is_the_analysed_one(self):
        n, nodes = counts(tu.path("geo_dt.msh"))
        self.assertGreater(n, 5000)
        self.assertEqual(self.geo["mesh"]["elements"], n)
        self.assertEqual(self.geo["mesh"]["nodes"], nodes)
        self.assertEqual(self.msh["mesh"]["elements"], n)

    def test_views(self):
        self.assertIn("dt", self.vgeo)
        self.assertEqual(sorted(self.vgeo), sorted(self.vmsh))
        for name, values in self.vgeo.items():
            other = self.vmsh[name]
            self.assertEqual(sorted(values), sorted(other), name)
            bad = [t for t, v in values.items() if not close(v, other[t])]
            self.assertEqual(bad[:5], [], "view '%s': %d values differ, e.g. %s" %
                             (name, len(bad), [(t, values[t], other[t]) for t in bad[:3]]))
        self.assertEqual(len(self.vgeo["dt"]), self.geo["mesh"]["elements"])

    def test_figures(self):
        for key in ("min", "recommended", "nodal", "basis_step"):
            a, b = self.geo["dt"][key], self.msh["dt"][key]
            self.assertTrue(math.isfinite(a), key)
            self.assertTrue(close(a, b), "%s: %r against %r" % (key, a, b))
        self.assertEqual(self.geo["dt"]["element"], self.msh["dt"]["element"])
        self.assertEqual(self.geo["dt"]["effect"], self.msh["dt"]["effect"])
        self.assertEqual(self.geo["dt"]["basis"], self.msh["dt"]["basis"])
        self.assertEqual(self.geo["mesh"]["nodes"], self.msh["mesh"]["nodes"])


if __name__ == "__main__":
    tu.main()
