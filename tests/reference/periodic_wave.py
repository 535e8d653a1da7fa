"""Independent reference for dtmap's phase-speed error on tetrahedral meshes:
plane waves run through a periodic box, in numpy/scipy, sharing no code
with dtmap.

- The box: Gmsh meshes a box whose opposite faces are periodic
  (gmsh.model.mesh.setPeriodic), so the surface meshes of opposite faces
  match node for node. Nodes that coincide modulo the box's sides are one
  unknown (a node class): the mesh then tiles space, and a plane wave
  exp(i k.x) whose wave vector fits the box (k = 2 pi (a/Lx, b/Ly, c/Lz),
  a, b, c whole) sees no boundary at all.
- The elements: linear (tet4) and quadratic (tet10) tetrahedra, isotropic
  elasticity at full integration (the gradients are constant or linear,
  so one point or the degree-2 four-point rule is exact), lumped mass:
  rho V / 4 per vertex for tet4, the HRZ diagonal for tet10 (the consistent
  diagonal scaled to the element's mass: 1/36 per vertex, 4/27 per
  mid-edge node, worked out below from the integrals of the shape
  functions).
- The run: undamped central differences from u0 = p cos(k.x), zero
  velocity (u1 = u0 - dt^2/2 M^-1 K u0), many waves at once (one column
  each). The projection q_n = sum_a m_a (p.u_a) cos(k.x_a) / sum_a m_a
  picks the Fourier component k. On a lattice it is one cosine at the
  Bloch frequency; on an unstructured mesh the interpolated plane wave is
  not a mode, and q_n is the coherent wave (a narrow peak) plus a spread
  of higher frequencies from the element fluctuations. The phase speed a
  simulation measures is that of the coherent wave: the frequency of the
  peak of |FFT(q)| (Hann window, zero-padded, refined by a parabola
  through the three largest bins), not the mean frequency of the
  projection (its Rayleigh quotient, which the fluctuations make too
  stiff).
- Central differences act mode by mode, sin(omega dt / 2) = omega_h dt / 2,
  so the run also gives the semi-discrete error (space alone),
  omega_h = 2 sin(omega dt / 2) / dt.

As a script: periodic_wave.py MESH.msh SPEC.json OUT.json, SPEC
  {"E":..., "nu":..., "rho":..., "box": [Lx, Ly, Lz], "dt": ..., "periods": N,
   "waves": [{"name":..., "k": [kx, ky, kz], "pol": [px, py, pz]}, ...]}
writes OUT {"waves": {name: {"error": fraction, "space": fraction, "omega": rad/s}}, "dt_critical": s}.
"""

import contextlib
import json
import math
import sys

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from scipy.spatial import cKDTree

# the degree-2 four-point rule on the reference tetrahedron (barycentric)
_A, _B = 0.5854101966249685, 0.1381966011250105
RULE4 = np.array([[_A, _B, _B, _B], [_B, _A, _B, _B], [_B, _B, _A, _B], [_B, _B, _B, _A]])

# HRZ for tet10: the consistent diagonal int N_a^2 over V is 1/70 at a vertex
# (4/35 - 4/20 + 1/10 from int L^n = V n! 3! / (n + 3)!) and 16 * 4 / 5040 =
# 8/105 at a mid-edge node; scaled to a total of 1: 1/36 and 4/27.
HRZ10 = np.array([1 / 36] * 4 + [4 / 27] * 6)


def periodic_box(box, h, algorithm="delaunay", order=1, path=None, transfinite=0, optimize=1, grading=1.0):
    """Mesh the box [0, Lx] x [0, Ly] x [0, Lz] with opposite faces periodic;
    transfinite n > 0: n x n x n cells each cut into tetrahedra (Gmsh's
    structured mesh, whose faces match without periodic constraints: with
    them Gmsh numbers the nodes otherwise and cuts the cells differently
    from place to place) instead of the unstructured mesher. grading g > 1:
    the size grows linearly along x from h at x = 0 to g h at x = Lx / 2 and
    falls back to h at x = Lx (a size field that is itself periodic, so the
    faces x = 0 and x = Lx still match). Writes path (msh 4, physical volume
    "block") when given. Returns nodes [N][3] and the element nodes
    [E][4 or 10] (0-based)."""
    algos = {"delaunay": 1, "hxt": 10, "mmg3d": 7}
    with _session() as gmsh:
        gmsh.model.add("box")
        vol = gmsh.model.occ.addBox(0, 0, 0, *box)
        gmsh.model.occ.synchronize()
        if not transfinite:  # a structured mesh matches across the box by construction
            _make_periodic(gmsh, box)
        else:
            for _, c in gmsh.model.getEntities(1):
                gmsh.model.mesh.setTransfiniteCurve(c, transfinite + 1)
            for _, s in gmsh.model.getEntities(2):
                gmsh.model.mesh.setTransfiniteSurface(s)
            gmsh.model.mesh.setTransfiniteVolume(vol)
        gmsh.option.setNumber("Mesh.CharacteristicLengthMax", h * grading)
        gmsh.option.setNumber("Mesh.CharacteristicLengthMin", h)
        if grading > 1:
            f = gmsh.model.mesh.field.add("MathEval")
            gmsh.model.mesh.field.setString(f, "F", "%r * (1 + %r * (1 - Fabs(2 * x / %r - 1)))" %
                                            (h, grading - 1, box[0]))
            gmsh.model.mesh.field.setAsBackgroundMesh(f)
            for name in ("ExtendFromBoundary", "FromPoints", "FromCurvature"):
                gmsh.option.setNumber("Mesh.CharacteristicLength" + name, 0)
        gmsh.option.setNumber("Mesh.Algorithm3D", algos[algorithm])
        gmsh.option.setNumber("Mesh.Optimize", optimize)
        gmsh.model.addPhysicalGroup(3, [vol], 1)
        gmsh.model.setPhysicalName(3, 1, "block")
        gmsh.model.mesh.generate(3)
        if order == 2:
            gmsh.model.mesh.setOrder(2)
        if path:
            gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
            gmsh.write(path)
        return _tets_of(gmsh, order)


@contextlib.contextmanager
def _session():
    """Gmsh initialised (quiet) for the block, finalised after it."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        yield gmsh
    finally:
        gmsh.finalize()


def _tets_of(gmsh, order):
    """Nodes [N][3] and tetrahedra [E][4 or 10] (0-based) of Gmsh's current model."""
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    _, en = gmsh.model.mesh.getElementsByType(4 if order == 1 else 11)
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    return xyz.reshape(-1, 3), index[en.astype(np.int64)].reshape(-1, 4 if order == 1 else 10)


def _make_periodic(gmsh, box):
    """Each face at x_d = L_d is the image of the face at x_d = 0 under the shift by L_d
    (the bounding-box queries with a margin well above OpenCASCADE's tolerance)."""
    eps = 1e-3 * min(box)
    for d in range(3):
        hi = [box[i] + eps if i != d else eps for i in range(3)]
        shift = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
        shift[4 * d + 3] = box[d]
        for dim, tag in gmsh.model.getEntitiesInBoundingBox(-eps, -eps, -eps, *hi, 2):
            b = list(gmsh.model.getBoundingBox(dim, tag))
            b[d] += box[d]
            b[d + 3] += box[d]
            image = gmsh.model.getEntitiesInBoundingBox(b[0] - eps, b[1] - eps, b[2] - eps, b[3] + eps, b[4] + eps,
                                                        b[5] + eps, 2)
            gmsh.model.mesh.setPeriodic(2, [image[0][1]], [tag], shift)


def read_msh(path, order=1):
    """Nodes [N][3] and tetrahedra [E][4 or 10] (0-based) of a .msh."""
    with _session() as gmsh:
        gmsh.open(path)
        return _tets_of(gmsh, order)


def node_classes(xyz, box):
    """The class of every node: nodes that coincide modulo the box's sides
    share one. Returns (cls [N], ncls, position of each class [ncls][3])."""
    box = np.asarray(box, float)
    tol = 1e-6 * box.min()
    w = np.mod(xyz, box)
    w[w > box - tol] = 0.0  # a node on a far face is its image on the near one
    pairs = cKDTree(w).query_pairs(tol, output_type="ndarray")
    parent = np.arange(len(xyz))
    for a, b in pairs:  # union-find over coinciding nodes (edges and corners chain)
        ra, rb = _root(parent, a), _root(parent, b)
        parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([_root(parent, a) for a in range(len(xyz))])
    uniq, cls = np.unique(roots, return_inverse=True)
    for d in range(3):  # every node on a far face has its image on the near one
        far = np.abs(xyz[:, d] - box[d]) < tol
        near = np.abs(xyz[:, d]) < tol
        if not np.isin(cls[far], cls[near]).all():
            raise ValueError("the faces x_%d = 0 and %g do not match: not a periodic mesh" % (d, box[d]))
    return cls, len(uniq), w[uniq]


def _root(parent, a):
    while parent[a] != a:
        parent[a] = parent[parent[a]]
        a = parent[a]
    return a


def _gradients(x):
    """Barycentric gradients [E][4][3] and volumes [E] of the vertices x [E][4][3]."""
    J = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]], axis=1)  # rows: edges
    Ji = np.linalg.inv(J)  # columns: gradients of L1..L3
    g = np.empty((len(x), 4, 3))
    g[:, 1:] = np.transpose(Ji, (0, 2, 1))
    g[:, 0] = -g[:, 1:].sum(axis=1)
    return g, np.abs(np.linalg.det(J)) / 6


def _midside_pairs(xyz, tet):
    """For each of the six mid-edge nodes of the first tet10, the two vertices it sits between."""
    pairs = []
    for m in range(4, 10):
        for a in range(4):
            for b in range(a + 1, 4):
                if np.allclose(0.5 * (xyz[tet[a]] + xyz[tet[b]]), xyz[tet[m]], atol=1e-9 * np.ptp(xyz)):
                    pairs.append((a, b))
    if len(pairs) != 6:
        raise ValueError("tet10 with curved or shifted mid-edge nodes")
    return pairs


def _shape_gradients(g, order, pairs):
    """Gradients of the shape functions [E][q][n][3] at the rule's points."""
    if order == 1:
        return g[:, None, :, :]
    out = np.empty((len(g), 4, 10, 3))
    for q, L in enumerate(RULE4):
        for a in range(4):
            out[:, q, a] = (4 * L[a] - 1) * g[:, a]
        for m, (a, b) in enumerate(pairs):
            out[:, q, 4 + m] = 4 * (L[a] * g[:, b] + L[b] * g[:, a])
    return out


def assemble(xyz, tets, box, chunk=20000):
    """K_lam, K_mu (sparse, 3 unknowns per node class: K = lam K_lam + mu K_mu),
    the lumped mass per unknown for density 1, and the class positions."""
    cls, ncls, pos = node_classes(xyz, box)
    nn = tets.shape[1]
    order = 1 if nn == 4 else 2
    pairs = _midside_pairs(xyz, tets[0]) if order == 2 else None
    weights = np.full(1, 1.0) if order == 1 else np.full(4, 0.25)
    rows, cols, dl, dm = [], [], [], []
    mass = np.zeros(ncls)
    for s in range(0, len(tets), chunk):
        t = tets[s:s + chunk]
        g, V = _gradients(xyz[t[:, :4]])
        G = _shape_gradients(g, order, pairs)
        lam = np.einsum("e,q,eqai,eqbj->eaibj", V, weights, G, G)
        gg = np.einsum("e,q,eqak,eqbk->eab", V, weights, G, G)
        mu = np.transpose(lam, (0, 3, 2, 1, 4)) + np.einsum("eab,ij->eaibj", gg, np.eye(3))
        dof = (3 * cls[t][:, :, None] + np.arange(3)).reshape(len(t), 3 * nn)
        rows.append(np.repeat(dof, 3 * nn, axis=1).ravel())
        cols.append(np.tile(dof, (1, 3 * nn)).ravel())
        dl.append(lam.reshape(len(t), -1).ravel())
        dm.append(mu.reshape(len(t), -1).ravel())
        share = np.full(nn, 0.25) if order == 1 else HRZ10
        np.add.at(mass, cls[t], V[:, None] * share)
    r, c = np.concatenate(rows), np.concatenate(cols)
    n = 3 * ncls
    Kl = scipy.sparse.csr_matrix((np.concatenate(dl), (r, c)), shape=(n, n))
    Km = scipy.sparse.csr_matrix((np.concatenate(dm), (r, c)), shape=(n, n))
    return Kl, Km, np.repeat(mass, 3), pos


def bloch_one_class(xyz, tets, lam, mu, rho, kvecs, chunk=2000):
    """The plane wave exp(i k.x) on every node of a mesh of linear tetrahedra
    whose nodes are one class (a structured mesh: one lattice of nodes): its
    3 x 3 dynamic matrix sum_e sum_ab K_ab cos(k.(x_b - x_a)) over the summed
    lumped mass, for each k of kvecs [nk][3], from the elements' own
    coordinates (any k, not only those that fit a box). On a lattice its
    eigenpairs are the Bloch branches (omega_h^2 and polarisations); on a
    mixture of cell patterns they are the plane wave's Rayleigh quotients
    (checked against the simulation by t613). Returns [nk][3][3]."""
    kvecs = np.asarray(kvecs, float)
    D = np.zeros((len(kvecs), 3, 3))
    mass = 0.0
    for s in range(0, len(tets), chunk):
        x = xyz[tets[s:s + chunk]]
        g, V = _gradients(x)
        Kl = np.einsum("e,eai,ebj->eaibj", V, g, g)
        gg = np.einsum("e,eak,ebk->eab", V, g, g)
        Ke = lam * Kl + mu * (np.transpose(Kl, (0, 1, 4, 3, 2)) + np.einsum("eab,ij->eaibj", gg, np.eye(3)))
        dx = x[:, None, :, :] - x[:, :, None, :]  # [e][a][b][3]: x_b - x_a
        c = np.cos(np.einsum("eabc,kc->keab", dx, kvecs))
        D += np.einsum("keab,eaibj->kij", c, Ke)
        mass += rho * V.sum()
    return D / mass


def lame(E, nu):
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def critical_step(K, m):
    """2 / sqrt(lambda_max(M^-1 K)): the exact stable step of central differences."""
    s = 1 / np.sqrt(m)
    A = scipy.sparse.diags(s) @ K @ scipy.sparse.diags(s)
    top = scipy.sparse.linalg.eigsh(A, k=1, which="LA", tol=1e-8, return_eigenvectors=False)[0]
    return 2 / math.sqrt(top)


def peak_frequency(q, dt):
    """The angular frequency of the largest peak of |FFT(q)| (Hann window,
    16x zero padding, a parabola through the three largest bins)."""
    n = len(q)
    pad = 16 * (1 << int(math.ceil(math.log2(n))))
    spec = np.abs(np.fft.rfft((q - q.mean()) * np.hanning(n), pad))
    j = int(np.argmax(spec[1:-1])) + 1
    a, b, c = np.log(spec[j - 1:j + 2] + 1e-300)
    shift = 0.5 * (a - c) / (a - 2 * b + c) if a - 2 * b + c != 0 else 0.0
    return 2 * math.pi * (j + shift) / (pad * dt)


def run_waves(K, m, pos, waves, dt, periods, speeds):
    """Central differences from u0 = p cos(k.x) for every wave (k, p) at once,
    each for `periods` periods of the exact wave (speeds: the exact speed of
    each wave's branch); returns each wave's measured angular frequency. The
    columns are ordered by length, so a finished wave leaves the product."""
    ncls = len(pos)
    need = [int(math.ceil(periods * 2 * math.pi / (s * np.linalg.norm(k)) / dt)) for (k, _), s in zip(waves, speeds)]
    order = np.argsort(need)[::-1]
    U = np.zeros((3 * ncls, len(waves)))
    W = np.zeros_like(U)
    for col, r in enumerate(order):
        k, p = waves[r]
        c = np.cos(pos @ np.asarray(k, float))
        for i in range(3):
            U[i::3, col] = p[i] * c
            W[i::3, col] = m[i::3] * p[i] * c / m[i::3].sum()
    steps = max(need)
    q = np.zeros((steps + 1, len(waves)))
    minv = (dt * dt / m)[:, None]
    Uold = U.copy()
    U = U - 0.5 * minv * (K @ U)
    q[0], q[1] = np.einsum("ir,ir->r", W, Uold), np.einsum("ir,ir->r", W, U)
    active = len(waves)
    for n in range(2, steps + 1):
        while need[order[active - 1]] < n:
            active -= 1
        a = slice(0, active)
        new = 2 * U[:, a] - Uold[:, a] - minv * (K @ U[:, a])
        Uold[:, a] = U[:, a]
        U[:, a] = new
        q[n, a] = np.einsum("ir,ir->r", W[:, a], U[:, a])
    omega = np.empty(len(waves))
    for col, r in enumerate(order):
        omega[r] = peak_frequency(q[:need[r] + 1, col], dt)
    return omega


def errors(omega, k, speed, dt):
    """(fully discrete, semi-discrete) phase-speed errors of a measured omega."""
    kk = np.linalg.norm(k)
    space = 2 * math.sin(omega * dt / 2) / dt
    return omega / (speed * kk) - 1, space / (speed * kk) - 1


def main(argv):
    mesh, spec_path, out = argv
    with open(spec_path) as f:
        spec = json.load(f)
    order = spec.get("order", 1)
    xyz, tets = read_msh(mesh, order)
    Kl, Km, m, pos = assemble(xyz, tets, spec["box"])
    lam, mu = lame(spec["E"], spec["nu"])
    K = (lam * Kl + mu * Km).tocsr()
    m = spec["rho"] * m
    cp, cs = math.sqrt((lam + 2 * mu) / spec["rho"]), math.sqrt(mu / spec["rho"])
    waves = [(w["k"], np.asarray(w["pol"], float) / np.linalg.norm(w["pol"])) for w in spec["waves"]]
    speeds = [cp if abs(np.dot(np.asarray(k) / np.linalg.norm(k), p)) > 0.5 else cs for k, p in waves]
    omega = run_waves(K, m, pos, waves, spec["dt"], spec.get("periods", 20), speeds)
    res = {}
    for w, om, (k, _), s in zip(spec["waves"], omega, waves, speeds):
        e, sp = errors(om, k, s, spec["dt"])
        res[w["name"]] = {"error": e, "space": sp, "omega": om}
    with open(out, "w") as f:
        json.dump({"waves": res, "dt_critical": critical_step(K, m)}, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[1:])
