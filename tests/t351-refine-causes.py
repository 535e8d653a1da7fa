"""Every stop of `dtmap refine` names its cause from what the model holds.
One small geometry per cause (tests/data/refine/), each refined at 1.3 times
its recommended step with at most 3 rounds:

- clamp.geo sets Mesh.MeshSizeMin = Mesh.MeshSizeMax: refine lifts them for
  its remeshes, meets the target, and names them ("size-options", with the
  options' values and the lines that would let the suggestion through).
- transfinite.geo (a transfinite square, 21 nodes a side) with --keep-counts:
  the target is not met; the first cause is "fixed-node-count" naming curves
  1-4, with a "Transfinite Curve{t} = n;" line each, n below 21 (the
  suggestion is coarser); the terminal prints the lines. Without it refine
  sets those counts itself (t325).
- extruded.geo (a slab extruded in 4 layers, 0.05 m each, at a target whose
  size exceeds them): refine stops before its first remesh (no remesh
  changes the layers), and "fixed-node-count" names the four curves along
  the extrusion, with the Layers{} count the target needs; without
  Recombine the layers are tetrahedra, so nothing is named as recombined.
- periodic.geo (a square whose right side copies its left): with a target out
  of reach of every strategy (30x), the causes name curve 2 as periodic, and
  the kept mesh, saved before later remeshes, is read back without a crash.
- discrete.geo (a volume bounded by an STL surface): Gmsh refuses every
  remesh ("No elements in volume 1"), of every strategy; refine exits 1 (not
  2), writes round 0's mesh and report, and quotes Gmsh's reason with the
  entity.
"""

import os
import shutil
import unittest

import testutil as tu

DATA = os.path.join(tu.SRC, "tests", "data", "refine")


def scene(name, dim):
    for f in os.listdir(DATA):
        shutil.copy(os.path.join(DATA, f), tu.path(f))
    return tu.elastic_scene(name, name + ".geo", dim)


def refine(name, dim, factor=1.3, rounds=3, *extra):
    scene(name, dim)
    code, log = tu.run("run", name + ".xml", "-q", "-o", name + "_dt.msh", "--report", name + "_dt.json")
    assert code == 0, log
    target = factor * tu.report(name + "_dt.json")["dt"]["recommended"]
    code, log = tu.run("refine", name + ".xml", "--target", "%.6e" % target, "--max-iter", str(rounds),
                       "-o", name + "_r.msh", "--report", name + "_r.json", *extra)
    return code, log, tu.report(name + "_r.json")["refine"]


def cause(ref, kind):
    found = [c for c in ref["causes"] if c["kind"] == kind]
    return found[0] if found else None


class Causes(unittest.TestCase):
    def test_clamp(self):
        code, log, ref = refine("clamp", 2)
        self.assertEqual(code, 0, log)
        c = cause(ref, "size-options")
        self.assertIsNotNone(c, log)
        self.assertIn("Mesh.MeshSizeMin = 0.05, Mesh.MeshSizeMax = 0.05", c["message"])
        self.assertIn("refine lifted them", c["message"])
        self.assertIn("Mesh.MeshSizeMax = ", c["fix"])
        self.assertIn("[size-options]", log)

    def test_transfinite(self):
        code, log, ref = refine("transfinite", 2, 1.3, 3, "--keep-counts")
        self.assertEqual(code, 1, log)
        c = ref["causes"][0]
        self.assertEqual(c["kind"], "fixed-node-count", log)
        self.assertEqual(sorted((e["dim"], e["tag"]) for e in c["entities"]), [(1, 1), (1, 2), (1, 3), (1, 4)])
        lines = c["fix"].splitlines()
        self.assertEqual(len(lines), 4)
        for t, line in zip(range(1, 5), lines):
            self.assertTrue(line.startswith("Transfinite Curve{%d} = " % t), line)
            n = int(line.split("=")[1].split(";")[0])
            self.assertTrue(2 <= n < 21, line)
        self.assertIn("Transfinite Curve{1} = ", log)
        self.assertEqual(log.count("4 curve(s) have a node count the model fixes"), 1, log)  # said once
        self.assertEqual(len(ref["rounds"]), 1, log)  # no remesh sets a count refine keeps

    def test_extruded(self):
        code, log, ref = refine("extruded", 3, 2.0)
        self.assertEqual(code, 1, log)
        self.assertEqual(len(ref["rounds"]), 1, log)  # stopped before any remesh
        self.assertIn("where the model fixes the node counts", ref["stopped"])
        c = cause(ref, "fixed-node-count")
        self.assertIsNotNone(c, log)
        self.assertEqual(len(c["entities"]), 4)  # the four vertical edges of the slab
        self.assertTrue(all(e["dim"] == 1 for e in c["entities"]))
        self.assertIn("Layers{", c["fix"])
        r = cause(ref, "recombined")
        self.assertIsNone(r)  # tetrahedra: Layers without Recombine make prisms split into tets

    def test_periodic(self):
        code, log, ref = refine("periodic", 2, factor=30.0, rounds=1)
        self.assertEqual(code, 1, log)  # 8x is met since refine searches (the input's sizes scaled by 10)
        # the kept mesh is read back after later remeshes: its periodic node pairs, which named nodes
        # of a cleared mesh, crashed Gmsh there before they were cut out of the saved mesh
        self.assertLess(ref["best"], len(ref["rounds"]) - 1, log)
        c = cause(ref, "periodic")
        self.assertIsNotNone(c, log)
        self.assertEqual([(e["dim"], e["tag"]) for e in c["entities"]], [(1, 2)])
        self.assertIn("Curve 2 copies Curve 4", c["message"])

    def test_refused(self):
        code, log, ref = refine("discrete", 3)
        self.assertEqual(code, 1, log)
        self.assertTrue(os.path.exists(tu.path("discrete_r.msh")))
        c = ref["causes"][0]
        self.assertEqual(c["kind"], "gmsh-refused")
        self.assertIn("remeshing after round 0", c["message"])  # no round of its own: named by the last one made
        self.assertIn("No elements in volume 1", c["message"])
        self.assertEqual(ref["stopped"], "Gmsh refused every remesh tried")
        self.assertTrue(all(r["kind"] == "input" for r in ref["rounds"]), log)
        self.assertEqual(ref["best"], 0)


if __name__ == "__main__":
    tu.main()
