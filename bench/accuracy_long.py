"""dtmap's phase-speed error on Gmsh's unstructured tetrahedra on periodic
boxes long along the wave (issue 37's check: the S wave lags less along the
axes there than in the cubes of the measured table), against the independent
simulation of tests/reference/periodic_wave.py (numpy/scipy, no dtmap code)
through tests/common/wavecheck.py's long_case: for each case dtmap's reported
worst, the simulation's P and S along x and along the box's diagonal at
dtmap's step, and their ratio (the band is 0.7-1.5). The graded box (size
2x in the middle of x, the wave along x) is also compared with the
simulation of a uniform box at its coarse size (its local elements).

Usage: accuracy_long.py [BUILD_DIR] [CASE...] (default build/, every case);
work files in BENCH_WORK (default /tmp/dtmap-accuracy-long). With
BEFORE=path/to/dtmap (an older build; a script setting LD_LIBRARY_PATH is
fine) the table gives that build's worst and ratio beside.
"""

import os
import re
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
ONLY = sys.argv[2:]
sys.argv = [sys.argv[0], ROOT, os.path.join(BUILD, "dtmap")]  # what tests/common/testutil.py reads
sys.path.insert(0, os.path.join(ROOT, "tests", "common"))
import testutil as tu  # noqa: E402
import wavecheck as wc  # noqa: E402

tu._tmp = os.environ.get("BENCH_WORK", "/tmp/dtmap-accuracy-long")
os.makedirs(tu._tmp, exist_ok=True)
H4 = 0.8 / 68  # 4 elements per S wavelength (median (6V)^(1/3)) at the S wave's 16 wavelengths along 0.8 m
# name: (label, box, h, per S wavelength, order, nu, grading, optimize)
CASES = {
    "long4": ("tet4, 4 per S wavelength", [0.8, 0.16, 0.16], H4, 4, 1, 1 / 3, 1.0, 1),
    "graded2": ("tet4 graded 2x along x, 4 per S wavelength at the coarse middle", [0.8, 0.16, 0.16], H4 / 2, 4,
                1, 1 / 3, 2.0, 1),
    "nu045": ("tet4, nu = 0.45, 4 per S wavelength", [0.8, 0.16, 0.16], H4, 4, 1, 0.45, 1.0, 1),
    "nu015": ("tet4, nu = 0.15, 4 per S wavelength", [0.8, 0.16, 0.16], H4, 4, 1, 0.15, 1.0, 1),
    "tet10_4": ("tet10, 4 per S wavelength", [0.8, 0.16, 0.16], 2 * H4, 4, 2, 1 / 3, 1.0, 1),
    "long6": ("tet4, 6 per S wavelength", [0.8, 0.12, 0.12], H4 / 1.5, 6, 1, 1 / 3, 1.0, 1),
    "unopt4": ("tet4 Delaunay without optimisation, 4 per S wavelength", [0.8, 0.16, 0.16], H4, 4, 1, 1 / 3, 1.0, 0),
}


def pct(v):
    return "%+.3f %%" % (100 * v) if v is not None else "unresolved"


def main():
    before = os.environ.get("BEFORE")
    clis = [None] + ([[before]] if before else [])
    print("| case | elements | per S wavelength | dtmap worst (wave, direction) | simulation: P x, S x, P diag, S diag "
          "| simulation worst | ratio |" + (" before: dtmap worst | before: ratio |" if before else ""))
    print("|---|---|---|---|---|---|---|" + ("---|---|" if before else ""))
    got = {}
    for name, (label, box, h, per, order, nu, grading, opt) in CASES.items():
        if ONLY and name not in ONLY:
            continue
        phases, res, worst, per_wl = wc.long_case(name, box, h, per, order, nu, grading, opt, clis, cache=True)
        got[name] = (phases, worst, per_wl)
        row = "| %s (%s) | %s | %.2f | %s (%s along (%s)) | %s | %s | %.2f |" % (
            label, name, open_count(name), per_wl, pct(phases[0]["worst"]), phases[0]["wave"],
            ", ".join("%.2g" % x for x in phases[0]["direction"]),
            ", ".join(pct(res[k]) for k in ("P x", "S x", "P diag", "S diag")), pct(worst), phases[0]["worst"] / worst)
        if before:
            row += " %s (%s) | %.2f |" % (pct(phases[1]["worst"]), phases[1]["wave"], phases[1]["worst"] / worst)
        print(row, flush=True)
    if "long4" in got and "graded2" in got:  # the graded box against its local elements: the uniform box
        (_, worst, per), (gp, _, gper) = got["long4"][:3], got["graded2"][:3]
        local = worst * (per / gper) ** 2
        print("\nThe graded box against the uniform box's simulation at its coarse elements per wavelength "
              "(%+.3f %%): ratio %s." % (100 * local, ", before ".join("%.2f" % (p["worst"] / local) for p in gp)))
    if not ONLY or "long4" in ONLY:
        print("\n| scene | wave | measured | predicted | agreement | verdict |")
        print("|---|---|---|---|---|---|")
        for w in "PS":
            print(verify("long4.xml", w), flush=True)


def verify(scene, wave):
    """verify --accuracy's row for scene and wave (along x): measured, predicted, agreement, exit code."""
    p = subprocess.run([os.path.join(BUILD, "dtmap"), "verify", scene, "--accuracy", "--wave", wave], cwd=tu._tmp,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    num = r"([-+]?[0-9.]+(?:e[-+]?[0-9]+)?)"
    m = re.search(r"measured " + num + r" %, predicted " + num + " %", p.stdout)
    if not m:
        return "| %s | %s | - | - | - | exit %d |" % (scene, wave, p.returncode)
    meas, pred = float(m.group(1)), float(m.group(2))
    return "| %s | %s along x | %+.3f %% | %+.3f %% | %+.1f %% | exit %d |" % (
        scene, wave, meas, pred, 100 * (meas - pred) / abs(pred), p.returncode)


def open_count(name):
    """The element count of case name's report."""
    return tu.report(name + ".json")["mesh"]["elements"]


if __name__ == "__main__":
    main()
