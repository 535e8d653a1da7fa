#!/usr/bin/python3
"""Benchmark (not a test): what the certified step costs at 1.2e6 tets
(issue 45). `dtmap run --posterior` with the default tolerance on
bench/perf.py's box_1m.msh (Gmsh's Delaunay cube, about 1.2e6 tets, made
once in BENCH_WORK), this build against another (DTMAP_BEFORE: the build
before the probable bound, whose step was Lanczos's estimate alone), in
alternating pairs, the ratio the median of the pairs with its range. Each
side's report gives its Lanczos steps, its certificate and its recommended
step, printed beside the times; the load average is recorded before and
after. Prints a markdown table for docs/performance.md.

Usage: DTMAP_BEFORE=/path/to/old/dtmap bench/perf_certified.py [PAIRS]
(BUILD_DIR: this build, default build-bench; BENCH_WORK as perf.py's).
"""
import json
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import perf  # noqa: E402  (its meshes, its timed child run)


def make_mesh():
    """perf.py's box_1m.msh and its scene, without perf.py's other meshes."""
    os.makedirs(perf.WORK, exist_ok=True)
    perf.write("box.geo", 'SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 1, 1, 1};\nPhysical Volume("block") = {1};\n')
    if not perf.exists("box_1m.msh"):
        perf.run(["gmsh", "box.geo", "-3", "-clmax", str(perf.H1M), "-o", "box_1m.msh"])
    perf.scene("msh1m.xml", '<mesh file="box_1m.msh"/>')


def one(dtmap, tag):
    """One run --posterior; its wall, CPU and report."""
    rep = f"cert_{tag}.json"
    t, rss, cpu = perf.run([dtmap, "run", "msh1m.xml", "-q", "-o", f"cert_{tag}.msh", "--views-only", "--posterior",
                            "-j", "2", "--report", rep])
    return t, cpu, rss, perf.report(rep)


def lanczos(r):
    """The first effect's Lanczos object and the recommended step."""
    return r["effect_minima"][0].get("lanczos", {}), r["dt"]["recommended"]


def main():
    pairs = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    before = os.environ.get("DTMAP_BEFORE")
    if not before:
        sys.exit("DTMAP_BEFORE must name the dtmap to compare with")
    make_mesh()
    load0 = perf.load()
    rows, ratios = [], []
    for i in range(pairs):
        a = one(perf.DTMAP, f"new{i}")
        b = one(before, f"old{i}")
        rows.append((a, b))
        ratios.append(a[0] / b[0])
    load1 = perf.load()
    new_best = min(rows, key=lambda p: p[0][0])[0]
    old_best = min(rows, key=lambda p: p[1][0])[1]
    ln, rn = lanczos(new_best[3])
    lo, ro = lanczos(old_best[3])
    print(f"| build | wall (s, best of {pairs}) | CPU (s) | peak RSS (MB) | Lanczos steps | certificate | "
          "recommended step (s) |")
    print("|---|---|---|---|---|---|---|")
    print(f"| before (Lanczos's estimate) | {old_best[0]:.2f} | {old_best[1]:.2f} | {old_best[2]:.0f} | "
          f"{lo.get('iterations')} | {lo.get('certificate')} | {ro:.6e} |")
    cert = ln.get("certificate")
    if cert == "probable":
        p = ln["probable"]
        cert = f"probable (failure {p['failure']:.0e}, eps {p['eps']:.3g}, n {p['n']})"
    print(f"| this build | {new_best[0]:.2f} | {new_best[1]:.2f} | {new_best[2]:.0f} | {ln.get('iterations')} | "
          f"{cert} | {rn:.6e} |")
    print()
    print(f"Whole `run --posterior` (1.2e6 tets, 2 threads), this build / before: median "
          f"{statistics.median(ratios):.2f}x over {pairs} alternating pairs (range {min(ratios):.2f}-"
          f"{max(ratios):.2f}); load {load0} before, {load1} after.")
    print(json.dumps({"ratios": ratios}))


if __name__ == "__main__":
    main()
