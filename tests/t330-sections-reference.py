"""Sections against an independent reference: the bundled reinforced block
(geometries/reinforced_block.xml: concrete tetrahedra with four embedded
steel rebars as trusses and an embedded steel plate as a membrane, sharing
their nodes) run by `dtmap run --posterior`, and the same mesh (the .msh
dtmap wrote) given to tests/reference/sections_ref.py, which assembles the
element and global matrices from the physics with numpy/scipy and shares
no code with dtmap. The reference's own closed-form self-test runs first.

Checks and tolerances:
- every rebar element's step is L / sqrt(E / rho), the exact truss step,
  from the node coordinates of the .msh: 1e-12 relative (the .msh keeps 16
  significant digits, the closed form is a few roundings);
- every element's step (the "dt" view) equals the reference's element
  bound: 1e-10 relative (both solve a small dense eigenproblem, dtmap's in
  the element frame or in closed form, the reference's in global axes);
- the global estimate (dt.global) is on the safe side of the reference's
  exact step of the assembled system, within 1e-4 of it (dtmap's Lanczos
  tolerance), allowing 1e-12 for the rounding of the two eigensolvers;
- the nodal bound and the element bound lie below the exact step;
- `dtmap verify` (central differences on the coupled truss + membrane +
  solid system, from its top mode) stays bounded for 2000 steps at 0.999
  of the exact step and blows up at 1.01 of it: 1 % above the limit the top
  mode grows by about 1.3 per step, far past 1e6 within 2000 steps.
"""

import json
import math
import os
import shutil
import subprocess
import sys
import unittest

import gmsh

import testutil as tu

REF = os.path.join(tu.SRC, "tests", "reference", "sections_ref.py")
STEEL_E, STEEL_RHO = 200e9, 7850.0


def rebar_lengths(path):
    """{tag: length} of the line elements of physical group 'rebar'."""
    gmsh.initialize(["t330", "-v", "0"])
    try:
        gmsh.open(path)
        out = {}
        for dim, tag in gmsh.model.getPhysicalGroups(1):
            if gmsh.model.getPhysicalName(dim, tag) != "rebar":
                continue
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                etags, enodes = gmsh.model.mesh.getElementsByType(1, ent)
                for k, et in enumerate(etags):
                    a = gmsh.model.mesh.getNode(enodes[2 * k])[0]
                    b = gmsh.model.mesh.getNode(enodes[2 * k + 1])[0]
                    out[int(et)] = math.dist(a, b)
        return out
    finally:
        gmsh.finalize()


class ReinforcedBlock(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for ext in ("geo", "xml"):
            shutil.copy(os.path.join(tu.SRC, "geometries", "reinforced_block." + ext), tu.tmpdir())
        code, out = tu.run("run", "reinforced_block.xml", "--posterior", "-o", "rb.msh", "--report", "rb.json")
        if code:
            raise AssertionError("dtmap run: exit %d\n%s" % (code, out))
        spec = os.path.join(tu.SRC, "tests", "reference", "reinforced_block.spec.json")
        subprocess.run([sys.executable, REF, tu.path("rb.msh"), spec, tu.path("ref.out")], check=True,
                       env=tu.plain_env(), stdout=subprocess.DEVNULL)
        with open(tu.path("ref.out")) as f:  # not *.json: only dtmap's reports are checked against the schema
            cls.ref = json.load(f)
        cls.rep = tu.report("rb.json")
        cls.dt = tu.view_values(tu.path("rb.msh"), "dt")

    def test_reference_self_test(self):
        p = subprocess.run([sys.executable, REF, "--self-test"], env=tu.plain_env(), stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True)
        self.assertEqual(p.returncode, 0, p.stdout)

    def test_every_kind_is_there(self):
        n = self.ref["nelements"]
        self.assertEqual(self.rep["mesh"]["elements"], n["solid"] + n["truss"] + n["membrane"])
        self.assertGreater(n["truss"], 0)
        self.assertGreater(n["membrane"], 0)
        self.assertEqual(len(self.dt), self.rep["mesh"]["elements"])

    def test_trusses_exact(self):
        lengths = rebar_lengths(tu.path("rb.msh"))
        self.assertEqual(len(lengths), self.ref["nelements"]["truss"])
        c = math.sqrt(STEEL_E / STEEL_RHO)
        for tag, length in lengths.items():
            want = length / c
            self.assertLessEqual(abs(self.dt[tag] - want), 1e-12 * want, "rebar element %d" % tag)

    def test_report_sections(self):
        by_kind = {s["kind"]: s for s in self.rep["sections"]}
        self.assertEqual(by_kind["truss"]["elements"], self.ref["nelements"]["truss"])
        self.assertEqual(by_kind["membrane"]["elements"], self.ref["nelements"]["membrane"])
        truss = by_kind["truss"]
        self.assertLessEqual(abs(truss["anchor"]["dt_min"] - truss["dt_min"]), 1e-12 * truss["dt_min"])
        want = self.ref["min_element_dt"]["membrane"]
        self.assertLessEqual(abs(by_kind["membrane"]["dt_min"] - want), 1e-10 * want)

    def test_verify_brackets_the_exact_step(self):
        exact = self.ref["global_dt"]
        for factor, want in ((0.999, 0), (1.01, 1)):
            code, out = tu.run("verify", "reinforced_block.xml", "--posterior", "--dt", "%.12e" % (factor * exact),
                               "--report", "v%g.json" % factor, "-q")
            self.assertEqual(code, want, "verify at %g x the exact step: %s" % (factor, out))

    def test_refine_keeps_sections(self):
        """refine to 1.3 x the recommended step of `run` (the nodal bound's:
        refine does not use the global estimate) remeshes the block with its
        embedded rebars and plate and meets the target; the kept mesh still
        holds trusses and membrane elements, each truss at its exact L/c."""
        target = 1.3 * self.rep["dt"]["safety"] * self.rep["dt"]["nodal"]
        code, out = tu.run("refine", "reinforced_block.xml", "--target", "%.6e" % target, "-o", "rr.msh",
                           "--report", "rr.json", "-q")
        self.assertEqual(code, 0, out)
        kinds = {s["kind"]: s for s in tu.report("rr.json")["sections"]}
        self.assertGreater(kinds["truss"]["elements"], 0)
        self.assertGreater(kinds["membrane"]["elements"], 0)
        t = kinds["truss"]
        self.assertLessEqual(abs(t["anchor"]["dt_min"] - t["dt_min"]), 1e-12 * t["dt_min"])

    def test_element_map(self):
        worst = 0.0
        for tag, want in self.ref["element_dt"].items():
            worst = max(worst, abs(self.dt[int(tag)] - want) / want)
        print("figures (docs/sections.md): element map, worst relative difference %.1e" % worst)
        self.assertLessEqual(worst, 1e-10)

    def test_global_safe_and_close(self):
        exact = self.ref["global_dt"]
        got = self.rep["dt"]["global"]
        print("figures (docs/sections.md): global / exact %.6f, nodal bound %.2f, element bound %.2f"
              % (got / exact, self.rep["dt"]["nodal"] / exact, self.rep["dt"]["min"] / exact))
        self.assertLessEqual(got, exact * (1 + 1e-12), "global estimate on the unsafe side")
        self.assertGreaterEqual(got, exact * (1 - 1e-4))
        self.assertLessEqual(self.rep["dt"]["nodal"], exact)
        self.assertLessEqual(self.rep["dt"]["min"], self.rep["dt"]["nodal"])


if __name__ == "__main__":
    tu.main()
