"""The figures of docs/accuracy.md's checks of the phase-speed error on
tetrahedra: the cases of tests t613, t614 and t615 (tests/common/wavecheck.py
and the independent simulation of tests/reference/periodic_wave.py), printed
as the tables the document shows, with `dtmap verify --accuracy` on each
unstructured box (P and S along x) and on the bundled disc meshed at 1 mm.

Usage: accuracy_check.py [BUILD_DIR] (default build/); work files in
BENCH_WORK (default /tmp/dtmap-accuracy-check). With BEFORE=path/to/dtmap
(an older build) the first table also gives that build's worst on the
same meshes.
"""

import os
import re
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
DTMAP = os.path.join(BUILD, "dtmap")
sys.argv = [sys.argv[0], ROOT, DTMAP]  # what tests/common/testutil.py reads
sys.path.insert(0, os.path.join(ROOT, "tests", "common"))
import testutil as tu  # noqa: E402
import wavecheck as wc  # noqa: E402

tu._tmp = os.environ.get("BENCH_WORK", "/tmp/dtmap-accuracy-check")
os.makedirs(tu._tmp, exist_ok=True)
BOX = [0.2, 0.16, 0.16]
UNSTRUCTURED = [("tet4", "per4", 17, 4, 1), ("tet4", "per6", 26, 4, 1), ("tet4", "per10", 21, 2, 1),
                ("tet10", "tet10_per3", 13, 4, 2), ("tet10", "tet10_per5", 11, 2, 2)]
NUM = r"([-+]?[0-9.]+(?:e[-+]?[0-9]+)?)"


def pct(v):
    return "%+.3f %%" % (100 * v)


def verify(scene, *args):
    """verify --accuracy's measured and predicted errors, agreement, periods and exit code."""
    p = subprocess.run([DTMAP, "verify", scene, "--accuracy"] + list(args), cwd=tu._tmp, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, universal_newlines=True)
    m = re.search(r"measured " + NUM + r" %, predicted " + NUM + " %", p.stdout)
    per = re.search(r", " + NUM + r" periods,", p.stdout)
    f = re.search(r"wave along \(.*\) at " + NUM + " Hz", p.stdout)
    if not m:
        return "| %s | %s | - | - | - | - | exit %d |" % (scene, " ".join(args), p.returncode)
    meas, pred = float(m.group(1)), float(m.group(2))
    return "| %s | %s at %s Hz | %s | %+.3f %% | %+.3f %% | %+.1f %% | exit %d |" % (
        scene, " ".join(args), f.group(1), per.group(1), meas, pred, 100 * (meas - pred) / abs(pred), p.returncode)


def before(name):
    """The worst phase error an older dtmap (BEFORE) reports on scene name, or ""."""
    old = os.environ.get("BEFORE")
    if not old:
        return ""
    subprocess.run([old, "run", name + ".xml", "-o", name + "_old.msh", "--report", name + "_old.json", "-q"],
                   cwd=tu._tmp, check=True)
    phase = [m for m in tu.report(name + "_old.json")["accuracy_measures"] if m["measure"] == "phase-speed error"][0]
    return " %s |" % pct(phase["worst"])


def main():
    extra = " before |" if os.environ.get("BEFORE") else ""
    print("| mesh | elements per S wavelength | dtmap worst (wave, direction) | simulation: P x, P diag, S x, "
          "S diag | simulation worst | ratio |" + extra)
    print("|---|---|---|---|---|---|" + ("---|" if extra else ""))
    rows = []
    for kind, name, n, m, order in UNSTRUCTURED:
        phase, res, worst, per_wl = wc.unstructured_case(name, BOX, n, m, order=order)
        d = ", ".join("%.2g" % x for x in phase["direction"])
        print("| %s Delaunay, %d cells along x | %.2f | %s (%s along (%s)) | %s | %s | %.2f |%s" % (
            kind, n, per_wl, pct(phase["worst"]), phase["wave"], d,
            ", ".join(pct(res[k]) for k in ("P x", "P diag", "S x", "S diag")), pct(worst), phase["worst"] / worst,
            before(name)), flush=True)
        rows += [verify(name + ".xml", "--wave", w) for w in "PS"]
    print("\n| mesh | cells per S wavelength | dtmap worst (wave, direction, model) | Bloch worst (wave, direction) | "
          "ratio | simulation against the Bloch prediction, S along the body diagonals |" + extra)
    print("|---|---|---|---|---|---|" + ("---|" if extra else ""))
    for name, kuhn in (("cube_lattice", True), ("transfinite", False)):
        phase, worst, where, gap, per_wl = wc.structured_case(name, 12, kuhn)
        print("| %s | %.2f | %s (%s along (%s), %s) | %s (%s along (%s)) | %.3f | %.1e of the error |%s" % (
            name, per_wl, pct(phase["worst"]), phase["wave"], ", ".join("%.2g" % x for x in phase["direction"]),
            phase["model"], pct(worst), where[0], ", ".join("%.2g" % x for x in where[1]), phase["worst"] / worst,
            gap, before(name)), flush=True)
    for geo in ("brazilian_disc.geo", "brazilian_disc.xml"):
        subprocess.run(["cp", os.path.join(ROOT, "geometries", geo), tu._tmp], check=True)
    with open(os.path.join(tu._tmp, "brazilian_disc.xml")) as f:
        text = f.read().replace('size="2e-3"', 'size="1e-3"')
    with open(os.path.join(tu._tmp, "disc_1mm.xml"), "w") as f:
        f.write(text)
    rows += [verify("disc_1mm.xml", "--wave", w, "--direction", d) for w in "PS" for d in ("1,0,0", "0.6,0.8,0")]
    print("\n| scene | wave | periods | measured | predicted | agreement | verdict |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
