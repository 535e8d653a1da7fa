#!/usr/bin/python3
"""What one element-step of Debian's CalculiX 2.20 (ccx) costs, measured on
dtmap's own CalculiX decks, one thread (OMP_NUM_THREADS=1), wall time.

Table mode (default): for each CalculiX element (C3D4, C3D10, C3D8, CPE3,
CPE4, CPE6, S3, S4) a scene of that element alone is written, `dtmap deck
--solver calculix` writes its deck, and the deck is run twice by ccx with
its *DYNAMIC period set to N1 + 1/2 and N2 + 1/2 of the increment ccx takes
(the solvers[] step of the deck's report: the smaller of ccx's own estimate
and the deck's increment). The cost per element-step is the difference of
the two wall times over elements x (N2 - N1), so reading the deck and
setting up do not count; each run is the best of --repeat. With --inc FILE
the figures are written as src/cost/ccx_cost.inc (the table dtmap reads).

The figure of an element-step depends on the mesh's size, not only on its
element: the arrays ccx allocates every increment for a large mesh pass
glibc's mmap threshold (32 MiB) and are faulted in and zeroed afresh each
increment (docs/accuracy.md), and beyond a switch every element-step costs
about twice as much (C3D4: 1.2 us per element-step up to 23,006 elements,
2.5 - 3 us from 26,618 on, the bundled notched beam's 31,313 included). So
each element is measured twice, on a mesh below the switch (CASES) and on
one several times beyond it (LARGE: 37,000 - 72,000 elements), and the
switch itself is found on C3D4 (the bundled box meshed at SWITCH_SIZES: the
largest mesh whose figure stays within 1.3x of the small one, and the next
one, whose mean element count is the switch). Other elements take C3D4's
switch in elements (not measured for them; docs/accuracy.md says so).
With --only and --inc, the rows of the elements not measured now (and the
switch, when C3D4 is not measured) are kept from the existing file.

The figures hold for the bound of integration points per element each
deck alone gave ccx (C3D4: 27): ccx sizes its per-element arrays, copied
every increment, by the bound of the whole deck (its allocation.f), which
the deck's elements set together (C3D4 with M3D3: 9). The cost per point of
that bound (CCX_POINT_NS) is measured on the C3D4 deck alone (27) and the
same deck with one M3D3 added (9): --only POINT measures it alone.

Check mode (--check): for each bundled example (geometries/*.xml) the deck
of `dtmap deck --solver calculix` is run for N2 + 1/2 increments, whole (set
up included), and its wall time is compared with what the deck's summary
predicts for those increments: the report's solvers[0].hours x 3600 x
N2 / (its element-steps / elements).

Each run is the one t371 makes (tests/common/deckutil.py: a seeded random
force at every node). Wall and CPU time (user + system) are both printed;
--cpu makes the table from CPU time, which stands for the wall time of an
idle machine when the machine is shared.

Bound mode (--bound): the reinforced block's deck as written (bound 9) and
without its M3D3 (27), the box's as written (27), with one M3D3 on three of
its nodes (9), with one free C3D6 (9) and one free C3D10 (15), each run
--repeat times (N1, N2 as the table), ccx's printed bound beside it.

Usage: /usr/bin/python3 bench/ccx_cost.py DTMAP [--inc src/cost/ccx_cost.inc] [--check] [--bound] [--cpu]
       [--n1 20] [--n2 220] [--repeat 2] [--only C3D4,S3]
Needs ccx (Debian's calculix-ccx) and Debian's python3 for the scenes.
"""
import argparse
import glob
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests", "common"))
import deckutil  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GEO = os.path.join(ROOT, "geometries")

HEX = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.1, 0.1};
Physical Volume("block") = {1};
Transfinite Curve{:} = %d; Transfinite Surface{:}; Recombine Surface{:}; Transfinite Volume{1};
"""
RECT = """SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 0.2, 0.1};
Physical Surface("slab") = {1};
%s
"""
STEEL = '<material name="steel" groups="%s" E="210e9" nu="0.3" rho="7850"/>'
SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="%s"/>
  <meshing size="%g" order="%d" dim="%d"/>
  %s
  %s
  <effects><elastic%s/></effects>
  <time duration="1e-4"/>
</dtmap-scene>
"""
QUADS = "Recombine Surface{1};"
# (CalculiX element, geometry file or text, size m, order, dim, group, section, formulation)
CASES = [
    ("C3D4", os.path.join(GEO, "box.geo"), 6e-3, 1, 3, "block", "", ' formulation="3d"'),
    ("C3D10", os.path.join(GEO, "box.geo"), 1.2e-2, 2, 3, "block", "", ' formulation="3d"'),
    ("C3D8", HEX % 21, 1.0, 1, 3, "block", "", ' formulation="3d"'),
    ("CPE3", RECT % "", 2.5e-3, 1, 2, "slab", "", ' formulation="plane-strain"'),
    ("CPE4", RECT % QUADS, 2.5e-3, 1, 2, "slab", "", ' formulation="plane-strain"'),
    ("CPE6", RECT % "", 5e-3, 2, 2, "slab", "", ' formulation="plane-strain"'),
    ("S3", RECT % "", 2.5e-3, 1, 2, "slab", '<section groups="slab" kind="shell" thickness="0.004"/>', ""),
    ("S4", RECT % QUADS, 2.5e-3, 1, 2, "slab", '<section groups="slab" kind="shell" thickness="0.004"/>', ""),
]
# The same elements on meshes far beyond the switch: (element, size m; a
# C3D8 size is the number of nodes per edge of the structured cube).
# None: not measured beyond the switch (Gmsh's recombination of 50,000 quads
# takes over 10 minutes here), so the small mesh's figure stands for both.
LARGE = {"C3D4": 4e-3, "C3D10": 5e-3, "C3D8": 41, "CPE3": 0.9e-3, "CPE4": None, "CPE6": 0.9e-3, "S3": 0.9e-3,
         "S4": None}
# Sizes of the bundled box (C3D4) around the switch, coarse to fine.
SWITCH_SIZES = [6.6e-3, 6.2e-3, 6.0e-3, 5.8e-3, 5.5e-3]
SWITCH_JUMP = 1.3  # a figure this far above the small mesh's is past the switch


def deck(dtmap, scene, out):
    rep = out[:-4] + ".json"
    r = subprocess.run([dtmap, "deck", scene, "--solver", "calculix", "-o", out, "--report", rep, "-q"],
                       capture_output=True, text=True)
    if r.returncode:
        sys.exit("dtmap deck %s: exit %d\n%s" % (scene, r.returncode, r.stdout + r.stderr))
    with open(rep) as f:
        return json.load(f)


def with_period(path, period):
    """The deck run as t371 runs it (tests/common/deckutil.py: slots opened,
    a seeded random force at every node, the displacements printed at the
    end), its *DYNAMIC time period set to period; returns the run's name."""
    run, _ = deckutil.prepare(path, period)
    return run


def run_ccx(run, repeat):
    """Best wall time and CPU time (user + system) of ccx on RUN.inp, one thread, s."""
    best = (float("inf"), float("inf"))
    for _ in range(repeat):
        c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        code, log, u, _, _ = deckutil.run("ccx", run, timeout=3600)
        w = time.perf_counter() - t0
        c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        if code or not (u < float("inf")):
            sys.exit("ccx %s failed (exit %d, largest |u| %g):\n%s" % (run, code, u, log[-2000:]))
        cpu = c1.ru_utime - c0.ru_utime + c1.ru_stime - c0.ru_stime
        best = min(best, (w, cpu))
    return best


def measure(a, tmp, elem, geo, size, order, dim, group, section, form, n1, n2, tag=""):
    """(elements, nodes, wall N1, wall N2, CPU N1, CPU N2, ns per element-step) of elem's deck at size."""
    if elem == "C3D8" and tag:
        geo = HEX % size
        size = 1.0
    gpath = geo if os.path.exists(geo) else os.path.join(tmp, elem + tag + ".geo")
    if gpath != geo:
        with open(gpath, "w") as f:
            f.write(geo)
    scene = os.path.join(tmp, elem + tag + ".xml")
    with open(scene, "w") as f:
        f.write(SCENE % (gpath, size, order, dim, STEEL % group, section, form))
    base = os.path.join(tmp, elem + tag + ".inp")
    rep = deck(a.dtmap, scene, base)
    n, step = rep["deck"]["elements"], rep["solvers"][0]["step"]
    t = []
    for k in (n1, n2):
        t.append(run_ccx(with_period(base, (k + 0.5) * step), a.repeat))
    i = 1 if a.cpu else 0
    ns = 1e9 * (t[1][i] - t[0][i]) / (n * (n2 - n1))
    return (n, rep["deck"]["nodes"], t[0][0], t[1][0], t[0][1], t[1][1], ns)


def ns_of(a, path, step, n):
    """CPU (--cpu) or wall ns per element-step of the deck at path (n elements, ccx's step)."""
    t = [run_ccx(with_period(path, (k + 0.5) * step), a.repeat) for k in (a.n1, a.n2)]
    i = 1 if a.cpu else 0
    return 1e9 * (t[1][i] - t[0][i]) / (n * (a.n2 - a.n1))


def with_membrane(path, out):
    """The deck at path with one M3D3 added on three nodes of its first
    C3D4 (numbered after its last element, a membrane as thick as the mesh
    is fine, so ccx's step stays): ccx's bound of integration points per
    element falls from 27 to 9 (its allocation.f), the work barely grows."""
    with open(path) as f:
        text = f.read()
    first = re.search(r"\*ELEMENT, TYPE=C3D4, ELSET=(\w+)\n(\d+), (\d+), (\d+), (\d+)", text)
    last = max(int(m.group(1)) for m in re.finditer(r"^(\d+), \d+, \d+, \d+, \d+$", text, re.M))
    sec = "*SOLID SECTION, ELSET=%s" % first.group(1)
    i = text.index(sec)
    mat = re.match(r"[^\n]*MATERIAL=(\w+)", text[i:]).group(1)
    text = text[:i] + "*ELEMENT, TYPE=M3D3, ELSET=DTMAP_POINTS\n%d, %s, %s, %s\n" % (
        (last + 1,) + first.group(3, 4, 5)) + "*MEMBRANE SECTION, ELSET=DTMAP_POINTS, MATERIAL=%s\n0.006\n" % mat + \
        text[i:]
    with open(out, "w") as f:
        f.write(text)


def without(path, out, heads):
    """The deck at path without its keyword blocks starting with one of heads."""
    with open(path) as f:
        lines = f.read().split("\n")
    keep, skip = [], False
    for line in lines:
        if line.startswith("*") and not line.startswith("**"):
            skip = any(line.startswith(h) for h in heads)
        if not skip:
            keep.append(line)
    with open(out, "w") as f:
        f.write("\n".join(keep))


def with_free(path, out, elem, h):
    """The deck at path with one free element elem (C3D6: a wedge of legs h;
    C3D10: a tetrahedron of legs 2h), its nodes and itself numbered after
    the deck's last, away from the mesh: only ccx's bound changes."""
    with open(path) as f:
        text = f.read()
    node = max(int(m.group(1)) for m in re.finditer(r"^(\d+), [-0-9.e+]+, [-0-9.e+]+, [-0-9.e+]+$", text, re.M))
    last = max(int(m.group(1)) for m in re.finditer(r"^(\d+), \d+, \d+, \d+, \d+$", text, re.M))
    x = 10.0
    if elem == "C3D6":
        pts = [(x, 0, 0), (x + h, 0, 0), (x, h, 0), (x, 0, h), (x + h, 0, h), (x, h, h)]
    else:
        c = [(x, 0, 0), (x + 2 * h, 0, 0), (x, 2 * h, 0), (x, 0, 2 * h)]
        mid = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
        pts = c + [tuple((c[i][k] + c[j][k]) / 2 for k in range(3)) for i, j in mid]
    first = re.search(r"\*ELEMENT, TYPE=C3D4, ELSET=(\w+)", text)
    sec = "*SOLID SECTION, ELSET=%s" % first.group(1)
    mat = re.search(re.escape(sec) + r", MATERIAL=(\w+)", text).group(1)
    add = "*NODE\n" + "".join("%d, %.9g, %.9g, %.9g\n" % ((node + 1 + i,) + p) for i, p in enumerate(pts))
    add += "*ELEMENT, TYPE=%s, ELSET=DTMAP_FREE\n%d, %s\n" % (elem, last + 1, ", ".join(
        str(node + 1 + i) for i in range(len(pts))))
    i = text.index(first.group(0))
    text = text[:i] + add + text[i:]
    j = text.index(sec)
    text = text[:j] + "*SOLID SECTION, ELSET=DTMAP_FREE, MATERIAL=%s\n" % mat + text[j:]
    with open(out, "w") as f:
        f.write(text)


def bound(a, tmp):
    """Rows of ns per element-step of bundled decks as written and with
    ccx's bound of integration points per element changed by one element
    added or removed."""
    for name, variants in (("reinforced_block", [("as written", None), ("without its M3D3", "noplate")]),
                           ("box", [("as written", None), ("with one M3D3 on three of its nodes", "m3d3"),
                                    ("with one free C3D6", "C3D6"), ("with one free C3D10", "C3D10")])):
        base = os.path.join(tmp, name + ".inp")
        rep = deck(a.dtmap, os.path.join(GEO, name + ".xml"), base)
        n, step = rep["deck"]["elements"], rep["solvers"][0]["step"]
        for label, how in variants:
            path = os.path.join(tmp, "%s_%s.inp" % (name, how)) if how else base
            if how == "noplate":
                without(base, path, ["*ELEMENT, TYPE=M3D3", "*MEMBRANE SECTION"])
            elif how == "m3d3":
                with_membrane(base, path)
            elif how:
                with_free(base, path, how, 0.008)
            run = with_period(path, 1.5 * step)
            log = deckutil.run("ccx", run)[1]
            mi = re.search(r"integration points per element:\s*(\d+)", log)
            ns = [ns_of(a, path, step, n) for _ in range(a.repeat)]
            print("| %s, %s | %s | %s |" % (name, label, mi.group(1) if mi else "?", ", ".join("%.0f" % x for x in ns)),
                  flush=True)


def points(a, tmp):
    """ns per point of ccx's bound of integration points per element and
    per element-step: the C3D4 deck alone (bound 27) against the same deck
    with one M3D3 added (bound 9)."""
    elem, geo, size, order, dim, group, section, form = CASES[0]
    scene = os.path.join(tmp, "points.xml")
    with open(scene, "w") as f:
        f.write(SCENE % (geo, size, order, dim, STEEL % group, section, form))
    base = os.path.join(tmp, "points.inp")
    rep = deck(a.dtmap, scene, base)
    n, step = rep["deck"]["elements"], rep["solvers"][0]["step"]
    with_membrane(base, os.path.join(tmp, "points9.inp"))
    ns27, ns9 = ns_of(a, base, step, n), ns_of(a, os.path.join(tmp, "points9.inp"), step, n)
    print("| C3D4, bound 27 / with one M3D3, bound 9 | %d | %.0f | %.0f | per point: **%.1f** |" % (
        n, ns27, ns9, (ns27 - ns9) / 18), flush=True)
    return (ns27 - ns9) / 18


def switch(a, tmp, small):
    """C3D4's switch in elements: the mean of the largest box mesh whose
    figure stays within SWITCH_JUMP of small (ns) and the next one."""
    below = None
    for h in SWITCH_SIZES:
        r = measure(a, tmp, "C3D4", os.path.join(GEO, "box.geo"), h, 1, 3, "block", "", ' formulation="3d"', a.n1,
                    a.n2, "_switch")
        print("| C3D4, box %.1f mm | %d | %d | %.3f | %.3f | %.3f | %.3f | **%.0f** |" % ((1e3 * h,) + r), flush=True)
        if r[6] > SWITCH_JUMP * small:
            return 0.5 * (below + r[0]) if below else r[0]
        below = r[0]
    return float("inf")


def merged(inc, rows, fit):
    """rows and the switch with the rows of inc (when it exists) that were
    not measured now kept (--only measures some elements), in CASES' order."""
    old = {}
    if os.path.exists(inc):
        with open(inc) as f:
            for m in re.finditer(r'\{"(\w+)", ([0-9.e+]+), ([0-9.e+]+), ([0-9.e+]+)\}', f.read()):
                old[m.group(1)] = [float(x) for x in m.group(2, 3, 4)]
    new = {r[0]: [r[7], r[8][6]] for r in rows}
    if fit is None:
        fit = next(iter(old.values()))[2] if old else float("inf")
    out = []
    for elem, *_ in CASES:
        if elem in new:
            out.append((elem, new[elem][0], new[elem][1]))
        elif elem in old:
            out.append((elem, old[elem][0], old[elem][1]))
    return out, fit


def table(a, tmp):
    rows = []
    for elem, geo, size, order, dim, group, section, form in CASES:
        if a.only and elem not in a.only.split(","):
            continue
        r = measure(a, tmp, elem, geo, size, order, dim, group, section, form, a.n1, a.n2)
        print("| %s | %d | %d | %.3f | %.3f | %.3f | %.3f | **%.0f** |" % ((elem,) + r), flush=True)
        big = r
        if LARGE[elem]:
            big = measure(a, tmp, elem, geo, LARGE[elem], order, dim, group, section, form, a.n1, a.n2, "_large")
            print("| %s, large | %d | %d | %.3f | %.3f | %.3f | %.3f | **%.0f** |" % ((elem,) + big), flush=True)
        rows.append((elem,) + r + (big,))
    c3d4 = [r for r in rows if r[0] == "C3D4"]
    fit = switch(a, tmp, c3d4[0][7]) if c3d4 else None
    if fit:
        print("switch: %.0f elements" % fit, flush=True)
    point = points(a, tmp) if not a.only or "POINT" in a.only.split(",") else None
    if a.inc:
        rows, fit = merged(a.inc, rows, fit)
        if point is None:
            with open(a.inc) as f:
                point = float(re.search(r"#define CCX_POINT_NS ([0-9.e+-]+)", f.read()).group(1))
        with open(a.inc, "w") as f:
            f.write("/* CalculiX 2.20 (Debian's ccx), explicit dynamics, one thread\n"
                    " * (OMP_NUM_THREADS=1): %s per element-step, ns, of dtmap's own\n"
                    " * CalculiX decks, per CalculiX element (N1 = %d, N2 = %d increments): on a\n"
                    " * mesh below the switch, on a mesh beyond it, and the switch in the\n"
                    " * mesh's elements (measured on C3D4, the same for every element).\n"
                    " * Regenerate with\n"
                    " *   /usr/bin/python3 bench/ccx_cost.py build/dtmap%s --inc src/cost/ccx_cost.inc\n"
                    " * (docs/accuracy.md, \"CalculiX's own runs\"). */\n" % (
                        "CPU time (user + system: the wall time of an idle machine)" if a.cpu else "wall time",
                        a.n1, a.n2, " --cpu" if a.cpu else ""))
            for elem, small, large in rows:
                f.write('{"%s", %.0f, %.0f, %.0f},\n' % (elem, small, large, fit))
            f.write("#define CCX_POINT_NS %.1f /* per point of ccx's bound of integration points per element, per "
                    "element-step */\n" % point)


def check(a, tmp):
    for scene in sorted(glob.glob(os.path.join(GEO, "*.xml"))):
        name = os.path.basename(scene)[:-4]
        if a.only and name not in a.only.split(","):
            continue
        base = os.path.join(tmp, name + ".inp")
        rep = deck(a.dtmap, scene, base)
        s, n = rep["solvers"][0], rep["deck"]["elements"]
        wall, cpu = run_ccx(with_period(base, (a.n2 + 0.5) * s["step"]), a.repeat)
        predicted = s["hours"] * 3600 * (a.n2 + 1) / (s["element_steps"] / n)
        print("| %s | %d | %.4e | %d | %.2f | %.2f | %.2f | %.2f | %.2f |" % (
            name, n, s["step"], a.n2 + 1, predicted, wall, cpu, wall / predicted, cpu / predicted), flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dtmap")
    ap.add_argument("--inc")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--n1", type=int, default=20)
    ap.add_argument("--n2", type=int, default=220)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--only")
    ap.add_argument("--bound", action="store_true", help="bundled decks with ccx's bound changed by one element")
    ap.add_argument("--cpu", action="store_true", help="the table from CPU time (user + system), for a shared machine")
    a = ap.parse_args()
    a.dtmap = os.path.abspath(a.dtmap)
    tmp = tempfile.mkdtemp(prefix="dtmap-ccx-cost-")
    try:
        if a.bound:
            print("| deck | bound | ns per element-step (%s), each of --repeat |\n|---|---|---|" % (
                "CPU" if a.cpu else "wall"), flush=True)
            bound(a, tmp)
        elif a.check:
            print("| example | elements | ccx's step (s) | increments | predicted (s) | wall (s) | CPU (s) | "
                  "wall / predicted | CPU / predicted |\n|---|---|---|---|---|---|---|---|---|", flush=True)
            check(a, tmp)
        else:
            print("| CalculiX element | elements | nodes | wall, N1 (s) | wall, N2 (s) | CPU, N1 (s) | CPU, N2 (s) | "
                  "ns per element-step (%s) |\n|---|---|---|---|---|---|---|---|" % ("CPU" if a.cpu else "wall"),
                  flush=True)
            table(a, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
