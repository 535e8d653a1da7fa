"""What the converged integration of curved second-order elements costs
(issue 21): a ball of radius 1 meshed by Gmsh at order 2 (tet10; the
elements along the sphere are curved, the interior ones straight-sided)
with about TARGET elements, run by `dtmap run --posterior` with
<elastic integration="converged"> (the default) and "full" (the full
rules everywhere: the cost before issue 21), alternating, REPS times each.
Prints a markdown table of the medians: wall time, the report's stage
timings (effects: the element map, which also measures curvature; global:
operator set-up + Lanczos) and the curvature counts. A benchmark, not a
test. Usage: curved_cost.py DTMAP WORKDIR [TARGET] [REPS]"""

import json
import os
import statistics
import subprocess
import sys
import time

import gmsh


def mesh(path, target):
    if os.path.exists(path):
        return
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.occ.addSphere(0, 0, 0, 1)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(3, [1], 1)
    gmsh.model.setPhysicalName(3, 1, "solid")
    h = (4.19 / (target / 5.5)) ** (1 / 3) * 1.2  # ~5.5 tets per h^3 cell (Delaunay)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(2)
    gmsh.write(path)
    gmsh.finalize()


def run(dtmap, work, model):
    scene = os.path.join(work, f"ball-{model}.xml")
    with open(scene, "w") as f:
        f.write('<dtmap-scene version="1">\n  <mesh file="ball.msh"/>\n'
                '  <material name="steel" groups="solid" E="210e9" nu="0.3" rho="7850"/>\n'
                f'  <effects><elastic integration="{model}"/></effects>\n</dtmap-scene>\n')
    rep = os.path.join(work, f"ball-{model}.json")
    t0 = time.time()
    subprocess.run([dtmap, "run", scene, "-q", "--posterior", "--report", rep, "--views-only", "-o",
                    os.path.join(work, f"ball-{model}-out.msh")], check=True, stderr=subprocess.DEVNULL)
    wall = time.time() - t0
    r = json.load(open(rep))
    return wall, r["timings"]["effects"], r["timings"]["global"], r


def main():
    dtmap, work = os.path.abspath(sys.argv[1]), sys.argv[2]
    target = float(sys.argv[3]) if len(sys.argv) > 3 else 2e5
    reps = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    os.makedirs(work, exist_ok=True)
    mesh(os.path.join(work, "ball.msh"), target)
    res = {"converged": [], "full": []}
    for _ in range(reps):
        for m in res:
            res[m].append(run(dtmap, work, m))
    r = res["converged"][0][3]
    c = r["curvature"]
    print(f"Ball, {r['mesh']['elements']} tet10, {c['curved']} curved "
          f"({c['rule_sensitive']} rule sensitive, max step change {c['max_rule_dependence']:.2g}); "
          f"{r['timings']['threads']} threads, medians of {reps} runs.\n")
    print("| integration | wall, s | effects, s | global, s | dt global, s |")
    print("|---|---|---|---|---|")
    for m, rows in res.items():
        med = [statistics.median(x[i] for x in rows) for i in range(3)]
        print(f"| {m} | {med[0]:.2f} | {med[1]:.2f} | {med[2]:.2f} | {rows[0][3]['dt']['global']:.6e} |")


if __name__ == "__main__":
    main()
