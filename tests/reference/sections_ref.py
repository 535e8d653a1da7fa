#!/usr/bin/python3
"""Independent reference for explicit critical time steps of meshes that mix
solids with trusses and membranes ("sections").

This script is written from the physics, not from dtmap's sources, so that
dtmap's results can be checked against something that shares no code with it.

For a lumped (diagonal) mass matrix M and a stiffness matrix K, the central
difference scheme is stable for dt <= 2 / omega_max, where omega_max^2 is the
largest eigenvalue of M^-1 K.  The script computes

  * the element bound of each element: dt_e = 2 / sqrt(lambda_max(Me^-1 Ke))
    with the element's own matrices (dense eigensolver, one element at a time);
  * the global step of the assembled system: 2 / sqrt(lambda_max(M^-1 K)).

Because the assembled lumped mass is the sum of the element masses, the global
step is never below the smallest element bound; the script asserts that.

Element kinds (SI units):
  solid         3D isotropic linear elasticity; tet4 (one point, exact) with
                lumped mass rho V / 4 per node; hex8 with 2x2x2 Gauss points
                and row-sum lumped mass (rho V / 8 per node for a
                parallelepiped).
  truss         line2, axial stiffness E A / L along the unit axis t, entered
                in 3D as t t^T blocks; lumped mass rho A L / 2 per node.
  membrane      tri3 / quad4 in 3D space, any orientation: plane stress in the
                element's own tangent plane, built in a local orthonormal 2D
                frame and rotated into 3D (no stiffness normal to the plane);
                lumped mass rho t area / 3 per node (tri3), row sums (quad4).
  plane-stress  tri3 / quad4 of a 2D mesh lying in z = const, 2 DOFs per node,
  plane-strain  thickness t multiplies K and M.

Usage:
  /usr/bin/python3 sections_ref.py MESH.msh SPEC.json OUT.json [--dense-check]
  /usr/bin/python3 sections_ref.py --self-test

SPEC.json:
  {"groups": {"<physical group name>": {"kind": "solid" | "truss" |
     "membrane" | "plane-stress" | "plane-strain", "E": Pa, "nu": -,
     "rho": kg/m^3, "area": m^2 (truss), "thickness": m (default 1)}}}

Elements that belong to no SPEC group are ignored.  Nodes are shared by tag, so
trusses and membranes embedded in a solid are coupled to it through the nodes
they share with it.

OUT.json:
  {"element_dt": {"<gmsh element tag>": dt_e}, "global_dt": s,
   "lambda_max": 1/s^2, "ndof": n, "nelements": {"solid": n, "truss": n,
   "membrane": n, ...}, plus the smallest element bound per kind and details
   of the eigensolver.}

Needs numpy, scipy and Gmsh's Python module (Debian: python3-numpy,
python3-scipy, python3-gmsh).
"""

import json
import math
import sys

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

# Element kinds, the mesh dimension each takes its elements from, and the Gmsh
# element types it accepts (1 line2, 2 tri3, 3 quad4, 4 tet4, 5 hex8).
KIND_DIM = {"solid": 3, "truss": 1, "membrane": 2, "plane-stress": 2, "plane-strain": 2}
KIND_TYPES = {"solid": (4, 5), "truss": (1,), "membrane": (2, 3),
              "plane-stress": (2, 3), "plane-strain": (2, 3)}
PLANE_KINDS = ("plane-stress", "plane-strain")

# Below this many DOFs the global problem is solved with a dense eigensolver.
DENSE_LIMIT = 3000


# --------------------------------------------------------------------------
# Material matrices (Voigt notation with engineering shear strains)
# --------------------------------------------------------------------------

def lame(E, nu):
    """Lame's first parameter and the shear modulus."""
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def elasticity_3d(E, nu):
    """6x6 isotropic elasticity, order xx, yy, zz, xy, yz, zx."""
    lam, mu = lame(E, nu)
    D = np.zeros((6, 6))
    D[:3, :3] = lam
    D[:3, :3] += 2 * mu * np.eye(3)
    D[3:, 3:] = mu * np.eye(3)
    return D


def plane_stress(E, nu):
    """3x3 plane-stress elasticity, order xx, yy, xy."""
    return E / (1 - nu ** 2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])


def plane_strain(E, nu):
    """3x3 plane-strain elasticity, order xx, yy, xy."""
    c = E / ((1 + nu) * (1 - 2 * nu))
    return c * np.array([[1 - nu, nu, 0], [nu, 1 - nu, 0], [0, 0, (1 - 2 * nu) / 2]])


# --------------------------------------------------------------------------
# Strain-displacement matrices from shape-function gradients
# --------------------------------------------------------------------------

def strain_matrix_3d(grads):
    """grads: (nnode, 3) gradients of the shape functions. Returns the
    6 x 3*nnode matrix B with eps = B u, u ordered node by node."""
    n = grads.shape[0]
    B = np.zeros((6, 3 * n))
    for a, (gx, gy, gz) in enumerate(grads):
        c = 3 * a
        B[0, c] = gx
        B[1, c + 1] = gy
        B[2, c + 2] = gz
        B[3, c], B[3, c + 1] = gy, gx
        B[4, c + 1], B[4, c + 2] = gz, gy
        B[5, c], B[5, c + 2] = gz, gx
    return B


def strain_matrix_2d(grads):
    """grads: (nnode, 2). Returns the 3 x 2*nnode in-plane strain matrix."""
    n = grads.shape[0]
    B = np.zeros((3, 2 * n))
    for a, (gx, gy) in enumerate(grads):
        c = 2 * a
        B[0, c] = gx
        B[1, c + 1] = gy
        B[2, c], B[2, c + 1] = gy, gx
    return B


def simplex_gradients(P):
    """Gradients of the linear shape functions of a simplex with vertices P
    ((n+1) x n), and its measure (length, area, volume)."""
    n = P.shape[1]
    A = np.hstack([np.ones((n + 1, 1)), P])
    coef = np.linalg.inv(A)           # N_a(x) = coef[0, a] + coef[1:, a] . x
    measure = abs(np.linalg.det(A)) / math.factorial(n)
    if measure <= 0:
        raise ValueError("degenerate element")
    return coef[1:, :].T, measure


# --------------------------------------------------------------------------
# Elements. Each returns (K, m): the element stiffness and the diagonal of its
# lumped mass, both with DOFs ordered node by node.
# --------------------------------------------------------------------------

def tet4(X, E, nu, rho):
    grads, V = simplex_gradients(X)
    B = strain_matrix_3d(grads)
    K = V * B.T @ elasticity_3d(E, nu) @ B
    return K, np.full(12, rho * V / 4)


# Natural coordinates of the corners of the reference square / cube, in Gmsh's
# node order.
QUAD_CORNERS = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], float)
HEX_CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], float)
GAUSS2 = (-1 / math.sqrt(3), 1 / math.sqrt(3))   # 2-point rule, weights 1


def multilinear(corners, xi):
    """Values (nnode,) and natural derivatives (nnode, dim) of the bi/trilinear
    shape functions at the natural point xi."""
    terms = 1 + corners * xi                       # (nnode, dim)
    N = np.prod(terms, axis=1) / 2 ** len(xi)
    dN = np.empty_like(corners)
    for d in range(len(xi)):
        others = np.prod(np.delete(terms, d, axis=1), axis=1)
        dN[:, d] = corners[:, d] * others / 2 ** len(xi)
    return N, dN


def isoparametric(X, corners, D, density, strain_matrix):
    """Stiffness and row-sum lumped mass of a bi/trilinear element with nodes
    X (nnode x dim) and full 2-point Gauss integration. density is mass per
    unit measure (rho, or rho t for a membrane), D already includes t."""
    nnode, dim = X.shape
    K = np.zeros((dim * nnode, dim * nnode))
    nodal_mass = np.zeros(nnode)
    for xi in np.array(np.meshgrid(*[GAUSS2] * dim)).reshape(dim, -1).T:
        N, dN = multilinear(corners, xi)
        J = X.T @ dN                               # dx/dxi, (dim, dim)
        detJ = np.linalg.det(J)
        if abs(detJ) <= 0:
            raise ValueError("degenerate element")
        grads = dN @ np.linalg.inv(J)              # dN/dx, (nnode, dim)
        B = strain_matrix(grads)
        K += abs(detJ) * B.T @ D @ B
        # Row sum of the consistent mass: sum_b int N_a N_b = int N_a.
        nodal_mass += density * abs(detJ) * N
    return K, np.repeat(nodal_mass, dim)


def hex8(X, E, nu, rho):
    return isoparametric(X, HEX_CORNERS, elasticity_3d(E, nu), rho, strain_matrix_3d)


def truss(X, E, A, rho):
    """Axial bar between X[0] and X[1] in 1, 2 or 3 dimensions."""
    d = X[1] - X[0]
    L = np.linalg.norm(d)
    if L <= 0:
        raise ValueError("zero-length truss")
    t = d / L
    k = E * A / L * np.outer(t, t)
    K = np.block([[k, -k], [-k, k]])
    return K, np.full(2 * len(t), rho * A * L / 2)


def tri3_plane(P, D, density):
    """Constant-strain triangle in 2D coordinates P (3x2); D includes t."""
    grads, area = simplex_gradients(P)
    B = strain_matrix_2d(grads)
    return area * B.T @ D @ B, np.full(6, density * area / 3)


def quad4_plane(P, D, density):
    return isoparametric(P, QUAD_CORNERS, D, density, strain_matrix_2d)


def tangent_frame(X):
    """Orthonormal in-plane axes (2x3, rows e1, e2) of a flat 3D polygon X,
    with e1 along its first edge. Raises if the polygon is not planar."""
    e1 = X[1] - X[0]
    normal = np.cross(X[1] - X[0], X[-1] - X[0]) if len(X) == 3 else \
        np.cross(X[2] - X[0], X[3] - X[1])
    normal /= np.linalg.norm(normal)
    e1 = e1 - (e1 @ normal) * normal
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    size = np.max(np.linalg.norm(X - X[0], axis=1))
    if np.max(np.abs((X - X[0]) @ normal)) > 1e-9 * size:
        raise ValueError("membrane element is not planar")
    return np.vstack([e1, e2])


def membrane(X, E, nu, rho, thickness):
    """Plane-stress tri3/quad4 in its own tangent plane, rotated into 3D."""
    R = tangent_frame(X)                           # (2, 3)
    P = (X - X[0]) @ R.T                           # local 2D coordinates
    D = thickness * plane_stress(E, nu)
    build = tri3_plane if len(X) == 3 else quad4_plane
    K2, m2 = build(P, D, rho * thickness)
    T = np.kron(np.eye(len(X)), R)                 # local DOFs = T @ global
    return T.T @ K2 @ T, np.repeat(m2[::2], 3)


def plane_element(X, kind, E, nu, rho, thickness):
    """tri3/quad4 of a 2D mesh, 2 DOFs per node, X given as (nnode, 2)."""
    D = thickness * (plane_stress(E, nu) if kind == "plane-stress" else plane_strain(E, nu))
    build = tri3_plane if len(X) == 3 else quad4_plane
    return build(X, D, rho * thickness)


def element_matrices(kind, X, prop):
    """Dispatch on the kind; X holds the node coordinates (nnode x ndim)."""
    E, rho = prop["E"], prop["rho"]
    nu = prop.get("nu", 0.0)
    t = prop.get("thickness", 1.0)
    if kind == "solid":
        return tet4(X, E, nu, rho) if len(X) == 4 else hex8(X, E, nu, rho)
    if kind == "truss":
        return truss(X, E, prop["area"], rho)
    if kind == "membrane":
        return membrane(X, E, nu, rho, t)
    return plane_element(X, kind, E, nu, rho, t)


# --------------------------------------------------------------------------
# Eigenvalues
# --------------------------------------------------------------------------

def lambda_max_dense(K, m):
    """Largest eigenvalue of diag(m)^-1 K, via the symmetric form
    diag(m)^-1/2 K diag(m)^-1/2."""
    s = 1 / np.sqrt(m)
    return scipy.linalg.eigh(s[:, None] * K * s[None, :], eigvals_only=True)[-1]


def element_dt(K, m):
    return 2 / math.sqrt(lambda_max_dense(K, m))


def assemble(elements, ndim):
    """elements: list of (node indices, K, m). Returns the sparse K (CSR) and
    the diagonal of M over ndim * nnode DOFs (node-major)."""
    nnode = 1 + max(int(max(idx)) for idx, _, _ in elements)
    rows, cols, vals = [], [], []
    mass = np.zeros(ndim * nnode)
    for idx, K, m in elements:
        dofs = (ndim * np.asarray(idx)[:, None] + np.arange(ndim)).ravel()
        rows.append(np.repeat(dofs, len(dofs)))
        cols.append(np.tile(dofs, len(dofs)))
        vals.append(K.ravel())
        np.add.at(mass, dofs, m)
    n = ndim * nnode
    K = scipy.sparse.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                shape=(n, n)).tocsr()
    return K, mass


def global_lambda_max(K, mass, force_dense=False):
    """Largest eigenvalue of M^-1 K (M diagonal). Returns (lambda, details)."""
    if np.any(mass <= 0):
        raise ValueError("a DOF has no mass")
    s = scipy.sparse.diags(1 / np.sqrt(mass))
    A = (s @ K @ s).tocsr()
    A = (A + A.T) / 2                               # remove round-off asymmetry
    n = A.shape[0]
    if force_dense or n < DENSE_LIMIT:
        lam = np.linalg.eigvalsh(A.toarray())[-1]
        return lam, {"solver": "dense eigvalsh"}
    v0 = np.random.default_rng(12345).standard_normal(n)
    vals, vecs = scipy.sparse.linalg.eigsh(A, k=1, which="LA", tol=1e-12, v0=v0)
    lam, v = vals[0], vecs[:, 0]
    # For a symmetric A and a unit v, some eigenvalue lies within |A v - lam v|
    # of lam: a bound on the error of the value eigsh returned.
    residual = np.linalg.norm(A @ v - lam * v) / np.linalg.norm(v)
    return lam, {"solver": "eigsh LA tol=1e-12", "residual_over_lambda": residual / lam}


# --------------------------------------------------------------------------
# Reading the mesh and the SPEC
# --------------------------------------------------------------------------

def read_groups(mesh_path, spec):
    """Opens the mesh with Gmsh and returns (coords, groups) where coords is
    (nnode, 3) over the nodes the SPEC groups use, and groups is a list of
    (name, kind, prop, [(element tag, gmsh type, node indices)])."""
    import gmsh
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(mesh_path)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        all_xyz = dict(zip(tags.tolist(), np.asarray(xyz).reshape(-1, 3)))
        names = {}
        for dim, ptag in gmsh.model.getPhysicalGroups():
            names.setdefault(gmsh.model.getPhysicalName(dim, ptag), []).append((dim, ptag))
        used = {}                                     # node tag -> index
        groups = []
        for name, prop in spec["groups"].items():
            kind = prop["kind"]
            if kind not in KIND_DIM:
                raise ValueError(f"group {name}: unknown kind {kind!r}")
            dim = KIND_DIM[kind]
            match = [p for d, p in names.get(name, []) if d == dim]
            if not match:
                raise ValueError(f"no physical group {name!r} of dimension {dim}")
            elems = []
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, match[0]):
                types, etags, enodes = gmsh.model.mesh.getElements(dim, ent)
                for etype, et, en in zip(types, etags, enodes):
                    if etype not in KIND_TYPES[kind]:
                        raise ValueError(f"group {name}: element type {etype} not supported for {kind}")
                    nper = len(en) // len(et)
                    for tag, conn in zip(et.tolist(), np.reshape(en, (-1, nper)).tolist()):
                        idx = [used.setdefault(n, len(used)) for n in conn]
                        elems.append((tag, etype, idx))
            groups.append((name, kind, prop, elems))
    finally:
        gmsh.finalize()
    coords = np.zeros((len(used), 3))
    for tag, i in used.items():
        coords[i] = all_xyz[tag]
    return coords, groups


# --------------------------------------------------------------------------
# The reference computation
# --------------------------------------------------------------------------

def compute(coords, groups, force_dense=False):
    kinds = {kind for _, kind, _, _ in groups}
    planar = bool(kinds & set(PLANE_KINDS))
    if planar:
        if kinds & {"solid", "membrane"}:
            raise ValueError("plane kinds cannot be mixed with solids or membranes")
        z = coords[:, 2]
        if np.ptp(z) > 1e-12 * max(1.0, np.ptp(coords[:, :2])):
            raise ValueError("plane kinds need a mesh lying in z = const")
    ndim = 2 if planar else 3
    X_all = coords[:, :ndim]

    element_dt_by_tag = {}
    min_dt = {}
    counts = {"solid": 0, "truss": 0, "membrane": 0}
    assembled = []
    lam_elem_max = 0.0
    for name, kind, prop, elems in groups:
        family = "plane" if kind in PLANE_KINDS else kind
        for tag, etype, idx in elems:
            K, m = element_matrices(kind, X_all[idx], prop)
            lam = lambda_max_dense(K, m)
            dt = 2 / math.sqrt(lam)
            if kind == "truss":
                L = np.linalg.norm(X_all[idx[1]] - X_all[idx[0]])
                expected = L / math.sqrt(prop["E"] / prop["rho"])
                assert abs(dt - expected) <= 1e-12 * expected, (tag, dt, expected)
            if str(tag) in element_dt_by_tag:
                raise ValueError(f"element {tag} is in two SPEC groups")
            element_dt_by_tag[str(tag)] = dt
            min_dt[family] = min(min_dt.get(family, math.inf), dt)
            counts[family] = counts.get(family, 0) + 1
            lam_elem_max = max(lam_elem_max, lam)
            assembled.append((idx, K, m))
    if not assembled:
        raise ValueError("no elements in the SPEC groups")

    K, mass = assemble(assembled, ndim)
    lam, details = global_lambda_max(K, mass, force_dense)
    # The assembled lumped mass is the sum of the element masses, so the
    # global lambda_max cannot exceed the largest element one.
    assert lam <= lam_elem_max * (1 + 1e-10), (lam, lam_elem_max)
    return {
        "element_dt": element_dt_by_tag,
        "global_dt": 2 / math.sqrt(lam),
        "lambda_max": lam,
        "ndof": int(K.shape[0]),
        "nelements": counts,
        "min_element_dt": min_dt,
        "element_lambda_max": lam_elem_max,
        "eigensolver": details,
    }


# --------------------------------------------------------------------------
# Self-test: closed forms, each with its tolerance and the reason for it
# --------------------------------------------------------------------------

def rotation(seed):
    """A random proper rotation (QR of a Gaussian matrix)."""
    q, r = np.linalg.qr(np.random.default_rng(seed).standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def check(label, got, want, rtol, reason):
    err = abs(got - want) / abs(want)
    ok = err <= rtol
    print(f"  {'ok  ' if ok else 'FAIL'} {label}: got {got:.15g}, want {want:.15g}, "
          f"rel err {err:.2e} <= {rtol:g} ({reason})")
    return ok


def strain_energy_stiffness(X, E, nu):
    """Stiffness of a linear tet by differentiating its strain energy twice,
    built without B or D: the displacement gradient comes from the edge
    vectors, and the energy density is lam/2 tr(eps)^2 + mu eps:eps."""
    lam, mu = lame(E, nu)
    edges = (X[1:] - X[0]).T                         # columns = edge vectors
    V = abs(np.linalg.det(edges)) / 6
    edges_inv = np.linalg.inv(edges)

    def energy(u):
        U = u.reshape(4, 3)
        H = (U[1:] - U[0]).T @ edges_inv            # du/dx
        eps = (H + H.T) / 2
        return V * (lam / 2 * np.trace(eps) ** 2 + mu * np.sum(eps * eps))

    # The energy is exactly quadratic, so the central second difference with a
    # unit step has no truncation error: only round-off remains.
    n = 12
    K = np.zeros((n, n))
    I = np.eye(n)
    for i in range(n):
        for j in range(n):
            K[i, j] = (energy(I[i] + I[j]) - energy(I[i] - I[j])
                       - energy(-I[i] + I[j]) + energy(-I[i] - I[j])) / 4
    return K


def self_test():
    ok = True
    # Round-off of a dense symmetric eigensolver on a small, well-scaled
    # matrix is a few units of 1e-16 times its norm; 1e-12 leaves a margin.
    eig_tol = 1e-12

    print("truss: dt = L / c, c = sqrt(E / rho)")
    E, rho, A = 200e9, 7850.0, 3.1e-4
    X = np.array([[0.1, -0.2, 0.3], [0.1, -0.2, 0.3]]) + np.array([[0, 0, 0], [0.31, 0.17, -0.44]])
    L = np.linalg.norm(X[1] - X[0])
    K, m = truss(X, E, A, rho)
    ok &= check("single truss dt", element_dt(K, m), L / math.sqrt(E / rho), eig_tol,
                "rank-one 6x6 problem, dense round-off only")

    print("regular tetrahedron, edge a: spectrum of M^-1 K is 0 (x6),")
    print("  8 (3 lam + 2 mu) / (rho a^2) (x1, breathing), 16 mu / (rho a^2) (x5, shear)")
    E, nu, rho, a = 30e9, 0.2, 2400.0, 0.07
    X = a / math.sqrt(2) * np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], float) / 2
    X = X @ rotation(7).T + np.array([1.0, -2.0, 0.5])
    lam_l, mu = lame(E, nu)
    K, m = tet4(X, E, nu, rho)
    s = 1 / np.sqrt(m)
    spectrum = np.linalg.eigvalsh(s[:, None] * K * s[None, :])
    want = np.sort([0] * 6 + [8 * (3 * lam_l + 2 * mu) / (rho * a * a)] + [16 * mu / (rho * a * a)] * 5)
    scale = want[-1]
    ok &= check("tet lambda_max", spectrum[-1], want[-1], eig_tol, "dense round-off only")
    zero_err = np.max(np.abs(spectrum[:6])) / scale
    print(f"  {'ok  ' if zero_err < eig_tol else 'FAIL'} tet rigid modes: max |lambda| / lambda_max "
          f"= {zero_err:.2e} <= {eig_tol:g} (six rigid-body modes)")
    ok &= zero_err < eig_tol
    ok &= check("tet shear eigenvalue (5-fold)", spectrum[6:11].mean(), want[6], eig_tol,
                "dense round-off only")
    ok &= check("tet dt = a sqrt(rho (1 - 2 nu) / (2 E))", element_dt(K, m),
                a * math.sqrt(rho * (1 - 2 * nu) / (2 * E)), eig_tol, "dense round-off only")
    K_fd = strain_energy_stiffness(X, E, nu)
    diff = np.max(np.abs(K_fd - K)) / np.max(np.abs(K))
    # The second differences subtract energies of size ~|K| and lose about
    # 1e-16 * |K| each, so agreement to 1e-10 of max |K| is expected.
    print(f"  {'ok  ' if diff < 1e-10 else 'FAIL'} tet K vs second derivative of the strain energy: "
          f"max |dK| / max |K| = {diff:.2e} <= 1e-10 (round-off of the differences)")
    ok &= diff < 1e-10
    ok &= check("tet lambda_max from the energy-built K", lambda_max_dense(K_fd, m), want[-1], 1e-10,
                "same round-off as the line above")

    print("hex8: a parallelepiped must reproduce the energy of any affine field")
    E, nu, rho = 70e9, 0.33, 2700.0
    F = np.array([[0.3, 0.05, 0.0], [0.02, 0.2, 0.04], [0.0, -0.03, 0.25]])
    X = HEX_CORNERS @ F.T / 2 @ rotation(3).T + 5.0
    V = abs(np.linalg.det(F))
    K, m = hex8(X, E, nu, rho)
    H = np.random.default_rng(1).standard_normal((3, 3)) * 1e-3
    u = (X @ H.T).ravel()
    eps = (H + H.T) / 2
    lam_l, mu = lame(E, nu)
    W = V * (lam_l / 2 * np.trace(eps) ** 2 + mu * np.sum(eps * eps))
    ok &= check("hex8 energy of an affine field", u @ K @ u / 2, W, 1e-12,
                "2x2x2 Gauss is exact for a parallelepiped; round-off only")
    ok &= check("hex8 lumped mass per node", m.min(), rho * V / 8, 1e-12,
                "row sums of the consistent mass, exact quadrature")
    ok &= check("hex8 lumped mass per node (max)", m.max(), rho * V / 8, 1e-12, "same")

    print("membrane: rotation invariance (3D tri3/quad4 vs the same element in xy, plane stress)")
    E, nu, rho, t = 200e9, 0.3, 7850.0, 0.01
    for label, P in (("right triangle", np.array([[0, 0], [0.3, 0], [0, 0.2]], float)),
                     ("quad", np.array([[0, 0], [0.3, 0.02], [0.27, 0.22], [-0.03, 0.18]], float))):
        K2, m2 = plane_element(P, "plane-stress", E, nu, rho, t)
        X = np.hstack([P, np.zeros((len(P), 1))]) @ rotation(11).T + np.array([0.4, -1.0, 2.0])
        K3, m3 = membrane(X, E, nu, rho, t)
        ok &= check(f"{label}: dt 3D membrane vs 2D plane stress", element_dt(K3, m3),
                    element_dt(K2, m2), eig_tol, "a rotation changes nothing but round-off")
        lam2 = np.linalg.eigvalsh(K2 / np.sqrt(np.outer(m2, m2)))
        lam3 = np.linalg.eigvalsh(K3 / np.sqrt(np.outer(m3, m3)))
        nz = len(P) * 2 - 3                                     # deforming modes
        spec_err = np.max(np.abs(lam3[-nz:] - lam2[-nz:])) / lam2[-1]
        print(f"  {'ok  ' if spec_err < eig_tol else 'FAIL'} {label}: all {nz} nonzero eigenvalues "
              f"agree to {spec_err:.2e} <= {eig_tol:g} of lambda_max")
        ok &= spec_err < eig_tol
        normal = np.cross(X[1] - X[0], X[2] - X[0])
        normal /= np.linalg.norm(normal)
        out = np.kron(np.ones(len(P)), normal)
        stiff_normal = abs(out @ K3 @ out) / np.max(np.abs(K3))
        print(f"  {'ok  ' if stiff_normal < eig_tol else 'FAIL'} {label}: no stiffness normal to the "
              f"plane ({stiff_normal:.2e} <= {eig_tol:g})")
        ok &= stiff_normal < eig_tol

    print("two-truss chain (3 nodes, springs k1, k2, masses m1, m2, m3):")
    print("  lambda = 0 and the roots of l^2 - b l + c, b = k1 (1/m1 + 1/m2) + k2 (1/m2 + 1/m3),")
    print("  c = k1 k2 (m1 + m2 + m3) / (m1 m2 m3)")
    E, rho, A = 200e9, 7850.0, 3.1e-4
    axis = rotation(5)[:, 0]
    for L1, L2 in ((0.05, 0.05), (0.05, 0.02)):
        coords = np.array([[0, 0, 0], L1 * axis, (L1 + L2) * axis]) + np.array([0.3, 0.1, -0.2])
        groups = [("bars", "truss", {"E": E, "rho": rho, "area": A},
                   [(1, 1, [0, 1]), (2, 1, [1, 2])])]
        out = compute(coords, groups, force_dense=True)
        k1, k2 = E * A / L1, E * A / L2
        m1, m2, m3 = rho * A * L1 / 2, rho * A * (L1 + L2) / 2, rho * A * L2 / 2
        b = k1 * (1 / m1 + 1 / m2) + k2 * (1 / m2 + 1 / m3)
        c = k1 * k2 * (m1 + m2 + m3) / (m1 * m2 * m3)
        lam_top = (b + math.sqrt(b * b - 4 * c)) / 2
        ok &= check(f"chain L1={L1}, L2={L2}: global lambda_max", out["lambda_max"], lam_top, eig_tol,
                    "9x9 dense problem, round-off only")
        c_wave = math.sqrt(E / rho)
        ok &= check(f"chain L1={L1}, L2={L2}: element dt of the shorter bar", min(out["element_dt"].values()),
                    min(L1, L2) / c_wave, eig_tol, "L / c")

    print("sparse eigsh vs dense on a chain of 1050 trusses (ndof 3153)")
    n = 1050
    Ls = 0.01 + 0.01 * np.random.default_rng(2).random(n)
    coords = np.outer(np.concatenate([[0], np.cumsum(Ls)]), axis)
    groups = [("bars", "truss", {"E": E, "rho": rho, "area": A},
               [(i + 1, 1, [i, i + 1]) for i in range(n)])]
    sparse = compute(coords, groups)
    K, mass = assemble([(idx, *truss(coords[idx], E, A, rho)) for _, _, idx in groups[0][3]], 3)
    dense, _ = global_lambda_max(K, mass, force_dense=True)
    ok &= check("eigsh lambda_max", sparse["lambda_max"], dense, 1e-10,
                "eigsh tol=1e-12; dense round-off ~1e-13")

    print("self-test", "passed" if ok else "FAILED")
    return 0 if ok else 1


def main(argv):
    if len(argv) == 2 and argv[1] == "--self-test":
        return self_test()
    args = [a for a in argv[1:] if not a.startswith("--")]
    flags = {a for a in argv[1:] if a.startswith("--")}
    if len(args) != 3 or flags - {"--dense-check"}:
        print(__doc__.split("Usage:")[1].split("SPEC.json:")[0].strip(), file=sys.stderr)
        return 2
    mesh, spec_path, out_path = args
    with open(spec_path) as f:
        spec = json.load(f)
    coords, groups = read_groups(mesh, spec)
    result = compute(coords, groups)
    if "--dense-check" in flags:
        dense = compute(coords, groups, force_dense=True)["lambda_max"]
        result["eigensolver"]["dense_lambda_max"] = dense
        result["eigensolver"]["dense_rel_diff"] = abs(dense - result["lambda_max"]) / dense
    with open(out_path, "w") as f:
        json.dump(result, f, indent=1, sort_keys=True)
    print(json.dumps({k: v for k, v in result.items() if k != "element_dt"}, indent=1, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
