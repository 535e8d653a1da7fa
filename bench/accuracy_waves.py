#!/usr/bin/python3
"""The two tables of `dtmap verify --accuracy` in docs/accuracy.md ("Proof by
simulation"): the measured phase-speed error of a plane wave against the
prediction, with the periods run and their agreement, read from each run's
`--report` (schema verifyWaveReport).

- lattices: the right-angled lattices, 1 mm cells at 600 kHz: tri3, 100 x 100
  cells cut along (1, 1), plane strain; tet4, 30^3 cubes cut into six
  tetrahedra around their (1, 1, 1) diagonal; steel;
- meshes: Gmsh's unstructured meshes of the bundled scenes at the sizes and
  frequencies of the table: the Brazilian disc (its granite hosts the wave) at
  2, 1 and 0.7 mm, recombined into quad4 at 1 mm and at order 2 at 3 mm; the
  box at 8 and 5 mm, at order 2 at 12 mm, and the box made 0.25 m wide at
  8 mm ("big box").

usage: bench/accuracy_waves.py DTMAP [lattices] [meshes]   (default: both)
Prints each table in Markdown. A benchmark, not a test (the big box takes
minutes); tests/t612-wave-meshes.py checks some of the rows.
"""

import itertools
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STEEL = '<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>'
DIRS = {"x": "1,0,0", "(0.6, 0.8)": "0.6,0.8,0", "(0.71, 0.71)": "0.7071067811865476,0.7071067811865476,0",
        "(1, 1, 1)": "1,1,1", "(0.6, 0.8, 0)": "0.6,0.8,0"}


def write_msh(path, dim, nodes, elements):
    """A msh 2.2 file: nodes [(x, y, z)], elements [node indices from 1] of one type, group 'block'."""
    etype = {2: 2, 3: 4}[dim]
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "1", '%d 1 "block"' % dim,
             "$EndPhysicalNames", "$Nodes", str(len(nodes))]
    lines += ["%d %r %r %r" % (k + 1, *p) for k, p in enumerate(nodes)]
    lines += ["$EndNodes", "$Elements", str(len(elements))]
    lines += ["%d %d 2 1 1 %s" % (k + 1, etype, " ".join(map(str, e))) for k, e in enumerate(elements)]
    with open(path, "w") as f:
        f.write("\n".join(lines + ["$EndElements", ""]))


def tri_lattice(path, n, h):
    idx = {p: k + 1 for k, p in enumerate(itertools.product(range(n + 1), repeat=2))}
    els = []
    for i, j in itertools.product(range(n), repeat=2):
        els += [(idx[i, j], idx[i + 1, j], idx[i + 1, j + 1]), (idx[i, j], idx[i + 1, j + 1], idx[i, j + 1])]
    write_msh(path, 2, [(i * h, j * h, 0.0) for i, j in idx], els)


def tet_lattice(path, n, h):
    """Each cube cut into six tetrahedra around its (0,0,0)-(1,1,1) diagonal (Kuhn), positively oriented."""
    pts = list(itertools.product(range(n + 1), repeat=3))
    idx = {p: k + 1 for k, p in enumerate(pts)}
    els = []
    for c in itertools.product(range(n), repeat=3):
        for perm in itertools.permutations(range(3)):
            p, nodes = list(c), [idx[c]]
            for axis in perm:
                p[axis] += 1
                nodes.append(idx[tuple(p)])
            a, b, d, e = nodes
            els.append((a, b, d, e) if volume(pts, a, b, d, e) > 0 else (a, d, b, e))
    write_msh(path, 3, [(i * h, j * h, k * h) for i, j, k in pts], els)


def volume(pts, a, b, d, e):
    """Six times the signed volume of tetrahedron (a, b, d, e) (node numbers from 1)."""
    p = [pts[v - 1] for v in (a, b, d, e)]
    u, v, w = ([p[i][k] - p[0][k] for k in range(3)] for i in (1, 2, 3))
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])


def mesh_scene(work, name, msh, formulation):
    path = os.path.join(work, name + ".xml")
    with open(path, "w") as f:
        f.write('<dtmap-scene version="1">\n  <mesh file="%s"/>\n  %s\n  <effects><elastic formulation="%s"/>'
                '</effects>\n  <time safety="0.9"/>\n</dtmap-scene>\n' % (msh, STEEL, formulation))
    return path


def bundled(work, name, size, order=1, geo_edit=None):
    """The bundled scene name with <meshing size> and order changed (and its .geo edited)."""
    geo = os.path.join(work, "%s_%g_%d.geo" % (name, size, order))
    with open(os.path.join(ROOT, "geometries", name + ".geo")) as f:
        text = f.read()
    with open(geo, "w") as f:
        f.write(geo_edit(text) if geo_edit else text)
    with open(os.path.join(ROOT, "geometries", name + ".xml")) as f:
        xml = f.read()
    xml = re.sub(r'<geometry file="[^"]*"/>', '<geometry file="%s"/>' % os.path.basename(geo), xml)
    xml = re.sub(r'size="[^"]*"', 'size="%g"' % size, xml, count=1)
    xml = re.sub(r'order="[^"]*"', 'order="%d"' % order, xml)
    xml = re.sub(r'\s*<output [^>]*/>', "", xml)
    path = geo[:-4] + ".xml"
    with open(path, "w") as f:
        f.write(xml)
    return path


def verify(dtmap, scene, wave, direction, freq):
    rep = scene[:-4] + "_%s_%s.json" % (wave, direction.replace(",", "_"))
    subprocess.run([dtmap, "verify", scene, "--accuracy", "--wave", wave, "--direction", direction, "--freq",
                    repr(freq), "--report", rep, "-q"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(rep) as f:
        return json.load(f)["accuracy"]


def pct(v, digits=4):
    return "%+.*g %%" % (digits, 100 * v)


def lattices(dtmap, work):
    print("| lattice | wave | direction | predicted | measured | agreement |\n|---|---|---|---|---|---|")
    tri_lattice(os.path.join(work, "tri.msh"), 100, 1e-3)
    tet_lattice(os.path.join(work, "tet.msh"), 30, 1e-3)
    rows = [("tri3", "tri", "plane-strain", w, d) for w, d in (("P", "x"), ("S", "x"), ("P", "(0.6, 0.8)"),
                                                              ("S", "(0.6, 0.8)"), ("S", "(0.71, 0.71)"))]
    rows += [("tet4", "tet", "3d", w, d) for w, d in (("P", "x"), ("S", "x"), ("P", "(1, 1, 1)"), ("S", "(1, 1, 1)"),
                                                     ("S", "(0.6, 0.8, 0)"))]
    for label, msh, form, wave, d in rows:
        a = verify(dtmap, mesh_scene(work, msh, msh + ".msh", form), wave, DIRS[d], 6e5)
        print("| %s | %s | %s | %s | %s | %s |" % (label, wave, d, pct(a["predicted"]), pct(a["measured"]),
                                                  pct(a["agreement"], 2)))


MESHES = [  # label, scene, size, order, .geo edit, frequency, waves
    ("disc, 2 mm (tri3)", "brazilian_disc", 2e-3, 1, None, 3e5, ("P x", "P (0.6, 0.8)", "S x", "S (0.6, 0.8)")),
    ("disc, 1 mm (tri3)", "brazilian_disc", 1e-3, 1, None, 6e5, ("P x", "P (0.6, 0.8)", "S x", "S (0.6, 0.8)")),
    ("disc, 0.7 mm (tri3)", "brazilian_disc", 7e-4, 1, None, 9e5, ("P x", "P (0.6, 0.8)", "S x", "S (0.6, 0.8)")),
    ("disc_q, 1 mm (quad4)", "brazilian_disc", 1e-3, 1, lambda t: t + "\nMesh.RecombineAll = 1;\n", 6e5,
     ("P x", "P (0.6, 0.8)", "S x", "S (0.6, 0.8)")),
    ("box, 8 mm (tet4)", "box", 8e-3, 1, None, 1.5e5, ("P x", "P (1, 1, 1)")),
    ("box, 5 mm (tet4)", "box", 5e-3, 1, None, 2e5, ("P x", "P (1, 1, 1)", "S x", "S (1, 1, 1)")),
    ("big box, 8 mm (tet4)", "box", 8e-3, 1, lambda t: t.replace("L = 0.1;", "L = 0.25;"), 7.5e4,
     ("P x", "P (1, 1, 1)", "S x", "S (1, 1, 1)")),
    ("disc, 3 mm, order 2 (tri6)", "brazilian_disc", 3e-3, 2, None, 3e5, ("P x", "S x")),
    ("box, 12 mm, order 2 (tet10)", "box", 12e-3, 2, None, 1e5, ("P x", "P (1, 1, 1)")),
]


def meshes(dtmap, work):
    print("| mesh | elements in the host | f | wave, direction | periods run | predicted | measured | agreement |\n"
          "|---|---|---|---|---|---|---|---|")
    for label, name, size, order, edit, freq, waves in MESHES:
        scene = bundled(work, name, size, order, edit)
        for k, wd in enumerate(waves):
            wave, d = wd.split(" ", 1)
            a = verify(dtmap, scene, wave, DIRS[d], freq)
            agree = pct(a["agreement"], 2)
            print("| %s | %s | %s | %s, %s | %.2f | %s | %s | %s |" % (
                label if k == 0 else "", a["elements"] if k == 0 else "", ("%g kHz" % (freq / 1e3)) if k == 0 else "",
                wave, d, a["periods"], pct(a["predicted"], 3), pct(a["measured"], 3),
                "**%s**" % agree if abs(a["agreement"]) > 0.2 else agree))


def main():
    dtmap = os.path.abspath(sys.argv[1])
    which = sys.argv[2:] or ["lattices", "meshes"]
    work = tempfile.mkdtemp(prefix="dtmap-waves-")
    try:
        for w in which:
            {"lattices": lattices, "meshes": meshes}[w](dtmap, work)
            print()
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
