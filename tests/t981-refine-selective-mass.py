"""refine --selective-mass: the way `mesh + selective mass` beside `mesh + mass`
(issue 44 item 4; src/study/refine_selective.c, src/cli/refine.c,
src/output/refine_report.c).

The geometry of t926: a steel block 20 x 20 x 10 mm with a layer 0.8 mm
thick fused on its top (OpenCASCADE fragments), meshed by Gmsh at 5 mm. The
layer caps the step whatever the mesh, so at 4x the input's recommended step
no mesh refine tries meets the target (--max-iter 1 keeps it short). Checks:

- refine --selective-mass --modes 3 prints both ways (the `mesh + mass` line,
  the `mesh + selective mass` line, and the side-by-side block with point
  masses and selective mass), exits 1 (the written mesh falls short) and
  says in its error that the selective way meets the target;
- the selective way's recommended step meets the target on a proven or
  probable bound, its cost against the input is the kept mesh's elements x
  ceil(duration / its step) x the mass solves' runtime factor over the
  input's element-steps (1e-12), and every figure of its selective_mass object equals
  `dtmap run --selective-mass --target T --modes 3` on the kept mesh as
  refine wrote it (1e-9 relative: the same mesh read back, the same Lanczos
  seed, tolerance and steps; only the measured wall times differ), as do the
  kept mesh's step without added mass, the point masses the way is compared
  with (deck --target's rule: run --modes's conventional variant) and the
  lowest 3 frequencies with their shifts under both;
- its translational mass equals the model's, rho V of the kept mesh's
  tetrahedra summed here from the .msh by Gmsh's Python API (1e-12: the
  same sum in another order), while the point masses change it;
- with --max-added-mass the mass round is kept (exit 0), and the selective
  way is of the mesh before its point masses: the same figures (1e-9);
- without --selective-mass one line says the way exists and the report's
  field is null; with it and a target the input meets, the way is "not
  needed";
- shells and beams: refused in the summary and the report, the refine not
  failed by it (exit 1 for the target only, never 2);
- bad combinations exit 2 and write nothing: --modes without
  --selective-mass, --modes 0, --selective-mass on a scene with a <mesh>
  instead of a <geometry>.
"""

import math
import os
import shutil

import numpy as np

import testutil as tu
from slab import GEO, SHELLS, read_tets

RHO = 7850.0
TIMED = {"product_ratio", "runtime_factor"}  # measured wall times (and every *seconds): not reproducible

SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
%s
<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
<effects><elastic formulation="3d"/></effects>
<time duration="1e-4"/>
</dtmap-scene>
"""
GEOMETRY = '<geometry file="slab.geo"/>\n<meshing dim="3" size="5e-3"/>'


def tet_mass(msh):
    """rho x the summed volume of the tet4s of msh, by Gmsh's API and numpy."""
    xyz, tets = read_tets(msh, "t981")
    x = xyz[tets]
    vol = np.abs(np.einsum("ij,ij->i", x[:, 1] - x[:, 0], np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]))) / 6
    return RHO * vol.sum()


def rel(a, b):
    return abs(a - b) / max(abs(b), 1e-300)


class RefineSelective(tu.unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        tu.write("slab.geo", GEO)
        tu.write("slab.xml", SCENE % GEOMETRY)
        code, log = tu.run("run", "slab.xml", "-q", "-o", "plain.msh", "--report", "plain.json")
        assert code == 0, log
        cls.input_step = tu.report("plain.json")["dt"]["recommended"]
        cls.target = 4 * cls.input_step
        cls.code, cls.log = tu.run("refine", "slab.xml", "--target", "%.12e" % cls.target, "--max-iter", "1",
                                   "--selective-mass", "--modes", "3", "-o", "kept.msh", "--report", "kept.json")
        cls.rep = tu.report("kept.json")
        cls.way = cls.rep["refine"]["ways"]["mesh_and_selective_mass"]
        tu.write("kept.xml", SCENE % '<mesh file="kept.msh"/>')
        code, log = tu.run("run", "kept.xml", "-q", "--selective-mass", "--target", "%.12e" % cls.target, "--modes",
                           "3", "-o", "kept_dt.msh", "--report", "run.json")
        assert code == 0, log
        cls.run_rep = tu.report("run.json")

    def test_both_ways_printed(self):
        print("input step %.6e s, target %.6e s; selective: %s" % (self.input_step, self.target,
                                                                   [l for l in self.log.splitlines()
                                                                    if "mesh + selective mass:" in l]))
        self.assertEqual(self.code, 1, self.log)  # the written mesh falls short
        self.assertFalse(self.rep["refine"]["met"])
        self.assertIsNone(self.rep["refine"]["ways"]["mesh"])
        self.assertIn("  mesh + mass:", self.log)
        self.assertIn("  mesh + selective mass: round %d scaled" % self.way["round"], self.log)
        self.assertIn("mesh + mass against mesh + selective mass on the kept mesh", self.log)
        self.assertIn("point masses (deck --target's rule)", self.log)
        self.assertIn("selective mass scaling", self.log)
        self.assertIn("dtmap deck SCENE.xml --solver calculix|lsdyna --target", self.log)
        self.assertIn("mesh + selective mass meets it", self.log)
        self.assertIn("modes        the lowest 3 elastic natural frequencies", self.log)

    def test_target_met_by_selective(self):
        sm = self.way["selective_mass"]
        self.assertEqual(self.way["state"], "computed")
        self.assertIn(sm["global"]["certificate"], ("proven", "probable"))
        self.assertTrue(sm["target_met"])
        self.assertGreaterEqual(sm["recommended"], self.target)
        self.assertEqual(self.way["round"], self.rep["refine"]["best"])
        self.assertLess(self.way["lumped_recommended"], self.target)
        # its cost against the input, as refine judges a round: elements x ceil(duration / step), times the
        # runtime factor of the mass solves (1e-12: the same arithmetic)
        rounds = self.rep["refine"]["rounds"]
        kept, steps = rounds[self.way["round"]], math.ceil(1e-4 / sm["recommended"])
        cost = kept["elements"] * steps * sm["cost"]["runtime_factor"] / rounds[0]["element_steps"]
        self.assertLessEqual(rel(self.way["cost_ratio"], cost), 1e-12)
        self.assertLessEqual(rel(self.way["runtime_ratio"],
                                 sm["cost"]["runtime_factor"] * self.way["lumped_recommended"] / sm["recommended"]),
                             1e-12)

    def test_equals_run_on_kept_mesh(self):
        def same(a, b, where):
            if isinstance(a, dict):
                self.assertEqual(sorted(a), sorted(b), where)
                for k in a:
                    if k not in TIMED and not k.endswith("seconds"):
                        same(a[k], b[k], where + "." + k)
            elif isinstance(a, list):
                self.assertEqual(len(a), len(b), where)
                for i, (x, y) in enumerate(zip(a, b)):
                    same(x, y, "%s[%d]" % (where, i))
            elif isinstance(a, float) and isinstance(b, float):
                self.assertLessEqual(rel(a, b), 1e-9, "%s: refine %r, run %r" % (where, a, b))
            else:
                self.assertEqual(a, b, where)

        sm, run = self.way["selective_mass"], self.run_rep["selective_mass"]
        print("refine's selective step %.12e s, run's %.12e s" % (sm["recommended"], run["recommended"]))
        same(sm, run, "selective_mass")
        self.assertLessEqual(rel(self.way["lumped_recommended"], self.run_rep["dt"]["recommended"]), 1e-9)
        same(self.rep["modes"], self.run_rep["modes"], "modes")
        conv = {v["name"]: v for v in self.run_rep["modes"]["variants"]}["conventional mass"]
        self.assertLessEqual(rel(self.way["conventional"]["added_mass"], conv["added_mass"]), 1e-9)
        self.assertLessEqual(rel(self.way["conventional"]["added_percent"], conv["added_percent"]), 1e-9)

    def test_translational_mass(self):
        m = self.way["selective_mass"]["mass"]
        model = tet_mass(tu.path("kept.msh"))
        print("translational mass %.12g kg, rho V %.12g kg, point masses +%.4g %%" % (
            m["translational_mass"], model, self.way["conventional"]["added_percent"]))
        self.assertLessEqual(rel(m["translational_mass"], model), 1e-12)
        self.assertLessEqual(rel(m["translational_mass_lumped"], model), 1e-12)
        self.assertGreater(min(m["added_mass"]), 0)
        self.assertGreater(self.way["conventional"]["added_percent"], 1)
        self.assertIn("unchanged", self.log)

    def test_with_point_masses(self):
        """--max-added-mass beside it: the mass round is kept (exit 0) and the selective way is of the same mesh
        before its point masses: the same figures as without them (1e-9, wall times aside)."""
        code, log = tu.run("refine", "slab.xml", "--target", "%.12e" % self.target, "--max-iter", "1",
                           "--selective-mass", "--max-added-mass", "60", "-o", "massr.msh", "--report", "massr.json")
        self.assertEqual(code, 0, log)
        rr = tu.report("massr.json")["refine"]
        self.assertEqual(rr["met_by"], "mesh and point masses")
        way = rr["ways"]["mesh_and_selective_mass"]
        self.assertEqual(way["round"], self.way["round"])
        for key in ("recommended", "element_target"):
            self.assertLessEqual(rel(way["selective_mass"][key], self.way["selective_mass"][key]), 1e-9)
        for key in ("translational_mass", "translational_mass_lumped"):
            self.assertLessEqual(rel(way["selective_mass"]["mass"][key], self.way["selective_mass"]["mass"][key]),
                                 1e-9)
        self.assertIn("the selective figures are of the mesh without them", log)

    def test_without_flag_and_not_needed(self):
        code, log = tu.run("refine", "slab.xml", "--target", "%.12e" % self.target, "--max-iter", "1", "-o",
                           "plainr.msh", "--report", "plainr.json")
        self.assertEqual(code, 1, log)
        self.assertIn("mesh + selective mass: not tried (--selective-mass", log)
        self.assertEqual(sum("mesh + selective mass" in l for l in log.splitlines()), 1)
        self.assertIsNone(tu.report("plainr.json")["refine"]["ways"]["mesh_and_selective_mass"])
        code, log = tu.run("refine", "slab.xml", "--target", "%.12e" % (0.5 * self.input_step), "--selective-mass",
                           "-o", "easy.msh", "--report", "easy.json")
        self.assertEqual(code, 0, log)
        self.assertEqual(tu.report("easy.json")["refine"]["ways"]["mesh_and_selective_mass"]["state"], "not needed")

    def test_shells_refused(self):
        shutil.copy(os.path.join(tu.SRC, "tests", "data", "shell_beam_single.geo"), tu.tmpdir())
        tu.write("shell.xml", SHELLS)
        code, log = tu.run("refine", "shell.xml", "--target", "1e-2", "--max-iter", "1", "--selective-mass", "-o",
                           "shell_r.msh", "--report", "shell_r.json")
        self.assertEqual(code, 1, log)
        self.assertIn("mesh + selective mass: refused:", log)
        self.assertIn("shells and beams is not supported", log)
        way = tu.report("shell_r.json")["refine"]["ways"]["mesh_and_selective_mass"]
        self.assertEqual(way["state"], "refused")
        self.assertIn("shells and beams", way["why"])

    def test_bad_combinations(self):
        cases = [(("slab.xml", "--modes", "3"), "--modes prices the selective mass way: give --selective-mass"),
                 (("slab.xml", "--selective-mass", "--modes", "0"), "--modes"),
                 (("kept.xml", "--selective-mass"), "refine needs a <geometry>")]
        for args, message in cases:
            code, log = tu.run("refine", *args, "--target", "%.12e" % self.target, "-o", "bad.msh", "--report",
                               "bad.json")
            self.assertEqual(code, 2, log)
            self.assertIn(message, log)
            self.assertFalse(os.path.exists(tu.path("bad.msh")))
            self.assertFalse(os.path.exists(tu.path("bad.json")))


if __name__ == "__main__":
    tu.main()
