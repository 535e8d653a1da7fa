"""A geometry Gmsh cannot mesh is refused with Gmsh's own errors, however
dtmap reads them (issue 46: while the supervised worker has Gmsh mesh curves
and surfaces on several threads, Gmsh's messages are read from its terminal,
a file, instead of its API logger, which is not thread-safe;
src/gmsh/session.c, src/gmsh/contain.c).

Two overlapping boxes closed by one surface loop (a volume whose boundary
intersects itself), HXT on 2 threads:
- `dtmap run` (the supervised worker, Gmsh's terminal in its log): exit 2,
  "Gmsh cannot mesh it: " and Gmsh's errors, "HXT 3D mesh failed; No
  elements in volume ...", and not the summary of the error counts Gmsh
  writes to its terminal only ("Mesh generation error summary", its lines
  of dashes);
- the same message with DTMAP_SUPERVISE=0 (a meshing child: the API
  logger, curves and surfaces one at a time) and with -v (Gmsh's terminal
  shown: the API logger again);
- no output file.
"""

import os
import unittest

import testutil as tu

GEO = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Box(2) = {0.5, 0.5, 0.5, 1, 1, 1};
Surface Loop(10) = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
Volume(3) = {10};
Physical Volume("block") = {3};
"""

SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="crossed.geo"/>
<meshing size="0.2" algorithm="hxt" threads="2"/>
<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
<effects><elastic/></effects>
</dtmap-scene>
"""


def error_line(log):
    """The line of dtmap's error."""
    return next(l for l in log.splitlines() if l.startswith("dtmap: error: "))


class MeshingErrors(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        tu.write("crossed.geo", GEO)
        tu.write("crossed.xml", SCENE)

    def refuse(self, *extra, env=None):
        old = dict(os.environ)
        os.environ.update(env or {})
        try:
            code, log = tu.run("run", "crossed.xml", "-o", "crossed_dt.msh", *extra)
        finally:
            os.environ.clear()
            os.environ.update(old)
        self.assertEqual(code, 2, log)
        self.assertFalse(os.path.exists(tu.path("crossed_dt.msh")))
        return error_line(log)

    def test_terminal(self):
        line = self.refuse("-q")
        self.assertIn("crossed.geo: Gmsh cannot mesh it: HXT 3D mesh failed; No elements in volume", line)
        self.assertNotIn("summary", line)
        self.assertNotIn("---", line)
        self.assertNotIn("(and more)", line)

    def test_same_every_way(self):
        line = self.refuse("-q")
        self.assertEqual(self.refuse("-q", env={"DTMAP_SUPERVISE": "0"}), line)
        self.assertEqual(self.refuse("-v"), line)


if __name__ == "__main__":
    tu.main()
