"""`dtmap verify --accuracy` on 2D and 3D meshes: the phase-speed error of a
plane wave simulated on the mesh against the measures' prediction
(src/study/wave.c, src/cost/along.c; docs/accuracy.md).

- A regular right-triangle lattice (the tri3 model's own lattice, 60 x 60
  cells of 1 mm, steel, plane strain; its opposite edges carry the same
  nodes, so it is a periodic sample: the whole wave, fitted to it, runs 12
  periods) near 600 kHz: the simulation reproduces the Bloch prediction
  within 5 % of it along the axis (P) and off the axis, where the S wave
  leads (+14 % along (0.8, 0.6)).
- The bundled disc meshed at 1 mm (tri3, granite host; a packet, the
  default frequency raised until it runs 3 periods: 1.04 MHz for P, 598 kHz
  for S): P and S, along x and along (0.6, 0.8), all within the 20 % band of
  the prediction from the mesh's own element shapes (src/cost/shapes.c;
  measured 2-7 %), the off-axis S wave lagging as the mesh does, not leading
  as the right-angled lattice would.
- The bundled box (tet4, 8 mm in a 0.1 m box) cannot hold a packet of 3
  periods at a frequency it resolves: verify says so and exits 2 (the
  tetrahedral checks run on periodic samples, t613-t615).
- Bad input exits 2 with a message: a branch other than P or S, a direction
  out of the plane of a 2D mesh, --wave without --accuracy.
- `--report` with `--accuracy` writes the wave and the printed figures as
  JSON (the lattice case): the same measured and predicted errors, the
  verdict, the step and its factor; the report names the wave.
"""

import itertools
import json
import os
import re
import shutil
import unittest

import testutil as tu

NUM = r"([-+]?[0-9.]+(?:e[-+]?[0-9]+)?)"


def lattice(name, n, h):
    """tri3 lattice of n x n cells of size h, each cut along (1, 1) (src/cost/dispersion.c), msh 2.2."""
    idx = {p: k + 1 for k, p in enumerate(itertools.product(range(n + 1), repeat=2))}
    els = []
    for i, j in itertools.product(range(n), repeat=2):
        els.append((idx[(i, j)], idx[(i + 1, j)], idx[(i + 1, j + 1)]))
        els.append((idx[(i, j)], idx[(i + 1, j + 1)], idx[(i, j + 1)]))
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "1", '2 1 "block"', "$EndPhysicalNames",
             "$Nodes", str(len(idx))]
    lines += ["%d %r %r 0" % (k, p[0] * h, p[1] * h) for p, k in idx.items()]
    lines += ["$EndNodes", "$Elements", str(len(els))]
    lines += ["%d 2 2 1 1 %d %d %d" % (k + 1, *e) for k, e in enumerate(els)]
    lines += ["$EndElements", ""]
    tu.write(name + ".msh", "\n".join(lines))
    return tu.write(name + ".xml", '<dtmap-scene version="1">\n  <mesh file="%s.msh"/>\n'
                    '  <material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>\n'
                    '  <effects><elastic formulation="plane-strain" length="eigen"/></effects>\n'
                    '  <time safety="0.9"/>\n</dtmap-scene>\n' % name)


def bundled(name):
    for ext in ("xml", "geo"):
        shutil.copy(os.path.join(tu.SRC, "geometries", name + "." + ext), tu.tmpdir())
    return tu.path(name + ".xml")


def accuracy(scene, *args):
    """Exit code, measured and predicted error (fractions) and the output."""
    code, out = tu.run("verify", scene, "--accuracy", *args)
    m = re.search(r"measured " + NUM + r" %, predicted " + NUM + " %", out)
    return code, (float(m.group(1)) / 100 if m else None), (float(m.group(2)) / 100 if m else None), out


class Lattice(unittest.TestCase):
    def test_bloch(self):
        scene = lattice("tri", 60, 1e-3)
        for wave, d in (("P", "1,0,0"), ("S", "1,0,0"), ("S", "0.8,0.6,0"), ("P", "0.6,0.8,0")):
            code, meas, pred, out = accuracy(scene, "--freq", "600e3", "--wave", wave, "--direction", d)
            self.assertEqual(code, 0, out)
            self.assertLess(abs(meas - pred), 0.05 * abs(pred), out)
            if wave == "S" and d != "1,0,0":
                self.assertGreater(pred, 0.1, out)  # the lattice's S wave leads off the axes


class Report(unittest.TestCase):
    def test_accuracy_report(self):
        scene, report = lattice("rep", 40, 1e-3), tu.path("wave.json")
        code, meas, pred, out = accuracy(scene, "--freq", "600e3", "--wave", "S", "--direction", "0.6,0.8,0",
                                         "--factor", "0.8", "--report", report)
        self.assertEqual(code, 0, out)
        with open(report) as f:
            r = json.load(f)
        acc = r["accuracy"]
        self.assertEqual(acc["wave"], "S")
        self.assertEqual(r["verdict"], "agrees")
        self.assertTrue(acc["periodic"])  # the lattice's opposite edges match
        self.assertGreaterEqual(acc["periods"], 11.9)
        # the wave vector nearest the one asked that fits the 40 mm sample: within a wavelength per side
        self.assertLess(abs(acc["direction"][0] - 0.6), 0.05)
        self.assertAlmostEqual(acc["frequency_asked"], 600e3, places=3)
        self.assertLess(abs(acc["frequency"] / 600e3 - 1), 0.1)
        # the printed figures are rounded to 1e-4 %
        self.assertLess(abs(acc["measured"] - meas), 1e-6, out)
        self.assertLess(abs(acc["predicted"] - pred), 1e-6, out)
        self.assertLess(abs(acc["agreement"] - (acc["measured"] - acc["predicted"]) / abs(acc["predicted"])), 1e-12)
        self.assertAlmostEqual(r["factor"], 0.8, places=12)
        self.assertAlmostEqual(r["step"], 0.8 * r["recommended"], delta=1e-12 * r["step"])
        self.assertGreater(r["steps"], 0)


class Bundled(unittest.TestCase):
    def test_disc_and_box(self):
        disc, box = bundled("brazilian_disc"), bundled("box")
        with open(disc) as f:
            text = f.read().replace('size="2e-3"', 'size="1e-3"')
        disc = tu.write("disc_1mm.xml", text)
        for wave in "PS":
            for d in ("1,0,0", "0.6,0.8,0"):
                code, meas, pred, out = accuracy(disc, "--wave", wave, "--direction", d)
                self.assertEqual(code, 0, out)
                self.assertIn("agrees", out)
                self.assertIn("raised to", out)  # the default frequency, until a packet runs 3 periods
                self.assertLess(abs(meas - pred), 0.2 * abs(pred), out)
                self.assertLess(meas, 0, out)  # lumped mass lags on these meshes, off the axes too
        code, meas, pred, out = accuracy(box, "--wave", "P")
        self.assertEqual(code, 2, out)
        self.assertIn("too small for a packet", out)
        code, meas, pred, out = accuracy(box, "--wave", "P", "--freq", "150e3")
        self.assertEqual(code, 2, out)
        self.assertIn("3 need", out)

    def test_bad_input(self):
        scene = lattice("small", 4, 1e-3)
        for args, what in ((("--wave", "Q"), "expected P or S"), (("--direction", "0,0,1"), "not a direction")):
            code, _, _, out = accuracy(scene, *args)
            self.assertEqual(code, 2, out)
            self.assertIn(what, out)
        code, out = tu.run("verify", scene, "--wave", "S")
        self.assertEqual(code, 2, out)
        self.assertIn("need --accuracy", out)


if __name__ == "__main__":
    tu.main()
