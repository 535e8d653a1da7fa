#!/usr/bin/python3
"""CalculiX explicit dynamics against dtmap's integration="calculix" step
(issue 21, docs/curved.md). A ball of curved tet10 (Gmsh Python API, order
2) is analysed by `dtmap run --posterior` with <elastic
integration="calculix">; the same mesh, free, runs in CalculiX's explicit
dynamics (*DYNAMIC, EXPLICIT, ALPHA=0: central differences) as C3D10 from a random
initial velocity (every mode excited, the top one included) at fixed
increments of 0.999x and 1.001x dtmap's global step, then bisected for
CalculiX's own stability limit. A run diverges when its largest final
displacement exceeds 1e3 times the one of the 0.999x run (or is not
finite). The exact step of the same discrete model is also computed here
(tests/reference/c3d10_element.py assembled, scipy eigsh), independently of
dtmap.

CalculiX 2.20 picks its explicit increment itself (its Courant estimate,
or selective mass scaling up to the minimum increment), so a fixed
increment needs a CalculiX built from its sources with one change: the
increment read from CCX_FIXED_INC (docs/curved.md says how). Pass that
binary as --ccx.

Usage: /usr/bin/python3 bench/ccx_c3d10.py DTMAP --ccx CCX [--size 0.45] [--steps 2000] [--bisect 8]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import gmsh
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "reference"))
import c3d10_element  # noqa: E402

E, NU, RHO = 210e9, 0.3, 7850.0
CCX_ORDER = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]  # Gmsh tet10 -> C3D10: the last two mid-edge nodes swap


def make_ball(path, size):
    gmsh.model.add("ball")
    gmsh.model.occ.addSphere(0, 0, 0, 1)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(3, [1], 1)
    gmsh.model.setPhysicalName(3, 1, "solid")
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(path)
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    etags, conn = gmsh.model.mesh.getElementsByType(11)
    gmsh.model.remove()
    return tags.astype(int), xyz.reshape(-1, 3), etags.astype(int), conn.astype(int).reshape(-1, 10)


def dtmap_step(dtmap, tmp):
    scene = os.path.join(tmp, "ball.xml")
    with open(scene, "w") as f:
        f.write('<dtmap-scene version="1">\n  <mesh file="ball.msh"/>\n'
                f'  <material name="steel" groups="solid" E="{E}" nu="{NU}" rho="{RHO}"/>\n'
                '  <effects><elastic integration="calculix"/></effects>\n</dtmap-scene>\n')
    rep = os.path.join(tmp, "ball.json")
    subprocess.run([dtmap, "run", scene, "-q", "--posterior", "-o", os.path.join(tmp, "out.msh"), "--report", rep],
                   check=True)
    r = json.load(open(rep))
    return r["dt"]["global"], r["dt"]["nodal"], r["curvature"]


def exact_step(tags, xyz, conn):
    index = {t: i for i, t in enumerate(tags)}
    rows, cols, vals = [], [], []
    mass = np.zeros(3 * len(tags))
    for e in conn:
        K, m, _ = c3d10_element.matrices(xyz[[index[t] for t in e]], E, NU)
        dof = np.array([3 * index[t] + i for t in e for i in range(3)])
        rows.append(np.repeat(dof, 30)), cols.append(np.tile(dof, 30)), vals.append(K.ravel())
        mass[dof] += np.repeat(RHO * m, 3)
    K = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(len(mass),) * 2)
    s = sp.diags(1 / np.sqrt(mass))
    lmax = spla.eigsh(s @ K @ s, k=1, which="LA", tol=1e-12, return_eigenvectors=False)[0]
    return 2 / np.sqrt(lmax)


def write_inp(path, tags, xyz, etags, conn, vel, dt, steps):
    with open(path, "w") as f:
        f.write("*NODE, NSET=NALL\n")
        for t, p in zip(tags, xyz):
            f.write("%d,%.14g,%.14g,%.14g\n" % (t, *p))
        f.write("*ELEMENT, TYPE=C3D10, ELSET=EALL\n")
        for t, e in zip(etags, conn):
            f.write("%d,%s\n" % (t, ",".join(str(e[k]) for k in CCX_ORDER)))
        f.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n%.14g, %.14g\n*DENSITY\n%.14g\n" % (E, NU, RHO))
        f.write("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*INITIAL CONDITIONS, TYPE=VELOCITY\n")
        for t, v in zip(tags, vel):
            for i in range(3):
                f.write("%d,%d,%.14g\n" % (t, i + 1, v[i]))
        # minimum increment tiny: no selective mass scaling; the increment is CCX_FIXED_INC
        f.write("*STEP, INC=100000000\n*DYNAMIC, EXPLICIT, ALPHA=0\n%.14g, %.14g, 1e-30, %.14g\n" % (dt, steps * dt, dt))
        f.write("*NODE PRINT, NSET=NALL, FREQUENCY=100000000\nU\n*END STEP\n")


def ccx_run(ccx, tmp, mesh, vel, dt, steps):
    write_inp(os.path.join(tmp, "c.inp"), *mesh, vel, dt, steps)
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_FIXED_INC="%.14g" % dt)
    p = subprocess.run([ccx, "-i", "c"], cwd=tmp, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    out = p.stdout.decode(errors="replace")
    if "SELECTED time increment:%e" % dt not in out.replace("  ", " ") and "%e" % dt not in out:
        sys.exit("ccx did not take the fixed increment %g:\n%s" % (dt, out[-1500:]))
    u = 0.0
    try:
        for line in open(os.path.join(tmp, "c.dat")):
            w = line.split()
            if len(w) == 4 and w[0].isdigit():
                vals = [float(x) for x in w[1:]]
                u = max(u, max(abs(x) for x in vals)) if all(np.isfinite(vals)) else np.inf
    except (OSError, ValueError):
        u = np.inf
    return u if p.returncode == 0 else np.inf


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dtmap")
    ap.add_argument("--ccx", required=True)
    ap.add_argument("--size", type=float, default=0.45)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--bisect", type=int, default=8)
    a = ap.parse_args()
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    tmp = tempfile.mkdtemp(prefix="dtmap-ccx-c3d10-")
    tags, xyz, etags, conn = make_ball(os.path.join(tmp, "ball.msh"), a.size)
    gmsh.finalize()
    dt, nodal, curv = dtmap_step(os.path.abspath(a.dtmap), tmp)
    ex = exact_step(tags, xyz, conn)
    vel = np.random.default_rng(21).uniform(-1, 1, (len(tags), 3))
    mesh = (tags, xyz, etags, conn)
    print(f"ball: {len(etags)} tet10, {curv['curved']} curved, model {curv['integration']}")
    print(f"dtmap global {dt:.9e} s, nodal {nodal:.9e} s; exact (this script) {ex:.9e} s; global/exact {dt / ex:.7f}")
    u0 = ccx_run(a.ccx, tmp, mesh, vel, 0.999 * dt, a.steps)
    u1 = ccx_run(a.ccx, tmp, mesh, vel, 1.001 * dt, a.steps)
    bad = lambda u: not np.isfinite(u) or u > 1e3 * u0  # noqa: E731
    print(f"CalculiX, {a.steps} increments: 0.999x max|u| {u0:.3e} m; 1.001x max|u| {u1:.3e} m "
          f"({'diverges' if bad(u1) else 'bounded'})")
    lo, hi = 0.999, 1.001
    for _ in range(a.bisect if not bad(u0) and bad(u1) else 0):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if bad(ccx_run(a.ccx, tmp, mesh, vel, mid * dt, a.steps)) else (mid, hi)
    print(f"CalculiX's limit in [{lo:.6f}, {hi:.6f}] x dtmap's global; over the exact step "
          f"[{lo * dt / ex:.6f}, {hi * dt / ex:.6f}]")
    ok = not bad(u0) and bad(u1)
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
