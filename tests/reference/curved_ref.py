"""Independent reference for dtmap on curved second-order meshes (issue 21):
element by element and on the assembled system, with a converged
quadrature, written with numpy/scipy and sharing no code with dtmap.

Meshes (made here with Gmsh's Python API at order 2, size as given):
  disc      a disc of radius 1, tri6 (plane strain)
  holed     a 2 x 1 plate with a hole of radius 0.3, tri6
  sphere    a ball of radius 1, tet10
  cylinder  a cylinder of radius 0.5 and height 1, tet10
each also with Gmsh's high-order optimisation ("-opt" variants) when
--optimised is given.

Reference: shape functions of tri6 and tet10 in Gmsh's node order,
Gauss-Legendre points collapsed onto the simplex (Duffy), the level raised
two points at a time until the element's largest eigenvalue moves by less
than 1e-10 relative; HRZ lumping (diagonal of the consistent mass scaled
to the element's measure); element step 2/sqrt(lambda_max(K, M)) by
scipy.linalg.eigh; the assembled M^-1/2 K M^-1/2 by scipy.sparse.linalg.eigsh
(tolerance 1e-12). dtmap is run with --posterior; its per-element dt view
and its global estimate (report dt.global, on the safe side) are compared.

Usage: curved_ref.py DTMAP [--optimised] [--size-2d H] [--size-3d H]
       curved_ref.py DTMAP --msh A.msh [B.msh ...]   (existing order-2 meshes)
Prints one line per mesh: elements, curved count, max relative element
step difference, and dtmap's global estimate over the reference's exact
step. Exits 1 when an element differs by more than 1e-6 or the global
ratio is above 1 or below 1 - 1e-4.
"""

import json
import os
import subprocess
import sys
import tempfile

import gmsh
import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

E, NU, RHO = 210e9, 0.3, 7850.0

TRI_EDGES = [(0, 1), (1, 2), (2, 0)]
TET_EDGES = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]


def shapes(d, p):
    """N[nq, nn] and dN[nq, nn, d] of tri6 (d = 2) or tet10 (d = 3) at
    reference points p[nq, d]."""
    lam = np.concatenate([1 - p.sum(axis=1, keepdims=True), p], axis=1)
    dl = np.vstack([-np.ones(d), np.eye(d)])
    edges = TRI_EDGES if d == 2 else TET_EDGES
    nn = d + 1 + len(edges)
    N = np.zeros((len(p), nn))
    dN = np.zeros((len(p), nn, d))
    for a in range(d + 1):
        N[:, a] = lam[:, a] * (2 * lam[:, a] - 1)
        dN[:, a, :] = (4 * lam[:, a] - 1)[:, None] * dl[a]
    for k, (i, j) in enumerate(edges):
        N[:, d + 1 + k] = 4 * lam[:, i] * lam[:, j]
        dN[:, d + 1 + k, :] = 4 * (lam[:, i][:, None] * dl[j] + lam[:, j][:, None] * dl[i])
    return N, dN


def collapsed(d, n):
    """Duffy-collapsed Gauss-Legendre rule with n points per direction."""
    x, w = np.polynomial.legendre.leggauss(n)
    x, w = (x + 1) / 2, w / 2
    if d == 2:
        a, b = np.meshgrid(x, x, indexing="ij")
        wa, wb = np.meshgrid(w, w, indexing="ij")
        p = np.stack([a * (1 - b), b], axis=-1).reshape(-1, 2)
        return p, (wa * wb * (1 - b)).ravel()
    a, b, c = np.meshgrid(x, x, x, indexing="ij")
    wa, wb, wc = np.meshgrid(w, w, w, indexing="ij")
    p = np.stack([a * (1 - b) * (1 - c), b * (1 - c), c], axis=-1).reshape(-1, 3)
    return p, (wa * wb * wc * (1 - b) * (1 - c) ** 2).ravel()


def lame(d):
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    return lam, E / (2 * (1 + NU))


def element(x, n):
    """Stiffness and HRZ masses of the element x[nn, d] with level n."""
    d = x.shape[1]
    p, w = collapsed(d, n)
    N, dN = shapes(d, p)
    J = np.einsum("ai,qaj->qij", x, dN)
    det = np.linalg.det(J)
    g = np.einsum("qaj,qji->qai", dN, np.linalg.inv(J))
    dv = det * w
    lam, mu = lame(d)
    nn = x.shape[0]
    K = np.einsum("q,qai,qbj->aibj", lam * dv, g, g) + np.einsum("q,qaj,qbi->aibj", mu * dv, g, g)
    K += np.einsum("q,qak,qbk,ij->aibj", mu * dv, g, g, np.eye(d))
    diag = np.einsum("q,qa->a", dv, N * N)
    m = diag * dv.sum() / diag.sum() * RHO
    return K.reshape(nn * d, nn * d), m, det.min()


def element_lambda(x):
    """Converged element eigenvalue, its K and masses."""
    d = x.shape[1]
    last = None
    for n in range(6, 40, 2):
        K, m, _ = element(x, n)
        mm = np.repeat(m, d)
        top = scipy.linalg.eigh(K, np.diag(mm), eigvals_only=True)[-1]
        if last is not None and abs(top - last) <= 1e-10 * top:
            return top, K, m
        last = top
    raise RuntimeError("no convergence")


def offset(x):
    d = x.shape[1]
    edges = TRI_EDGES if d == 2 else TET_EDGES
    return max(np.linalg.norm(x[d + 1 + k] - (x[i] + x[j]) / 2) / np.linalg.norm(x[j] - x[i])
               for k, (i, j) in enumerate(edges))


def make_mesh(name, path, size, optimised):
    gmsh.model.add(name)
    occ = gmsh.model.occ
    if name == "disc":
        occ.addDisk(0, 0, 0, 1, 1)
    elif name == "holed":
        occ.cut([(2, occ.addRectangle(0, 0, 0, 2, 1))], [(2, occ.addDisk(1, 0.5, 0, 0.3, 0.3))])
    elif name == "sphere":
        occ.addSphere(0, 0, 0, 1)
    else:
        occ.addCylinder(0, 0, 0, 0, 0, 1, 0.5)
    occ.synchronize()
    d = 2 if name in ("disc", "holed") else 3
    tags = [t for _, t in gmsh.model.getEntities(d)]
    gmsh.model.addPhysicalGroup(d, tags, 1)
    gmsh.model.setPhysicalName(d, 1, "solid")
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.mesh.generate(d)
    gmsh.model.mesh.setOrder(2)
    if optimised:
        gmsh.model.mesh.optimize("HighOrder")
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(path)
    gmsh.model.remove()
    return d


def read_elements(path, d):
    gmsh.open(path)
    types, etags, enodes = gmsh.model.mesh.getElements(d)
    ntags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = dict(zip(ntags, coords.reshape(-1, 3)))
    nn = 6 if d == 2 else 10
    out = {}
    for t, tags, nodes in zip(types, etags, enodes):
        nodes = nodes.reshape(-1, nn)
        for tag, ns in zip(tags, nodes):
            out[int(tag)] = (ns, np.array([xyz[k][:d] for k in ns]))
    gmsh.clear()
    return out


def read_view(path, name):
    gmsh.open(path)
    for tag in gmsh.view.getTags():
        idx = gmsh.view.getIndex(tag)
        if gmsh.option.getString(f"View[{idx}].Name") == name:
            _, tags, data, _, _ = gmsh.view.getModelData(tag, 0)
            vals = {int(t): v[0] for t, v in zip(tags, data)}
            gmsh.clear()
            return vals
    raise KeyError(name)


def assembled(elems, d):
    """Largest eigenvalue of M^-1/2 K M^-1/2 over the mesh, and the element
    steps."""
    index, rows, cols, vals, steps = {}, [], [], [], {}
    for tag, (nodes, x) in elems.items():
        for k in nodes:
            index.setdefault(int(k), len(index))
    mass = np.zeros(len(index) * d)
    for tag, (nodes, x) in elems.items():
        top, K, m = element_lambda(x)
        steps[tag] = 2 / np.sqrt(top)
        dofs = np.array([index[int(k)] * d + i for k in nodes for i in range(d)])
        rows.append(np.repeat(dofs, len(dofs)))
        cols.append(np.tile(dofs, len(dofs)))
        vals.append(K.ravel())
        mass[dofs] += np.repeat(m, d)
    K = scipy.sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))))
    s = scipy.sparse.diags(1 / np.sqrt(mass))
    top = scipy.sparse.linalg.eigsh(s @ K @ s, k=1, which="LA", tol=1e-12)[0][0]
    return 2 / np.sqrt(top), steps


def run_case(dtmap, name, size, optimised, tmp, given=None):
    tag = name + ("-opt" if optimised else "")
    msh = os.path.join(tmp, tag + ".msh")
    if given:  # an existing order-2 mesh (tet10, or tri6 in z = 0), every element analysed
        import shutil
        shutil.copy(given, msh)
        gmsh.open(msh)
        d = gmsh.model.getDimension()
        gmsh.clear()
    else:
        d = make_mesh(name, msh, size, optimised)
    form = "" if d == 3 else ' formulation="plane-strain"'
    scene = os.path.join(tmp, tag + ".xml")
    groups = ' default="true"' if given else ' groups="solid"'
    with open(scene, "w") as f:
        f.write(f'<dtmap-scene version="1">\n  <mesh file="{tag}.msh"/>\n'
                f'  <material name="steel"{groups} E="{E}" nu="{NU}" rho="{RHO}"/>\n'
                f"  <effects><elastic{form}/></effects>\n</dtmap-scene>\n")
    out, rep = os.path.join(tmp, tag + "-out.msh"), os.path.join(tmp, tag + ".json")
    subprocess.run([dtmap, "run", scene, "-q", "--posterior", "-o", out, "--report", rep], check=True)
    report = json.load(open(rep))
    elems = read_elements(msh, d)
    exact, steps = assembled(elems, d)
    dt = read_view(out, "dt")
    worst = max(abs(dt[t] / steps[t] - 1) for t in steps)
    curved = sum(offset(x) > 1e-9 for _, x in elems.values())
    ratio = report["dt"]["global"] / exact
    print(f"{tag:14s} {len(elems):6d} elements {curved:5d} curved  element max |rel diff| {worst:.2e}  "
          f"global/exact {ratio:.8f}  curvature {report.get('curvature', {}).get('rule_sensitive')} rule-sensitive")
    return worst <= 1e-6 and 1 - 1e-4 <= ratio <= 1


def main():
    args = sys.argv[1:]
    if not args:
        print(__doc__)
        return 2
    dtmap = os.path.abspath(args[0])
    optimised = "--optimised" in args
    s2 = float(args[args.index("--size-2d") + 1]) if "--size-2d" in args else 0.25
    s3 = float(args[args.index("--size-3d") + 1]) if "--size-3d" in args else 0.35
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        if "--msh" in args:  # curved_ref.py DTMAP --msh A.msh [B.msh ...]
            for m in args[args.index("--msh") + 1:]:
                ok &= run_case(dtmap, os.path.splitext(os.path.basename(m))[0], 0, False, tmp, m)
            gmsh.finalize()
            return 0 if ok else 1
        for opt in ([False, True] if optimised else [False]):
            for name, size in (("disc", s2), ("holed", s2 / 2), ("sphere", s3), ("cylinder", s3 / 1.5)):
                ok &= run_case(dtmap, name, size, opt, tmp)
    gmsh.finalize()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
