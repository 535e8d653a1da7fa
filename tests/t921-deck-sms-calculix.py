"""`dtmap deck --solver calculix --target T --selective-mass` (issue 44):
Debian's ccx 2.20 applies its own selective mass scaling at the target, and
adds what the deck predicts by CalculiX's rule (src/deck/sms.c).

Two models, each deck run in Debian's ccx from a seeded random initial
velocity at every node, no loads:
- the bundled box (10161 tetrahedra), T = 6e-7 s (20.7x ccx's own estimate);
- a thin wall, 0.1 x 0.1 m and 2 mm thick, of 100 equal bricks (C3D8),
  T = 1e-6 s (3.8x ccx's own estimate).

What is checked, for each:
- the deck's *DYNAMIC minimum increment is T (what switches ccx's scaling
  on), and ccx prints "Selective Mass Scaling is active" and selects T as
  its increment (7 digits printed: within 1e-6);
- the elements ccx scales (its JOB_WarnElementMassScaled.nam) are exactly
  the deck's set DTMAP_SMS_SCALED, and their count is the report's;
- the largest beta ccx prints is the report's (within 1e-9: ccx prints 17
  digits);
- the mass: CalculiX's artificial energy, which it prints with the others
  (here every 10 increments), is v^T M_add v over its velocities v (resultsmech.f sums it
  with no factor 1/2), M_add the sum over the elements of
  beta_e m_e / (n (n - 1)) (n I - 1 1^T) per direction. Here it is computed
  from the velocities ccx prints at the same increment with beta_e =
  (T / dt_e)^2 - 1 from dtmap's own per-element rule (`dtmap run
  --solver-rule calculix`, view "dt calculix") and m_e = rho x the element's
  volume from the deck's nodes: it must be ccx's within 5 % (the issue's
  tolerance; both sides are the same quadratic form, so agreement is to
  ccx's 7 printed digits). The same beta_e and m_e must sum to the report's
  predicted sum beta_e m_e (1e-9), so the added mass ccx applies is the one
  predicted, element by element as the energy weighs them;
- the wall's bricks are equal, so ccx's own printed figures give the added
  mass on their own: its count x its largest beta x one brick's mass (the
  model's mass / 100) is the prediction within 5 %;
- energy stays bounded: over 200 increments at T, the internal and kinetic
  energies ccx prints plus half its artificial one (the kinetic energy of
  the added mass) stay finite and within 10 % of their first printed value
  (without loads or damping central differences keep this sum up to an
  oscillation of a few percent: 3 % on the wall; an unstable run grows
  without bound), and the velocities it prints are finite.
Beside them, the reinforced block and the stiffened panel (membranes,
springs, shells, a beam) check ccx's count and largest beta (below).
On the old code (no --selective-mass) the deck command exits 2.
"""

import math
import os
import random
import re
import shutil
import subprocess
import unittest

import deckutil as du
import testutil as tu

CCX = shutil.which("ccx") or "ccx"
RHO = 7850.0
PRINT = 10  # increments between ccx's prints
WALL_GEO = """Point(1) = {0, 0, 0, 0.01}; Point(2) = {0.1, 0, 0, 0.01};
Line(1) = {1, 2}; Transfinite Curve{1} = 11;
e[] = Extrude{0, 0.1, 0}{Curve{1}; Layers{10}; Recombine;};
v[] = Extrude{0, 0, 0.002}{Surface{e[1]}; Layers{1}; Recombine;};
Physical Volume("wall") = {v[1]};
"""
WALL_XML = """<dtmap-scene version="1">
  <geometry file="wall.geo"/>
  <meshing dim="3"/>
  <material name="steel" groups="wall" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic/></effects>
  <time duration="1e-4"/>
</dtmap-scene>
"""


def deck(scene, name, target):
    out, rep = tu.path(name + ".inp"), tu.path(name + ".json")
    code, text = tu.run("deck", scene, "--solver", "calculix", "--target", "%g" % target, "--selective-mass", "-o",
                        out, "--report", rep, "-q")
    if code:
        raise AssertionError("dtmap deck %s: exit %d\n%s" % (scene, code, text))
    return out, tu.report(rep)


def own_steps(scene, name):
    """{element tag: CalculiX's rule} from dtmap run --solver-rule calculix."""
    msh = tu.path(name + "_rule.msh")
    code, text = tu.run("run", scene, "--solver-rule", "calculix", "-o", msh, "-q")
    if code:
        raise AssertionError("dtmap run --solver-rule: exit %d\n%s" % (code, text))
    return tu.view_values(msh, "dt calculix")


def inp_elements(lines):
    """{element id: [node ids]} and the element set names of the *ELEMENT blocks."""
    els, sets, on = {}, [], False
    for line in lines:
        if line.startswith("*"):
            m = re.match(r"\*ELEMENT, TYPE=\w+, ELSET=(\w+)", line)
            on = bool(m)
            if m:
                sets.append(m.group(1))
            continue
        if on and line.strip():
            v = [int(x) for x in line.split(",")]
            els[v[0]] = v[1:]
    return els, sets


def inp_set(lines, name):
    """The ids of *ELSET name."""
    i, ids = lines.index("*ELSET, ELSET=%s" % name) + 1, set()
    while i < len(lines) and not lines[i].startswith("*"):
        ids |= {int(x) for x in lines[i].split(",") if x.strip()}
        i += 1
    return ids


def tet_volume(x):
    u, v, w = ([x[k][i] - x[0][i] for i in range(3)] for k in (1, 2, 3))
    return abs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
               u[2] * (v[0] * w[1] - v[1] * w[0])) / 6


def volume(x):
    """A tetrahedron's, or a hexahedron's as six tetrahedra about its 0-6 diagonal."""
    if len(x) == 4:
        return tet_volume(x)
    faces = ((1, 2), (2, 3), (3, 7), (7, 4), (4, 5), (5, 1))
    return sum(tet_volume([x[0], x[a], x[b], x[6]]) for a, b in faces)


def prepare(path, n_inc, seed=5):
    """RUN.inp beside the deck: slots opened, a random initial velocity at
    every node, energies and velocities printed every increment, n_inc
    increments of the deck's step. Returns (run name, its lines, the
    velocities)."""
    run, step = du.prepare(path, n_inc * 1.0)
    with open(path) as f:
        lines = f.read().split("\n")
    with open(run + ".inp") as f:
        runl = f.read().split("\n")
    i = runl.index(du.DYNAMIC)
    dyn = lines[lines.index(du.DYNAMIC) + 1]
    v = [x.strip() for x in dyn.split(",")]
    runl[i + 1] = "%s, %.14g, %s, %s" % (v[0], n_inc * float(v[0]), v[2], v[3])  # the deck's minimum kept
    with open(run + ".inp", "w") as f:
        f.write("\n".join(runl))
    base = os.path.splitext(path)[0]
    nodes, (_, sets) = du.inp_nodes(lines), inp_elements(lines)
    rng = random.Random(seed)
    with open(base + "_model.inp", "w") as f:
        ids = du.write_node_set(f, nodes)
        f.write("*ELSET, ELSET=DTMAPTEST_EALL\n" + ", ".join(sets) + "\n")
        f.write("*INITIAL CONDITIONS, TYPE=VELOCITY\n")
        for n in ids:
            for d in (1, 2, 3):
                f.write("%d, %d, %.9g\n" % (n, d, rng.uniform(-1, 1)))
    with open(base + "_step.inp", "w") as f:
        # one print frequency for all (ccx keeps the last): energies and velocities every PRINT increments
        f.write("*EL PRINT, ELSET=DTMAPTEST_EALL, TOTALS=ONLY, FREQUENCY=%d\nELSE\n"
                "*NODE PRINT, NSET=DTMAPTEST_ALL, FREQUENCY=%d\nV\n" % (PRINT, PRINT))
    return run, lines


def run_ccx(run):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    env.pop("LD_PRELOAD", None)
    d, name = os.path.split(run)
    p = subprocess.run([CCX, "-i", name], cwd=d, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       timeout=600)
    return p.returncode, p.stdout.decode(errors="replace")


def first_velocities(run):
    """{(node, direction): velocity} ccx prints first (increment PRINT)."""
    with open(run + ".dat") as f:
        text = f.read()
    block = text.split(" velocities ")[1].split("\n")[2:]
    v = {}
    for line in block:
        w = line.split()
        if len(w) != 4:
            break
        for d in range(3):
            v[(int(w[0]), d)] = float(w[1 + d])
    return v


def artificial(els, beta, mass, v):
    """v^T M_add v with CalculiX's added matrix."""
    e_total = 0.0
    for e, nodes in els.items():
        n = len(nodes)
        f = beta[e] * mass[e] / (n * (n - 1))
        for d in range(3):
            s1 = sum(v[(k, d)] for k in nodes)
            s2 = sum(v[(k, d)] ** 2 for k in nodes)
            e_total += f * (n * s2 - s1 * s1)
    return e_total


def floats(pattern, log):
    return [float(x) for x in re.findall(pattern, log)]


class SelectiveCalculix(unittest.TestCase):
    def check(self, scene, name, target, bricks=False):
        path, rep = deck(scene, name, target)
        d = rep["deck"]
        sm = d["selective_mass"]
        self.assertTrue(sm["solver_scales"])
        self.assertEqual(d["step"], target)
        self.assertLess(d["own_estimate"], target)
        run, lines = prepare(path, 200)
        dyn = [float(x) for x in lines[lines.index(du.DYNAMIC) + 1].split(",")]
        self.assertEqual(dyn[2], target, "the minimum increment is the target")
        code, log = run_ccx(run)
        self.assertEqual(code, 0, log[-2000:])
        self.assertIn("Job finished", log)
        self.assertIn("Selective Mass Scaling is active", log)
        sel = floats(r"SELECTED time increment:\s*(\S+)", log)
        self.assertTrue(sel and all(abs(s / target - 1) < 1e-6 for s in sel), sel)
        # the elements and the largest beta
        els, _ = inp_elements(lines)
        with open(run + "_WarnElementMassScaled.nam") as f:
            scaled = {int(x) for x in f.read().split()[1:]}
        self.assertEqual(scaled, inp_set(lines, "DTMAP_SMS_SCALED"))
        self.assertEqual(len(scaled), sm["elements"])
        self.assertEqual(int(re.search(r"In total\s+(\d+)\s+elements were scaled", log).group(1)), sm["elements"])
        beta_ccx = floats(r"beta \(maximum\) =\s*(\S+)", log)[0]
        self.assertLess(abs(beta_ccx / sm["beta_max"] - 1), 1e-9, (beta_ccx, sm["beta_max"]))
        # the mass, element by element, against ccx's artificial energy
        nodes = du.inp_nodes(lines)
        own = own_steps(scene, name)
        beta = {e: max(0.0, (target / own[e]) ** 2 - 1) for e in els}
        mass = {e: RHO * volume([nodes[k] for k in els[e][:8]]) for e in els}
        predicted = sum(beta[e] * mass[e] for e in els)
        self.assertLess(abs(predicted / sm["added_mass"] - 1), 1e-9, (predicted, sm["added_mass"]))
        e_ccx = floats(r"artificial energy due to selective mass scaling =\s*(\S+)", log)
        e_dtmap = artificial(els, beta, mass, first_velocities(run))
        self.assertLess(abs(e_ccx[0] / e_dtmap - 1), 0.05, (e_ccx[0], e_dtmap))
        if bricks:  # equal elements: ccx's own figures give the added mass
            from_ccx = len(scaled) * beta_ccx * d["model_mass"] / len(els)
            self.assertLess(abs(from_ccx / sm["added_mass"] - 1), 0.05, (from_ccx, sm["added_mass"]))
        # bounded energy
        internal = floats(r"internal energy =\s*(\S+)", log)
        kinetic = floats(r"kinetic energy =\s*(\S+)", log)
        total = [a + b + c / 2 for a, b, c in zip(internal, kinetic, e_ccx)]  # ccx's figure is twice the energy
        self.assertEqual(len(total), 200 // PRINT)
        self.assertTrue(all(math.isfinite(t) and abs(t / total[0] - 1) < 0.1 for t in total), total)
        self.assertTrue(0 < du.max_displacement(run + ".dat") < float("inf"))
        return sm, e_ccx[0], e_dtmap, total

    def test_box(self):
        sm, e_ccx, e_dtmap, total = self.check(os.path.join(tu.SRC, "geometries", "box.xml"), "box", 6e-7)
        print("box: %d elements, beta max %.6g, predicted %.6g kg; artificial energy ccx %.7g, dtmap %.7g; "
              "total energy %.4g to %.4g" % (sm["elements"], sm["beta_max"], sm["added_mass"], e_ccx, e_dtmap,
                                              min(total), max(total)))

    def test_thin_wall(self):
        tu.write("wall.geo", WALL_GEO)
        scene = tu.write("wall.xml", WALL_XML)
        sm, e_ccx, e_dtmap, total = self.check(scene, "wall", 1e-6, bricks=True)
        print("wall: %d elements, beta max %.6g, predicted %.6g kg; artificial energy ccx %.7g, dtmap %.7g; "
              "total energy %.4g to %.4g" % (sm["elements"], sm["beta_max"], sm["added_mass"], e_ccx, e_dtmap,
                                              min(total), max(total)))

    def test_layers_and_springs(self):
        """The reinforced block (tetrahedra, membranes, trusses as springs
        and masses) and the stiffened panel (shells, a beam) at 3e-6 s:
        ccx's count of scaled elements is the report's plus the springs
        and mass elements it counts without adding them mass, its largest
        beta the report's, its increment the target; 20 increments from a
        seeded random force at every node end with finite displacements.
        The mass of the layers it builds is not checked (their nodes are
        its own)."""
        for name in ("reinforced_block", "stiffened_panel"):
            with self.subTest(example=name):
                path, rep = deck(os.path.join(tu.SRC, "geometries", name + ".xml"), name, 3e-6)
                sm = rep["deck"]["selective_mass"]
                run, _ = du.prepare(path, 20 * 3e-6)
                with open(run + ".inp") as f:
                    runl = f.read().split("\n")
                i = runl.index(du.DYNAMIC)
                runl[i + 1] = "3e-06, 6e-05, 3e-06, 3e-06"
                with open(run + ".inp", "w") as f:
                    f.write("\n".join(runl))
                code, log = run_ccx(run)
                self.assertEqual(code, 0, log[-2000:])
                self.assertIn("Job finished", log)
                count = int(re.search(r"In total\s+(\d+)\s+elements were scaled", log).group(1))
                self.assertEqual(count, sm["elements"] + sm.get("counted_without_mass", 0))
                self.assertLess(abs(floats(r"beta \(maximum\) =\s*(\S+)", log)[0] / sm["beta_max"] - 1), 1e-9)
                self.assertTrue(all(abs(s / 3e-6 - 1) < 1e-6 for s in floats(r"SELECTED time increment:\s*(\S+)", log)))
                self.assertTrue(0 < du.max_displacement(run + ".dat") < float("inf"))
                print("%s: ccx scaled %d = %d + %d without mass, beta max %.6g, predicted %.6g kg" %
                      (name, count, sm["elements"], sm.get("counted_without_mass", 0), sm["beta_max"],
                       sm["added_mass"]))


if __name__ == "__main__":
    tu.main()
