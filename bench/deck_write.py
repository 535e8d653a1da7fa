#!/usr/bin/python3
"""The cost of writing a deck (docs/deck.md, "Speed"): a box of about 1e6
tetrahedra (Gmsh's HXT), written by `dtmap deck` for each solver (the
report's deck.seconds: planning the parts and sets, the solver's own
estimate over every element and the file; not the analysis before it) and
by Gmsh's own INP export of the same mesh (gmsh.write to .inp after
gmsh.open, timed around the write alone), alternately, REPS times each; the
medians of the wall times, and Gmsh's CPU time, with the file sizes. The
machine may be shared: compare the medians, and the CPU column for Gmsh.

Usage: /usr/bin/python3 bench/deck_write.py DTMAP [--size 0.00155] [--reps 3] [--keep DIR]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import gmsh

SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
  <mesh file="box.msh"/>
  <material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic/></effects>
  <time duration="1e-4"/>
</dtmap-scene>
"""


def make_box(path, size):
    gmsh.initialize(["deck_write", "-v", "0"])
    gmsh.model.occ.addBox(0, 0, 0, 0.1, 0.1, 0.1)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(3, [1], 1)
    gmsh.model.setPhysicalName(3, 1, "block")
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.Algorithm3D", 10)
    gmsh.option.setNumber("General.NumThreads", 2)
    gmsh.model.mesh.generate(3)
    n = len(gmsh.model.mesh.getElementsByType(4)[0])
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(path)
    gmsh.finalize()
    return n


GMSH_WRITE = """
import gmsh, sys, time
gmsh.initialize(["w", "-v", "0"])
gmsh.open(sys.argv[1])
gmsh.option.setNumber("Mesh.SaveGroupsOfElements", 1)
gmsh.option.setNumber("Mesh.SaveGroupsOfNodes", 1)
c0, w0 = time.process_time(), time.perf_counter()
gmsh.write(sys.argv[2])
print(time.perf_counter() - w0, time.process_time() - c0)
gmsh.finalize()
"""


def gmsh_inp(msh, out):
    p = subprocess.run([sys.executable, "-c", GMSH_WRITE, msh, out], check=True, stdout=subprocess.PIPE,
                       universal_newlines=True)
    wall, cpu = (float(x) for x in p.stdout.split())
    return wall, cpu


def dtmap_deck(dtmap, scene, solver, out, rep):
    subprocess.run([dtmap, "deck", scene, "--solver", solver, "-o", out, "--report", rep, "-q", "-j", "1"], check=True)
    with open(rep) as f:
        return json.load(f)["deck"]["seconds"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dtmap")
    ap.add_argument("--size", type=float, default=0.00155)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--keep")
    a = ap.parse_args()
    tmp = a.keep or tempfile.mkdtemp(prefix="dtmap-deck-write-")
    msh, scene = os.path.join(tmp, "box.msh"), os.path.join(tmp, "box.xml")
    n = make_box(msh, a.size) if not os.path.exists(msh) else None
    with open(scene, "w") as f:
        f.write(SCENE)
    times = {k: [] for k in ("gmsh", "gmsh_cpu", "calculix", "abaqus", "lsdyna")}
    files = {}
    for _ in range(a.reps):
        for solver in ("calculix", "abaqus", "lsdyna"):
            files[solver] = os.path.join(tmp, "deck_" + solver + (".k" if solver == "lsdyna" else ".inp"))
            times[solver].append(dtmap_deck(os.path.abspath(a.dtmap), scene, solver, files[solver],
                                            os.path.join(tmp, solver + ".json")))
            files["gmsh"] = os.path.join(tmp, "gmsh.inp")
            wall, cpu = gmsh_inp(msh, files["gmsh"])
            times["gmsh"].append(wall), times["gmsh_cpu"].append(cpu)
    med = {k: statistics.median(v) for k, v in times.items()}
    print("box of %s tetrahedra (%s), %d repetitions, medians" % (n or "(kept)", msh, a.reps))
    print("| writer | wall, s | over Gmsh's | file, MB |")
    print("|---|---|---|---|")
    print("| Gmsh 4.8.4, `gmsh.write(x.inp)` (CPU %.2f s) | %.2f | 1.00 | %.0f |" % (
        med["gmsh_cpu"], med["gmsh"], os.path.getsize(files["gmsh"]) / 1e6))
    for solver in ("calculix", "abaqus", "lsdyna"):
        print("| `dtmap deck --solver %s` | %.2f | %.2f | %.0f |" % (
            solver, med[solver], med[solver] / med["gmsh"], os.path.getsize(files[solver]) / 1e6))
    return 0


if __name__ == "__main__":
    sys.exit(main())
