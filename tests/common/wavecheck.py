"""The check of dtmap's phase-speed error on tetrahedral meshes against the
independent periodic-box simulation of tests/reference/periodic_wave.py
(numpy/scipy, no dtmap code), for tests t613 and t614.

A case: Gmsh meshes a box whose opposite faces are periodic; dtmap runs it
with <time f-max> at the frequency whose S wavelength fits the box m times
along x (m even), and reports its worst phase-speed error and its step; the
reference runs, at that step and on the same mesh, the plane waves P and S
along x and along the box's diagonal (the direction (1/Lx, 1/Ly, 1/Lz)) at
that frequency and takes the worst of the four. The material has nu = 1/3,
so that c_P = 2 c_S exactly: the P wave at f-max fits the box m/2 times
along x. Along the diagonal the wave vectors that fit are whole multiples
of one, so the reference runs the two around f-max's wave number and
interpolates the error over (k h)^2 (smooth) between them.
"""

import json
import math
import os
import subprocess
import sys

import numpy as np

import testutil as tu

sys.path.insert(0, os.path.join(tu.SRC, "tests", "reference"))
import periodic_wave as pw  # noqa: E402

E, NU, RHO = 210e9, 1.0 / 3.0, 7850.0
LAM, MU = pw.lame(E, NU)
CS = math.sqrt(MU / RHO)
CP = 2 * CS  # nu = 1/3


def scene(name, msh, f_max, nu=NU):
    return tu.write(name + ".xml", '<dtmap-scene version="1">\n  <mesh file="%s"/>\n'
                    '  <material name="steel" groups="block" E="%r" nu="%r" rho="%r"/>\n'
                    '  <effects><elastic formulation="3d" length="eigen"/></effects>\n'
                    '  <time safety="0.9" f-max="%r"/>\n</dtmap-scene>\n' % (msh, E, nu, RHO, f_max))


def dtmap_phase(name, cli=None):
    """Run dtmap (or the program cli) on scene name; its phase measure and recommended step."""
    if cli:
        p = subprocess.run(cli + ["run", name + ".xml", "-o", name + "_dt.msh", "--report", name + ".json", "-q"],
                           cwd=tu.tmpdir(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        code, out = p.returncode, p.stdout
    else:
        code, out = tu.run("run", name + ".xml", "-o", name + "_dt.msh", "--report", name + ".json", "-q")
    if code:
        raise RuntimeError(out)
    r = tu.report(name + ".json")
    phase = [m for m in r["accuracy_measures"] if m["measure"] == "phase-speed error"][0]
    return phase, r["dt"]["recommended"]


def transverse(d):
    a = np.cross(d, [1.0, 0, 0] if abs(d[0]) < 0.9 else [0, 1.0, 0])
    return a / np.linalg.norm(a)


class Box:
    """A periodic box meshed by Gmsh and its reference operator (Poisson's
    ratio nu; grading g > 1: the size grows from h at x = 0 to g h at the
    middle of x and back, pw.periodic_box)."""

    def __init__(self, name, box, h, algorithm="delaunay", order=1, nu=NU, grading=1.0, optimize=1):
        self.name, self.box = name, list(box)
        self.xyz, self.tets = pw.periodic_box(box, h, algorithm=algorithm, order=order, path=tu.path(name + ".msh"),
                                              grading=grading, optimize=optimize)
        _, V = pw._gradients(self.xyz[self.tets[:, :4]])
        self.h6 = float(np.median(np.cbrt(6 * V)))  # the element size: median (6V)^(1/3)
        cx = self.xyz[self.tets[:, :4]][:, :, 0].mean(axis=1)  # the coarse middle tenth along x (graded)
        mid = np.abs(cx - box[0] / 2) < box[0] / 20
        self.h6_coarse = float(np.median(np.cbrt(6 * V[mid])))
        lam, mu = pw.lame(E, nu)
        self.cs, self.cp = math.sqrt(mu / RHO), math.sqrt((lam + 2 * mu) / RHO)
        Kl, Km, m, self.pos = pw.assemble(self.xyz, self.tets, box)
        self.K, self.m = (lam * Kl + mu * Km).tocsr(), RHO * m

    def run(self, waves, dt, periods=12):
        """Fully discrete errors of waves [(k, pol, speed)] at step dt."""
        om = pw.run_waves(self.K, self.m, self.pos, [(k, p) for k, p, _ in waves], dt, periods,
                          [c for _, _, c in waves])
        return [pw.errors(o, k, c, dt)[0] for o, (k, _, c) in zip(om, waves)]


def reference_worst(box, m, dt):
    """The reference's errors at f-max (S wave number 2 pi m / Lx) of P and S
    along x and along the diagonal, and the worst of them."""
    Lx = box.box[0]
    kS = 2 * math.pi * m / Lx
    ex = np.array([1.0, 0, 0])
    unit = 2 * math.pi / np.array(box.box)  # the diagonal's smallest fitting wave vector
    d = unit / np.linalg.norm(unit)
    res, waves = {}, [(ex * kS / 2, ex, CP), (ex * kS, np.array([0, 1.0, 0]), CS)]
    brackets = []
    for label, kf, pol, c in (("P diag", kS / 2, d, CP), ("S diag", kS, transverse(d), CS)):
        a = max(1, int(math.floor(kf / np.linalg.norm(unit))))
        brackets.append((label, kf, a))
        waves += [(a * unit, pol, c), ((a + 1) * unit, pol, c)]
    err = box.run(waves, dt)
    res["P x"], res["S x"] = err[0], err[1]
    for i, (label, kf, a) in enumerate(brackets):
        k0, k1 = a * np.linalg.norm(unit), (a + 1) * np.linalg.norm(unit)
        g0, g1 = err[2 + 2 * i] / k0 ** 2, err[3 + 2 * i] / k1 ** 2
        res[label] = (g0 + (g1 - g0) * (kf - k0) / (k1 - k0)) * kf ** 2
    return res, max(res.values(), key=abs)


def fitting_errors(box, f, dt):
    """The reference's errors at frequency f (any nu) of P and S along x and
    along the box's diagonal: each wave at the wave numbers that fit the box
    around 2 pi f / c (one when it fits), the error over (k h)^2
    interpolated linearly in k between them (smooth; below the first that
    fits, that one's error over (k h)^2). Returns the errors and the worst
    of them."""
    ex = np.array([1.0, 0, 0])
    unit = 2 * math.pi / np.array(box.box)
    d = unit / np.linalg.norm(unit)
    kx, kd = 2 * math.pi / box.box[0], np.linalg.norm(unit)
    specs = [("P x", ex, kx, ex, box.cp), ("S x", ex, kx, np.array([0, 1.0, 0]), box.cs),
             ("P diag", d, kd, d, box.cp), ("S diag", d, kd, transverse(d), box.cs)]
    waves, plan = [], []
    for label, n, step, pol, c in specs:
        kf = 2 * math.pi * f / c
        a = max(1, int(math.floor(kf / step + 1e-9)))
        ks = [a] if abs(kf / step - a) < 1e-6 or kf < step else [a, a + 1]  # below the first: err / k^2 of it
        plan.append((label, kf, step, ks, len(waves)))
        waves += [(j * step * n, pol, c) for j in ks]
    err = box.run(waves, dt)
    res = {}
    for label, kf, step, ks, i in plan:
        if len(ks) == 1:
            res[label] = err[i] * (kf / (ks[0] * step)) ** 2
            continue
        k0, k1 = ks[0] * step, ks[1] * step
        g0, g1 = err[i] / k0 ** 2, err[i + 1] / k1 ** 2
        res[label] = (g0 + (g1 - g0) * (kf - k0) / (k1 - k0)) * kf ** 2
    return res, max(res.values(), key=abs)


def long_case(name, box, h, per, order=1, nu=NU, grading=1.0, optimize=1, clis=(None,), cache=False):
    """A periodic box long along x (the S lag along the axes comes from the
    faces across the wave: a long box has few), Gmsh's Delaunay at size h
    (graded: h at the ends, grading h in the middle), at the frequency whose
    S wave has per elements per wavelength (the S wavelength over the median
    (6V)^(1/3); graded: of the coarse middle tenth), moved to the nearest
    whole number of S wavelengths along x. dtmap (each program of clis;
    None: the one under test) at that f-max, and the reference's errors at
    dtmap's step (fitting_errors). With cache, the mesh, scene and the
    reference's figures of an earlier call are reused (NAME.ref).
    Returns ([dtmap's phase measure per program], errors, worst, S elements
    per wavelength)."""
    ref = tu.path(name + ".ref")  # not .json: testutil checks those against the report's schema
    if cache and os.path.exists(ref):
        with open(ref) as fh:
            r = json.load(fh)
        phases = [dtmap_phase(name, cli)[0] for cli in clis]
        return phases, r["res"], r["worst"], r["per"]
    b = Box(name, box, h, order=order, nu=nu, grading=grading, optimize=optimize)
    size = b.h6_coarse if grading > 1 else b.h6
    m = max(1, round(box[0] / (per * size)))
    f = b.cs * m / box[0]
    scene(name, name + ".msh", f, nu)
    phases, dts = zip(*[dtmap_phase(name, cli) for cli in clis])
    res, worst = fitting_errors(b, f, dts[0])
    if cache:
        with open(ref, "w") as fh:
            json.dump({"res": res, "worst": worst, "per": b.cs / f / size, "tets": len(b.tets)}, fh)
    return list(phases), res, worst, b.cs / f / size


def unstructured_case(name, box, n, m, algorithm="delaunay", order=1):
    """Mesh, run dtmap and the reference; (dtmap's phase measure, reference
    errors, reference worst, S elements per wavelength by median (6V)^(1/3))."""
    b = Box(name, box, box[0] / n, algorithm, order)
    f = CS * m / box[0]
    scene(name, name + ".msh", f)
    phase, dt = dtmap_phase(name)
    res, worst = reference_worst(b, m, dt)
    return phase, res, worst, CS / f / b.h6


def describe(phase, res, worst, per_wl):
    return "per S wavelength %.2f: dtmap %s (%s along %s, %s) against the reference's worst %+.4f %% (%s); ratio %.2f" % (
        per_wl, "%+.4f %%" % (100 * phase["worst"]) if phase["worst"] is not None else "unresolved",
        phase.get("wave"), phase.get("direction"), phase.get("model"), 100 * worst,
        json.dumps({k: round(100 * v, 4) for k, v in res.items()}),
        phase["worst"] / worst if phase["worst"] is not None else float("nan"))


def kuhn_msh(name, n, L):
    """The box [0, L]^3 of n^3 cubes, each cut into the six tetrahedra around
    its main diagonal, all alike (the cube lattice of src/cost/dispersion.c),
    as msh 2.2 with the physical volume "block"."""
    g = n + 1
    idx = lambda i, j, k: 1 + i + g * (j + g * k)  # noqa: E731
    perm = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "1", '3 1 "block"', "$EndPhysicalNames",
             "$Nodes", str(g ** 3)]
    lines += ["%d %r %r %r" % (idx(i, j, k), i * L / n, j * L / n, k * L / n)
              for k in range(g) for j in range(g) for i in range(g)]
    els = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                for p in perm:
                    v = [[i, j, k]]
                    for s in range(3):
                        v.append(list(v[-1]))
                        v[-1][p[s]] += 1
                    if np.linalg.det(np.array(v[1:]) - v[0]) < 0:  # positive orientation
                        v[2], v[3] = v[3], v[2]
                    els.append([idx(*x) for x in v])
    lines += ["$EndNodes", "$Elements", str(len(els))]
    lines += ["%d 4 2 1 1 %d %d %d %d" % (e + 1, *t) for e, t in enumerate(els)]
    lines += ["$EndElements", ""]
    return tu.write(name + ".msh", "\n".join(lines))


def plane_wave_matrix(box, k):
    """The reference's own 3 x 3 matrix of the plane wave exp(i k.x) on the
    node classes over its mass: on a structured mesh (one node class) its
    eigenpairs are the Bloch branches and their polarisations."""
    c, s = np.cos(box.pos @ k), np.sin(box.pos @ k)
    U, W = [], []
    for i in range(3):
        u, w = np.zeros(3 * len(box.pos)), np.zeros(3 * len(box.pos))
        u[i::3], w[i::3] = c, s
        U.append(u), W.append(w)
    D = np.array([[U[i] @ (box.K @ U[j]) + W[i] @ (box.K @ W[j]) for j in range(3)] for i in range(3)])
    return D / (U[0] @ (box.m * U[0]) + W[0] @ (box.m * W[0]))


def directions(n=100):
    """The axes, face and body diagonals and n more spread over the half sphere (unit)."""
    fixed = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1), (0, 1, 1), (0, 1, -1),
             (1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1)]
    d = [np.array(v, float) / np.linalg.norm(v) for v in fixed]
    for i in range(n):
        z, phi = (i + 0.5) / n, i * math.pi * (3 - math.sqrt(5))
        d.append(np.array([math.sqrt(1 - z * z) * math.cos(phi), math.sqrt(1 - z * z) * math.sin(phi), z]))
    return np.array(d)


def full_error(w2, c, k, dt):
    """The fully discrete error of a semi-discrete omega_h^2 (central differences)."""
    return 2 * math.asin(math.sqrt(max(w2, 0)) * dt / 2) / dt / (c * k) - 1


def bloch_worst(xyz, tets, f, dt):
    """The worst fully discrete error over directions() of the structured
    mesh's branches at frequency f (P at its wave number, S at its own)."""
    worst, where = 0.0, None
    dirs = directions()
    for c in (CP, CS):
        k = 2 * math.pi * f / c
        D = pw.bloch_one_class(xyz, tets, LAM, MU, RHO, k * dirs)
        for d, Dk in zip(dirs, D):
            w, vec = np.linalg.eigh(Dk)
            P = np.argmax(np.abs(vec.T @ d))
            for j in range(3):
                if (j == P) == (c == CP):
                    e = full_error(w[j], c, k, dt)
                    if abs(e) > abs(worst):
                        worst, where = e, ("P" if c == CP else "S", d)
    return worst, where


def structured_case(name, n, kuhn):
    """A structured box of n^3 cells of 0.01 m (Gmsh's transfinite
    tetrahedra, or the cube lattice written here) at the frequency of the S
    wave with one wavelength along a body diagonal of the box. Returns
    dtmap's phase measure; the reference's Bloch worst (bloch_worst: P and
    S, 113 directions) and where; and the largest difference between its
    plane-wave prediction and the simulation of the S waves along the four
    body diagonals (polarised as its branches), relative to the error."""
    L = 0.01 * n
    b = Box.__new__(Box)
    b.name, b.box = name, [L] * 3
    if kuhn:
        kuhn_msh(name, n, L)
        b.xyz, b.tets = pw.read_msh(tu.path(name + ".msh"))
    else:
        b.xyz, b.tets = pw.periodic_box(b.box, L / n, transfinite=n, path=tu.path(name + ".msh"))
    Kl, Km, m, b.pos = pw.assemble(b.xyz, b.tets, b.box)
    b.K, b.m = (LAM * Kl + MU * Km).tocsr(), RHO * m
    kS = 2 * math.pi * math.sqrt(3) / L
    f = CS * kS / (2 * math.pi)
    scene(name, name + ".msh", f)
    phase, dt = dtmap_phase(name)
    worst, where = bloch_worst(b.xyz, b.tets, f, dt)
    diag = np.array([(1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1)], float) / math.sqrt(3)
    D = pw.bloch_one_class(b.xyz, b.tets, LAM, MU, RHO, kS * diag)
    waves, predicted = [], []
    for d, Dk in zip(diag, D):
        w, vec = np.linalg.eigh(Dk)
        for j in range(3):
            if abs(vec[:, j] @ d) < 0.5:  # the S branches
                waves.append((kS * d, vec[:, j], CS))
                predicted.append(full_error(w[j], CS, kS, dt))
    sim = b.run(waves, dt)
    gap = max(abs(s - p) / max(abs(p), 1e-3) for s, p in zip(sim, predicted))
    return phase, worst, where, gap, n / math.sqrt(3)
