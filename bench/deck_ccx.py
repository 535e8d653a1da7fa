#!/usr/bin/python3
"""A real solver confirms the step of `dtmap deck` (docs/deck.md): the
CalculiX deck of every bundled example (geometries/*.xml) runs in a
CalculiX whose explicit increment can be fixed (bench/ccx_fixed_inc.sh:
CalculiX 2.20's sources with the increment read from CCX_FIXED_INC; the
element routines, the lumping and the time scheme are CalculiX's own), from
a seeded random force at every node (tests/common/deckutil.py), for a fixed
number of increments:
- at the deck's step (the nodal bound, safety 0.9) and at the step of the
  --posterior deck (the global estimate, safety 0.9): bounded;
- at 1.05x dtmap's exact step (its global estimate, within 1e-4 of the
  exact step of dtmap's discrete model): blows up.
A run blows up when its largest final displacement is more than 1e3 times
the one at the deck's step, or not finite. Where the deck's step is below
0.9 x the exact step (CalculiX builds the example's 2D or 1D elements as
solids of its own), CalculiX's limit is also bisected, as a multiple of the
exact step. It also prints, for the three solvers, each one's own estimate
for the same mesh by its rule beside the deck's step (the ratio is what
fixing the step gains).

Usage: /usr/bin/python3 bench/deck_ccx.py DTMAP --ccx CCX_FIXED [--steps 500] [--bisect 6] [--only NAME]
       [--estimates-only]
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "common"))
import deckutil as du  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def deck(dtmap, scene, tmp, name, solver, *extra):
    ext = ".k" if solver == "lsdyna" else ".inp"
    out, rep = os.path.join(tmp, name + ext), os.path.join(tmp, name + ".json")
    subprocess.run([dtmap, "deck", scene, "--solver", solver, "-o", out, "--report", rep, "-q", *extra], check=True)
    with open(rep) as f:
        return out, json.load(f)


def run(ccx, path, dt, steps):
    name, _ = du.prepare(path, steps * dt, increment=dt)
    code, log, u, est, sel = du.run(ccx, name, fixed=dt, timeout=7200)
    if code or sel is None or abs(sel / dt - 1) > 1e-6:
        sys.exit("ccx did not run at the fixed increment %g (exit %d):\n%s" % (dt, code, log[-1500:]))
    return u


def example(a, scene, tmp):
    name = os.path.basename(scene)[:-4]
    nodal, rn = deck(a.dtmap, scene, tmp, name + "_nodal", "calculix")
    post, rp = deck(a.dtmap, scene, tmp, name + "_post", "calculix", "--posterior")
    exact = rp["dt"]["global"]
    t0 = time.time()
    u0 = run(a.ccx, nodal, rn["deck"]["step"], a.steps)
    u1 = run(a.ccx, post, rp["deck"]["step"], a.steps)
    u2 = run(a.ccx, post, 1.05 * exact, a.steps)
    bad = lambda u: not u < 1e3 * u0  # noqa: E731
    row = dict(name=name, elements=rn["mesh"]["elements"], exact=exact, nodal=rn["deck"]["step"] / exact,
               post=rp["deck"]["step"] / exact, u0=u0, u1=u1, u2=u2, ok=not bad(u0) and not bad(u1) and bad(u2),
               basis=rp["deck"]["basis"], own=rp["deck"]["own_estimate"] / exact, limit=None)
    if rp["deck"]["step"] < 0.9 * exact * (1 - 1e-9) and a.bisect:
        lo, hi = rp["deck"]["step"] / exact, 1.05
        for _ in range(a.bisect):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if bad(run(a.ccx, post, mid * exact, a.steps)) else (mid, hi)
        row["limit"] = (lo, hi)
    row["seconds"] = time.time() - t0
    return row


def estimates(a, scene, tmp):
    name = os.path.basename(scene)[:-4]
    out = []
    for solver in ("calculix", "abaqus", "lsdyna"):
        _, r = deck(a.dtmap, scene, tmp, name + "_" + solver, solver)
        _, p = deck(a.dtmap, scene, tmp, name + "_" + solver + "_post", solver, "--posterior")
        d, q = r["deck"], p["deck"]
        out.append((solver, d["own_estimate"], d["step"], d["step"] / d["own_estimate"], q["step"],
                    q["step"] / q["own_estimate"], q.get("tssfac")))
    return name, out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dtmap")
    ap.add_argument("--ccx", required=True)
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--bisect", type=int, default=6)
    ap.add_argument("--only")
    ap.add_argument("--estimates-only", action="store_true", help="only the solvers' own estimates (no ccx run)")
    a = ap.parse_args()
    a.dtmap = os.path.abspath(a.dtmap)
    tmp = tempfile.mkdtemp(prefix="dtmap-deck-ccx-")
    scenes = sorted(glob.glob(os.path.join(ROOT, "geometries", "*.xml")))
    if a.only:
        scenes = [s for s in scenes if os.path.basename(s)[:-4] == a.only]
    ok = True
    if not a.estimates_only:
        print("| example | elements | exact step (s) | deck / exact | --posterior deck / exact | ccx at the deck's "
              "step | at the --posterior deck's | at 1.05x exact | ccx's limit / exact | ccx's own / exact |")
        print("|---|---|---|---|---|---|---|---|---|---|")
    for s in scenes if not a.estimates_only else []:
        r = example(a, s, tmp)
        ok &= r["ok"]
        st = lambda u: "diverges" if not u < 1e3 * r["u0"] else "bounded (%.2g m)" % u  # noqa: E731
        lim = "[%.4f, %.4f] ([%.4f, %.4f] x the deck's)" % (r["limit"] + tuple(x / r["post"] for x in r["limit"])) \
            if r["limit"] else "-"
        print("| %s | %d | %.5g | %.4f | %.4f | %s | %s | %s | %s | %.4f |" % (
            r["name"], r["elements"], r["exact"], r["nodal"], r["post"], st(r["u0"]), st(r["u1"]), st(r["u2"]), lim,
            r["own"]), flush=True)
    print("\n| example | solver | solver's own estimate (s) | deck's step (s) | step / own | --posterior deck's "
          "step (s) | step / own | its TSSFAC |")
    print("|---|---|---|---|---|---|---|---|")
    for s in scenes:
        name, rows = estimates(a, s, tmp)
        for solver, own, step, ratio, pstep, pratio, tss in rows:
            print("| %s | %s | %.5g | %.5g | %.3f | %.5g | %.3f | %s |" % (
                name, solver, own, step, ratio, pstep, pratio, "%.7g" % tss if tss else "-"), flush=True)
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
