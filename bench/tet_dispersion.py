"""The measured phase-speed error of Gmsh's tetrahedral meshes: the table
behind dtmap's prediction for unstructured tet4 and tet10 meshes
(src/cost/measured.inc, read by src/cost/measured.c; docs/accuracy.md).

For each mesher (Gmsh's Delaunay and HXT; Frontal needs Netgen, which
Debian's Gmsh is built without), each order (tet4, tet10) and a few sizes,
Gmsh meshes a periodic unit cube; plane waves P and S (two polarisations)
along the axes, the face diagonals and the body diagonals, at every wave
number that fits the cube up to about 2 elements per wavelength, run
through it by central differences at 0.9 of the exact stable step
(tests/reference/periodic_wave.py, numpy/scipy, no dtmap code). Each run
gives the semi-discrete error (space alone: central differences act mode by
mode, sin(omega dt / 2) = omega_h dt / 2, so the step is taken out exactly;
--courant-check runs one mesh at two steps to show it).

The abscissa is kappa = k s, s the root mean square of the elements' mean
edges weighted by their volumes: dtmap evaluates each element at k times
its own mean edge and averages the errors over the elements' volumes
(src/cost/measured.c), which is the same mean to first order (the error is
quadratic in k s). Per element order, Poisson's ratio, branch and direction
class (axis, face diagonal, body diagonal) the measured err / kappa^2 of
every mesh and mesher is fitted by a polynomial in kappa^2 and written at
the table's points kappa_j = pi (j + 1) / 16 (the layout of dtm_dispersion).

--faces-check measures the S wave's dependence on the sample's size (the
share of elements next to its faces).

The S wave along the axes is measured on long boxes instead (--long: 4 x 1
x 1, periodic, the waves along the long side, tet4): in a cube of 18 to 26
cells it lags up to 1.4 times more than on a box long along the wave (the
faces across the wave: Gmsh meshes them first and the elements beside them
are aligned with them), and a box longer still or wider across the wave
changes it no more (docs/accuracy.md). The long boxes' records replace the
cubes' in the tet4 S axis rows. --long --patch measures only those and
rewrites those rows of the existing measured.inc, keeping the others (the
cubes' raw measurements are not needed).

Usage: tet_dispersion.py [--work DIR] [--quick] [--fit-only] [--out FILE] [--courant-check] [--faces-check]
                         [--long [--patch]]
Measurements are kept in DIR/raw.jsonl (one line per wave, appended as they
run) so that --fit-only refits without running again.
"""

import argparse
import json
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "reference"))
import periodic_wave as pw  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
E, RHO = 210e9, 7850.0
NUS = (0.15, 0.25, 0.3, 0.35, 0.45)  # the table's Poisson's ratios
MEASURED_NUS = {1: NUS, 2: (0.15, 0.3, 0.45)}  # measured; tet10's others interpolated in lam / mu
SIZES = {1: (18, 20, 22, 26), 2: (9, 10, 11)}  # cells per cube side: h = 1 / n
KAPPA_MAX = 3.4
NKH = 16
CLASSES = ("axis", "face", "body")
DIRS = {"axis": [(1, 0, 0), (0, 1, 0), (0, 0, 1)],
        "face": [(1, 1, 0), (1, 0, 1), (0, 1, 1)],
        "body": [(1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1)]}


def mesh_stats(xyz, tets):
    """rms of the mean edges weighted by volume, and the median (6V)^(1/3)."""
    x = xyz[tets[:, :4]]
    _, V = pw._gradients(x)
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    edge = np.mean([np.linalg.norm(x[:, a] - x[:, b], axis=1) for a, b in pairs], axis=0)
    return math.sqrt(np.sum(V * edge ** 2) / np.sum(V)), float(np.median(np.cbrt(6 * V)))


def transverse(d):
    a = np.cross(d, [1.0, 0, 0] if abs(d[0]) < 0.9 else [0, 1.0, 0])
    a /= np.linalg.norm(a)
    return a, np.cross(d, a)


def waves_of(s):
    """(class, direction, a, k, pol, branch) of every wave with kappa <= KAPPA_MAX in the unit cube."""
    out = []
    for cls in CLASSES:
        for d in DIRS[cls]:
            d = np.array(d, float)
            n = d / np.linalg.norm(d)
            a = 1
            while 2 * math.pi * a * np.linalg.norm(d) * s <= KAPPA_MAX:
                k = 2 * math.pi * a * d
                t1, t2 = transverse(n)
                out += [(cls, d, a, k, n, "P"), (cls, d, a, k, t1, "S"), (cls, d, a, k, t2, "S")]
                a += 1
    return out


def measure(algorithm, order, n, nus, raw, courant=(0.9,)):
    xyz, tets = pw.periodic_box([1, 1, 1], 1.0 / n, algorithm=algorithm, order=order)
    s, h6 = mesh_stats(xyz, tets)
    Kl, Km, m, pos = pw.assemble(xyz, tets, [1, 1, 1])
    ws = waves_of(s)
    for nu in nus:
        lam, mu = pw.lame(E, nu)
        K = (lam * Kl + mu * Km).tocsr()
        cp, cs = math.sqrt((lam + 2 * mu) / RHO), math.sqrt(mu / RHO)
        dtc = pw.critical_step(K, RHO * m)
        for c in courant:
            t0 = time.process_time()
            speeds = [cp if w[5] == "P" else cs for w in ws]
            omega = pw.run_waves(K, RHO * m, pos, [(w[3], w[4]) for w in ws], c * dtc, 12, speeds)
            for w, om, sp in zip(ws, omega, speeds):
                full, space = pw.errors(om, w[3], sp, c * dtc)
                rec = {"algorithm": algorithm, "order": order, "n": n, "tets": len(tets), "nu": nu, "courant": c,
                       "class": w[0], "dir": w[1].tolist(), "a": w[2], "pol": w[4].tolist(), "branch": w[5],
                       "kappa": float(np.linalg.norm(w[3]) * s), "s": s, "h6": h6, "error": full, "space": space}
                raw.write(json.dumps(rec) + "\n")
            raw.flush()
            print("%-8s tet%-2d n %2d nu %.2f C %.2f: %d tets, %d waves, %.0f s CPU" %
                  (algorithm, 4 if order == 1 else 10, n, nu, c, len(tets), len(ws), time.process_time() - t0),
                  flush=True)


LONG = [4, 1, 1]  # the long box: the waves along x
LONG_SIZES = (("delaunay", 18), ("hxt", 18))  # mesher, cells per unit
LONG_A = (4, 6, 8, 11, 14, 17, 20, 23, 26, 29, 32, 35)  # wavelengths along the box (those with kappa <= KAPPA_MAX)


def measure_long(algorithm, n, nus, raw):
    """tet4's S wave along the long side of the periodic box LONG (both
    polarisations), at the wave numbers LONG_A that reach KAPPA_MAX; records
    of class "axis" with sample "long"."""
    xyz, tets = pw.periodic_box(LONG, 1.0 / n, algorithm=algorithm)
    s, h6 = mesh_stats(xyz, tets)
    Kl, Km, m, pos = pw.assemble(xyz, tets, LONG)
    ex = np.array([1.0, 0, 0])
    ws = [(a, 2 * math.pi * a / LONG[0] * ex, pol) for a in LONG_A if 2 * math.pi * a / LONG[0] * s <= KAPPA_MAX
          for pol in (np.array([0, 1.0, 0]), np.array([0, 0, 1.0]))]
    for nu in nus:
        lam, mu = pw.lame(E, nu)
        K = (lam * Kl + mu * Km).tocsr()
        cs = math.sqrt(mu / RHO)
        dt = 0.9 * pw.critical_step(K, RHO * m)
        t0 = time.process_time()
        omega = pw.run_waves(K, RHO * m, pos, [(w[1], w[2]) for w in ws], dt, 12, [cs] * len(ws))
        for (a, k, pol), om in zip(ws, omega):
            full, space = pw.errors(om, k, cs, dt)
            rec = {"algorithm": algorithm, "order": 1, "n": n, "tets": len(tets), "nu": nu, "courant": 0.9,
                   "class": "axis", "dir": [1, 0, 0], "a": a, "pol": pol.tolist(), "branch": "S", "sample": "long",
                   "kappa": float(np.linalg.norm(k) * s), "s": s, "h6": h6, "error": full, "space": space}
            raw.write(json.dumps(rec) + "\n")
        raw.flush()
        print("long box %-8s tet4 n %2d nu %.2f: %d tets, %d waves, %.0f s CPU" %
              (algorithm, n, nu, len(tets), len(ws), time.process_time() - t0), flush=True)


def face_fraction(xyz, tets):
    """The volume fraction of the elements with a node on the unit cube's faces."""
    on = ((np.abs(xyz) < 1e-9) | (np.abs(xyz - 1) < 1e-9)).any(axis=1)
    _, V = pw._gradients(xyz[tets[:, :4]])
    return float(V[on[tets].any(axis=1)].sum() / V.sum())


def faces_check(sizes=(16, 24, 32), nu=1 / 3):
    """The S wave along the axes and the body diagonals of Delaunay tet4 cubes
    of growing size (k s up to 2.2): its error over (k s)^2 against the
    share of the volume next to the faces."""
    lam, mu = pw.lame(E, nu)
    cs = math.sqrt(mu / RHO)
    for n in sizes:
        xyz, tets = pw.periodic_box([1, 1, 1], 1.0 / n)
        s, _ = mesh_stats(xyz, tets)
        Kl, Km, m, pos = pw.assemble(xyz, tets, [1, 1, 1])
        K = (lam * Kl + mu * Km).tocsr()
        dt = 0.9 * pw.critical_step(K, RHO * m)
        ws = [w for w in waves_of(s) if w[5] == "S" and w[0] != "face" and np.linalg.norm(w[3]) * s <= 2.2]
        omega = pw.run_waves(K, RHO * m, pos, [(w[3], w[4]) for w in ws], dt, 12, [cs] * len(ws))
        g = {}
        for w, om in zip(ws, omega):
            kap = float(np.linalg.norm(w[3]) * s)
            g.setdefault((w[0], round(kap, 2)), []).append(pw.errors(om, w[3], cs, dt)[1] / kap ** 2)
        print("cube of %d cells, %d tets, faces' share %.3f: %s" % (
            n, len(tets), face_fraction(xyz, tets),
            " ".join("%s %.2f: %+.4f" % (c, k, np.mean(v)) for (c, k), v in sorted(g.items()))), flush=True)


def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def fit_series(recs):
    """err / kappa^2 at the table's points from a least-squares polynomial in
    kappa^2 (degree 2, less with fewer distinct points) through the measured
    points (semi-discrete errors), fitted three times, each without the
    points off the last fit by more than a quarter of its error (and 0.005):
    near two mean edges per wavelength the spectrum's largest peak is
    sometimes another branch's, far from the wave's own. Past the largest
    kappa kept the table holds the fit's value there (no extrapolation).
    Returns the values, the rms residual of the points kept, the largest
    kappa kept and the points left out."""
    k = np.array([r["kappa"] for r in recs])
    g = np.array([r["space"] for r in recs]) / k ** 2
    keep = np.ones(len(k), bool)
    for _ in range(3):
        deg = min(2, len(set(np.round(k[keep], 6))) - 1)
        fit = np.polynomial.Polynomial.fit(k[keep] ** 2, g[keep], deg)
        resid = np.abs(g - fit(k ** 2)) * k ** 2
        keep = resid <= np.maximum(0.25 * np.abs(fit(k ** 2)) * k ** 2, 0.005)
    kh = np.minimum(math.pi * (np.arange(NKH) + 1) / NKH, k[keep].max())
    return fit(kh ** 2), float(np.sqrt(np.mean(resid[keep] ** 2))), float(k[keep].max()), int((~keep).sum())


def lam_mu(nu):
    return 2 * nu / (1 - 2 * nu)


def fit(recs):
    """table[order][nu][branch][class] = 16 values; with the rms residual and
    the largest kappa measured. A ratio not measured for an order is
    interpolated linearly in lam / mu between the measured ones around it."""
    table, info = {}, []
    for order in (1, 2):
        for nu in MEASURED_NUS[order]:
            for b, branch in enumerate("PS"):
                for cls in CLASSES:
                    sel = [r for r in recs if r["order"] == order and r["nu"] == nu and r["branch"] == branch and
                           r["class"] == cls and r["courant"] == 0.9]
                    if any(r.get("sample") == "long" for r in sel):  # the long boxes replace the cubes
                        sel = [r for r in sel if r.get("sample") == "long"]
                    if not sel:
                        continue
                    vals, rms, kmax, out = fit_series(sel)
                    table[(order, nu, b, cls)] = vals
                    info.append((order, "%.2f" % nu, branch, cls, len(sel), rms, kmax, out))
        for nu in NUS:
            if nu in MEASURED_NUS[order]:
                continue
            lo = max(v for v in MEASURED_NUS[order] if v < nu)
            hi = min(v for v in MEASURED_NUS[order] if v > nu)
            w = (lam_mu(nu) - lam_mu(lo)) / (lam_mu(hi) - lam_mu(lo))
            for b in range(2):
                for cls in CLASSES:
                    if (order, lo, b, cls) in table and (order, hi, b, cls) in table:
                        table[(order, nu, b, cls)] = (1 - w) * table[(order, lo, b, cls)] + w * table[(order, hi, b, cls)]
            info.append((order, "%.2f" % nu, "-", "interpolated in lam/mu", 0, 0.0, 0.0, 0))
    return table, info


def header(info, recs):
    """The comment lines of measured.inc: the meshes and the fit of each series."""
    meshes = sorted({(r["algorithm"], r["order"], r["n"], r["tets"]) for r in recs if r.get("sample") != "long"})
    longs = sorted({(r["algorithm"], r["n"], r["tets"]) for r in recs if r.get("sample") == "long"})
    lines = ["/* The measured phase-speed error of Gmsh's unstructured tetrahedral meshes,",
             " * generated by bench/tet_dispersion.py (do not edit: run it again). Semi-discrete",
             " * error / kappa^2 at kappa_j = pi (j + 1) / %d, kappa = k times the mean edge;" % NKH,
             " * [order - 1][Poisson's ratio][P, S][axis, face diagonal, body diagonal][j].",
             " * From %d plane waves on %d periodic cubes:" % (sum(r.get("sample") != "long" for r in recs),
                                                              len(meshes))]
    for alg, order, n, tets in meshes:
        lines.append(" *   %s, tet%d, %d cells per side: %d tetrahedra" % (alg, 4 if order == 1 else 10, n, tets))
    lines += long_lines(recs, longs)
    lines.append(" * Per series: waves, fit residual (rms, fraction), largest kappa, waves left out:")
    for order, nu, branch, cls, cnt, rms, kmax, left in info:
        lines.append(" *   tet%d nu %s %s %-4s: %3d waves, rms %.2e, kappa <= %.2f, %d out" %
                     (4 if order == 1 else 10, nu, branch, cls, cnt, rms, kmax, left) +
                     (" (long boxes)" if order == 1 and branch == "S" and cls == "axis" and longs else "")
                     if cnt else " *   tet%d nu %s: %s" % (4 if order == 1 else 10, nu, cls))
    return lines


def long_lines(recs, longs):
    if not longs:
        return []
    return [" * and tet4's S wave along the axes (it replaces the cubes' there) from %d plane waves on %d"
            % (sum(r.get("sample") == "long" for r in recs), len(longs)),
            " * periodic boxes of 4 x 1 x 1, the waves along the long side:"] + \
        [" *   %s, tet4, %d cells per unit: %d tetrahedra" % m for m in longs]


def write_table(table, info, recs, out, lines=None):
    lines = list(lines) if lines is not None else header(info, recs)
    lines.append(" */")
    lines.append("#define DTM_MEASURED_NU %d" % len(NUS))
    lines.append("static const double measured_nu[DTM_MEASURED_NU] = {%s};" % ", ".join("%.2f" % v for v in NUS))
    lines.append("static const double measured_g[2][DTM_MEASURED_NU][2][3][%d] = {" % NKH)
    for order in (1, 2):
        lines.append("    {")
        for nu in NUS:
            lines.append("        {")
            for b in range(2):
                rows = [table.get((order, nu, b, cls), np.zeros(NKH)) for cls in CLASSES]
                body = ",\n".join("                {%s}" % ", ".join("%.5e" % v for v in row) for row in rows)
                lines.append("            {\n%s}," % body)
            lines.append("        },")
        lines.append("    },")
    lines.append("};")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    subprocess.run(["clang-format", "-i", "--assume-filename=x.c", out], check=False)


def patch_table(recs, path):
    """Rewrite the tet4 S axis rows of the measured.inc at path from the long
    boxes' records, keeping every other row and the header's other lines."""
    text = open(path).read()
    head, body = text.split(" */", 1)
    vals = [float(v) for v in re.findall(r"[-+]?\d\.\d+e[-+]\d+", body[body.index("measured_g"):])]
    g = np.array(vals).reshape(2, len(NUS), 2, 3, NKH)
    lines = [ln for ln in head.rstrip("\n").split("\n") if "(long boxes)" not in ln or "S axis" in ln]
    lines = [ln for ln in lines if not ln.startswith(" * and tet4's S wave along the axes") and
             not ln.startswith(" * periodic boxes of 4 x 1 x 1") and "cells per unit" not in ln]
    longs = sorted({(r["algorithm"], r["n"], r["tets"]) for r in recs if r.get("sample") == "long"})
    at = lines.index(" * Per series: waves, fit residual (rms, fraction), largest kappa, waves left out:")
    lines[at:at] = long_lines(recs, longs)
    for i, nu in enumerate(NUS):
        sel = [r for r in recs if r.get("sample") == "long" and r["nu"] == nu]
        if not sel:
            continue
        v, rms, kmax, out = fit_series(sel)
        g[0, i, 1, 0] = v
        tag = " *   tet4 nu %.2f S axis:" % nu
        lines = [tag + " %3d waves, rms %.2e, kappa <= %.2f, %d out (long boxes)" % (len(sel), rms, kmax, out)
                 if ln.startswith(tag) else ln for ln in lines]
    table = {(o + 1, nu, b, cls): g[o, i, b, c] for o in range(2) for i, nu in enumerate(NUS) for b in range(2)
             for c, cls in enumerate(CLASSES)}
    write_table(table, [], [], path, lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--work", default=os.environ.get("BENCH_WORK", "/tmp/dtmap-tet-dispersion"))
    ap.add_argument("--out", default=os.path.join(ROOT, "src", "cost", "measured.inc"))
    ap.add_argument("--quick", action="store_true", help="one mesh per order and mesher, nu 0.3")
    ap.add_argument("--fit-only", action="store_true")
    ap.add_argument("--courant-check", action="store_true", help="one Delaunay tet4 mesh at 0.9 and 0.3 of the step")
    ap.add_argument("--faces-check", action="store_true", help="the S wave of tet4 cubes of 16, 24 and 32 cells")
    ap.add_argument("--long", action="store_true", help="only the long boxes (tet4's S wave along the axes)")
    ap.add_argument("--patch", action="store_true", help="with --long: rewrite only those rows of --out")
    o = ap.parse_args()
    os.makedirs(o.work, exist_ok=True)
    raw_path = os.path.join(o.work, "raw.jsonl")
    if o.faces_check:
        return faces_check()
    if o.courant_check:
        with open(os.path.join(o.work, "courant.jsonl"), "w") as raw:
            measure("delaunay", 1, 16, (0.3,), raw, courant=(0.9, 0.3))
        return
    if not o.fit_only:
        done = {(r["algorithm"], r["order"], r["n"], r["nu"], r.get("sample", "cube")) for r in load(raw_path)} \
            if os.path.exists(raw_path) else set()
        with open(raw_path, "a") as raw:
            for alg, n in LONG_SIZES[:1] if o.quick else LONG_SIZES:
                nus = [nu for nu in ((0.3,) if o.quick else NUS) if (alg, 1, n, nu, "long") not in done]
                if nus:
                    measure_long(alg, n, nus, raw)
            for order in () if o.long else (1, 2):
                for n in SIZES[order][:1] if o.quick else SIZES[order]:
                    for alg in ("delaunay", "hxt"):
                        nus = [nu for nu in ((0.3,) if o.quick else MEASURED_NUS[order])
                               if (alg, order, n, nu, "cube") not in done]
                        if nus:
                            measure(alg, order, n, nus, raw)
    recs = load(raw_path)
    if o.patch:
        return patch_table(recs, o.out)
    table, info = fit(recs)
    write_table(table, info, recs, o.out)
    for order, nu, branch, cls, cnt, rms, kmax, left in info:
        print("tet%-2d nu %s %s %-4s %3d waves, fit rms %.2e, kappa <= %.2f, %d out" %
              (4 if order == 1 else 10, nu, branch, cls, cnt, rms, kmax, left))


if __name__ == "__main__":
    main()
