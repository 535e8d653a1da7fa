#!/usr/bin/python3
"""Benchmark (not a test): `dtmap run` from a geometry against `gmsh -3 -bin`
of the same geometry, stage by stage, before and after a change (issue 46,
item 4). Prints a markdown section (with --surfaces, also the CPU time of each
thread meshing the surfaces, Gmsh's defaults against one thread at a time;
with --msh, also perf.py's 1.2e6-tet .msh row, before and after);
with --write, it replaces the section
"## From a geometry, stage by stage: size H" of docs/performance.md (one
section per size and OMP_WAIT_POLICY, which it passes on to every side).

The case is bench/perf.py's geometry row: the unit cube box.geo meshed by
HXT on 2 threads at size H (default perf.py's 0.0158, about 1e6 tets;
`BENCH_SIZE=0.027` gives about 2e5). Each round runs Gmsh, the "before"
dtmap (DTMAP_BEFORE: a build of the code before the change, if given) and
the "after" dtmap (BUILD_DIR's), back to back under the same load, the
order rotated from one round to the next; a ratio is the median over the
rounds of dtmap's wall time over Gmsh's in the same round (range in
parentheses), a stage's time the median over the rounds.

Stages: Gmsh's meshing is what its log gives (`-v 4`: "Done meshing 1D
(Wall ...)", 2D, 3D), everything else of its run (start, reading the
.geo, writing the .msh, exit) is "the rest". dtmap's come from its report:
mesh (reading the .geo and meshing), extract (the Gmsh API's arrays into
dtmap's, the locality order, the checks, where the mesh sits on the model),
effects (the element map), nodal, advice, cost (the cost and the accuracy
measures), output (what is left of writing after the analysis: the mesh
is written on a thread of its own while the analysis computes, then the
views are appended); the rest is the wall time not in a stage (start, the
summary, the report, exit). Meshes are made in BENCH_WORK (default
/tmp/dtmap-perf, shared with bench/perf.sh).
"""
import os
import re
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import perf  # noqa: E402  (bench/perf.py's helpers; its main is guarded)

ROOT = perf.ROOT
WORK = perf.WORK
AFTER = perf.DTMAP
BEFORE = os.environ.get("DTMAP_BEFORE", "")
ROUNDS = int(os.environ.get("BENCH_ROUNDS", "3"))
SIZE = float(os.environ.get("BENCH_SIZE", str(perf.H1M)))
POLICY = os.environ.get("OMP_WAIT_POLICY", "")
HEADING = f"## From a geometry, stage by stage: size {SIZE}" + (f", OMP_WAIT_POLICY={POLICY}" if POLICY else "")
STAGES = (("mesh", "meshing (dtmap: with reading the .geo)"), ("extract", "extraction and locality order"),
          ("effects", "element map"), ("nodal", "nodal bound"), ("advice", "size suggestion and shapes"),
          ("cost", "cost and accuracy measures"), ("output", "writing left after the analysis"))


def timed_gmsh(tag):
    """Gmsh's run (wall, RSS, CPU) and its log's meshing walls {"1D": s, "2D": s, "3D": s}."""
    cmd = ["sh", "-c", f"gmsh box.geo -3 -clmax {SIZE} -algo hxt -nt 2 -bin -v 4 -o g_{tag}.msh "
                        f"> g_{tag}.log 2>&1"]
    u = perf.usage(cmd)
    with open(os.path.join(WORK, f"g_{tag}.log")) as f:
        log = f.read()
    walls = {d: float(w) for d, w in re.findall(r"Done meshing (\dD) \(Wall ([0-9.eE+-]+)s", log)}
    return u, walls


def timed_dtmap(exe, tag):
    """dtmap's run (wall, RSS, CPU) and its report's elements and timings."""
    rep = f"gs_{tag}.json"
    u = perf.usage([exe, "run", "gs.xml", "-q", "-o", f"gs_{tag}.msh", "--report", rep])
    r = perf.report(rep)
    return u, r["mesh"]["elements"], r["timings"]


def rounds():
    sides = ["gmsh"] + (["before"] if BEFORE else []) + ["after"]
    exe = {"before": BEFORE, "after": AFTER}
    res = {k: [] for k in sides}
    for i in range(ROUNDS):
        order = sides[i % len(sides):] + sides[:i % len(sides)]
        for k in order:
            res[k].append(timed_gmsh(k) if k == "gmsh" else timed_dtmap(exe[k], k))
    return res


def med(xs):
    return statistics.median(xs)


def stage_table(res):
    g = res["gmsh"]
    dt = [k for k in ("before", "after") if k in res]
    lines = ["| stage | Gmsh, s | " + " | ".join(f"dtmap {k}, s" for k in dt) + " |",
             "|---|---|" + "---|" * len(dt)]
    gm = [sum(w.values()) for _, w in g]
    g12 = [w.get("1D", 0) + w.get("2D", 0) for _, w in g]

    def dtcol(f):
        return " | ".join(f"{med([f(x) for x in res[k]]):.2f}" for k in dt)

    lines.append(f"| meshing (Gmsh: 1D + 2D + 3D of its log; dtmap: reading the .geo and meshing) | {med(gm):.2f} | "
                 + dtcol(lambda x: x[2]["mesh"]) + " |")
    lines.append(f"| of which curves and surfaces (Gmsh's log) | {med(g12):.2f} | " + " | ".join("" for _ in dt) + " |")
    for key, what in STAGES[1:]:
        lines.append(f"| {what} (`{key}`) | | " + dtcol(lambda x, key=key: x[2][key]) + " |")
    rest_g = [u[0] - m for (u, _), m in zip(g, gm)]

    def rest(x):
        return x[0][0] - sum(x[2][k] for k, _ in STAGES) - x[2].get("scene", 0)

    lines.append(f"| the rest (Gmsh: start, reading, writing the .msh, exit; dtmap: start, scene, summary, report, "
                 f"exit) | {med(rest_g):.2f} | " + dtcol(rest) + " |")
    lines.append(f"| **total, wall** | **{med([u[0] for u, _ in g]):.2f}** | "
                 + " | ".join(f"**{med([x[0][0] for x in res[k]]):.2f}**" for k in dt) + " |")
    lines.append(f"| CPU (all threads) | {med([u[2] for u, _ in g]):.2f} | " + dtcol(lambda x: x[0][2]) + " |")
    lines.append(f"| peak RSS, MB | {max(u[1] for u, _ in g):.0f} | "
                 + " | ".join(f"{max(x[0][1] for x in res[k]):.0f}" for k in dt) + " |")
    return lines


def ratios(res):
    g = [u[0] for u, _ in res["gmsh"]]
    out = []
    for k in ("before", "after"):
        if k in res:
            r = [x[0][0] / w for x, w in zip(res[k], g)]
            out.append(f"{k} **{med(r):.2f}x** ({min(r):.2f}-{max(r):.2f})")
    return out


def section(res, load0, load1, seconds):
    n = res["after"][0][1]
    env = (f"OMP_WAIT_POLICY={POLICY} " if POLICY else "") + "DTMAP_BEFORE=OLD/dtmap "
    policy = (f"every side with OMP_WAIT_POLICY={POLICY} (OpenMP threads sleep as soon as they are idle instead "
              f"of spinning: on a loaded machine a spinning thread burns the share its partner needs); "
              if POLICY else "")
    text = [HEADING, "",
            f"Generated by `bench/geometry_stages.py` (`{env}BENCH_ROUNDS={ROUNDS} BENCH_SIZE={SIZE} "
            f"bench/geometry_stages.py --write`) on {os.cpu_count()} cores ({time.strftime('%Y-%m-%d %H:%M')}), "
            f"{seconds:.0f} s; load average {load0} before, {load1} after; {policy}{ROUNDS} rounds. `dtmap run` of "
            f"box.geo, HXT on 2 threads at size {SIZE} ({n:.3g} tets), against `gmsh box.geo -3 -clmax {SIZE} -algo "
            f"hxt -nt 2 -bin`: medians over the rounds of each stage's wall time (dtmap's from its report), the peak "
            f"RSS the largest.", ""]
    text += stage_table(res)
    text += ["", "Whole run, dtmap over Gmsh in the same round (median, range): " + "; ".join(ratios(res)) + ".", ""]
    return "\n".join(text) + "\n"


def write_doc(text):
    path = os.path.join(ROOT, "docs", "performance.md")
    with open(path) as f:
        doc = f.read()
    start = doc.find(HEADING)
    if start < 0:
        doc = doc.rstrip("\n") + "\n\n" + text
    else:
        end = doc.find("\n## ", start + len(HEADING))
        doc = doc[:start] + text + (doc[end + 1:] if end >= 0 else "")
    with open(path + ".tmp", "w") as f:
        f.write(doc)
    os.replace(path + ".tmp", path)


SURFACES = """
import gmsh, os, sys
gmsh.initialize(["surfaces", "-v", "0"])
gmsh.open("box.geo")
gmsh.option.setNumber("Mesh.MeshSizeMax", %g)
gmsh.option.setNumber("General.NumThreads", 2)
if int(sys.argv[1]):
    gmsh.option.setNumber("Mesh.MaxNumThreads1D", 1)
    gmsh.option.setNumber("Mesh.MaxNumThreads2D", 1)
gmsh.model.mesh.generate(1)
def cpu():
    out = {}
    for t in os.listdir("/proc/self/task"):
        f = open("/proc/self/task/%%s/stat" %% t).read().split(")")[1].split()
        out[t] = (int(f[11]) + int(f[12])) / os.sysconf("SC_CLK_TCK")
    return out
a = cpu()
gmsh.model.mesh.generate(2)
b = cpu()
print(" + ".join("%%.2f" %% (b[k] - a.get(k, 0)) for k in sorted(b) if b[k] - a.get(k, 0) > 0.005))
"""


def surfaces():
    """The CPU time of each thread meshing the surfaces (Gmsh's Python API, /proc): with
    Gmsh's defaults on 2 threads (what `gmsh -nt 2` does) and one at a time (what dtmap
    did before issue 46)."""
    out = []
    for serial in (0, 1):
        p = subprocess.run(["/usr/bin/python3", "-c", SURFACES % SIZE, str(serial)], cwd=WORK, check=True,
                           capture_output=True, text=True)
        out.append(p.stdout.strip())
    return (f"Surfaces of box.geo at size {SIZE}, CPU seconds per thread: {out[0]} with Gmsh's defaults on 2 "
            f"threads (`gmsh -nt 2`), {out[1]} one at a time (Mesh.MaxNumThreads2D = 1, dtmap before issue 46).")


def msh_row():
    """perf.py's 1.2e6-tet .msh row (box_1m.msh, made as bench/perf.py makes it) in ROUNDS rounds of
    `gmsh box_1m.msh -0 -bin`, before, after: the medians of dtmap's ratios to Gmsh (range)."""
    if not perf.exists("box_1m.msh"):
        perf.run(["gmsh", "box.geo", "-3", "-clmax", str(perf.H1M), "-o", "box_1m.msh"])
    perf.scene("msh1m.xml", '<mesh file="box_1m.msh"/>')
    exe = {"before": BEFORE, "after": AFTER}
    sides = [k for k in ("before", "after") if exe[k]]
    load0, walls = perf.load(), {k: [] for k in ["gmsh"] + sides}
    for _ in range(ROUNDS):
        walls["gmsh"].append(perf.usage(["gmsh", "box_1m.msh", "-0", "-bin", "-o", "gm1.msh"])[0])
        for k in sides:
            walls[k].append(perf.usage([exe[k], "run", "msh1m.xml", "-q", "-o", f"m1_{k}.msh"])[0])
    parts = []
    for k in sides:
        r = [w / g for w, g in zip(walls[k], walls["gmsh"])]
        parts.append(f"{k} **{med(r):.2f}x** ({min(r):.2f}-{max(r):.2f}), best {min(walls[k]):.2f} s")
    return (f"The 1.2e6-tet .msh row (`dtmap run` of perf.py's box_1m.msh against `gmsh box_1m.msh -0 -bin`, best "
            f"{min(walls['gmsh']):.2f} s; {ROUNDS} rounds, load average {load0} before, {perf.load()} after): "
            + "; ".join(parts) + ".")


def main():
    os.makedirs(WORK, exist_ok=True)
    perf.write("box.geo", 'SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 1, 1, 1};\nPhysical Volume("block") = {1};\n')
    perf.scene("gs.xml", '<geometry file="box.geo"/>', f'<meshing size="{SIZE}" algorithm="hxt" threads="2"/>')
    load0, t0 = perf.load(), time.time()
    res = rounds()
    text = section(res, load0, perf.load(), time.time() - t0)
    if "--msh" in sys.argv:
        text += "\n" + msh_row() + "\n"
    if "--surfaces" in sys.argv:
        text += "\n" + surfaces() + "\n"
    print(text)
    if "--write" in sys.argv:
        write_doc(text)


if __name__ == "__main__":
    main()
