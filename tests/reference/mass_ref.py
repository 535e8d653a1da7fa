"""Independent reference for the point masses refine adds: the exact
critical step of a linear simplex mesh (tri3 or tet4) with its lumped mass
plus the masses of its NodeData view 'added mass at nodes', written with
numpy/scipy and sharing no code with dtmap.

The mesh is read with Gmsh's Python API (nodes, the elements of the highest
dimension, the view's values by node tag). Linear elasticity (3D, or plane
stress or plane strain in 2D) with constant strain: K_e = V B^T D B, the
row-sum lumped mass rho V / (d + 1) at each node of each element, plus the
point mass of the node on each of its d unknowns. The largest eigenvalue of
M^-1/2 K M^-1/2 comes from scipy.sparse.linalg.eigsh (tolerance 1e-12), and
the exact step of central differences is 2 / sqrt(lambda_max).

Usage: mass_ref.py MESH.msh E NU RHO FORMULATION
Prints one JSON object: elements, nodes, point_mass (kg, the view's sum),
lambda_max (1/s^2), exact_step (s).
"""

import json
import sys

import gmsh
import numpy as np
import scipy.sparse
import scipy.sparse.linalg

VIEW = "added mass at nodes"


def read(path):
    gmsh.initialize(["mass_ref", "-v", "0"])
    try:
        gmsh.open(path)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        index = {int(t): i for i, t in enumerate(tags)}
        dim = gmsh.model.getDimension()
        types, _, conn = gmsh.model.mesh.getElements(dim)
        if list(types) != [2 if dim == 2 else 4]:
            raise SystemExit("%s: only linear triangles or tetrahedra, got types %s" % (path, list(types)))
        cells = np.array([index[int(t)] for t in conn[0]]).reshape(-1, dim + 1)
        masses = np.zeros(len(tags))
        for v in gmsh.view.getTags():
            if gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(v)) != VIEW:
                continue
            _, vt, data, _, _ = gmsh.view.getModelData(v, 0)
            for t, d in zip(vt, data):
                masses[index[int(t)]] = d[0]
        return dim, xyz.reshape(-1, 3)[:, :dim], cells, masses
    finally:
        gmsh.finalize()


def elasticity(dim, E, nu, formulation):
    if dim == 3:
        lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
        D = np.zeros((6, 6))
        D[:3, :3] = lam
        D[np.arange(3), np.arange(3)] += 2 * mu
        D[np.arange(3, 6), np.arange(3, 6)] = mu
        return D
    if formulation == "plane-stress":
        c = E / (1 - nu * nu)
        return c * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    c = E / ((1 + nu) * (1 - 2 * nu))
    return c * np.array([[1 - nu, nu, 0], [nu, 1 - nu, 0], [0, 0, (1 - 2 * nu) / 2]])


def strain_matrix(dim, grads):
    """B [strains, (d+1) d] of a linear simplex from its shape gradients."""
    n = len(grads)
    if dim == 2:
        B = np.zeros((3, 2 * n))
        B[0, 0::2], B[1, 1::2] = grads[:, 0], grads[:, 1]
        B[2, 0::2], B[2, 1::2] = grads[:, 1], grads[:, 0]
        return B
    B = np.zeros((6, 3 * n))
    for k in range(3):
        B[k, k::3] = grads[:, k]
    B[3, 0::3], B[3, 1::3] = grads[:, 1], grads[:, 0]
    B[4, 1::3], B[4, 2::3] = grads[:, 2], grads[:, 1]
    B[5, 0::3], B[5, 2::3] = grads[:, 2], grads[:, 0]
    return B


def assemble(dim, x, cells, masses, E, nu, rho, formulation):
    D = elasticity(dim, E, nu, formulation)
    nd = dim * len(x)
    rows, cols, vals = [], [], []
    m = np.repeat(masses, dim).astype(float)
    for c in cells:
        J = (x[c[1:]] - x[c[0]]).T
        V = abs(np.linalg.det(J)) / (2 if dim == 2 else 6)
        grads = np.vstack([-np.ones(dim), np.eye(dim)]) @ np.linalg.inv(J)
        B = strain_matrix(dim, grads)
        Ke = V * B.T @ D @ B
        dofs = (dim * c[:, None] + np.arange(dim)).ravel()
        rows.append(np.repeat(dofs, len(dofs)))
        cols.append(np.tile(dofs, len(dofs)))
        vals.append(Ke.ravel())
        m[dofs] += rho * V / (dim + 1)
    K = scipy.sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(nd, nd))
    return K, m


def main():
    path, E, nu, rho, formulation = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
    dim, x, cells, masses = read(path)
    K, m = assemble(dim, x, cells, masses, E, nu, rho, formulation)
    s = scipy.sparse.diags(1 / np.sqrt(m))
    lam = scipy.sparse.linalg.eigsh(s @ K @ s, k=1, which="LA", tol=1e-12, return_eigenvectors=False)[0]
    print(json.dumps({"elements": len(cells), "nodes": len(x), "point_mass": float(masses.sum()),
                      "lambda_max": float(lam), "exact_step": float(2 / np.sqrt(lam))}))


if __name__ == "__main__":
    main()
