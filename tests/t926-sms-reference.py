"""Selective mass scaling against an independent assembly (issue 44;
src/spectral/sms.c, sms_global.c, src/analysis/selective.c).

A steel block 20 x 20 x 10 mm with a layer 0.8 mm thick fused on its top
(OpenCASCADE fragments, one physical volume), meshed by Gmsh at 5 mm: the
layer's flat tetrahedra hold the step down. `dtmap run` gives the input's
recommended step; `dtmap run --selective-mass --target T` at T = 2x and 5x
that step. The reference is assembled here in numpy from the output .msh
(read with Gmsh's Python API), by its own formulas: each tet4's stiffness
V B^T D B of linear elasticity, its lumped mass rho V / 4 per node, its own
step 2 / sqrt(lambda_max(K_e, M_e)) by scipy.linalg.eigh on the 12 x 12
pencil, beta = max(0, (T / safety / dt_e)^2 - 1), the added mass beta
(W - w w^T / m) per direction, and lambda_max of the dense pencil (K, M_s)
by scipy.linalg.eigh. Checks:

- dtmap's scaled global step is at or below the exact one (1e-12 for the
  rounding of the two assemblies) and within its tolerance of it: the
  Lanczos residual is at most 1e-4 theta, so the step is at most 1e-4 / 2
  below, plus the certificate's rounding margin (1e-4 allowed in all);
  and it is proven (the mesh is far within the certificate's budget);
  with the certificate refused (DTMAP_BENCH_CERT_BUDGET=1 flop) the
  probable bound holds the exact lambda_max and its eps is at most
  1 - safety^2;
- the elements scaled, the largest beta, the smallest element step before
  (1e-9: the kernel's element eigen-solver against scipy's), and the
  trace of M_add per direction (1e-9);
- the translational mass is the model's rho V exactly (1e-12), with and
  without the scaling, and the target is met;
- second order (tet10, the same geometry): proven, the target met, the
  translational mass rho V (1e-9: the curved boundary is flat here, the
  volume the same as the tet4 mesh's to rounding);
- bad combinations exit 2 with their message: no target, --target without
  --selective-mass, a diffusion-only scene, shells and beams (not
  supported); nothing is written.
"""

import math
import os
import shutil
import subprocess

import numpy as np
import scipy.linalg

import testutil as tu
from slab import GEO, SHELLS, read_tets

E, NU, RHO, SAFETY = 210e9, 0.3, 7850.0, 0.9
TOL = 1e-4  # Lanczos's relative residual (dtmap's default)

SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="slab.geo"/>
<meshing dim="3" size="5e-3"/>
<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850" %s/>
<effects>%s</effects>
<time duration="1e-4"/>
</dtmap-scene>
"""


def elasticity():
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    d = np.zeros((6, 6))
    d[:3, :3] = lam
    d[np.arange(3), np.arange(3)] += 2 * mu
    d[np.arange(3, 6), np.arange(3, 6)] = mu
    return d


def tet_matrices(x, d):
    """Stiffness (12 x 12, node-major) and volume of a tet4."""
    a = np.hstack([np.ones((4, 1)), x])
    vol = abs(np.linalg.det(a)) / 6
    grads = np.linalg.inv(a)[1:, :].T  # dN_a/dx_j: row a
    b = np.zeros((6, 12))
    for n in range(4):
        gx, gy, gz = grads[n]
        b[:, 3 * n:3 * n + 3] = [[gx, 0, 0], [0, gy, 0], [0, 0, gz], [gy, gx, 0], [0, gz, gy], [gz, 0, gx]]
    return vol * b.T @ d @ b, vol


class Reference:
    """K, the lumped M, each element's step and its nodal masses."""

    def __init__(self, msh):
        self.xyz, self.tets = read_tets(msh, "t926")
        n = 3 * len(self.xyz)
        self.K, self.m = np.zeros((n, n)), np.zeros(n)
        self.dt, self.vol = [], []
        d = elasticity()
        for t in self.tets:
            ke, vol = tet_matrices(self.xyz[t], d)
            dofs = (3 * t[:, None] + np.arange(3)).ravel()
            self.K[np.ix_(dofs, dofs)] += ke
            self.m[dofs] += RHO * vol / 4
            lam = scipy.linalg.eigh(ke, np.full(12, RHO * vol / 4) * np.eye(12), eigvals_only=True)[-1]
            self.dt.append(2 / math.sqrt(lam))
            self.vol.append(vol)
        self.dt, self.vol = np.array(self.dt), np.array(self.vol)

    def scaled(self, target):
        """beta per element, M_s and the trace of M_add per direction."""
        beta = np.maximum(0, (target / SAFETY / self.dt) ** 2 - 1)
        ms, trace = np.diag(self.m), 0.0
        for t, b, vol in zip(self.tets, beta, self.vol):
            if b <= 0:
                continue
            w = np.full(4, RHO * vol / 4)
            add = b * (np.diag(w) - np.outer(w, w) / w.sum())
            trace += np.trace(add)
            for c in range(3):
                dofs = 3 * t + c
                ms[np.ix_(dofs, dofs)] += add
        return beta, ms, trace

    def lambda_max(self, ms):
        n = len(self.m)
        return scipy.linalg.eigh(self.K, ms, eigvals_only=True, subset_by_index=[n - 1, n - 1])[0]


class SelectiveMass(tu.unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        tu.write("slab.geo", GEO)
        tu.write("slab.xml", SCENE % ("", "<elastic formulation=\"3d\"/>"))
        code, log = tu.run("run", "slab.xml", "-q", "-o", "plain.msh", "--report", "plain.json")
        assert code == 0, log
        cls.input_step = tu.report("plain.json")["dt"]["recommended"]
        cls.ref = Reference(tu.path("plain.msh"))
        cls.runs = {}
        for factor in (2, 5):
            name = "sms%d" % factor
            code, log = tu.run("run", "slab.xml", "--selective-mass", "--target", "%.12e" % (factor * cls.input_step),
                               "-o", name + ".msh", "--report", name + ".json")
            assert code == 0, log
            cls.runs[factor] = (tu.report(name + ".json")["selective_mass"], log)

    def test_global_step(self):
        for factor, (sm, log) in self.runs.items():
            target = factor * self.input_step
            _, ms, _ = self.ref.scaled(target)
            exact = 2 / math.sqrt(self.ref.lambda_max(ms))
            dt = sm["global"]["dt"]
            print("target %dx = %.4e s: exact scaled step %.6e s, dtmap %.6e s (%s), %d Lanczos steps"
                  % (factor, target, exact, dt, sm["global"]["certificate"], sm["global"]["iterations"]))
            self.assertEqual(sm["global"]["certificate"], "proven")
            self.assertLessEqual(dt, exact * (1 + 1e-12))
            self.assertGreaterEqual(dt, exact * (1 - TOL))
            self.assertTrue(sm["target_met"])
            self.assertGreaterEqual(sm["recommended"], target)
            self.assertIn("PROVEN", log)
            self.assertIn("target MET", log)

    def test_probable(self):
        """The certificate refused (a budget of 1 flop): the probable bound."""
        target = 2 * self.input_step
        env = dict(os.environ, DTMAP_BENCH_CERT_BUDGET="1")
        p = subprocess.run([tu.CLI, "run", "slab.xml", "--selective-mass", "--target", "%.12e" % target, "-q", "-o",
                            "prob.msh", "--report", "prob.json"], cwd=tu.tmpdir(), env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True)
        self.assertEqual(p.returncode, 0, p.stdout)
        g = tu.report("prob.json")["selective_mass"]["global"]
        _, ms, _ = self.ref.scaled(target)
        exact = self.ref.lambda_max(ms)
        print("probable: bound / exact lambda_max %.6f, eps %.3g, %d steps" % (g["bound"] / exact, g["eps"],
                                                                             g["iterations"]))
        self.assertEqual(g["certificate"], "probable")
        self.assertEqual(g["deterministic"], "too dear")
        self.assertGreaterEqual(g["bound"], exact * (1 - 1e-12))
        self.assertLessEqual(g["eps"], 1 - SAFETY ** 2)

    def test_second_order(self):
        """tet10 (the lumped weights at the levels the analysis kept): it runs, proven, the target met, the
        translational mass kept; no reference here."""
        tu.write("slab2.xml", (SCENE % ("", "<elastic formulation=\"3d\"/>")).replace('size="5e-3"',
                                                                                    'size="5e-3" order="2"'))
        code, log = tu.run("run", "slab2.xml", "-q", "-o", "plain2.msh", "--report", "plain2.json")
        self.assertEqual(code, 0, log)
        target = 2 * tu.report("plain2.json")["dt"]["recommended"]
        code, log = tu.run("run", "slab2.xml", "--selective-mass", "--target", "%.12e" % target, "-o", "o2.msh",
                           "--report", "o2.json")
        self.assertEqual(code, 0, log)
        sm = tu.report("o2.json")["selective_mass"]
        self.assertEqual(sm["global"]["certificate"], "proven")
        self.assertTrue(sm["target_met"])
        m = sm["mass"]
        self.assertLessEqual(abs(m["translational_mass"] / m["translational_mass_lumped"] - 1), 1e-12)
        self.assertLessEqual(abs(m["translational_mass_lumped"] / (RHO * self.ref.vol.sum()) - 1), 1e-9)

    def test_elements_and_mass(self):
        total = RHO * self.ref.vol.sum()
        for factor, (sm, log) in self.runs.items():
            beta, _, trace = self.ref.scaled(factor * self.input_step)
            el, mass = sm["elements"], sm["mass"]
            self.assertEqual(el["scaled"], int((beta > 0).sum()))
            self.assertLessEqual(abs(el["beta_max"] / beta.max() - 1), 1e-9)
            self.assertLessEqual(abs(el["dt_input"] / self.ref.dt.min() - 1), 1e-9)
            for c in range(3):
                self.assertLessEqual(abs(mass["added_mass"][c] / trace - 1), 1e-9)
                self.assertLessEqual(abs(mass["model_mass"][c] / total - 1), 1e-12)
            self.assertLessEqual(abs(mass["translational_mass"] / total - 1), 1e-12)
            self.assertLessEqual(abs(mass["translational_mass_lumped"] / total - 1), 1e-12)
            self.assertIn("unchanged", log)
            self.assertGreater(sm["cost"]["cg_iterations"], 0)
            self.assertGreaterEqual(sm["cost"]["runtime_factor"], 1)

    def test_modes(self):
        """run --modes 4 beside --selective-mass at 2x and 5x: the selective variant's frequencies are the
        dense scaled pencil's lowest elastic ones (1e-8: the shift-invert Lanczos's convergence test is 1e-9
        on the eigenvalue, as t942's), its trace per direction the reference's (1e-9), no translational mass,
        each shift 100 (f_s / f - 1) of the reference (1e-5 percentage points), and the selective_mass
        object's accuracy the largest of them against the 1 % limit, with the summary's WARNING exactly
        when it is above."""
        lam0 = scipy.linalg.eigh(self.ref.K, np.diag(self.ref.m), eigvals_only=True, subset_by_index=[0, 9])
        f0 = np.sqrt(np.abs(lam0[6:])) / (2 * math.pi)
        above = []
        for factor in (2, 5):
            above.append(self.modes_at(factor, f0))
        self.assertEqual(above, [False, True])  # the 5x target moves the low modes by more than 1 %

    def modes_at(self, factor, f0):
        target = factor * self.input_step
        name = "modes%d" % factor
        code, log = tu.run("run", "slab.xml", "--selective-mass", "--target", "%.12e" % target, "--modes", "4", "-o",
                           name + ".msh", "--report", name + ".json")
        self.assertEqual(code, 0, log)
        rep = tu.report(name + ".json")
        modes = rep["modes"]
        v = {x["name"]: x for x in modes["variants"]}["selective mass"]
        _, ms, trace = self.ref.scaled(target)
        lam1 = scipy.linalg.eigh(self.ref.K, ms, eigvals_only=True, subset_by_index=[0, 13])
        f1 = np.sqrt(np.abs(lam1[6:])) / (2 * math.pi)
        print("modes at %dx: model %s Hz, selective %s Hz" % (factor, np.array(modes["frequencies"][:4]), f1[:4]))
        self.assertEqual(v["rigid"], 6)
        shifts = []
        for i in range(4):
            self.assertLessEqual(abs(modes["frequencies"][i] / f0[i] - 1), 1e-8)
            self.assertLessEqual(abs(v["frequencies"][i] / f1[i] - 1), 1e-8)
            j = v["match"][i] - 1  # matched by shape: at 5x the scaled modes reorder
            if factor == 2:
                self.assertEqual(j, i)
            shifts.append(100 * (f1[j] / f0[i] - 1))
            self.assertLessEqual(abs(v["shifts"][i] - shifts[-1]), 1e-5)
        self.assertAlmostEqual(v["deformation_mass"] / trace, 1, delta=1e-9)
        self.assertEqual(v["added_mass"], 0)
        self.assertIn("added to the deformation modes only", log)
        acc = rep["selective_mass"]["accuracy"]
        worst = max(abs(x) for x in shifts)
        print("accuracy at %dx: largest selective shift %.4g %% (reference %.4g %%), within 1 %%: %s"
              % (factor, acc["max_shift"], worst, acc["within_limit"]))
        self.assertEqual(acc["modes"], 4)
        self.assertLessEqual(abs(acc["max_shift"] - worst), 1e-5)
        self.assertEqual(acc["within_limit"], worst <= 1.0)
        self.assertEqual("WARNING: selective mass moves the low modes" in log, worst > 1.0)
        self.assertIn("the lowest 4 elastic modes move by up to", log)
        return worst > 1.0

    def test_bad_combinations(self):
        cases = [(("--selective-mass",), "needs a target step"),
                 (("--target", "1e-6"), "--target is the step of --selective-mass or of --modes'")]
        for extra, message in cases:
            code, log = tu.run("run", "slab.xml", "-o", "bad.msh", *extra)
            self.assertEqual(code, 2, log)
            self.assertIn(message, log)
            self.assertFalse(os.path.exists(tu.path("bad.msh")))
        tu.write("heat.xml", SCENE % ('conductivity="50" heat-capacity="460"', "<thermal/>"))
        code, log = tu.run("run", "heat.xml", "-o", "bad.msh", "--selective-mass", "--target", "1e-3")
        self.assertEqual(code, 2, log)
        self.assertIn("needs an elastic (wave) effect", log)
        self.assertFalse(os.path.exists(tu.path("bad.msh")))
        shutil.copy(os.path.join(tu.SRC, "tests", "data", "shell_beam_single.geo"), tu.tmpdir())
        tu.write("shell.xml", SHELLS)
        code, log = tu.run("run", "shell.xml", "-o", "bad.msh", "--selective-mass", "--target", "1e-5")
        self.assertEqual(code, 2, log)
        self.assertIn("shells and beams is not supported", log)
        self.assertFalse(os.path.exists(tu.path("bad.msh")))


if __name__ == "__main__":
    tu.main()
