"""The ways refine reaches a target, on real Gmsh geometries:

- Counts it sets itself (tests/data/refine/chained.geo: three transfinite
  quadrangles in a row sharing their vertical curves, the first graded by
  a progression, the third with a top side of two curves): at 1.3x and 2x
  the recommended step one remesh meets the target, the written mesh has
  the counts the report lists, and every transfinite surface's opposite
  sides have as many segments (curves 1 = 4, 2 = 5, 3 = 6 + 7, the four
  verticals equal), with curve 1's progression kept (its first segment
  over its last is 1.03^(n-2) to 1e-6: Gmsh places the nodes to about that).
- The global basis: a target between the nodal-bound and the global basis
  of the bundled plate's input mesh is met by the input itself with
  --posterior (exit 0, no remesh, "met by the input"), while without it
  refine remeshes. --posterior on a scene whose effects have no global
  estimate (cohesive alone) is bad input, exit 2, nothing written.
- Point masses: the extruded slab (extruded.geo, 4 layers) at 1.15x the
  step cannot be met by any mesh (the layers cap it); its nodes need about
  1.15^2 - 1 of their mass, so with --max-added-mass 40 it is met by
  mesh + mass (exit 0, "met: mesh + X % added mass at N nodes"), the view
  'added mass at nodes' in the output sums to the report's total, and
  `run` and `verify` on that output read the mass back: its recommended
  step equals refine's to 1e-12 (the same nodal bound, summed in the same
  order). With --max-added-mass 1 it is not (exit 1, the percentage it
  would need, above 1). --max-added-mass -1, 101 or nan is a usage error.
- Gmsh's optimisers (the bundled plate, one remesh at 1.3x): none by
  default; `--optimise relocate,laplace` runs both 2D passes (the report's
  round lists them, and the mesh's step differs from the remesh without
  them), `--optimise gmsh` runs nothing in 2D (the same step as none: the
  same field gives the same mesh), an unknown pass is a usage error.
- A partitioned model (partitioned.geo: meshed, then `PartitionMesh 3`, as
  Gmsh's tutorial t21): refine at 1.3x remeshes the whole model, not the
  partition entities (before, the remesh held 10 elements and no
  triangle: exit 2), meets the target, and keeps the curve group
  'left_side', whose '_' Gmsh's unpartition takes for a partitioner's name.
"""

import math
import os
import shutil
import unittest

import testutil as tu

DATA = os.path.join(tu.SRC, "tests", "data", "refine")


def scene(name, geo, dim, extra=""):
    for f in os.listdir(DATA):
        shutil.copy(os.path.join(DATA, f), tu.path(f))
    return tu.elastic_scene(name, geo, dim, time='duration="1e-4"' + extra)



def curve_nodes(msh):
    import gmsh
    gmsh.initialize(["t325", "-v", "0"])
    try:
        gmsh.open(msh)
        out = {}
        for _, c in gmsh.model.getEntities(1):
            tags, xyz, _ = gmsh.model.mesh.getNodes(1, c, includeBoundary=True)
            out[c] = (len(tags), xyz.reshape(-1, 3))
        return out
    finally:
        gmsh.finalize()


class Counts(unittest.TestCase):
    def check(self, factor):
        scene("chained", "chained.geo", 2)
        target = factor * tu.run_dt("chained")["recommended"]
        code, log, rep = tu.refine("chained", target)
        self.assertEqual(code, 0, log)
        ref = rep["refine"]
        self.assertEqual(ref["met_by"], "mesh", log)
        self.assertEqual(len(ref["rounds"]), 2, log)  # one remesh
        self.assertGreater(len(ref["counts"]), 0, log)
        nodes = curve_nodes(tu.path("chained_r.msh"))
        n = {c: v[0] for c, v in nodes.items()}
        for c in ref["counts"]:
            self.assertEqual(n[c["curve"]], c["to"], c)
            self.assertLess(c["to"], c["from"], c)
        self.assertEqual(n[1], n[4])
        self.assertEqual(n[2], n[5])
        self.assertEqual(n[3] - 1, (n[6] - 1) + (n[7] - 1))
        self.assertEqual(len({n[8], n[9], n[10], n[11]}), 1)
        # curve 1 from (0,0) to (1,0), graded 1.03: its nodes by x
        xs = sorted(p[0] for p in nodes[1][1])
        first, last = xs[1] - xs[0], xs[-1] - xs[-2]
        self.assertAlmostEqual(last / first, 1.03 ** (n[1] - 2), delta=1e-6 * last / first)

    def test_chained_1_3(self):
        self.check(1.3)

    def test_chained_2(self):
        self.check(2.0)


def plate_scene():
    shutil.copy(os.path.join(tu.SRC, "geometries", "plate_with_hole.geo"), tu.path("plate_with_hole.geo"))
    tu.write("plate.xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="plate_with_hole.geo"/>
<meshing size="5e-3" min-size="1e-3" dim="2"/>
<material name="aluminium" groups="plate" E="70e9" nu="0.33" rho="2700"/>
<effects><elastic formulation="plane-stress"/></effects>
<time duration="1e-4"/>
</dtmap-scene>
""")


class GlobalBasis(unittest.TestCase):
    def test_met_by_input(self):
        plate_scene()
        nodal = tu.run_dt("plate")["recommended"]
        glob = tu.run_dt("plate", "--posterior")["recommended"]
        self.assertGreater(glob, 1.05 * nodal)
        target = math.sqrt(nodal * glob)  # between the two
        code, log, rep = tu.refine("plate", target, "--posterior")
        self.assertEqual(code, 0, log)
        self.assertIn("met by the input mesh as it is (global estimate): no remesh", log)
        self.assertIn("a solver must run at this step fixed", log)
        ref = rep["refine"]
        self.assertEqual((ref["met_by"], len(ref["rounds"]), ref["basis"]), ("input", 1, "global estimate"))
        self.assertEqual(rep["below_target"], 0)
        self.assertLess(ref["element_bound"], target)
        code, log, rep = tu.refine("plate", target, "--max-iter", "1")
        self.assertEqual(rep["refine"]["basis"], "nodal bound")
        self.assertGreaterEqual(len(rep["refine"]["rounds"]), 2, log)  # the nodal basis remeshes
        self.assertEqual(rep["refine"]["rounds"][1]["strategy"], "field", log)  # the size field first

    def test_posterior_needs_an_estimate(self):
        scene("cohesive_only", "transfinite.geo", 2)
        text = open(tu.path("cohesive_only.xml")).read().replace(
            '<effects><elastic formulation="plane-stress"/></effects>',
            '<effects><cohesive groups="block"/></effects>').replace(
                'rho="7850"', 'rho="7850" fracture-energy="100" strength="3e6"')
        tu.write("cohesive_only.xml", text)
        code, log = tu.run("refine", "cohesive_only.xml", "--target", "1", "--posterior", "-q")
        self.assertEqual(code, 2, log)  # the cohesive step has no global estimate
        self.assertIn("needs an effect that has one", log)
        self.assertFalse(os.path.exists(tu.path("cohesive_only_refined.msh")))


class Mass(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        scene("slab", "extruded.geo", 3)
        cls.target = 1.15 * tu.run_dt("slab")["recommended"]

    def test_within(self):
        code, log, rep = tu.refine("slab", self.target, "--max-added-mass", "40")
        self.assertEqual(code, 0, log)
        self.assertIn("met: mesh + ", log)
        ref = rep["refine"]
        self.assertEqual(ref["met_by"], "mesh and point masses", log)
        last = ref["rounds"][-1]
        self.assertEqual(last["kind"], "mass")
        self.assertLessEqual(last["added_percent"], 40)
        pm = rep["point_masses"]
        view = tu.view_values(tu.path("slab_r.msh"), "added mass at nodes")
        self.assertEqual(len(view), pm["nodes"])
        self.assertAlmostEqual(sum(view.values()), pm["total"], delta=1e-12 * pm["total"])
        self.assertAlmostEqual(pm["total"], last["added_mass"], delta=1e-12 * pm["total"])
        self.assertGreaterEqual(rep["dt"]["recommended"], self.target)
        # read back: run and verify on the refined mesh include the masses
        tu.write("slab_again.xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<mesh file="slab_r.msh"/>
<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
<effects><elastic formulation="3d"/></effects>
<time duration="1e-4"/>
</dtmap-scene>
""")
        again = tu.run_dt("slab_again")["recommended"]
        self.assertAlmostEqual(again, rep["dt"]["recommended"], delta=1e-12 * again)
        self.assertAlmostEqual(tu.report("slab_again_dt.json")["point_masses"]["total"], pm["total"],
                               delta=1e-12 * pm["total"])
        code, log = tu.run("verify", "slab_again.xml", "--steps", "500")
        self.assertEqual(code, 0, log)

    def test_beyond(self):
        code, log, rep = tu.refine("slab", self.target, "--max-added-mass", "1")
        self.assertEqual(code, 1, log)
        ref = rep["refine"]
        self.assertGreater(ref["mass_needed_percent"], 1)
        self.assertEqual(ref["met_by"], "not met")
        self.assertNotIn("point_masses", rep)
        self.assertIn("what the rule adds, not the least share", log)  # labelled as the rule's

    def test_bad_limits(self):
        for bad in ("-1", "101", "nan"):
            code, log = tu.run("refine", "slab.xml", "--target", "1", "--max-added-mass", bad)
            self.assertEqual(code, 2, log)


class Optimisers(unittest.TestCase):
    def test_passes(self):
        plate_scene()
        target = 1.3 * tu.run_dt("plate")["recommended"]
        steps = {}
        for passes, ran in ((None, []), ("relocate,laplace", ["relocate", "laplace"]), ("gmsh", [])):
            extra = ("--optimise", passes) if passes else ()
            code, log, rep = tu.refine("plate", target, "--max-iter", "1", *extra)
            r1 = rep["refine"]["rounds"][1]
            self.assertEqual(r1["optimisers"], ran, log)  # Gmsh's tetrahedral pass does not run in 2D
            steps[passes] = r1["recommended"]
        self.assertNotEqual(steps["relocate,laplace"], steps[None])  # the passes moved nodes
        self.assertEqual(steps["gmsh"], steps[None])  # the same field, the same mesh
        code, log = tu.run("refine", "plate.xml", "--target", "1", "--optimise", "relocate,bogus")
        self.assertEqual(code, 2, log)
        self.assertIn("bogus", log)


class Partitioned(unittest.TestCase):
    def test_remesh_whole(self):
        scene("parts", "partitioned.geo", 2)
        dt = tu.run_dt("parts")["recommended"]
        code, log, rep = tu.refine("parts", 1.3 * dt)
        self.assertEqual(code, 0, log)
        self.assertEqual(rep["refine"]["met_by"], "mesh", log)
        self.assertGreaterEqual(rep["dt"]["recommended"], 1.3 * dt * (1 - 1e-12), log)
        import gmsh
        gmsh.initialize(["t325", "-v", "0"])
        try:
            gmsh.open(tu.path("parts_r.msh"))
            names = {gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()}
            self.assertIn("left_side", names, names)
            d, t = names["left_side"]
            lines = sum(len(gmsh.model.mesh.getElements(d, e)[1][0]) for e in gmsh.model.getEntitiesForPhysicalGroup(d, t))
            self.assertGreater(lines, 0)  # its curve elements, not an empty group
            self.assertGreater(rep["mesh"]["elements"], 100, log)  # triangles, not the 10 boundary elements
        finally:
            gmsh.finalize()


if __name__ == "__main__":
    tu.main()
