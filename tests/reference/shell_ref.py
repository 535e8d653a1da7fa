"""Independent reference for dtmap's flat Reissner-Mindlin shell kernel
(src/kernel/shell.c): builds the single-element matrices from the textbook
formulas with numpy, in global axes, shares no code with dtmap, and
compares the element eigenvalues with the kernel's.

Formulation (the same physics, written another way):
- frame: the plane through the nodes by SVD (least-squares normal), first
  axis along the largest principal direction (not dtmap's edge 0-1: the
  eigenvalues must not depend on it);
- membrane (plane stress) and bending: B^T D B, quad4 with 2x2 Gauss,
  tri3 with its centroid (everything constant);
- transverse shear: quad4 at the centre; tri3 MITC3 in Lee and Bathe's
  covariant form (tying points (1/2, 0), (0, 1/2), (1/2, 1/2),
  e_rt = e_rt1 + c s, e_st = e_st2 - c r, c = e_rt3 - e_rt1 - e_st3 +
  e_st2), converted to Cartesian strains by J^-T, 3-point rule;
- lumped mass: rho t integral N_a (2x2 Gauss) per translation, times
  t^2/12 per rotation (drilling included), drilling stiffness zero;
- eigenvalues by scipy.linalg.eigh(K, M) on the full 6 nn global problem;
  the membrane value with the membrane stiffness alone; the scale s of the
  scaled convention by bisection on lambda_max(K, M(s)) (relative 1e-12),
  the smallest s >= 1 with lambda <= lambda_membrane.

Usage: shell_ref.py CASES, where each line of CASES is
  name type E nu rho k t area x[3 nn] lambda_m lambda_phys lambda_scaled s
(written by tests/t113-shell-kernel.c). Prints the comparison table and
exits 1 if any number differs by more than 1e-9 relative. Run without
arguments it only runs its own self-test (square plate closed forms).
"""

import sys

import numpy as np
import scipy.linalg as sl

G2 = np.array([-1.0, 1.0]) / np.sqrt(3.0)


def shape(typ, r, s):
    """Shape functions and reference derivatives (nn,), (nn, 2)."""
    if typ == 2:
        return np.array([1 - r - s, r, s]), np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])
    xi = np.array([-1.0, 1.0, 1.0, -1.0])
    eta = np.array([-1.0, -1.0, 1.0, 1.0])
    N = 0.25 * (1 + xi * r) * (1 + eta * s)
    dN = np.stack([0.25 * xi * (1 + eta * s), 0.25 * eta * (1 + xi * r)], axis=1)
    return N, dN


def frame(X):
    c = X.mean(axis=0)
    _, _, vt = np.linalg.svd(X - c)
    e1, e2 = vt[0], vt[1]
    n = np.cross(e1, e2)
    if np.dot(n, np.cross(X[1] - X[0], X[2] - X[0])) < 0:
        e2 = -e2
        n = -n
    return np.array([e1, e2, n]), (X - c) @ np.array([e1, e2]).T


def full_rule(typ):
    if typ == 2:
        return [((1 / 3, 1 / 3), 0.5)]
    return [((a, b), 1.0) for a in G2 for b in G2]


def geometry(typ, xy, r, s):
    N, dN = shape(typ, r, s)
    J = dN.T @ xy  # J[i, j] = d x_j / d r_i
    g = np.linalg.solve(J, dN.T).T  # (nn, 2) physical gradients
    return N, g, np.linalg.det(J), J


def plane_stress(E, nu, f):
    return f * E / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])


# local unknowns per node: u v w thx thy thz; beta_x = thy, beta_y = -thx
def b_membrane(g, nn):
    B = np.zeros((3, 6 * nn))
    for a in range(nn):
        B[0, 6 * a] = g[a, 0]
        B[1, 6 * a + 1] = g[a, 1]
        B[2, 6 * a] = g[a, 1]
        B[2, 6 * a + 1] = g[a, 0]
    return B


def b_bending(g, nn):
    B = np.zeros((3, 6 * nn))
    for a in range(nn):
        B[0, 6 * a + 4] = g[a, 0]
        B[1, 6 * a + 3] = -g[a, 1]
        B[2, 6 * a + 4] = g[a, 1]
        B[2, 6 * a + 3] = -g[a, 0]
    return B


def b_shear(N, g, nn):
    B = np.zeros((2, 6 * nn))
    for a in range(nn):
        B[0, 6 * a + 2] = g[a, 0]
        B[0, 6 * a + 4] = N[a]
        B[1, 6 * a + 2] = g[a, 1]
        B[1, 6 * a + 3] = -N[a]
    return B


def covariant(xy, r, s):
    """Covariant shear strain rows (e_rt, e_st) = J (gamma_x, gamma_y)."""
    N, g, _, J = geometry(2, xy, r, s)
    return J @ b_shear(N, g, 3)


def mitc3_b(xy, r, s):
    e1 = covariant(xy, 0.5, 0.0)
    e2 = covariant(xy, 0.0, 0.5)
    e3 = covariant(xy, 0.5, 0.5)
    c = e3[0] - e1[0] - e3[1] + e2[1]
    ert = e1[0] + c * s
    est = e2[1] - c * r
    _, _, _, J = geometry(2, xy, r, s)
    return np.linalg.solve(J, np.stack([ert, est]))


def local_matrices(typ, E, nu, rho, k, t, xy):
    nn = 3 if typ == 2 else 4
    n = 6 * nn
    Km, Kb, Ks = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    Dm, Db = plane_stress(E, nu, t), plane_stress(E, nu, t**3 / 12)
    kgt = k * E / (2 * (1 + nu)) * t
    mass = np.zeros(nn)
    for (r, s), w in full_rule(typ):
        N, g, dj, _ = geometry(typ, xy, r, s)
        Km += w * dj * b_membrane(g, nn).T @ Dm @ b_membrane(g, nn)
        Kb += w * dj * b_bending(g, nn).T @ Db @ b_bending(g, nn)
    if typ == 3:
        N, g, dj, _ = geometry(typ, xy, 0.0, 0.0)
        Bs = b_shear(N, g, nn)
        Ks += 4 * dj * kgt * Bs.T @ Bs
        for (r, s), w in full_rule(typ):
            N, _, dj, _ = geometry(typ, xy, r, s)
            mass += w * dj * N
    else:
        for r, s in ((1 / 6, 1 / 6), (2 / 3, 1 / 6), (1 / 6, 2 / 3)):
            _, _, dj, _ = geometry(typ, xy, r, s)
            Bs = mitc3_b(xy, r, s)
            Ks += dj / 6 * kgt * Bs.T @ Bs
        _, _, dj, _ = geometry(typ, xy, 1 / 3, 1 / 3)
        mass[:] = dj / 2 / 3
    m = np.repeat(rho * t * mass, 6) * np.tile([1, 1, 1, t * t / 12, t * t / 12, t * t / 12], nn)
    return Km, Kb + Ks, m


def to_global(R, K):
    n = K.shape[0]
    T = np.kron(np.eye(n // 3), R)
    return T.T @ K @ T


def lam_max(K, m):
    return sl.eigh(K, np.diag(m), eigvals_only=True)[-1]


def scale_bisect(K, m, target):
    rot = np.tile([0, 0, 0, 1, 1, 1], len(m) // 6).astype(bool)

    def lam(s):
        return lam_max(K, np.where(rot, s * m, m))

    if lam(1.0) <= target:
        return 1.0
    lo, hi = 1.0, 2.0
    while lam(hi) > target:
        lo, hi = hi, 2 * hi
    while hi - lo > 1e-12 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if lam(mid) > target else (lo, mid)
    return hi


def element(typ, E, nu, rho, k, t, X):
    R, xy = frame(X)
    Km, Kt, m = local_matrices(typ, E, nu, rho, k, t, xy)
    Kmg, Kg = to_global(R, Km), to_global(R, Km + Kt)
    lm = lam_max(Kmg, m)
    lp = lam_max(Kg, m)
    s = scale_bisect(Kg, m, lm * (1 + 1e-12))
    rot = np.tile([0, 0, 0, 1, 1, 1], len(m) // 6).astype(bool)
    ls = lam_max(Kg, np.where(rot, s * m, m))
    return lm, lp, ls, s


def self_test():
    E, nu, rho, k = 200e9, 0.3, 7800.0, 5 / 6
    G = E / (2 * (1 + nu))
    X = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    for t in (0.01, 0.1):
        lm, lp, _, s = element(3, E, nu, rho, k, t, X)
        lts = 12 * k * G / (rho * t * t)
        assert abs(lm / (4 * E / ((1 - nu) * rho)) - 1) < 1e-12
        assert abs(lp / max(lm, lts * (1 + t * t / 3)) - 1) < 1e-12
        assert abs(s / (lts / (lm - 4 * k * G / rho)) - 1) < 1e-9


def main():
    self_test()
    if len(sys.argv) < 2:
        print("self-test passed")
        return 0
    bad = 0
    print("| element | t/h | lambda_m C | rel. diff | lambda_phys C | rel. diff | lambda_scaled C | rel. diff "
          "| s C | rel. diff |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for line in open(sys.argv[1]):
        f = line.split()
        name, typ = f[0], int(f[1])
        E, nu, rho, k, t, area = map(float, f[2:8])
        nn = 3 if typ == 2 else 4
        X = np.array(list(map(float, f[8:8 + 3 * nn]))).reshape(nn, 3)
        c = list(map(float, f[8 + 3 * nn:12 + 3 * nn]))
        ref = element(typ, E, nu, rho, k, t, X)
        rel = [abs(a - b) / abs(b) for a, b in zip(c, ref)]
        bad += any(r > 1e-9 for r in rel)
        cells = " | ".join(f"{a:.10g} | {r:.1e}" for a, r in zip(c, rel))
        print(f"| {name} | {t / np.sqrt(area):.2f} | {cells} |")
    print("FAIL" if bad else "all within 1e-9")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
