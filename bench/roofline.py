#!/usr/bin/python3
"""Benchmark (not a test): the roofline table of the element kernels
(issue 46), written by bench/roofline.sh into docs/performance.md.

Runs bench_roofline (bench/roofline.c: flops per element counted from the
code, ns per element of thread CPU time, one thread, the best of many
interleaved passes, and the peak of a plain 30 x 30 matrix product compiled
with the same flags, in the same run). With ROOFLINE_BEFORE naming another
build's bench_roofline (a build of the code before a change), the two
binaries run in turn REPS times and every row keeps its best time over
each binary's runs, so before and after share the load. The load average
is recorded before and after. Prints the markdown section.
"""
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.environ.get("BUILD_DIR", os.path.join(ROOT, "build-bench"))
BEFORE_NAME = os.environ.get("ROOFLINE_BEFORE_NAME", "the code before the change")  # what before is, in words
AFTER = os.path.join(BUILD, "bench", "bench_roofline")
BEFORE = os.environ.get("ROOFLINE_BEFORE", "")
REPS = int(os.environ.get("BENCH_REPS", "3"))
ELEMENTS = os.environ.get("ROOFLINE_ELEMENTS", "400")
ROUNDS = os.environ.get("ROOFLINE_ROUNDS", "15")


def load():
    with open("/proc/loadavg") as f:
        return f.read().split()[0]


def one(exe):
    """{'peak': GFlop/s, 'peak_avx': ..., 'points': ..., rows: {(kernel, path): (flops, ns)}}."""
    out = subprocess.run([exe, ELEMENTS, ROUNDS], check=True, capture_output=True, text=True).stdout
    res = {"rows": {}}
    for line in out.splitlines():
        if line.startswith("ROW|"):
            _, k, p, flops, ns, _ = line.split("|")
            res["rows"][(k, p)] = (float(flops), float(ns))
        elif line.startswith("peak_avx "):
            res["peak_avx"] = float(line.split()[1])
        elif line.startswith("peak "):
            res["peak"] = float(line.split()[1])
        elif "rule points" in line:
            res["points"] = line.split(":")[-1].split()[0]
    return res


def best(runs):
    """Every row's best time and the best peaks over runs."""
    out = {"peak": max(r["peak"] for r in runs), "peak_avx": max(r.get("peak_avx", 0) for r in runs),
           "points": runs[0].get("points", "?"), "rows": {}}
    for r in runs:
        for key, (flops, ns) in r["rows"].items():
            old = out["rows"].get(key)
            out["rows"][key] = (flops, min(ns, old[1]) if old else ns)
    return out


def main():
    exes = ([("before", BEFORE)] if BEFORE else []) + [("after", AFTER)]
    la = load()
    runs = {label: [] for label, _ in exes}
    for _ in range(REPS):
        for label, exe in exes:
            runs[label].append(one(exe))
    lb = load()
    res = {label: best(r) for label, r in runs.items()}
    peak = max(r["peak"] for r in res.values())
    peak_avx = max(r["peak_avx"] for r in res.values())
    a = res["after"]
    print("## Roofline of the element kernels (`bench/roofline.sh`)\n")
    print(f"One thread, thread CPU time (the time the shared machine gives other processes is not counted), "
          f"each row the best of {REPS} runs x {ROUNDS} interleaved passes over {ELEMENTS} random elements; "
          f"load average {la} before, {lb} after ({os.cpu_count()} cores). Peak: a plain 30 x 30 matrix product "
          f"(i-k-j loops, C += A B) compiled with the kernels' flags (x86-64 baseline, SSE2) "
          f"**{peak:.2f} GFlop/s**; the same loop compiled for AVX, the lanes' instructions, "
          f"**{peak_avx:.2f} GFlop/s**. Flops per element are counted from the code (bench/roofline.c says how; "
          f"a curved tet10 here takes {a['points']} rule points on average). `before` is "
          + (f"the build named by ROOFLINE_BEFORE ({BEFORE_NAME}), `after` this one; "
             if BEFORE else "absent (no ROOFLINE_BEFORE); ")
          + "`one by one` is `dtm_kernel_elastic_lambda_at` per element, `lanes` "
          "`dtm_kernel_elastic_lambda_lanes` four at a time. The peak is that plain loop's, not the "
          "processor's: a kernel above 100 % of it schedules its work better than the loop does.\n")
    print("| kernel | path | flops / element | " + " | ".join(f"{lab}: ns / element | {lab}: GFlop/s"
                                                          for lab, _ in exes) + " | of peak (after) |")
    print("|---|---|---|" + "---|---|" * len(exes) + "---|")
    for key in a["rows"]:
        flops = a["rows"][key][0]
        cells = []
        for label, _ in exes:
            r = res[label]["rows"].get(key)
            cells.append(f"{r[1]:.0f} | {flops / r[1]:.2f}" if r else "- | -")
        roof = peak_avx if key[1] == "lanes" and peak_avx > 0 else peak
        print(f"| {key[0]} | {key[1]} | {flops:,.0f} | " + " | ".join(cells) +
              f" | {100 * flops / a['rows'][key][1] / roof:.0f}% |")
    if BEFORE:
        print("\nTime after / before, the same path (where the before build has no lanes, after's lanes "
              "against its one by one: the element map's change):\n")
        for key in a["rows"]:
            b = res["before"]["rows"].get(key)
            against = ""
            if not b and key[1] == "lanes":
                b, against = res["before"]["rows"].get((key[0], "one by one")), " (against one by one)"
            if b:
                print(f"- {key[0]}, {key[1]}: **{a['rows'][key][1] / b[1]:.2f}**{against}")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
