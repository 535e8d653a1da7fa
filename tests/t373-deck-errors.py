"""`dtmap deck` on bad input and faults:
- an unknown solver, or none: exit 2, the message lists the solvers;
- an element kind the solver lacks: exit 2 naming the kind and the group
  (LS-DYNA and tet10: no length rule to set its TSSFAC by; Abaqus/Explicit
  and quad8 plane elements), nothing written, and what would work: the
  solvers that take it (tet10: calculix and abaqus, not lsdyna; plane
  strain quad8: calculix alone), or, for hex20 and hex27, which no solver
  takes, a first-order mesh (its hex8 taken by all three), never "choose
  another solver";
- --max-added-mass negative, not a number or above 100: exit 2; without
  --target: exit 2; a need above it: exit 1 with the figures, nothing
  written (an older deck stays as it was);
- an output path that is an input of the scene (the scene, its geometry):
  exit 2, the input unchanged; -o and --report one file: exit 2;
- a write that fails (the child's files may not grow past 64 kB:
  RLIMIT_FSIZE, SIGXFSZ ignored, so the write fails with EFBIG): exit 2
  naming the deck and the reason, the older deck byte for byte as it was,
  and no temporary left beside it."""

import os
import resource
import shutil
import signal
import subprocess
import unittest

import testutil as tu

SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="%s.geo"/>
  <meshing size="0.03" order="2" dim="%d"/>
  <material name="steel" groups="%s" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic%s/></effects>
</dtmap-scene>
"""
BOX = 'SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 0.1, 0.05, 0.04};\nPhysical Volume("block") = {1};\n'
SLAB = ('SetFactory("OpenCASCADE");\nRectangle(1) = {0, 0, 0, 0.1, 0.05};\nPhysical Surface("slab") = {1};\n'
        'Recombine Surface{1};\nMesh.SecondOrderIncomplete = 1;\n')
HEX = ('SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 0.1, 0.05, 0.04};\nPhysical Volume("block") = {1};\n'
       'Transfinite Curve{:} = 3; Transfinite Surface{:}; Recombine Surface{:}; Transfinite Volume{1};\n')
OLD = "an older deck\n"


def box():
    return os.path.join(tu.SRC, "geometries", "box.xml")


def deck(*args):
    return tu.run("deck", *args)


def text(path):
    with open(path) as f:
        return f.read()


class Errors(unittest.TestCase):
    def test_solvers(self):
        for args in (("--solver", "radioss"), ()):
            code, out = deck(box(), *args)
            self.assertEqual(code, 2, out)
            self.assertIn("calculix, abaqus, lsdyna", out)

    def lacks(self, name, geo, dim, group, form, solver, words, absent=()):
        tu.write(name + ".geo", geo)
        scene = tu.write(name + ".xml", SCENE % (name, dim, group, form))
        out_path = tu.path(name + ".k")
        code, out = deck(scene, "--solver", solver, "-o", out_path)
        self.assertEqual(code, 2, out)
        for w in words:
            self.assertIn(w, out)
        for w in absent:
            self.assertNotIn(w, out)
        self.assertFalse(os.path.exists(out_path))

    def test_kind_lacking(self):
        self.lacks("tet10", BOX, 3, "block", "", "lsdyna", ["LS-DYNA", "solid tet10", "group 'block'",
                                                             "(choose another solver: calculix, abaqus)"])
        self.lacks("quad8", SLAB, 2, "slab", ' formulation="plane-strain"', "abaqus",
                   ["Abaqus/Explicit", "plane-strain quad8", "group 'slab'", "(choose another solver: calculix)"])

    def test_second_order_hexahedra(self):
        """hex20 and hex27: no solver takes them; the error names the
        first-order mesh whose hex8 all three take."""
        for name, geo in (("hex20", HEX + "Mesh.SecondOrderIncomplete = 1;\n"), ("hex27", HEX)):
            for solver in ("calculix", "abaqus", "lsdyna"):
                with self.subTest(elements=name, solver=solver):
                    self.lacks(name, geo, 3, "block", "", solver,
                               ["solid %s elements of group 'block'" % name, "no solver here takes them",
                                'a first-order mesh would (<meshing order="1"> in the scene): calculix, abaqus, '
                                "lsdyna take its hex8 elements"], ["choose another solver"])

    def test_max_added_mass(self):
        for p in ("-1", "nan", "101"):
            code, out = deck(box(), "--solver", "abaqus", "--target", "6e-7", "--max-added-mass", p)
            self.assertEqual(code, 2, out)
        code, out = deck(box(), "--solver", "abaqus", "--max-added-mass", "5")
        self.assertEqual(code, 2, out)
        self.assertIn("--target", out)
        path = tu.write("kept.inp", OLD)
        code, out = deck(box(), "--solver", "abaqus", "--target", "6e-7", "--max-added-mass", "1", "-o", path)
        self.assertEqual(code, 1, out)
        self.assertIn("above --max-added-mass 1 %", out)
        self.assertIn("kg added at", out)
        self.assertEqual(text(path), OLD)
        code, out = deck(box(), "--solver", "abaqus", "--target", "6e-7", "--max-added-mass", "10", "-o", path, "-q")
        self.assertEqual(code, 0, out)

    def test_inputs_refused(self):
        folder = tu.path("inputs")
        os.makedirs(folder, exist_ok=True)
        for f in ("box.xml", "box.geo"):
            shutil.copy(os.path.join(tu.SRC, "geometries", f), folder)
        scene = os.path.join(folder, "box.xml")
        for target in (scene, os.path.join(folder, "box.geo")):
            before = text(target)
            code, out = deck(scene, "--solver", "calculix", "-o", target)
            self.assertEqual(code, 2, out)
            self.assertIn("is an input of the scene", out)
            self.assertEqual(text(target), before)
        same = os.path.join(folder, "same.inp")
        code, out = deck(scene, "--solver", "calculix", "-o", same, "--report", same)
        self.assertEqual(code, 2, out)
        self.assertFalse(os.path.exists(same))

    def test_failed_write(self):
        folder = tu.path("full")
        os.makedirs(folder, exist_ok=True)
        path = os.path.join(folder, "box.inp")
        with open(path, "w") as f:
            f.write(OLD)

        def limit():
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (64 * 1024, 64 * 1024))

        p = subprocess.run([tu.CLI, "deck", box(), "--solver", "calculix", "-o", path], cwd=folder,
                           preexec_fn=limit, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True)
        self.assertEqual(p.returncode, 2, p.stdout)
        self.assertIn(path, p.stdout)
        self.assertIn("File too large", p.stdout)
        self.assertEqual(text(path), OLD)
        self.assertEqual(sorted(os.listdir(folder)), ["box.inp"])


if __name__ == "__main__":
    tu.main()
