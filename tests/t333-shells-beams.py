"""Shell and beam sections, end to end through `dtmap run`, against closed
forms and an independent reference.

1. One quad4 shell element and one beam element (tests/data/shell_beam_single.geo),
   under both rotary-inertia conventions, against the closed forms of
   docs/structural-kernels.md:
   - shell, square of side h, thickness t: scaled, the membrane step
     2/sqrt(lambda_m), lambda_m = 4E/((1 - nu) rho h^2);
     physical, lambda = max(lambda_m, 12 k G/(rho t^2) (1 + t^2/(3 h^2)));
   - beam of length L, circular profile radius r (I_y = I_z = I): scaled,
     the bar step L/sqrt(E/rho); physical, lambda = max(4E/(rho L^2),
     4kG/(rho L^2) + kGA/(rho I)) (torsion, 8G/(rho L^2), stays below);
   - the global estimate of the two separate elements is the larger
     eigenvalue of the two, so its step is the smaller element step: within
     1e-4 (Lanczos tolerance), never above (1e-12 rounding).
   Tolerance 1e-12 relative on the element steps: both sides are a few
   roundings of the same closed form once the kernel has solved its
   eigenproblem (its Schur-complement scale is exact, not bisected).
2. The bundled stiffened panel (geometries/stiffened_panel.xml: a curved
   shell skin with a beam stiffener on its nodes), against
   tests/reference/structural_ref.py (numpy/scipy, its own beam, the shell
   of shell_ref.py, rotary scales by bisection, assembled system with six
   unknowns per node):
   - every element step within 1e-10 (the reference's bisection stops at
     1e-12 relative in the scale);
   - the global estimate safe and within 1e-4 of the exact step;
   - nodal and element bounds below the exact step;
   - `dtmap verify` from the top mode is bounded at 0.999 of the exact
     step and blows up at 1.01 of it (1 % above the limit the top mode grows
     by about 1.2 per step, far past 1e6 in the run's steps).
3. The report names the convention the step uses and the physical step.
"""

import json
import math
import os
import shutil
import subprocess
import sys
import unittest

import testutil as tu

REF = os.path.join(tu.SRC, "tests", "reference", "structural_ref.py")
E, NU, RHO, K = 200e9, 0.3, 7850.0, 5.0 / 6.0
G = E / (2 * (1 + NU))
H, T = 0.1, 0.01  # shell square side and thickness
L, R = 0.05, 0.01  # beam length and radius

SINGLE = """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="shell_beam_single.geo"/>
  <meshing size="1" order="1" dim="2"/>
  <material name="steel" groups="plate rod" E="200e9" nu="0.3" rho="7850"/>
  <section groups="plate" kind="shell" thickness="0.01" %s/>
  <section groups="rod" kind="beam" radius="0.01" %s/>
  <effects><elastic/></effects>
  <output mesh="%s.msh" report="%s.json"/>
</dtmap-scene>
"""


def single(name, rotary):
    attr = 'rotary="%s"' % rotary if rotary else ""
    tu.write(name + ".xml", SINGLE % (attr, attr, name, name))
    code, out = tu.run("run", name + ".xml", "--posterior")
    if code:
        raise AssertionError("dtmap run %s: exit %d\n%s" % (name, code, out))
    return tu.report(name + ".json"), tu.view_values(tu.path(name + ".msh"), "dt")


def by_kind(rep):
    return {s["kind"]: s for s in rep["sections"]}


class SingleElements(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.copy(os.path.join(tu.SRC, "tests", "data", "shell_beam_single.geo"), tu.tmpdir())
        cls.scaled = single("scaled", None)
        cls.physical = single("physical", "physical")

    def close(self, got, want, rel, what):
        self.assertLessEqual(abs(got - want), rel * want, "%s: got %.17g, want %.17g" % (what, got, want))

    def steps(self, rep):
        k = by_kind(rep)
        return k["shell"]["dt_min"], k["beam"]["dt_min"]

    def test_scaled_closed_forms(self):
        shell, beam = self.steps(self.scaled[0])
        self.close(shell, 2 / math.sqrt(4 * E / ((1 - NU) * RHO * H * H)), 1e-12, "shell membrane step")
        self.close(beam, L / math.sqrt(E / RHO), 1e-12, "beam bar step L/c")

    def test_physical_closed_forms(self):
        shell, beam = self.steps(self.physical[0])
        lam_m = 4 * E / ((1 - NU) * RHO * H * H)
        lam_ts = 12 * K * G / (RHO * T * T) * (1 + T * T / (3 * H * H))
        self.close(shell, 2 / math.sqrt(max(lam_m, lam_ts)), 1e-12, "shell thickness-shear step")
        A, I = math.pi * R * R, math.pi * R ** 4 / 4
        lam = max(4 * E / (RHO * L * L), 4 * K * G / (RHO * L * L) + K * G * A / (RHO * I))
        self.close(beam, 2 / math.sqrt(lam), 1e-12, "beam shear-rotation step")

    def test_report_gives_both_conventions(self):
        for (rep, _), conv in ((self.scaled, "scaled"), (self.physical, "physical")):
            for kind in ("shell", "beam"):
                ri = by_kind(rep)[kind]["rotary_inertia"]
                self.assertEqual(ri["convention"], conv)
                self.assertEqual(ri["step_uses"], conv)
        s, p = by_kind(self.scaled[0]), by_kind(self.physical[0])
        for kind in ("shell", "beam"):  # the scaled run's physical figure is the physical run's step
            self.close(s[kind]["rotary_inertia"]["dt_physical_min"], p[kind]["dt_min"], 1e-12, kind)
            self.assertEqual(p[kind]["rotary_inertia"]["scale_max"], 1)
            self.assertGreater(s[kind]["rotary_inertia"]["scale_max"], 1)

    def test_global_is_the_smaller_element(self):
        for rep, _ in (self.scaled, self.physical):
            want = min(self.steps(rep))
            got = rep["dt"]["global"]
            self.assertLessEqual(got, want * (1 + 1e-12))
            self.assertGreaterEqual(got, want * (1 - 1e-4))


class StiffenedPanel(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for ext in ("geo", "xml"):
            shutil.copy(os.path.join(tu.SRC, "geometries", "stiffened_panel." + ext), tu.tmpdir())
        code, out = tu.run("run", "stiffened_panel.xml", "--posterior", "-o", "sp.msh", "--report", "sp.json")
        if code:
            raise AssertionError("dtmap run: exit %d\n%s" % (code, out))
        cls.rep = tu.report("sp.json")
        cls.dt = tu.view_values(tu.path("sp.msh"), "dt")
        beam = by_kind(cls.rep)["beam"]
        spec = {"E": E, "nu": NU, "rho": RHO, "convention": "scaled", "shells": {"skin": 0.005},
                "beams": {"stiffener": {"area": beam["area"], "iy": beam["iy"], "iz": beam["iz"], "j": beam["j"],
                                        "orientation": [1, 0, 0]}}}
        tu.write("spec.txt", json.dumps(spec))
        subprocess.run([sys.executable, REF, tu.path("sp.msh"), tu.path("spec.txt"), tu.path("ref.out")],
                       check=True, env=tu.plain_env(), stdout=subprocess.DEVNULL)
        with open(tu.path("ref.out")) as f:
            cls.ref = json.load(f)

    def test_profile(self):
        """width 0.01 along the section's y, height 0.04 along its z."""
        beam = by_kind(self.rep)["beam"]
        self.assertAlmostEqual(beam["area"], 4e-4, delta=1e-18)
        self.assertLessEqual(abs(beam["iy"] - 0.01 * 0.04 ** 3 / 12), 1e-15 * beam["iy"])
        self.assertLessEqual(abs(beam["iz"] - 0.04 * 0.01 ** 3 / 12), 1e-15 * beam["iz"])

    def test_element_map(self):
        self.assertEqual(len(self.ref["elements"]), len(self.dt))
        worst = max(abs(self.dt[int(tag)] - want) / want for tag, want in self.ref["elements"].items())
        print("figures (docs/sections.md): element map, worst relative difference %.1e" % worst)
        self.assertLessEqual(worst, 1e-10)

    def test_global_safe_and_close(self):
        exact, got = self.ref["dt_exact"], self.rep["dt"]["global"]
        print("figures (docs/sections.md): global / exact %.6f, nodal bound %.3f, element bound %.3f"
              % (got / exact, self.rep["dt"]["nodal"] / exact, self.rep["dt"]["min"] / exact))
        self.assertLessEqual(got, exact * (1 + 1e-12), "global estimate on the unsafe side")
        self.assertGreaterEqual(got, exact * (1 - 1e-4))
        self.assertLessEqual(self.rep["dt"]["nodal"], exact)
        self.assertLessEqual(self.rep["dt"]["min"], self.rep["dt"]["nodal"])

    def test_verify_brackets_the_exact_step(self):
        exact = self.ref["dt_exact"]
        for factor, want in ((0.999, 0), (1.01, 1)):
            code, out = tu.run("verify", "stiffened_panel.xml", "--posterior", "--dt", "%.12e" % (factor * exact),
                               "--report", "v%g.json" % factor, "-q")
            self.assertEqual(code, want, "verify at %g x the exact step: %s" % (factor, out))


if __name__ == "__main__":
    tu.main()
