"""Independent reference for dtmap's natural modes (tests t942, t943): the
linear tetrahedra of the current Gmsh model (nodes and elements read with
Gmsh's API, from a .msh or a live mesh), K = sum V B^T D B with isotropic D,
the row-sum lumped mass rho V / 4 per node and unknown, extra masses built
here (a selective-mass matrix of the form beta_e (W_e - w_e w_e^T / m_e)
(x) I_3), and the dense pencil solved by scipy.linalg.eigh. Shares no code
with dtmap."""

import gmsh
import numpy
import scipy.linalg


def elasticity(E, NU):
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    D = numpy.zeros((6, 6))
    D[:3, :3] = lam
    D[range(3), range(3)] += 2 * mu
    D[range(3, 6), range(3, 6)] = mu
    return D


def tet4(X, D):
    """Stiffness (12 x 12, node-major) and volume of a linear tetrahedron."""
    A = numpy.hstack([numpy.ones((4, 1)), X])
    grads = numpy.linalg.inv(A)[1:, :].T  # [node][x, y, z]
    B = numpy.zeros((6, 12))
    for a, (gx, gy, gz) in enumerate(grads):
        B[:, 3 * a:3 * a + 3] = [[gx, 0, 0], [0, gy, 0], [0, 0, gz], [gy, gx, 0], [0, gz, gy], [gz, 0, gx]]
    V = abs(numpy.linalg.det(A)) / 6
    return V * B.T @ D @ B, V


class Reference:
    """K, the lumped mass and the element list of the current Gmsh mesh."""

    def __init__(self, E, NU, RHO):
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        coords = dict(zip((int(t) for t in tags), xyz.reshape(-1, 3)))
        _, conn = gmsh.model.mesh.getElementsByType(4)
        conn = conn.reshape(-1, 4).astype(int)
        self.tags = sorted({int(t) for t in conn.ravel()})
        self.pos = {t: i for i, t in enumerate(self.tags)}
        self.x = numpy.array([coords[t] for t in self.tags])
        n = 3 * len(self.tags)
        self.K, self.m = numpy.zeros((n, n)), numpy.zeros(n)
        self.elements, D = [], elasticity(E, NU)
        for c in conn:
            nodes = [self.pos[int(t)] for t in c]
            Ke, V = tet4(self.x[nodes], D)
            dofs = [3 * v + k for v in nodes for k in range(3)]
            self.K[numpy.ix_(dofs, dofs)] += Ke
            self.m[dofs] += RHO * V / 4
            self.elements.append((nodes, RHO * V))

    def eig(self, extra=None):
        B = numpy.diag(self.m) + (extra if extra is not None else 0)
        return scipy.linalg.eigh(self.K, B)

    def sms(self, beta_of):
        """beta_e (W_e - w_e w_e^T / m_e) (x) I_3 over every element, beta_e = beta_of(its centroid)."""
        S = numpy.zeros_like(self.K)
        for nodes, me in self.elements:
            beta = beta_of(self.x[nodes].mean(axis=0))
            w = numpy.full(4, me / 4)
            Me = beta * numpy.kron(numpy.diag(w) - numpy.outer(w, w) / me, numpy.eye(3))
            dofs = [3 * v + k for v in nodes for k in range(3)]
            S[numpy.ix_(dofs, dofs)] += Me
        return S


def elastic(values, vectors=None):
    """The eigenpairs past the 6 rigid ones."""
    return values[6:], (vectors[:, 6:] if vectors is not None else None)


def mac(a, b, m):
    return (a @ (m * b)) ** 2 / ((a @ (m * a)) * (b @ (m * b)))
