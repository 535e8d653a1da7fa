#!/usr/bin/python3
"""Independent numbers for t117: one tet10 integrated and lumped as CalculiX
2.20 does for C3D10 in explicit dynamics (docs/curved.md): the 4-point
degree-2 rule for stiffness, mass diagonal and measure; the diagonal scaled
so that the corners carry alp/(1+alp) of the 4-point mass and the mid-edge
nodes 1/(1+alp), alp = 0.1203. Own shape functions (Gmsh's tet10 node
order), numpy only. Prints the lumped weights (mass / (rho V)) and the
largest eigenvalue of M^-1 K (1/s^2) of the unit right tet10 and of a curved
one (mid-edge node 4 moved), E = 70e9 Pa, nu = 0.3, rho = 2700 kg/m^3."""
import numpy as np

EDGES = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]  # Gmsh tet10


def shape(p):
    """N[10] and dN/du[10][3] at reference point p."""
    u, v, w = p
    L = np.array([1 - u - v - w, u, v, w])
    dL = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    N = np.zeros(10)
    dN = np.zeros((10, 3))
    for a in range(4):
        N[a] = L[a] * (2 * L[a] - 1)
        dN[a] = (4 * L[a] - 1) * dL[a]
    for k, (i, j) in enumerate(EDGES):
        N[4 + k] = 4 * L[i] * L[j]
        dN[4 + k] = 4 * (L[i] * dL[j] + L[j] * dL[i])
    return N, dN


def rule():
    a = (5 - np.sqrt(5)) / 20
    b = 1 - 3 * a
    pts = [(a, a, a), (b, a, a), (a, b, a), (a, a, b)]
    return np.array(pts), np.full(4, 1 / 24)


def element(x, E=70e9, nu=0.3, rho=2700, alp=0.1203):
    """Lumped weights m / V, 4-point measure V and lambda_max of one tet10."""
    K, m, vol = matrices(x, E, nu, alp)
    M = np.repeat(rho * m, 3)
    s = 1 / np.sqrt(M)
    lmax = np.linalg.eigvalsh(s[:, None] * K * s[None, :]).max()
    return m / vol, vol, lmax


def matrices(x, E, nu, alp=0.1203):
    """Stiffness K[30][30] (N/m), lumped masses per density m[10] (m^3) and
    the 4-point measure of the tet10 with nodes x[10][3]."""
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    K = np.zeros((30, 30))
    d = np.zeros(10)
    vol = 0
    P, W = rule()
    for p, wt in zip(P, W):
        N, dN = shape(p)
        J = dN.T @ x  # J[i][j] = d x_j / d u_i
        dv = np.linalg.det(J) * wt
        g = np.linalg.solve(J, dN.T).T  # dN/dx [10][3]
        for a in range(10):
            for b in range(10):
                blk = lam * np.outer(g[a], g[b]) + mu * np.outer(g[b], g[a]) + mu * (g[a] @ g[b]) * np.eye(3)
                K[3 * a:3 * a + 3, 3 * b:3 * b + 3] += blk * dv
        d += N * N * dv
        vol += dv
    m = d.copy()
    m[:4] *= vol * alp / (1 + alp) / d[:4].sum()
    m[4:] *= vol / (1 + alp) / d[4:].sum()
    return K, m, vol


def unit_tet10():
    c = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    return np.vstack([c, [(c[i] + c[j]) / 2 for i, j in EDGES]])


if __name__ == "__main__":
    x = unit_tet10()
    w, vol, l = element(x)
    print("straight: weights", " ".join("%.17g" % v for v in w), "vol %.17g lambda %.17g" % (vol, l))
    x[4] += [0.05, -0.08, 0.03]
    w, vol, l = element(x)
    print("curved: weights", " ".join("%.17g" % v for v in w), "vol %.17g lambda %.17g" % (vol, l))
