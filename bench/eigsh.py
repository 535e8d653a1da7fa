#!/usr/bin/python3
"""Benchmark helper (not a test): scipy's eigsh on the assembled problem
dtmap's global estimate solves, for bench/perf.sh.

Reads a tet4 mesh with Gmsh's Python API, assembles the linear-elastic
stiffness K (P1 tets, K_ai,bj = V (lam g_ai g_bj + mu g_aj g_bi +
mu delta_ij g_a.g_b), g the barycentric gradients) and the row-sum lumped
mass (rho V / 4 per node and component) with numpy, forms the symmetric
A = M^-1/2 K M^-1/2 as a CSR matrix, and times eigsh(A, k=1, which='LA',
tol) alone: the assembly is not timed. Prints one JSON line.
Usage: eigsh.py MESH.msh E nu rho tol
"""
import json
import sys
import time

import gmsh
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh


def read_tets(path):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(path)
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    _, conn = gmsh.model.mesh.getElementsByType(4)
    gmsh.finalize()
    order = np.argsort(tags)
    index = np.empty(int(tags.max()) + 1, dtype=np.int64)
    index[tags[order]] = order
    return xyz.reshape(-1, 3), index[conn.astype(np.int64)].reshape(-1, 4)


def assemble(x, t, lam, mu, rho, chunk=200000):
    n = 3 * len(x)
    K = sp.csr_matrix((n, n))
    m = np.zeros(len(x))
    eye = np.eye(3)
    for c0 in range(0, len(t), chunk):
        tc = t[c0:c0 + chunk]
        J = np.stack([x[tc[:, k]] - x[tc[:, 0]] for k in (1, 2, 3)], axis=2)  # columns: edges
        V = np.abs(np.linalg.det(J)) / 6
        Ji = np.linalg.inv(J)  # rows: gradients of the barycentrics 1..3
        G = np.concatenate([-Ji.sum(axis=1, keepdims=True), Ji], axis=1)  # (n, 4, 3)
        Ke = lam * np.einsum("nai,nbj->naibj", G, G) + mu * np.einsum("naj,nbi->naibj", G, G)
        Ke += mu * np.einsum("nak,nbk->nab", G, G)[:, :, None, :, None] * eye[None, None, :, None, :]
        Ke *= V[:, None, None, None, None]
        dof = (3 * tc[:, :, None] + np.arange(3)[None, None, :]).reshape(-1, 12)
        rows = np.repeat(dof, 12, axis=1).ravel()
        cols = np.tile(dof, (1, 12)).ravel()
        K = K + sp.csr_matrix((Ke.reshape(-1), (rows, cols)), shape=(n, n))
        np.add.at(m, tc.ravel(), np.repeat(rho * V / 4, 4))
    return K.tocsr(), np.repeat(m, 3)


def main():
    path, E, nu, rho, tol = sys.argv[1], *map(float, sys.argv[2:6])
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    x, t = read_tets(path)
    t0 = time.perf_counter()
    K, m = assemble(x, t, lam, mu, rho)
    d = sp.diags(1 / np.sqrt(m))
    A = (d @ K @ d).tocsr()
    t1 = time.perf_counter()
    w = eigsh(A, k=1, which="LA", tol=tol, return_eigenvectors=False)
    t2 = time.perf_counter()
    print(json.dumps({"lambda": float(w[0]), "eigsh_seconds": t2 - t1, "assembly_seconds": t1 - t0,
                      "tets": len(t), "nnz": A.nnz}))


main()
