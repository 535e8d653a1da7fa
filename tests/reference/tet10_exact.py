"""Exact stable step of a tet10 mesh under a fixed high-degree quadrature
(issue 45): an independent assembly, numpy/scipy only, no dtmap code and no
code shared with curved_ref.py.

Rule: the collapsed (Duffy) map of the unit cube onto the unit tetrahedron,
x = a (1 - b)(1 - c), y = b (1 - c), z = c, whose Jacobian (1 - b)(1 - c)^2
is taken into the weights: Gauss-Jacobi points with weight (1 - c)^2 in c,
(1 - b) in b and Gauss-Legendre in a. With n points per direction the rule
is exact for every polynomial of total degree 2n - 1 on the tetrahedron;
degree q asks n = ceil((q + 1) / 2). A curved tet10's stiffness is a
rational function of the reference coordinates, so no degree is exact for
it: the step converges as q grows, and the caller compares two degrees.

Element: tet10 shape functions in Gmsh's node order; stiffness of isotropic
linear elasticity, K_(ai)(bj) = integral lam g_ai g_bj + mu g_aj g_bi +
mu delta_ij g_ak g_bk dv (g the physical shape gradients); HRZ lumping,
the lumping dtmap gives tet10 under its default model (src/kernel/lump.c,
dtm_lumped_finish): the diagonal integral rho N_a^2 dv scaled so that the
element's masses sum to rho times its volume. The mass integrand has degree
7 on a curved tet10 (4 on a straight one), so every q >= 7 integrates it
exactly.

Exact step: 2 / sqrt(lambda_max) of M^-1/2 K M^-1/2 over the whole mesh
(free, M diagonal), scipy.sparse.linalg.eigsh at tolerance 0 (machine
precision). Element steps: 2 / sqrt of each element's largest generalized
eigenvalue (scipy.linalg.eigh).

Converged: with "converged" for the degrees, each element starts at degree
16 and goes up by 8 until its mass-scaled stiffness changes by at most
1e-12 relative (Frobenius norm); the exact step is assembled from every
element's last degree, and again from the degree before it, so that the
two steps show how far the assembled step has converged.

Usage: tet10_exact.py MESH.msh E NU RHO [DEGREE ... | converged]
Prints JSON: {"nodes", "elements", "degrees": [{"degree", "points",
"exact_step", "element_steps": {tag: step}}]} for each degree (default 16),
or, converged, {"nodes", "elements", "exact_step", "previous_step",
"element_steps", "degrees": {degree: elements ending there}}.
"""

import json
import math
import sys

import gmsh
import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg
import scipy.special

EDGES = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]  # Gmsh's tet10 mid-edge nodes 4..9


def rule(q):
    """Points p[nq, 3] and weights w[nq] on the unit tetrahedron, exact for
    total degree q (their sum is 1/6)."""
    n = math.ceil((q + 1) / 2)

    def on01(alpha):  # Gauss-Jacobi for weight (1 - t)^alpha on [0, 1]
        x, w = scipy.special.roots_jacobi(n, alpha, 0)
        return (x + 1) / 2, w / 2 ** (alpha + 1)

    (a, wa), (b, wb), (c, wc) = on01(0), on01(1), on01(2)
    A, B, C = np.meshgrid(a, b, c, indexing="ij")
    W = np.einsum("i,j,k->ijk", wa, wb, wc)
    p = np.stack([A * (1 - B) * (1 - C), B * (1 - C), C], axis=-1).reshape(-1, 3)
    return p, W.ravel()


def shapes(p):
    """N[nq, 10] and dN[nq, 10, 3] of tet10 at reference points p[nq, 3]."""
    lam = np.column_stack([1 - p.sum(axis=1), p])
    dl = np.vstack([-np.ones(3), np.eye(3)])
    N = np.empty((len(p), 10))
    dN = np.empty((len(p), 10, 3))
    for a in range(4):
        N[:, a] = lam[:, a] * (2 * lam[:, a] - 1)
        dN[:, a] = (4 * lam[:, a] - 1)[:, None] * dl[a]
    for k, (i, j) in enumerate(EDGES):
        N[:, 4 + k] = 4 * lam[:, i] * lam[:, j]
        dN[:, 4 + k] = 4 * (lam[:, i, None] * dl[j] + lam[:, j, None] * dl[i])
    return N, dN


def elements(X, q, E, nu, rho, chunk=64):
    """Stiffness K[ne, 30, 30] and HRZ masses m[ne, 10] of the elements
    X[ne, 10, 3] with the rule of degree q."""
    p, w = rule(q)
    N, dN = shapes(p)
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    ne = len(X)
    K = np.empty((ne, 30, 30))
    m = np.empty((ne, 10))
    for s in range(0, ne, chunk):
        x = X[s:s + chunk]
        J = np.einsum("eai,qaj->eqij", x, dN)  # dx_i / dxi_j
        det = np.linalg.det(J)
        if (det <= 0).any():
            raise ValueError("an element has det J <= 0 at a point of the degree-%d rule" % q)
        g = np.einsum("qaj,eqji->eqai", dN, np.linalg.inv(J)).reshape(len(x), len(w), 30)
        dv = det * w
        T = np.matmul(np.transpose(g * dv[:, :, None], (0, 2, 1)), g).reshape(len(x), 10, 3, 10, 3)
        Ke = lam * T + mu * np.transpose(T, (0, 1, 4, 3, 2))
        Ke += mu * np.einsum("eakbk,ij->eaibj", T, np.eye(3))
        K[s:s + chunk] = Ke.reshape(len(x), 30, 30)
        diag = dv @ (N * N)
        m[s:s + chunk] = rho * diag * (dv.sum(axis=1) / diag.sum(axis=1))[:, None]
    return K, m


def read(path):
    """Element tags, node tags [ne, 10] and coordinates [ne, 10, 3] of the
    tet10 of a .msh, and the node count."""
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(path)
    ntags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = np.zeros((int(ntags.max()) + 1, 3))
    xyz[ntags.astype(int)] = coords.reshape(-1, 3)
    etags, enodes = gmsh.model.mesh.getElementsByType(11)
    gmsh.finalize()
    nodes = enodes.astype(int).reshape(-1, 10)
    return etags.astype(int), nodes, xyz[nodes], len(ntags)


def assembled_step(nodes, K, m):
    """2 / sqrt(lambda_max) of M^-1/2 K M^-1/2 assembled from K[ne, 30, 30]
    and m[ne, 10] on the node tags nodes[ne, 10]."""
    used, local = np.unique(nodes, return_inverse=True)
    dofs = (3 * local.reshape(-1, 10)[:, :, None] + np.arange(3)).reshape(-1, 30)
    rows = np.repeat(dofs, 30, axis=1).ravel()
    cols = np.tile(dofs, (1, 30)).ravel()
    n = 3 * len(used)
    A = scipy.sparse.csr_matrix((K.ravel(), (rows, cols)), shape=(n, n))
    mass = np.zeros(n)
    np.add.at(mass, dofs.ravel(), np.repeat(m, 3, axis=1).ravel())
    s = scipy.sparse.diags(1 / np.sqrt(mass))
    top = scipy.sparse.linalg.eigsh(s @ A @ s, k=1, which="LA", tol=0)[0][0]
    return 2 / math.sqrt(top)


def element_steps(tags, K, m):
    steps = {}
    for t, Ke, me in zip(tags, K, m):
        lmax = scipy.linalg.eigh(Ke, np.diag(np.repeat(me, 3)), eigvals_only=True)[-1]
        steps[int(t)] = 2 / math.sqrt(lmax)
    return steps


def exact(tags, nodes, X, q, E, nu, rho):
    K, m = elements(X, q, E, nu, rho)
    return assembled_step(nodes, K, m), element_steps(tags, K, m)


def converged(tags, nodes, X, E, nu, rho, start=16, step=8, tol=1e-12, top=64):
    """Each element's matrices at degrees start, start + step, ... until they
    change by at most tol relative (Frobenius norm of the mass-scaled K);
    the step of the last degrees and of the degrees before them."""
    K, m = elements(X, start, E, nu, rho)
    prev = K.copy()
    deg = np.full(len(X), start)
    todo = np.arange(len(X))
    q = start
    while len(todo) and q < top:
        q += step
        Kn, _ = elements(X[todo], q, E, nu, rho)
        r = 1 / np.sqrt(np.repeat(m[todo], 3, axis=1))
        scale = r[:, :, None] * r[:, None, :]
        change = np.linalg.norm((Kn - K[todo]) * scale, axis=(1, 2)) / np.linalg.norm(Kn * scale, axis=(1, 2))
        prev[todo], K[todo], deg[todo] = K[todo], Kn, q
        todo = todo[change > tol]
    if len(todo):
        raise RuntimeError("%d elements not converged at degree %d" % (len(todo), q))
    return {"exact_step": assembled_step(nodes, K, m), "previous_step": assembled_step(nodes, prev, m),
            "element_steps": element_steps(tags, K, m), "degrees": {int(d): int((deg == d).sum()) for d in np.unique(deg)}}


def main(argv):
    if len(argv) < 5:
        print(__doc__)
        return 2
    path, E, nu, rho = argv[1], float(argv[2]), float(argv[3]), float(argv[4])
    tags, nodes, X, nn = read(path)
    if argv[5:] == ["converged"]:
        out = {"nodes": nn, "elements": len(tags)}
        out.update(converged(tags, nodes, X, E, nu, rho))
        json.dump(out, sys.stdout)
        print()
        return 0
    degrees = [int(a) for a in argv[5:]] or [16]
    out = {"nodes": nn, "elements": len(tags), "degrees": []}
    for q in degrees:
        step, steps = exact(tags, nodes, X, q, E, nu, rho)
        out["degrees"].append({"degree": q, "points": len(rule(q)[1]), "exact_step": step, "element_steps": steps})
    json.dump(out, sys.stdout)
    print()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
