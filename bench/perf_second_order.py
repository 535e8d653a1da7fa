#!/usr/bin/python3
"""Benchmark (not a test): second-order tetrahedra, written as
docs/performance-second-order.md by bench/perf_second_order.sh.

Rows (issue 38's goals):
- tet10 read from a binary .msh (a unit box by Gmsh's Delaunay, second
  order, about 1e5 and 1e6 tet10): `dtmap run` against `gmsh X.msh -0 -bin`
  (Gmsh's own read + write of the same file), goal at most 3x;
- a ball of curved tet10 (second-order nodes on the sphere) against its
  straight-sided twin (the same elements, Mesh.SecondOrderLinear = 1), goal
  at most 1.5x.
Each ratio is the median of REPS alternating pairs (each pair back to back,
under the same load), with its range; a time is the best of the REPS. The
report's stage timings (wall, 2 threads) of the best run give the element
map's cost per element (`effects` stage) and the extraction's per node.
With DTMAP_BEFORE naming another build's dtmap (main's, say), every row
runs for it too, in the same alternation, so before and after share the
load. The load average is recorded before and after.

The rows' functions (meshes, rows_msh, rows_curved) are importable, so
bench/perf.py can reuse them.
"""
import json
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import perf  # noqa: E402  (bench/perf.py: its main is guarded)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.environ.get("BUILD_DIR", os.path.join(ROOT, "build-bench"))
DTMAP = os.path.join(BUILD, "dtmap")
BEFORE = os.environ.get("DTMAP_BEFORE", "")
BEFORE_NAME = os.environ.get("DTMAP_BEFORE_NAME", "another build (DTMAP_BEFORE)")  # what `before` is, in words
WORK = os.environ.get("BENCH_WORK", "/tmp/dtmap-perf-second-order")
REPS = int(os.environ.get("BENCH_REPS", "5"))
SIZES = [float(s) for s in os.environ.get("BENCH_SIZES", "1e5 1e6").split()]
BALL = float(os.environ.get("BENCH_BALL", "1e5"))  # curved ball, tet10
STEEL = 'E="210e9" nu="0.3" rho="7850"'
H_PER_TET = 0.045 / (55954 ** (-1 / 3))  # the box's Delaunay: 55,954 tet10 at size 0.045


def run(cmd, cwd=None):
    """(wall s, CPU s of the child and its children)."""
    t, _, cpu, _, _ = perf.usage(cmd, cwd=cwd or WORK)
    return t, cpu


def load():
    with open("/proc/loadavg") as f:
        return f.read().split()[0]


def write(name, text):
    with open(os.path.join(WORK, name), "w") as f:
        f.write(text)


def scene(name, mesh):
    write(name, f'<?xml version="1.0"?>\n<dtmap-scene version="1">\n<mesh file="{mesh}"/>\n'
                f'<material name="steel" groups="block" {STEEL}/>\n<effects><elastic/></effects>\n'
                '</dtmap-scene>\n')


BALLS = """
import gmsh
gmsh.initialize(["perf", "-v", "0"])
gmsh.model.occ.addSphere(0, 0, 0, 1)
gmsh.model.occ.synchronize()
gmsh.model.addPhysicalGroup(3, [1], 1)
gmsh.model.setPhysicalName(3, 1, "block")
h = (4.19 / (%g / 5.5)) ** (1 / 3) * 1.2
for k, v in (("MeshSizeMax", h), ("MeshSizeMin", h), ("MeshSizeFromCurvature", 0)):
    gmsh.option.setNumber("Mesh." + k, v)
gmsh.model.mesh.generate(3)
gmsh.option.setNumber("Mesh.Binary", 1)
gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)
gmsh.model.mesh.setOrder(2)
gmsh.write("%s")
gmsh.model.mesh.setOrder(1)
gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)
gmsh.model.mesh.setOrder(2)
gmsh.write("%s")
gmsh.finalize()
"""


def box_name(n):
    return f"box10_{n:.0e}.msh".replace("+0", "")


def meshes():
    os.makedirs(WORK, exist_ok=True)
    write("box.geo", 'SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 1, 1, 1};\nPhysical Volume("block") = {1};\n')
    for n in SIZES:
        name = box_name(n)
        if not os.path.exists(os.path.join(WORK, name)):
            h = H_PER_TET * n ** (-1 / 3)
            run(["gmsh", "box.geo", "-3", "-order", "2", "-clmax", f"{h:.5g}", "-bin", "-o", name])
        scene(name.replace(".msh", ".xml"), name)
    curved, straight = f"ball10_{BALL:.0e}_curved.msh", f"ball10_{BALL:.0e}_straight.msh"
    if not os.path.exists(os.path.join(WORK, curved)):
        subprocess.run(["/usr/bin/python3", "-c", BALLS % (BALL, straight, curved)], cwd=WORK, check=True)
    scene("ball_curved.xml", curved)
    scene("ball_straight.xml", straight)


def binaries():
    """(label, dtmap) of the builds measured: before (if given), after."""
    return ([("before", BEFORE)] if BEFORE else []) + [("after", DTMAP)]


def report(name):
    with open(os.path.join(WORK, name)) as f:
        return json.load(f)


def alternate(cmds):
    """Run the commands cmds {key: argv} in turn, REPS times: {key: [(wall, CPU, i)]}."""
    out = {k: [] for k in cmds}
    for i in range(REPS):
        for k, c in cmds.items():
            out[k].append(run(c) + (i,))
    return out


def stages(rep, n, nodes):
    t = rep["timings"]
    return {"effects": t["effects"], "extract": t["extract"], "us_elem": 1e6 * t["effects"] / n,
            "us_node": 1e6 * t["extract"] / nodes, "threads": t.get("threads", 0)}


def rows_msh():
    """tet10 from .msh against gmsh -0 -bin: rows of the table."""
    rows = []
    for n in SIZES:
        name = box_name(n)
        xml = name.replace(".msh", ".xml")
        cmds = {"gmsh": ["gmsh", name, "-0", "-bin", "-o", "g.msh"]}
        for label, exe in binaries():
            # binary, as its counterpart (`-bin`): below 1e5 elements dtmap's default output is ASCII
            cmds[label] = [exe, "run", xml, "-q", "--format", "binary", "-o", f"o_{label}.msh", "--report",
                           f"r_{label}.json"]
        la = load()
        res = alternate(cmds)
        lb = load()
        g = res["gmsh"]
        for label, _ in binaries():
            d = res[label]
            ratios = [x[0] / y[0] for x, y in zip(d, g)]
            cpu = statistics.median(x[1] / y[1] for x, y in zip(d, g))
            r = report(f"r_{label}.json")
            st = stages(r, r["mesh"]["elements"], r["mesh"]["nodes"])
            rows.append(f"| tet10 box, {r['mesh']['elements']:,} elements, {label} | {min(x[0] for x in d):.2f} "
                        f"({min(x[1] for x in d):.2f}) | {min(x[0] for x in g):.2f} ({min(x[1] for x in g):.2f}) | "
                        f"**{statistics.median(ratios):.2f}x** ({min(ratios):.2f}-{max(ratios):.2f}); CPU {cpu:.2f}x | "
                        f"{st['effects']:.2f} s = {st['us_elem']:.1f} us/element | {st['extract']:.2f} s = "
                        f"{st['us_node']:.2f} us/node | {la} / {lb} | <= 3x |")
    return rows


def rows_curved():
    """Curved tet10 against the straight-sided twin: rows of the table."""
    rows = []
    cmds = {}
    for label, exe in binaries():
        cmds[label + " curved"] = [exe, "run", "ball_curved.xml", "-q", "-o", f"bc_{label}.msh", "--report",
                                   f"bc_{label}.json"]
        cmds[label + " straight"] = [exe, "run", "ball_straight.xml", "-q", "-o", f"bs_{label}.msh", "--report",
                                     f"bs_{label}.json"]
    la = load()
    res = alternate(cmds)
    lb = load()
    for label, _ in binaries():
        c, s = res[label + " curved"], res[label + " straight"]
        ratios = [x[0] / y[0] for x, y in zip(c, s)]
        cpu = statistics.median(x[1] / y[1] for x, y in zip(c, s))
        rc, rs = report(f"bc_{label}.json"), report(f"bs_{label}.json")
        n = rc["mesh"]["elements"]
        ec, es = rc["timings"]["effects"], rs["timings"]["effects"]
        rows.append(f"| curved ball, {n:,} tet10 ({rc['curvature']['curved']:,} curved), {label} | "
                    f"{min(x[0] for x in c):.2f} ({min(x[1] for x in c):.2f}) | {min(x[0] for x in s):.2f} "
                    f"({min(x[1] for x in s):.2f}) | **{statistics.median(ratios):.2f}x** ({min(ratios):.2f}-"
                    f"{max(ratios):.2f}); CPU {cpu:.2f}x | {ec:.2f} / {es:.2f} s = {1e6 * ec / n:.1f} / {1e6 * es / n:.1f} "
                    f"us/element | {la} / {lb} | <= 1.5x |")
    return rows


def main():
    meshes()
    start = load()
    msh = rows_msh()
    curved = rows_curved()
    cpu = os.cpu_count()
    print("# Performance of second-order tetrahedra\n")
    print("Generated by `bench/perf_second_order.sh` (bench/perf_second_order.py): issue 38's rows for tet10, "
          "apart from the full docs/performance.md run (30-60 minutes).\n")
    print(f"Machine: {cpu} cores, shared: the load average (1 minute) is given before / after each group of "
          f"rows (it was {start} at the start). Wall seconds, with CPU seconds (user + system) in brackets, "
          f"best of {REPS}; ratios are the median of {REPS} alternating pairs with their range, then the median "
          "of the pairs' CPU ratios (the steadier one on a loaded machine). "
          f"`before` is {BEFORE_NAME}, `after` this branch's, measured in the same "
          "alternation. Stage times are the report's (wall, 2 threads) of the last run.\n")
    print("## tet10 read from a binary .msh against Gmsh's read + write (`gmsh X.msh -0 -bin`)\n")
    print("dtmap writes binary here too (`--format binary`): below 1e5 elements its default is ASCII, which "
          "would compare its text output with Gmsh's binary one (the curved rows below compare dtmap with "
          "itself, both in the default format).\n")
    print("| mesh, build | dtmap run (s) | gmsh -0 -bin (s) | ratio | element map (`effects`) | extraction "
          "(`extract`) | load | goal |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(msh))
    print("\n## Curved tet10 against the straight-sided twin (`Mesh.SecondOrderLinear = 1`)\n")
    print("| mesh, build | curved (s) | straight (s) | ratio | element map curved / straight | load | goal |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(curved))
    print(f"\nMeasured by `bench/perf_second_order.sh`; load average at the end {load()}.")


if __name__ == "__main__":
    main()
