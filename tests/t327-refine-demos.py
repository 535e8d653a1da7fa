"""refine's loop on Gmsh's own demos (Debian's gmsh-doc, which
scripts/setup.sh installs; each meshed the same way in every run seen),
at 1.3x the recommended step:

- A thin layer among other elements below the target is tried by one
  remesh (gmsh-doc's demos/boolean/neuron.geo at 1.3x its step: `run
  --target` names a layer whose best reach it estimates below the target,
  yet one remesh meets it, 12420 -> 6599 elements; before, refine stopped
  at once, exit 1).
- A first remesh that costs more than the input without meeting the target
  does not end the loop (gmsh-doc's demos/boolean/simple3.geo, plane
  stress, at 1.3x: round 1 has 382 elements against 328 and a shorter
  step; round 2 meets the target with 218 elements, 0.47x the cost; before,
  refine stopped after round 1, exit 1).
- Two remeshes in a row that do not beat the kept mesh end the size-field
  strategy (gmsh-doc's demos/boolean/import2.geo at 1.3x: 6 elements below
  the target in the model's extruded wedge in every round; rounds 1 and 2
  at 1.5e-8 and 2.3e-8 s against the input's 2.5e-8 s; before, the third
  round was spent too); the other strategies follow (the input's sizes
  scaled met it in the runs seen; before this search refine exited 1).
- A kept mesh that costs more than the input is said to (gmsh-doc's
  demos/boolean/slicer.geo, a STEP part, at 1.3x its input's global-basis
  step with --posterior: one remesh meets the target with 4496 elements
  against 3031, 1.07x the element-steps; the same counts in every run
  seen): exit 0 and a warning on stderr with the ratio and the counts.
- Refine searches before it concludes (issue 35):
  - gmsh-doc's tutorial/t15.geo at 1.3x its global-basis step with
    --posterior: before, refine stopped before any remesh naming "thickness"
    (exit 1); the input's sizes scaled (the strategy "scaled", what
    Mesh.MeshSizeFactor does) meet it, 506 -> about 200 elements, about
    0.3x the element-steps; exit 0, and nothing is said about a stop.
  - demos/simple_geo/pripyrtet.geo at 1.3x: every element below the target
    lies in the revolve whose Layers{} fix its counts: refine stops before
    any remesh (before, it spent two), naming the layer curves first.
  - demos/boolean/component8.step at 1.5x: before, refine stopped before any
    remesh naming a thin layer; now a uniform mesh at the size the target
    implies is tried first, and the cause rests on it; the stop is said once
    and refine.causes[] is not empty on exit 1.
  Gmsh 4.8 does not mesh CAD identically twice (the worst step scatters by
  up to about 9 %): the assertions are on what was tried and said, and on
  met targets, not on element counts.
"""

import gzip
import os
import shutil
import unittest

import testutil as tu


def demo(name, *extra, dim=3, where="demos/boolean", ext=".geo"):
    """gmsh-doc's demos/boolean/NAME.geo (or WHERE/NAME.EXT, and the files it
    reads) in the test's directory, with a steel scene NAME.xml (3D, or plane
    stress)."""
    ex = "/usr/share/doc/gmsh-doc/doc/gmsh/" + where
    assert os.path.isdir(ex), "%s: install gmsh-doc (scripts/setup.sh does)" % ex
    for f in (name + ext,) + extra:  # Debian compresses the larger examples
        src = os.path.join(ex, f)
        if os.path.exists(src):
            shutil.copy(src, tu.path(f))
        else:
            with gzip.open(src + ".gz", "rb") as z, open(tu.path(f), "wb") as out:
                shutil.copyfileobj(z, out)
    tu.elastic_scene(name, name + ext, dim, material='default="true"', time='duration="1e-3"')


class Dearer(unittest.TestCase):
    def test_warned(self):
        demo("slicer", "component8.step")
        dt = tu.run_dt("slicer", "--posterior")["recommended"]
        code, log, rep = tu.refine("slicer", 1.3 * dt, "--posterior")
        self.assertEqual(code, 0, log)
        rounds = rep["refine"]["rounds"]
        kept, first = rounds[rep["refine"]["best"]], rounds[0]
        ratio = kept["element_steps"] / first["element_steps"]
        self.assertGreater(ratio, 1.0, "the remesh of slicer.geo no longer costs more than its input: %s" % rounds)
        self.assertIn("the kept mesh meets the target but costs x%.3f" % ratio, log)
        self.assertIn("(%d against %d)" % (kept["elements"], first["elements"]), log)


class LayerTried(unittest.TestCase):
    def test_one_remesh(self):
        demo("neuron")
        dt = tu.run_dt("neuron")["recommended"]
        with open(tu.path("neuron.xml")) as f:
            tu.write("neuron_t.xml", f.read().replace('duration="1e-3"', 'duration="1e-3" target="%.9e"' % (1.3 * dt)))
        code, log = tu.run("run", "neuron_t.xml", "-q", "--report", "n_t.json", "-o", "n_t.msh")
        self.assertEqual(code, 0, log)
        layers = tu.report("n_t.json")["thickness_limited"]
        self.assertTrue(layers and all(l["reach"] < 1.3 * dt for l in layers), layers)  # the estimate says no
        code, log, rep = tu.refine("neuron", 1.3 * dt)
        self.assertEqual(code, 0, log)  # and one remesh does
        self.assertEqual(rep["refine"]["met_by"], "mesh", log)
        self.assertEqual(len(rep["refine"]["rounds"]), 2, log)


class DearerFirstRound(unittest.TestCase):
    def test_goes_on(self):
        demo("simple3", dim=2)
        dt = tu.run_dt("simple3")["recommended"]
        code, log, rep = tu.refine("simple3", 1.3 * dt)
        self.assertEqual(code, 0, log)
        rounds = rep["refine"]["rounds"]
        self.assertEqual(len(rounds), 3, log)
        self.assertGreater(rounds[1]["element_steps"], rounds[0]["element_steps"], log)  # the dearer first remesh
        self.assertLess(rounds[1]["recommended"], 1.3 * dt, log)
        self.assertEqual(rep["refine"]["best"], 2, log)  # met, and cheaper than the input
        self.assertLess(rounds[2]["element_steps"], rounds[0]["element_steps"], log)


class TwoRoundsBeatNothing(unittest.TestCase):
    def test_stops(self):
        demo("import2", "component8.step")
        dt = tu.run_dt("import2")["recommended"]
        code, log, rep = tu.refine("import2", 1.3 * dt)
        ref = rep["refine"]
        field = [r for r in ref["rounds"] if r.get("strategy") == "field"]
        self.assertEqual(len(field), 2, log)  # the size field ends after two, not the budget's three
        later = [r.get("strategy") for r in ref["rounds"][3:]]
        self.assertTrue(later and "field" not in later, log)  # then the other strategies, not exit 1 at once
        if code == 0:  # the input's sizes scaled met it in every run seen (before: exit 1, stalled)
            self.assertEqual(ref["met_by"], "mesh", log)
        else:
            self.assertEqual(code, 1, log)
            self.assertTrue(ref["causes"], log)


class Searches(unittest.TestCase):
    def test_scaled_meets_t15(self):
        demo("t15", "t1.geo", where="tutorial")
        dt = tu.run_dt("t15", "--posterior")["recommended"]
        code, log, rep = tu.refine("t15", 1.3 * dt, "--posterior", "--max-iter", "3", "--max-added-mass", "2")
        self.assertEqual(code, 0, log)  # before: exit 1, "thickness" before any remesh, "needs 4.45 %"
        ref = rep["refine"]
        self.assertEqual(ref["met_by"], "mesh", log)  # by a mesh, no mass needed
        self.assertLess(ref["cost_change"], -0.3, log)  # cheaper than the input (about 0.3x; scatter allowed)
        self.assertIn(ref["rounds"][ref["best"]]["strategy"], ("scaled", "uniform"), log)
        self.assertEqual(ref["stopped"], "the target is met")
        self.assertNotIn("stopped:", log)  # nothing about a stop on a run that met the target
        self.assertEqual([c["kind"] for c in ref["causes"] if c["kind"] != "size-options"], [], log)

    def test_layers_before_any_remesh(self):
        demo("pripyrtet", where="demos/simple_geo")
        dt = tu.run_dt("pripyrtet")["recommended"]
        code, log, rep = tu.refine("pripyrtet", 1.3 * dt, "--max-iter", "3")
        self.assertEqual(code, 1, log)
        ref = rep["refine"]
        self.assertEqual(len(ref["rounds"]), 1, log)  # before: two remeshes first
        self.assertIn("extrusion Layers{}", ref["stopped"])
        c = ref["causes"][0]
        self.assertEqual(c["kind"], "fixed-node-count", log)
        self.assertEqual(sorted(e["tag"] for e in c["entities"]), [13, 14])
        self.assertIn("Layers{", c["fix"])

    def test_uniform_before_a_cause(self):
        demo("component8", where="demos/boolean", ext=".step")
        dt = tu.run_dt("component8")["recommended"]
        code, log, rep = tu.refine("component8", 1.5 * dt, "--max-iter", "3")
        ref = rep["refine"]
        strategies = [r.get("strategy") for r in ref["rounds"][1:]]
        self.assertIn("uniform", strategies, log)  # before: no remesh, "no mesh of that layer reaches it"
        if code == 0:  # Gmsh's scatter may let a mesh meet it: nothing about a stop then
            self.assertEqual(ref["stopped"], "the target is met")
            return
        self.assertEqual(code, 1, log)
        self.assertTrue(ref["causes"], log)  # never empty on exit 1
        first = ref["causes"][0]
        self.assertIn(first["kind"], ("thickness", "shape-limited", "stalled", "budget"), log)
        if first["kind"] in ("thickness", "shape-limited"):
            self.assertIn("on a uniform mesh of", first["message"])  # shown by the mesh tried
        self.assertEqual(log.count("stopped:"), 1, log)  # the stop is said once
        self.assertEqual(log.count(ref["stopped"]), 1, log)
        self.assertEqual(log.count(first["message"]), 1, log)
        self.assertNotIn(", or ", ref["stopped"])  # one case, not a three-way sentence


if __name__ == "__main__":
    tu.main()
