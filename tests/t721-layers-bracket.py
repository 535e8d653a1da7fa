"""Thin layers, each with its own thickness (issue 43, item 3): the CAx-IF
as1 L-bracket (cut out of Gmsh's demos/boolean/as1-tu-203.stp from Debian's
gmsh-doc, as t720 does; 10 mm walls, two holes whose ligament to the edge
x = 55 mm is 2.5 mm, one 5 mm from the inner face of the upright wall),
refined in metres to a target no mesh reaches (1e-6 s; the input's step is
2e-7 s), so that every element of the kept coarse mesh is capped by the
thickness of the part it sits in.

- The layers are told apart: the one holding most elements is a wall,
  10 mm thick, and one layer is a ligament, 2.5 mm thick (5 %: the figure
  the issue asks for; the geometric gap dtmap projects onto the two CAD
  boundaries is exact to rounding, the 5 % leaves room for the mesh's own
  node distance on another mesh). Before, every element fell into one
  layer 2.57 mm thick, the wall's remedy a shell 4x too thin.
- Where both boundaries of a layer are curves or surfaces, its thickness is
  one of the CAD's gaps (10 mm walls; 2.5 mm from the two holes by the
  edge x = 55 mm; 5 mm from the base's hole to the upright's inner face
  x = 15 mm), measured here by sampling the holes' faces with Gmsh's
  getValue (400 x 5 points: their extreme x is exact at the sampled seam),
  within 1e-6 relative: dtmap projects onto the CAD (src/gmsh/gap.c), so
  only OpenCASCADE's projection tolerance remains.
- No layer is thinner than the thinnest place of the part (the ligament,
  2.5 mm, less 5 %), and each layer's shell remedy is its own thickness:
  never thinner than the layer it replaces.
- The elements of the layers add up to the thickness-limited ones of the
  shape list, and the summary prints at most 4 layers, saying how many
  more the report holds.
- Without a target (`run` on the input), the smallest steps lie across a
  10 mm wall (5 %), and the step a fresh mesh reaches there is printed as
  an estimate, not as a bound ("at most"): remeshes are not bound by it
  (issue 43 item 7: refine kept meshes above it on real parts).
"""

import gzip
import os
import sys
import unittest

import testutil as tu

sys.path.insert(0, os.path.join(tu.SRC, "bench", "cad"))
import corpus  # noqa: E402  (bench/cad/corpus.py)

DEMOS = "/usr/share/doc/gmsh-doc/doc/gmsh/demos/boolean"
WALL, LIGAMENT, TOL = 10e-3, 2.5e-3, 0.05


def cad_gaps(brep):
    """The bracket's gaps in m from its geometry: the walls' thickness (the
    base's two planes z = 20, 30 mm) and the base's holes' distances to the
    planes they face (the edge x = 55 mm, the upright's inner face x = 15 mm)."""
    import gmsh
    import numpy
    gmsh.initialize(["t721", "-v", "0"])
    try:
        gmsh.model.occ.importShapes(brep)
        gmsh.model.occ.synchronize()
        lo_x, hi_x = [], []
        for _, t in gmsh.model.getEntities(2):
            box = gmsh.model.getBoundingBox(2, t)
            if gmsh.model.getType(2, t) == "Plane" or box[2] < 20 - 1e-6 or box[5] > 30 + 1e-6:
                continue  # a plane, or a hole of the upright (the base is 20 <= z <= 30 mm)
            lo, hi = gmsh.model.getParametrizationBounds(2, t)
            uv = [x for u in numpy.linspace(lo[0], hi[0], 400) for v in numpy.linspace(lo[1], hi[1], 5) for x in (u, v)]
            p = numpy.array(gmsh.model.getValue(2, t, uv)).reshape(-1, 3)
            lo_x.append(p[:, 0].min()), hi_x.append(p[:, 0].max())
    finally:
        gmsh.finalize()
    return {"wall": 10e-3, "edge": (55 - max(hi_x)) * 1e-3, "upright": (min(lo_x) - 15) * 1e-3}


class Bracket(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        stp = tu.path("as1-tu-203.stp")
        with gzip.open(os.path.join(DEMOS, "as1-tu-203.stp.gz"), "rb") as f, open(stp, "wb") as g:
            g.write(f.read())
        row = [r for r in corpus.table() if r["name"] == "as1_l_bracket"][0]
        brep = tu.path("bracket.brep")
        corpus.cut_solid(stp, brep, row["solid"])
        geo = tu.write("bracket.geo", corpus.wrapper("bracket", "bracket.brep", ".brep"))
        tu.write("bracket.xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="%s"/>
<meshing dim="3" size="5e-3"/>
<material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>
<effects><elastic formulation="3d" length="eigen"/></effects>
<time safety="0.9" duration="1e-3"/>
</dtmap-scene>
""" % geo)
        cls.gaps = cad_gaps(brep)
        code, cls.out, rep = tu.refine("bracket", 1e-6)
        assert code == 1, cls.out  # the target is out of reach
        cls.rep = rep
        cls.layers = rep["thickness_limited"]

    def test_walls_and_ligament_apart(self):
        self.assertGreaterEqual(len(self.layers), 2, self.layers)
        most = max(self.layers, key=lambda l: l["elements"])
        self.assertAlmostEqual(most["thickness"] / WALL, 1, delta=TOL)
        self.assertTrue(any(abs(l["thickness"] / LIGAMENT - 1) <= TOL for l in self.layers), self.layers)

    def test_thickness_from_the_cad(self):
        self.assertAlmostEqual(self.gaps["edge"] / LIGAMENT, 1, delta=1e-9)
        gaps = sorted(self.gaps.values())
        for l in self.layers:
            if min(d for d, _ in l["boundaries"]) < 1:
                continue  # a model point: nothing to project onto
            near = min(gaps, key=lambda g: abs(l["thickness"] / g - 1))
            self.assertAlmostEqual(l["thickness"] / near, 1, delta=1e-6, msg=(l, gaps))

    def test_never_thinner_than_the_layer(self):
        for l in self.layers:
            self.assertGreaterEqual(l["thickness"], LIGAMENT * (1 - TOL), l)
            self.assertEqual(l["remedies"]["shell_thickness"], l["thickness"], l)
        for l in self.layers:
            self.assertIn('thickness="%.3g"' % l["thickness"], self.out)

    def test_counts_and_cap(self):
        thin = [s for s in self.rep["shape_limited"] if s["feature"]["kind"] == "thin"]
        self.assertLessEqual(len(thin), sum(l["elements"] for l in self.layers))
        if self.rep["shape_limited_count"] <= len(self.rep["shape_limited"]):
            self.assertEqual(len(thin), sum(l["elements"] for l in self.layers))
        self.assertLessEqual(self.out.count("  layer "), 4)
        if len(self.layers) > 4:
            self.assertIn("... and %d more layer(s)" % (len(self.layers) - 4), self.out)

    def test_reach_is_an_estimate(self):
        code, out = tu.run("run", "bracket.xml", "-o", "b.msh", "--report", "b.json")
        self.assertEqual(code, 0, out)
        layers = tu.report("b.json")["thickness_limited"]
        self.assertTrue(layers and all(l["at_minimum"] for l in layers), layers)
        self.assertAlmostEqual(layers[0]["thickness"] / WALL, 1, delta=TOL)
        line = [l for l in out.splitlines() if l.startswith("thickness ")]
        self.assertEqual(len(line), len(layers), out)
        self.assertIn("(an estimate, not a bound", line[0])
        self.assertNotIn("at most", line[0])
        self.assertNotIn("s at most", out)


if __name__ == "__main__":
    tu.main()
