#!/usr/bin/python3
"""Benchmark (not a test): the two rows of docs/performance.md that issue 38
sets goals for at scale, run before and after a change, side by side with
Gmsh, written as docs/performance-big.md by bench/perf_big.sh.

- 1e7 tets from a binary .msh (box_10m.msh, made as bench/perf.py makes
  it): `dtmap run` against `gmsh box_10m.msh -0 -bin` (read + write);
- 1e6 tets from a geometry (box.geo, HXT on 2 threads): `dtmap run`
  against `gmsh box.geo -3 -algo hxt -nt 2 -bin`.

Each round runs Gmsh, the "before" dtmap (DTMAP_BEFORE: a build of main,
if given) and the "after" dtmap (BUILD_DIR's) back to back, under the same
load; a ratio is the median over the rounds of dtmap's wall time over
Gmsh's in the same round, with its range. Besides wall and CPU time, the
page faults (minor faults of the process and its children, which is where
the kernel zeroes the fresh pages of a new array) and the peak RSS. The
per-element cost of each stage comes from the run's report (its timings,
the run of the median ratio). Helpers, the sizes and the scenes are
bench/perf.py's.
"""
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import perf  # noqa: E402  (bench/perf.py: run only as a script, its main is guarded)

WORK = perf.WORK
AFTER = perf.DTMAP
BEFORE = os.environ.get("DTMAP_BEFORE", "")
ROUNDS = int(os.environ.get("BENCH_ROUNDS", "5"))
ROUNDS_10M = int(os.environ.get("BENCH_ROUNDS_10M", str(ROUNDS)))
STAGES = ("extract", "effects", "nodal", "advice", "cost", "measures", "output")


def run(cmd):
    """(wall s, peak RSS MB, CPU s, system s, minor faults) of cmd and its children."""
    return perf.usage(cmd)


def make_meshes():
    os.makedirs(WORK, exist_ok=True)
    perf.write("box.geo", 'SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 1, 1, 1};\nPhysical Volume("block") = {1};\n')
    if not perf.exists("box_10m.msh"):
        run(["gmsh", "box.geo", "-3", "-clmax", str(perf.H10M), "-algo", "hxt", "-nt", "2", "-bin", "-o",
             "box_10m.msh"])
    perf.scene("msh10m.xml", '<mesh file="box_10m.msh"/>')
    perf.scene("hxt1m.xml", '<geometry file="box.geo"/>', f'<meshing size="{perf.H1M}" algorithm="hxt" threads="2"/>')


def rounds(n, gmsh_cmd, dtmap_args, tag):
    """n rounds of Gmsh, before, after: {side: [results]} and the reports' timings
    {side: [timings]} (report of each dtmap run)."""
    sides = {"gmsh": gmsh_cmd}
    if BEFORE:
        sides["before"] = [BEFORE] + dtmap_args
    sides["after"] = [AFTER] + dtmap_args
    res = {k: [] for k in sides}
    tim = {k: [] for k in sides if k != "gmsh"}
    for _ in range(n):
        for k, cmd in sides.items():
            rep = f"{tag}_{k}.json"
            res[k].append(run(cmd + (["--report", rep] if k != "gmsh" else [])))
            if k != "gmsh":
                r = perf.report(rep)
                tim[k].append((r["mesh"]["elements"], r["timings"]))
    return res, tim


def median_index(ratios):
    """Index of the round whose ratio is the median (the lower middle for an even count)."""
    order = sorted(range(len(ratios)), key=lambda i: ratios[i])
    return order[(len(order) - 1) // 2]


ROWS, STAGE_ROWS = [], []


def fmt_ratio(rs):
    return f"**{statistics.median(rs):.2f}x** ({min(rs):.2f}-{max(rs):.2f})" if len(rs) > 1 else f"**{rs[0]:.2f}x**"


def record(what, res, tim, goal):
    g = res["gmsh"]
    gbest = min(x[0] for x in g)
    cells = [what, f"{gbest:.2f} ({min(x[2] for x in g):.2f})"]
    for side in ("before", "after"):
        if side not in res:
            cells += ["", "", "", ""]
            continue
        d = res[side]
        ratios = [x[0] / y[0] for x, y in zip(d, g)]
        i = median_index(ratios)
        cells += [f"{min(x[0] for x in d):.2f} ({min(x[2] for x in d):.2f}, sys {min(x[3] for x in d):.2f})",
                  fmt_ratio(ratios), f"{statistics.median(x[4] for x in d) / 1e3:.0f}k",
                  f"{max(x[1] for x in d):.0f}"]
        n, t = tim[side][i]
        STAGE_ROWS.append(f"| {what} | {side} | {n:.3g} | " +
                          " | ".join(f"{1e9 * t[k] / n:.0f}" for k in STAGES) + " |")
    cells += [f"{statistics.median(x[4] for x in g) / 1e3:.0f}k", f"{max(x[1] for x in g):.0f}", goal]
    ROWS.append("| " + " | ".join(cells) + " |")


def main():
    make_meshes()
    load0, t0 = perf.load(), time.time()
    res, tim = rounds(ROUNDS_10M, ["gmsh", "box_10m.msh", "-0", "-bin", "-o", "g10.msh"],
                      ["run", "msh10m.xml", "-q", "-o", "o10.msh"], "r10m")
    n = tim["after"][0][0]
    record(f"run from a .msh ({n:.3g} tets, binary in and out)", res, tim, "<= 2x, <= 3 GB")
    res, tim = rounds(ROUNDS, ["gmsh", "box.geo", "-3", "-clmax", str(perf.H1M), "-algo", "hxt", "-nt", "2", "-bin",
                               "-o", "gh.msh"], ["run", "hxt1m.xml", "-q", "-o", "oh.msh"], "rh")
    n = tim["after"][0][0]
    record(f"run from geometry, HXT on 2 threads ({n:.3g} tets)", res, tim, "<= 1.1x")
    load1 = perf.load()
    print("# Performance at scale: 1e7 tets and meshing, before and after\n")
    print(f"Generated by `bench/perf_big.sh` on {os.cpu_count()} cores ({time.strftime('%Y-%m-%d')}), "
          f"{time.time() - t0:.0f} s; load average {load0} before, {load1} after; {ROUNDS_10M} rounds for the "
          f"1e7 row, {ROUNDS} for the geometry row. Each round runs Gmsh, dtmap before (a build of main) and "
          f"dtmap after (this branch) back to back; a time is the best of the rounds, a ratio the median of "
          f"the rounds' ratios to Gmsh (range in parentheses), page faults the median, peak RSS the largest.\n")
    print("| what | Gmsh, s (CPU) | before, s (CPU, sys) | before / Gmsh | before faults | before RSS, MB "
          "| after, s (CPU, sys) | after / Gmsh | after faults | after RSS, MB | Gmsh faults | Gmsh RSS, MB "
          "| goal |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(ROWS))
    print("\nRegenerate with `DTMAP_BEFORE=/path/to/main/build/dtmap bench/perf_big.sh` (`bench/perf_big.py`); "
          "without DTMAP_BEFORE the before columns stay empty.\n")
    print("## Cost per element (ns), from the reports of the median rounds\n")
    print("| run | build | elements | " + " | ".join(STAGES) + " |")
    print("|---|---|---|" + "---|" * len(STAGES))
    print("\n".join(STAGE_ROWS))
    print("\nFrom the reports' timings (wall) of the runs above (`bench/perf_big.py`): extract includes the "
          "locality order; effects is the element map; cost includes measures; output is what is left of "
          "writing after the analysis (the mesh is written on a thread of its own meanwhile).")


if __name__ == "__main__":
    main()
