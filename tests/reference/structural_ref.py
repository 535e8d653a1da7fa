"""Independent reference for dtmap's shell and beam sections on a whole
mesh: the element bounds and the exact largest eigenvalue of the assembled
system with rotations, from numpy/scipy, sharing no code with dtmap.

- shells: tests/reference/shell_ref.py's element (flat Reissner-Mindlin
  facet, MITC3 or 1-point shear, SVD frame, its own bisection for the
  rotary scale);
- beams: a two-node Timoshenko beam written here from the textbook
  (axial EA/L, torsion G J/L, bending E I/L, shear k G A L at the midpoint),
  lumped mass rho A L/2 per translation and the isotropic rotary inertia
  rho L/2 min(I_y, I_z) about every axis (the convention dtmap states for
  a diagonal mass in global axes), its own frame from the orientation
  vector, the rotary scale by bisection to the axial eigenvalue 4E/(rho L^2);
- assembly: 6 unknowns per node of a shell or beam (the same node numbering
  as the .msh), eigsh (or dense) on M^-1/2 K M^-1/2.

Usage: structural_ref.py MESH SPEC OUT, SPEC a JSON object
  {"E":..., "nu":..., "rho":..., "k": 5/6, "convention": "scaled"|"physical",
   "shells": {"group": thickness, ...},
   "beams": {"group": {"area":..., "iy":..., "iz":..., "j":..., "orientation": [x, y, z]}, ...}}
writes OUT as JSON {"elements": {tag: dt}, "lambda_max": ..., "dt_exact": ...}.
"""

import json
import math
import os
import sys

import numpy as np
import scipy.linalg

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sections_ref  # noqa: E402  (assembly-free helpers: global eigensolver)
import shell_ref  # noqa: E402


def beam_frame(X, orientation):
    e1 = X[1] - X[0]
    L = np.linalg.norm(e1)
    e1 = e1 / L
    ref = np.asarray(orientation, float) if orientation is not None and np.any(orientation) else (
        np.array([0.0, 1.0, 0.0]) if abs(e1[2]) > 0.99 else np.array([0.0, 0.0, 1.0]))
    e2 = ref - ref.dot(e1) * e1
    e2 /= np.linalg.norm(e2)
    return np.array([e1, e2, np.cross(e1, e2)]), L


def beam_local(E, nu, rho, k, A, iy, iz, j, L):
    """Local K (12 x 12) and mass diagonal, unknowns (u, v, w, rx, ry, rz) per node."""
    G = E / (2 * (1 + nu))
    K = np.zeros((12, 12))

    def pair(i, c):
        K[np.ix_([i, 6 + i], [i, 6 + i])] += c * np.array([[1, -1], [-1, 1]])

    pair(0, E * A / L)
    pair(3, G * j / L)
    pair(4, E * iy / L)
    pair(5, E * iz / L)
    # shear strains at the midpoint: gamma_xz = w' + ry, gamma_xy = v' - rz
    bxz = np.zeros(12)
    bxz[[2, 8]] = [-1 / L, 1 / L]
    bxz[[4, 10]] = [0.5, 0.5]
    bxy = np.zeros(12)
    bxy[[1, 7]] = [-1 / L, 1 / L]
    bxy[[5, 11]] = [-0.5, -0.5]
    K += k * G * A * L * (np.outer(bxz, bxz) + np.outer(bxy, bxy))
    rot = rho * L / 2 * min(iy, iz)
    m = np.tile([rho * A * L / 2] * 3 + [rot] * 3, 2)
    return K, m


def rotations(n):
    return np.tile([0, 0, 0, 1, 1, 1], n).astype(bool)


def beam_element(X, E, nu, rho, k, sec, convention):
    R, L = beam_frame(X, sec.get("orientation"))
    K, m = beam_local(E, nu, rho, k, sec["area"], sec["iy"], sec["iz"], sec["j"], L)
    T = np.kron(np.eye(4), R)
    Kg = T.T @ K @ T
    if convention == "scaled":
        s = shell_ref.scale_bisect(Kg, m, 4 * E / (rho * L * L) * (1 + 1e-12))
        m = np.where(rotations(2), s * m, m)
    return Kg, m


def shell_element(X, E, nu, rho, k, t, convention):
    typ = 2 if len(X) == 3 else 3
    R, xy = shell_ref.frame(X)
    Km, Kt, m = shell_ref.local_matrices(typ, E, nu, rho, k, t, xy)
    Kg = shell_ref.to_global(R, Km + Kt)
    if convention == "scaled":
        target = shell_ref.lam_max(shell_ref.to_global(R, Km), m)
        s = shell_ref.scale_bisect(Kg, m, target * (1 + 1e-12))
        m = np.where(rotations(len(X)), s * m, m)
    return Kg, m


def read_mesh(path, spec):
    """[(tag, node indices, X, kind, group)] of the shell and beam groups."""
    import gmsh
    gmsh.initialize(["structural_ref", "-v", "0"])
    try:
        gmsh.open(path)
        ntags, xyz, _ = gmsh.model.mesh.getNodes()
        index = {int(t): i for i, t in enumerate(ntags)}
        coords = np.asarray(xyz).reshape(-1, 3)
        out = []
        for dim, ptag in gmsh.model.getPhysicalGroups():
            name = gmsh.model.getPhysicalName(dim, ptag)
            kind = "shell" if name in spec.get("shells", {}) else "beam" if name in spec.get("beams", {}) else None
            if kind is None:
                continue
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
                types, etags, enodes = gmsh.model.mesh.getElements(dim, ent)
                for typ, et, en in zip(types, etags, enodes):
                    nn = len(en) // len(et)
                    for q, tag in enumerate(et):
                        idx = [index[int(v)] for v in en[q * nn:(q + 1) * nn]]
                        out.append((int(tag), idx, coords[idx], kind, name))
        return out
    finally:
        gmsh.finalize()


def compute(elements, spec):
    E, nu, rho = spec["E"], spec["nu"], spec["rho"]
    k, conv = spec.get("k", 5 / 6), spec.get("convention", "scaled")
    per, assembled = {}, []
    used = sorted({i for _, idx, _, _, _ in elements for i in idx})
    local = {v: i for i, v in enumerate(used)}
    for tag, idx, X, kind, name in elements:
        if kind == "shell":
            K, m = shell_element(X, E, nu, rho, k, spec["shells"][name], conv)
        else:
            K, m = beam_element(X, E, nu, rho, k, spec["beams"][name], conv)
        per[tag] = 2 / math.sqrt(sections_ref.lambda_max_dense(K, m))
        assembled.append(([local[i] for i in idx], K, m))
    K, mass = sections_ref.assemble(assembled, 6)
    # drilling rotations of nodes that only shells reach carry mass but no
    # stiffness: they add zero eigenvalues, never the largest
    lam, details = sections_ref.global_lambda_max(K, mass)
    return {"elements": per, "lambda_max": lam, "dt_exact": 2 / math.sqrt(lam), "details": details,
            "dofs": int(len(mass))}


def self_test():
    """A single beam element against its closed forms (docs/structural-kernels.md
    with the isotropic rotary inertia rho L/2 I_min)."""
    E, nu, rho, k = 200e9, 0.3, 7850.0, 5 / 6
    G = E / (2 * (1 + nu))
    b, h, L = 0.01, 0.04, 0.05
    sec = {"area": b * h, "iy": b * h ** 3 / 12, "iz": h * b ** 3 / 12, "j": 1e-9, "orientation": [1, 0, 0]}
    X = np.array([[0, 0, 0], [0, L, 0]], float)
    K, m = beam_element(X, E, nu, rho, k, sec, "physical")
    lam = scipy.linalg.eigh(K, np.diag(m), eigvals_only=True)[-1]
    imin, imax = min(sec["iy"], sec["iz"]), max(sec["iy"], sec["iz"])
    want = max(4 * E / (rho * L * L), 4 * k * G / (rho * L * L) + k * G * sec["area"] / (rho * imin),
               4 * E * imax / (rho * L * L * imin), 4 * G * sec["j"] / (rho * imin * L * L))
    assert abs(lam / want - 1) < 1e-10, (lam, want)
    K, m = beam_element(X, E, nu, rho, k, sec, "scaled")
    lam = scipy.linalg.eigh(K, np.diag(m), eigvals_only=True)[-1]
    assert abs(lam / (4 * E / (rho * L * L)) - 1) < 1e-9, lam


def main(argv):
    self_test()
    if len(argv) < 4:
        print("self-test passed")
        return 0
    with open(argv[2]) as f:
        spec = json.load(f)
    res = compute(read_mesh(argv[1], spec), spec)
    with open(argv[3], "w") as f:
        json.dump(res, f)
    print("reference: %d elements, %d unknowns, exact step %.10e s" % (len(res["elements"]), res["dofs"],
                                                                       res["dt_exact"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
