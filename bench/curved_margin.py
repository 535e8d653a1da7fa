"""The quadrature margin of curved tet10 meshes (docs/curved.md, issue 45):
meshes Gmsh's demo simple_geo/cone.geo (gmsh-doc) as `gmsh cone.geo -3
-order 2 -optimize_ho` and a ball of radius 1 (size 0.12, order 2) with
Gmsh's Python API in WORK, runs `dtmap run --posterior` (steel) with each
binary given, and compares its global step with the exact step of the
converged integration (tests/reference/tet10_exact.py ... converged).
Prints one table row per mesh: tet10, margin / theta of the first binary,
then global / exact per binary. A benchmark, not a test (the ball's
reference takes minutes).

Usage: /usr/bin/python3 bench/curved_margin.py WORK DTMAP [DTMAP_BEFORE ...]
"""

import json
import os
import subprocess
import sys

import gmsh

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REF = os.path.join(ROOT, "tests", "reference", "tet10_exact.py")
CONE = "/usr/share/doc/gmsh-doc/doc/gmsh/demos/simple_geo/cone.geo"


def make(work, name):
    path = os.path.join(work, name + ".msh")
    gmsh.initialize(["curved_margin", "-v", "0"])
    if name == "cone":
        gmsh.open(CONE)
        gmsh.option.setNumber("Mesh.HighOrderOptimize", 2)  # -optimize_ho
    else:
        gmsh.model.occ.addSphere(0, 0, 0, 1)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.12)
    gmsh.option.setNumber("Mesh.ElementOrder", 2)
    gmsh.model.mesh.generate(3)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(path)
    gmsh.finalize()
    with open(os.path.join(work, name + ".xml"), "w") as f:
        f.write('<dtmap-scene version="1">\n  <mesh file="%s.msh"/>\n'
                '  <material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>\n'
                '  <effects><elastic/></effects>\n</dtmap-scene>\n' % name)
    return path


def run(work, dtmap, name, i):
    rep = os.path.join(work, "%s-%d.json" % (name, i))
    subprocess.run([dtmap, "run", os.path.join(work, name + ".xml"), "-q", "--posterior", "-o",
                    os.path.join(work, "%s-%d.msh" % (name, i)), "--report", rep], check=True)
    with open(rep) as f:
        r = json.load(f)
    return r["dt"]["global"], r["effect_minima"][0]["lanczos"]


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    work, binaries = argv[1], argv[2:]
    os.makedirs(work, exist_ok=True)
    print("| mesh | tet10 | margin / theta | " + " | ".join("global / exact, %s" % b for b in binaries) + " |")
    for name in ("cone", "ball"):
        path = make(work, name)
        runs = [run(work, b, name, i) for i, b in enumerate(binaries)]
        ref = json.loads(subprocess.run([sys.executable, REF, path, "210e9", "0.3", "7850", "converged"],
                                        stdout=subprocess.PIPE, universal_newlines=True, check=True).stdout)
        lz = runs[0][1]
        cells = ["%.7f" % (g / ref["exact_step"]) for g, _ in runs]
        print("| %s | %d | %.2g | %s |" % (name, ref["elements"], lz.get("quadrature_margin", 0) / lz["theta"],
                                           " | ".join(cells)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
