"""Two parts of the real-CAD corpus (bench/cad/parts.tsv) end to end, and
the survey's verdict on a stop.

1. Gmsh's demos/boolean/component8.step (a STEP file in millimetres) and
   the L-bracket cut out of demos/boolean/as1-tu-203.stp (Debian's
   gmsh-doc, which scripts/setup.sh installs), through the wrapper .geo of
   bench/cad/corpus.py (Geometry.OCCTargetUnit for STEP, a 1e-3 dilation
   for BREP), mesh with `dtmap run` in metres:
   - the bracket cut is one solid of the table's volume (1 %: the table
     gives 4 digits);
   - the tetrahedra's total volume is the solid's volume (OpenCASCADE's,
     in mm^3) x 1e-9 within 2 % (curved faces are faceted by the mesh; a
     wrong scale is a factor 1e-9 or 1 away), and the mesh's extent lies
     between 0.8 and 1 times the solid's box x 1e-3 (OpenCASCADE's box
     encloses the control points of spline faces and the tolerance: 0.86
     of it for component8);
   - the smallest element step is its eigen length over the P-wave speed
     of steel, sqrt(E (1 - nu) / (rho (1 + nu) (1 - 2 nu))), within 1e-12
     relative (both are printed with 15 digits or more), and it lies
     between 1e-3 and 1 times the meshing size over that speed (a tet's
     eigen length is a fraction of its size; the 1e-3 is a sliver's);
   - the recommended step is safety x the basis step.
2. bench/cad/survey.py against a stand-in for dtmap whose recommended step
   grows with the uniform size until a cap: a refine stop is called wrong
   exactly when a coarser uniform mesh reaches the target at no more
   element-steps than the input, at the first such size factor, and
   bench/cad/table.py counts it so.
"""

import gzip
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import gmsh

import testutil as tu

CAD = os.path.join(tu.SRC, "bench", "cad")
sys.path.insert(0, CAD)
import corpus  # noqa: E402  (bench/cad/corpus.py)

DEMOS = "/usr/share/doc/gmsh-doc/doc/gmsh/demos/boolean"
E, NU, RHO = 210e9, 0.3, 7850.0
C_P = math.sqrt(E * (1 - NU) / (RHO * (1 + NU) * (1 - 2 * NU)))


def gunzip(name):
    dst = tu.path(name)
    with gzip.open(os.path.join(DEMOS, name + ".gz"), "rb") as f, open(dst, "wb") as g:
        g.write(f.read())
    return dst


def mesh_volume_and_extent(msh):
    """Sum of the tetrahedra's volumes and the nodes' extent, read with Gmsh's API."""
    import numpy
    gmsh.initialize(["t720", "-v", "0"])
    try:
        gmsh.open(msh)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        xyz = numpy.array(coords).reshape(-1, 3)
        index = {int(t): i for i, t in enumerate(tags)}
        _, nodes = gmsh.model.mesh.getElementsByType(4)
        tet = numpy.array([index[int(n)] for n in nodes]).reshape(-1, 4)
        a, b, c, d = (xyz[tet[:, k]] for k in range(4))
        vol = numpy.abs(numpy.einsum("ij,ij->i", numpy.cross(b - a, c - a), d - a)).sum() / 6
        return vol, xyz.max(axis=0) - xyz.min(axis=0), len(tet)
    finally:
        gmsh.finalize()


class Parts(unittest.TestCase):
    def check_part(self, name, part_file, fmt, size):
        nvol, vol_mm3, box_mm = corpus.describe(part_file)
        self.assertEqual(nvol, 1)
        geo = tu.write(name + ".geo", corpus.wrapper(name, os.path.basename(part_file), fmt))
        tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="%s"/>
<meshing dim="3" size="%g"/>
<material name="steel" default="true" E="%g" nu="%g" rho="%g"/>
<effects><elastic formulation="3d" length="eigen"/></effects>
<time safety="0.9" duration="1e-3"/>
</dtmap-scene>
""" % (geo, size, E, NU, RHO))
        dt = tu.run_dt(name)
        vol, extent, ntets = mesh_volume_and_extent(tu.path(name + "_dt.msh"))
        self.assertGreater(ntets, 500)
        self.assertAlmostEqual(vol / (vol_mm3 * 1e-9), 1, delta=0.02)
        for got, want in zip(extent, box_mm):
            self.assertLessEqual(got, want * 1e-3 * (1 + 1e-9))
            self.assertGreater(got, 0.8 * want * 1e-3)
        worst = tu.report(name + "_dt.json")["worst"][0]
        self.assertAlmostEqual(worst["dt"], dt["min"], delta=1e-15 * dt["min"])
        self.assertAlmostEqual(worst["length"] / worst["dt"] / C_P, 1, delta=1e-12)
        self.assertGreater(dt["min"], 1e-3 * size / C_P)
        self.assertLess(dt["min"], size / C_P)
        self.assertAlmostEqual(dt["recommended"], 0.9 * dt["basis_step"], delta=1e-14 * dt["recommended"])

    def test_component8_step(self):
        self.check_part("component8", gunzip("component8.step"), ".step", 3e-3)

    def test_as1_l_bracket_brep(self):
        row = [r for r in corpus.table() if r["name"] == "as1_l_bracket"][0]
        brep = tu.path("as1_l_bracket.brep")
        corpus.cut_solid(gunzip("as1-tu-203.stp"), brep, row["solid"])
        self.assertAlmostEqual(corpus.describe(brep)[1] / row["solid"], 1, delta=0.01)
        self.check_part("as1_l_bracket", brep, ".brep", 5e-3)


# A stand-in for dtmap: `run` meshes at the scene's size h (m) into
# (1e-2 / h)^3 elements with a step of min(k h, cap); `refine` stops (exit 1)
# with one cause. Its reports hold only what survey.py reads.
FAKE = r'''#!/usr/bin/env python3
import json, math, re, sys
k, cap = %(k)r, %(cap)r
a = sys.argv[1:]
h = float(re.search(r'size="([^"]+)"', open(a[1]).read()).group(1))
rep = a[a.index("--report") + 1]
n = int(round((1e-2 / h) ** 3))
rec = min(k * h, cap)
if a[0] == "run":
    json.dump({"mesh": {"elements": n}, "dt": {"recommended": rec, "basis": "nodal bound"},
               "cost": {"element_steps": n * math.ceil(1e-3 / rec)}}, open(rep, "w"))
    sys.exit(0)
json.dump({"refine": {"rounds": [{"kind": "input", "element_steps": 1}], "best": 0, "met": False,
                      "met_by": "not met", "stopped": "stalled",
                      "causes": [{"kind": "stalled", "message": "stalled"}]}}, open(rep, "w"))
sys.exit(1)
'''


class Verdict(unittest.TestCase):
    def survey(self, cap):
        work = tempfile.mkdtemp(prefix="t720-")  # outside tu.tmpdir(): these reports are not dtmap's
        try:
            fake = os.path.join(work, "dtmap")
            with open(fake, "w") as f:
                f.write(FAKE % {"k": 1e-4, "cap": cap})
            os.chmod(fake, 0o755)
            parts = os.path.join(work, "parts")
            os.makedirs(parts)
            # 8.5 V / 8000 = h^3 gives h = 1e-3 m: 1000 elements, below 3e3, so the survey
            # halves the size (the cube root of 1000 / 8000) and keeps h = 5e-4 m, 8000 elements
            with open(os.path.join(parts, "parts.list"), "w") as f:
                f.write("as1_bolt\tas1_bolt.geo\tgeo\t1\t%r\t\t\n" % (8000 / 8.5 * 1e-9 * 1e9))
            out = os.path.join(work, "out")
            subprocess.run([sys.executable, os.path.join(CAD, "survey.py"), "--dtmap", fake, "--parts-dir", parts,
                            "--out", out, "--configs", "1.5-default"], check=True, stdout=subprocess.DEVNULL)
            res = json.load(open(os.path.join(out, "as1_bolt", "1.5-default.json")))
            table = subprocess.run([sys.executable, os.path.join(CAD, "table.py"), out], check=True,
                                   stdout=subprocess.PIPE, universal_newlines=True).stdout
            return res, table
        finally:
            shutil.rmtree(work, ignore_errors=True)

    def test_wrong_stop(self):
        # the step grows with the size: x1.5 reaches the 1.5x target with (1/1.5)^3 the elements
        # and 1/1.5 the steps (the ceilings move it by < 1e-3)
        res, table = self.survey(cap=1.0)
        self.assertEqual(res["outcome"], "stop")
        self.assertTrue(res["wrong"])
        self.assertEqual(res["uniform_factor"], 1.5)
        self.assertEqual(res["input_elements"], 8000)
        self.assertAlmostEqual(res["uniform_cost_ratio"], (1 / 1.5) ** 3 / 1.5, delta=0.02)
        self.assertIn("| 1.5-default | 1 | 0 (0) | 0 | 1 | 0 | 0 |", table)

    def test_true_stop(self):
        # the step is capped at 1.2x the input's: no uniform size reaches 1.5x
        res, table = self.survey(cap=1.2 * 1e-4 * 5e-4)
        self.assertEqual(res["outcome"], "stop")
        self.assertFalse(res["wrong"])
        self.assertEqual(len(res["uniform"]), 6)
        self.assertIn("| 1.5-default | 1 | 0 (0) | 1 | 0 | 0 | 0 |", table)


if __name__ == "__main__":
    tu.main()
