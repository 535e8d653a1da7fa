"""`verify --accuracy` finds every fully periodic tetrahedral box periodic,
whatever the order of its nodes (issue 45: the face matching of
src/study/periodic.c sorted with an "equal within tolerance" that is not a
consistent order, and refused some boxes, or some orders of one box).

- Gmsh meshes four periodic boxes (tests/reference/periodic_wave.py:
  gmsh.model.mesh.setPeriodic on each pair of opposite faces, Delaunay),
  unit cubes of 8, 10 and 12 cells and a 0.2 x 0.16 x 0.16 m box; the
  reference's own node classes (a k-d tree, no dtmap code) confirm that
  every face node has its twin on the opposite face.
- Each box is written five times as msh 2.2 with its node tags shuffled and
  its nodes and elements listed in a shuffled order (20 files in all): on
  each, `verify --accuracy` exits 0 and its report says the sample is
  periodic. On the code before the fix the 12-cell cube was refused in
  every order (exit 2: "the mesh is too small for a packet").
- `run` and `verify --accuracy` name the same two worst phase errors of a
  mesh (issue 45: verify printed a single element's own error, about 2x
  run's, which averages each element's spacing over three rings): run's
  report's phase measure and verify's `accuracy.mesh_measure` carry the
  same worst (averaged over the neighbourhood, 3 rings) and worst_alone,
  and both summaries print the same line naming them; on Gmsh's
  tetrahedra the two differ. This wave's own worst element alone (P along
  x: one branch, one direction) is at most the mesh's worst element alone
  (every branch and direction) in magnitude, within 1e-3 of it (the
  measure samples its curve at 512 points of k h and interpolates).
"""

import unittest

import numpy as np

import testutil as tu
import wavecheck as wc
from wavecheck import pw

BOXES = [("cube8", [1.0, 1.0, 1.0], 1 / 8), ("cube10", [1.0, 1.0, 1.0], 1 / 10), ("cube12", [1.0, 1.0, 1.0], 1 / 12),
         ("slab", [0.2, 0.16, 0.16], 0.04)]
ORDERS = 5  # shuffles of each box: 20 files


def shuffled_msh(name, xyz, tets, rng):
    """name.msh (2.2): the mesh with node tags a random permutation of 1..N,
    nodes listed in another random order, elements in a random order."""
    tag = rng.permutation(len(xyz)) + 1
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "1", '3 1 "block"', "$EndPhysicalNames",
             "$Nodes", str(len(xyz))]
    lines += ["%d %r %r %r" % (tag[i], *xyz[i]) for i in rng.permutation(len(xyz))]
    lines += ["$EndNodes", "$Elements", str(len(tets))]
    lines += ["%d 4 2 1 1 %d %d %d %d" % (e + 1, *tag[tets[t]]) for e, t in enumerate(rng.permutation(len(tets)))]
    return tu.write(name + ".msh", "\n".join(lines + ["$EndElements", ""]))


class Shuffled(unittest.TestCase):
    def test_every_order_is_periodic(self):
        rng = np.random.default_rng(45)
        for box_name, box, h in BOXES:
            xyz, tets = pw.periodic_box(box, h)
            _, ncls, _ = pw.node_classes(xyz, box)  # raises when a face node has no twin
            self.assertLess(ncls, len(xyz), box_name)
            for k in range(ORDERS):
                name = "%s_%d" % (box_name, k)
                shuffled_msh(name, xyz, tets, rng)
                wc.scene(name, name + ".msh", 20000.0)
                code, out = tu.run("verify", name + ".xml", "--accuracy", "--top", "0", "--report", name + ".json")
                self.assertEqual(code, 0, name + ":\n" + out)
                acc = tu.report(name + ".json")["accuracy"]
                self.assertTrue(acc["periodic"], name + ":\n" + out)
                print(name, len(tets), "tets:", [ln.strip() for ln in out.splitlines() if "agreement" in ln])

    def test_run_and_verify_name_the_same_worst(self):
        xyz, tets = pw.periodic_box([1.0, 1.0, 1.0], 1 / 12, path=tu.path("same.msh"))
        wc.scene("same", "same.msh", wc.CP / 1.0)  # the P wave fits the box once: verify runs that frequency
        code, run_out = tu.run("run", "same.xml", "-o", "same_dt.msh", "--report", "same.json", "--top", "0")
        self.assertEqual(code, 0, run_out)
        code, ver_out = tu.run("verify", "same.xml", "--accuracy", "--top", "0", "--report", "same_v.json")
        self.assertEqual(code, 0, ver_out)
        ran = [m for m in tu.report("same.json")["accuracy_measures"] if m["measure"] == "phase-speed error"][0]
        acc = tu.report("same_v.json")["accuracy"]
        ver = acc["mesh_measure"]
        for key in ("worst", "worst_alone", "worst_element", "worst_alone_element", "worst_rings", "median",
                    "elements", "frequency"):
            self.assertEqual(ran[key], ver[key], key)
        self.assertEqual(ran["worst_rings"], 3)
        self.assertGreater(abs(ran["worst_alone"]), 1.2 * abs(ran["worst"]), ran)
        line = "worst %+.3g %% averaged over its neighbourhood (3 rings of elements), %+.3g %% element alone" % (
            100 * ran["worst"], 100 * ran["worst_alone"])
        self.assertIn(line, run_out)
        self.assertIn(line, ver_out)
        self.assertLessEqual(abs(acc["predicted_worst_element"]), abs(ver["worst_alone"]) + 1e-3 * abs(ver["worst_alone"]),
                             (acc, ver))
        print(line, "; this wave's worst element alone %+.3g %%" % (100 * acc["predicted_worst_element"]))


if __name__ == "__main__":
    tu.main()
