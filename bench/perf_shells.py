#!/usr/bin/python3
"""Benchmark (not a test) of issue 38's shell goal: the stiffened panel at
5 mm (geometries/stiffened_panel.geo, about 1.2e5 tri3 on a 60-degree
cylinder and 240 line2 on its crown) run as shells and beams against the
same mesh as membranes and trusses, by two builds of dtmap: BEFORE (main's
code) and AFTER (this branch). Prints docs/performance-shells.md (called by
bench/perf_shells.sh).

Each row is the median of REPS alternating pairs (shell run, then membrane
run, back to back, so both see the same load), of wall times; the ratio is
the median of the pairs' ratios, with their range. The stage timings are
the medians of the reports' (wall). The load average is printed before and
after. Last, both builds run each shell scene once more with ASCII output
and every view they write (element and node data: dt, nodal dt, ...) is
compared value by value: the largest relative difference is printed.

Environment: BEFORE (a dtmap binary), AFTER (a dtmap binary), BENCH_WORK
(default /tmp/dtmap-perf-shells), BENCH_REPS (default 5).
"""
import json
import os
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import perf  # noqa: E402  (bench/perf.py: its main is guarded)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORK = os.environ.get("BENCH_WORK", "/tmp/dtmap-perf-shells")
REPS = int(os.environ.get("BENCH_REPS", "5"))
BUILDS = {"before": os.environ["BEFORE"], "after": os.environ["AFTER"]}
STEEL = '<material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>'
MEMBRANE = ('<section groups="skin" kind="membrane" thickness="0.005"/>\n'
            '<section groups="stiffener" kind="truss" area="4e-4"/>')
SHELL = ('<section groups="skin" kind="shell" thickness="0.005"%s/>\n'
         '<section groups="stiffener" kind="beam" width="0.01" height="0.04" orientation="1 0 0"%s/>')
SCENES = {"membrane": MEMBRANE, "shell": SHELL % ("", ""),
          "shell_physical": SHELL % (' rotary="physical"', ' rotary="physical"')}
STAGES = ("extract", "effects", "nodal", "advice", "global")
PANEL = perf.PANEL  # the stiffened panel at 5 mm, as bench/perf.py meshes it


def load():
    return open("/proc/loadavg").read().split()[0]


def setup():
    os.makedirs(WORK, exist_ok=True)
    if not os.path.exists(os.path.join(WORK, "panel.msh")):
        subprocess.run(["/usr/bin/python3", "-c", PANEL], cwd=WORK, check=True)
    for name, body in SCENES.items():
        with open(os.path.join(WORK, name + ".xml"), "w") as f:
            f.write('<?xml version="1.0"?>\n<dtmap-scene version="1">\n<mesh file="panel.msh"/>\n%s\n%s\n'
                    '<effects><elastic/></effects>\n</dtmap-scene>\n' % (STEEL, body))


def run(build, scene, posterior, extra=()):
    """Wall time and report of one run."""
    rep = os.path.join(WORK, "%s_%s.json" % (build, scene))
    cmd = [BUILDS[build], "run", scene + ".xml", "-q", "--views-only", "-o", "%s_%s.msh" % (build, scene),
           "--report", rep] + (["--posterior", "--tol", "1e-3"] if posterior else []) + list(extra)
    t0 = time.perf_counter()
    subprocess.run(cmd, cwd=WORK, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    with open(rep) as f:
        return wall, json.load(f)


def pairs(build, scene, posterior):
    """REPS alternating pairs (scene, membrane): walls, ratios, stage medians."""
    a, b, ta, tb = [], [], {s: [] for s in STAGES}, {s: [] for s in STAGES}
    for _ in range(REPS):
        wa, ra = run(build, scene, posterior)
        wb, rb = run(build, "membrane", posterior)
        a.append(wa), b.append(wb)
        for s in STAGES:
            ta[s].append(ra["timings"].get(s, 0)), tb[s].append(rb["timings"].get(s, 0))
    ratios = [x / y for x, y in zip(a, b)]
    med = lambda v: statistics.median(v)
    return (med(a), med(b), med(ratios), min(ratios), max(ratios), {s: med(ta[s]) for s in STAGES},
            {s: med(tb[s]) for s in STAGES}, ra)


def views(path):
    """{(view name, kind): {tag: value}} of the ASCII .msh path."""
    out, lines, i = {}, open(path).read().split("\n"), 0
    while i < len(lines):
        kind = lines[i].strip()
        if kind in ("$ElementData", "$NodeData"):
            ns = int(lines[i + 1]); name = lines[i + 2].strip().strip('"')
            j = i + 2 + ns
            nr = int(lines[j]); j += nr + 1
            ni = int(lines[j]); ints = [int(v) for v in lines[j + 1:j + 1 + ni]]; j += ni + 1
            d = {}
            for k in range(ints[2]):
                f = lines[j + k].split()
                d[int(f[0])] = [float(v) for v in f[1:]]
            out[(name, kind)] = d
            i = j + ints[2]
        i += 1
    return out


def equality(scene):
    """Largest relative difference over every view value of the two builds."""
    got = {}
    for build in BUILDS:
        run(build, scene, False, ["--format", "ascii", "--top", "0"])
        got[build] = views(os.path.join(WORK, "%s_%s.msh" % (build, scene)))
    worst, n = 0.0, 0
    for key, d in got["before"].items():
        e = got["after"][key]
        for tag, vals in d.items():
            for x, y in zip(vals, e[tag]):
                n += 1
                if x != y:
                    worst = max(worst, abs(x - y) / max(abs(x), abs(y)))
    return worst, n, len(got["before"])


def main():
    setup()
    start = load()
    rows, stages, reports = [], [], {}
    for scene, label in (("shell", "scaled rotary inertia (the default)"), ("shell_physical", "physical rotary inertia")):
        for posterior in (False, True) if scene == "shell" else (False,):  # physical: Lanczos alone takes a minute
            for build in BUILDS:
                r = pairs(build, scene, posterior)
                reports[(build, scene)] = r[7]
                what = "`run --posterior --tol 1e-3`" if posterior else "`run`"
                rows.append("| %s, %s | %s | %.2f | %.2f | **%.2fx** (%.2f-%.2f) |" %
                            (label, what, build, r[0], r[1], r[2], r[3], r[4]))
                stages.append("| %s, %s | %s | %s |" % (label, what, build,
                              " | ".join("%.2f / %.2f" % (r[5][s], r[6][s]) for s in STAGES)))
    end = load()
    n = reports[("after", "shell")]["mesh"]["elements"]
    print("# Shells against membranes (issue 38)\n")
    print("The stiffened panel at 5 mm (%d elements: tri3 skin, line2 stiffener) run as shells and beams" % n)
    print("against the same mesh as membranes and trusses, by main's code (before) and this branch (after);")
    print("medians of %d alternating pairs (shell run, membrane run) of wall time, s; the ratio is the" % REPS)
    print("median of the pairs' ratios (their range in brackets). %d cores; load average %s at the start," %
          (os.cpu_count(), start))
    print("%s at the end (a shared machine: other jobs ran beside it). Goal: shells at most 2x membranes.\n" % end)
    print("| shells | build | shells (s) | membranes (s) | ratio |")
    print("|---|---|---|---|---|")
    print("\n".join(rows))
    print("\nGenerated by `bench/perf_shells.sh`.\n")
    print("Stage timings, medians of the same runs (s, wall), shells / membranes:\n")
    print("| shells | build | " + " | ".join(STAGES) + " |")
    print("|---|---|" + "---|" * len(STAGES))
    print("\n".join(stages))
    print("\nGenerated by `bench/perf_shells.sh`.\n")
    print("Equality of the maps: each shell scene run once more by both builds with ASCII output; every")
    print("value of every view (element and node data) compared:\n")
    for scene in ("shell", "shell_physical"):
        worst, nv, nviews = equality(scene)
        print("- %s: %d values in %d views, largest relative difference %.2e." % (scene, nv, nviews, worst))
    for scene in ("shell", "shell_physical"):
        sb = [s.get("rotary_inertia", {}) for s in reports[("before", scene)]["sections"]]
        sa = [s.get("rotary_inertia", {}) for s in reports[("after", scene)]["sections"]]
        for x, y in zip(sb, sa):
            print("- %s, section report: dt_physical_min %.15e / %.15e (element %s / %s), scale_max %.15g / %.15g." %
                  (scene, x["dt_physical_min"], y["dt_physical_min"], x["physical_element"], y["physical_element"],
                   x["scale_max"], y["scale_max"]))


if __name__ == "__main__":
    sys.exit(main())
