"""Selective mass scaling on thin-walled real-CAD parts (issue 44; docs/selective-mass.md).

For each part (its wrapper .geo from bench/cad/corpus.py, in metres): steel
(E = 210e9, nu = 0.3, rho = 7850), 3D elastic, safety 0.9, a coarse uniform
size chosen from the part's volume (about TETS_AIM tetrahedra; a thin wall
makes more). `dtmap run` gives the input's recommended step R; then for
each factor F (default 2 and 5)

    dtmap run SCENE --selective-mass --target F x R --modes 10 --report R.json

and the table takes from the report: the scaled model's global step and its
certificate, the target met, the largest |shift| of the lowest 10 elastic
frequencies under selective mass and under conventional point masses
reaching the same target (the `modes` object's two variants), the added
mass (conventional: % of the model's mass; selective: trace(M_add) /
trace(M) per direction, the translational mass unchanged), the CG
iterations per mass solve and the run-time factor `run` predicts, and the
seconds of the command.

With --verify PARTS, those parts are integrated by dtmap's own central
differences at the first factor's target: `dtmap verify --selective-mass
--target T --steps N` (the CG iterations per step and the seconds of its
loop, which it prints) against `dtmap verify --steps N` on the lumped model
at its own recommended step. The measured factor per step is the ratio of
their seconds per step; `run` predicts 1 + CG x (M_s product / K product)
at the solver's tolerance 1e-6, while verify solves to 1e-10, so the
prediction is also given with verify's own iteration count.

The parts are brought from bench/cad/parts.tsv (corpus.py's functions)
into --parts-dir when their .geo is missing: the gmsh-doc ones from Debian's
gmsh-doc, the others from the git mirrors (--mirrors).

Usage: selective_mass.py --dtmap D --parts-dir P --out O [--parts A,B]
       [--factors 2,5] [--verify A,B] [--steps N] [--mirrors DIR] [--table-only]
Prints the two tables (Markdown) and writes O/results.json (--table-only:
prints the tables of an earlier O/results.json).
"""

import argparse
import json
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "cad"))

import corpus  # noqa: E402
from survey import SCENE  # noqa: E402  (the corpus survey's scene: steel, eigen lengths)

PARTS = ["thin_blend_plate", "thin_blend_shell", "sheet_clamp", "as1_l_bracket", "as1_plate", "ski_part"]
TETS_AIM = 2500



def bring(parts, out, mirrors):
    os.makedirs(out, exist_ok=True)
    for row in corpus.table():
        name = row["name"]
        if name not in parts or os.path.exists(os.path.join(out, name + ".geo")):
            continue
        data = corpus.raw_bytes(row, mirrors)
        fmt = corpus.suffix(row["path"])
        if row["solid"] is not None:
            raw = os.path.join(out, name + "_source" + fmt)
            with open(raw, "wb") as f:
                f.write(data)
            part, fmt = name + ".brep", ".brep"
            corpus.cut_solid(raw, os.path.join(out, part), row["solid"])
        else:
            part = name + fmt
            with open(os.path.join(out, part), "wb") as f:
                f.write(data)
        with open(os.path.join(out, name + ".geo"), "w") as f:
            f.write(corpus.wrapper(name, part, fmt))


def volume(path):
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        gmsh.open(path)
        return sum(gmsh.model.occ.getMass(3, t) for _, t in gmsh.model.getEntities(3))
    finally:
        gmsh.finalize()


def command(cmd, cwd):
    t0 = time.time()
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    return p.returncode, time.time() - t0, p.stdout.decode("utf-8", "replace")


def drop(path):
    for f in (path, path + ".opt"):
        if os.path.exists(f):
            os.remove(f)


def run_part(a, name):
    d = os.path.join(a.out, name)
    os.makedirs(d, exist_ok=True)
    geo = os.path.join(os.path.abspath(a.parts_dir), name + ".geo")
    size = (8.5 * volume(geo) / TETS_AIM) ** (1 / 3)
    scene = os.path.join(d, "scene.xml")
    with open(scene, "w") as f:
        f.write(SCENE.format(geo=geo, size=size))
    rc, sec, log = command([a.dtmap, "run", scene, "-q", "--report", "input.json", "-o", "input.msh"], d)
    drop(os.path.join(d, "input.msh"))
    if rc != 0:
        return {"part": name, "error": log[-400:]}
    j = json.load(open(os.path.join(d, "input.json")))
    res = {"part": name, "size": size, "elements": j["mesh"]["elements"], "input": j["dt"]["recommended"],
           "input_seconds": sec, "cases": []}
    for fac in a.factors:
        target = fac * res["input"]
        rep = "sms_%g.json" % fac
        cmd = [a.dtmap, "run", scene, "-q", "--selective-mass", "--target", "%.6e" % target, "--modes", "10",
               "--report", rep, "-o", "sms.msh"]
        rc, sec, log = command(cmd, d)
        drop(os.path.join(d, "sms.msh"))
        case = {"factor": fac, "target": target, "rc": rc, "seconds": sec}
        if rc == 0:
            case.update(case_figures(json.load(open(os.path.join(d, rep)))))
        else:
            case["error"] = log[-400:]
        res["cases"].append(case)
    if name in a.verify:
        res["verify"] = verify_part(a, d, scene, a.factors[0] * res["input"])
    return res


def case_figures(j):
    s, m = j["selective_mass"], j.get("modes") or {}
    out = {"dt_scaled": s["global"]["dt"], "certificate": s["global"]["certificate"],
           "recommended": s["recommended"], "met": s["target_met"], "scaled": s["elements"]["scaled"],
           "beta_max": s["elements"]["beta_max"], "share": s["mass"]["share"],
           "translational": s["mass"]["translational_mass"],
           "translational_lumped": s["mass"]["translational_mass_lumped"], "cg": s["cost"]["cg_iterations"],
           "product_ratio": s["cost"]["product_ratio"], "runtime_factor": s["cost"]["runtime_factor"]}
    for v in m.get("variants", []):
        key = "sms" if v["name"].startswith("selective") else "conv"
        if not v.get("computed"):
            out[key + "_why"] = v.get("why")
            continue
        shifts = [abs(x) for x in v["shifts"] if x is not None]
        out[key + "_shift"] = max(shifts) if shifts else None
        out[key + "_unmatched"] = sum(1 for x in v["shifts"] if x is None)
        out[key + "_added_percent"] = v["added_percent"]
    return out


def verify_part(a, d, scene, target):
    steps = str(a.steps)
    rc, sec, log = command([a.dtmap, "verify", scene, "--selective-mass", "--target", "%.6e" % target, "--steps",
                            steps], d)
    out = {"target": target, "steps": a.steps, "sms_rc": rc}
    m = re.search(r"([0-9.]+) CG iterations per step; growth .*? ([0-9.e+-]+): (\w+), ([0-9.]+) s", log)
    if m:
        out.update(sms_cg=float(m.group(1)), sms_growth=float(m.group(2)), sms_verdict=m.group(3),
                   sms_seconds=float(m.group(4)))
    rc, sec, log = command([a.dtmap, "verify", scene, "--steps", steps], d)
    out["lumped_rc"] = rc
    m = re.search(r"elastic\s+([0-9.e+-]+)\s+\[[^]]*\]\s+([0-9.]+)\s+(\w+)", log)
    if m:
        out.update(lumped_growth=float(m.group(1)), lumped_seconds=float(m.group(2)), lumped_verdict=m.group(3))
    return out


def pct(x):
    return "-" if x is None else "%.3g %%" % x


def shift(c, key):
    """The largest |shift| of a variant, and how many of the 10 found no partner by MAC."""
    if key + "_why" in c:
        return "not computed"
    text = pct(c.get(key + "_shift"))
    n = c.get(key + "_unmatched") or 0
    return text + (" (%d unmatched)" % n if n else "")


def tables(results, load):
    print("| part | elements | input step (s) | F | target (s) | SMS global step (s), certificate | met | scaled (largest beta) "
          "| largest \\|shift\\| of the lowest 10, SMS / conventional | added mass: conventional (% of the model) "
          "/ SMS (trace share per direction; translational mass) | CG per solve; time per step, run time at the "
          "target (x the lumped model's) | s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        if "error" in r:
            print("| %s | failed: %s |" % (r["part"], " ".join(r["error"].split())[-120:]))
            continue
        for c in r["cases"]:
            head = "| %s | %d | %.4e | %g | %.4e" % (r["part"], r["elements"], r["input"], c["factor"], c["target"])
            if c["rc"] != 0:
                print(head + " | exit %s: %s |" % (c["rc"], " ".join(c["error"].split())[-160:]))
                continue
            share = max(c["share"])
            same = "unchanged" if abs(c["translational"] - c["translational_lumped"]) <= 1e-9 * c[
                "translational_lumped"] else "CHANGED"
            print(head + " | %.4e, %s | %s | %d (%.3g) | %s / %s | %s / %.3g %% (%s) | %.1f; %.2fx, %.2fx | %.0f |" % (
                c["dt_scaled"], c["certificate"], "yes" if c["met"] else "NO", c["scaled"], c["beta_max"],
                shift(c, "sms"), shift(c, "conv"),
                pct(c.get("conv_added_percent")), 100 * share, same, c["cg"], c["runtime_factor"],
                c["runtime_factor"] / c["factor"], c["seconds"]))
    print()
    print("| part | target (s) | steps | SMS: CG per step, growth, s per step | lumped at its own step: growth, s per "
          "step | measured time per step, SMS / lumped | run's prediction (CG at 1e-6) | with verify's CG (1e-10) |")
    print("|---|---|---|---|---|---|---|---|")
    for r in results:
        v = r.get("verify")
        if not v or "sms_seconds" not in v or "lumped_seconds" not in v:
            continue
        c = r["cases"][0]
        n = v["steps"]
        measured = v["sms_seconds"] / v["lumped_seconds"]
        print("| %s | %.4e | %d | %.1f, %.3g (%s), %.3g | %.3g (%s), %.3g | %.2fx | %.2fx | %.2fx |" % (
            r["part"], v["target"], n, v["sms_cg"], v["sms_growth"], v["sms_verdict"], v["sms_seconds"] / n,
            v["lumped_growth"], v["lumped_verdict"], v["lumped_seconds"] / n, measured, c["runtime_factor"],
            1 + v["sms_cg"] * c["product_ratio"]))
    print()
    print("load average at the start / end: %s / %s" % load)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dtmap", required=True)
    ap.add_argument("--parts-dir", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--parts", default=",".join(PARTS))
    ap.add_argument("--factors", default="2,5")
    ap.add_argument("--verify", default="thin_blend_plate,as1_l_bracket,ski_part")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--mirrors", default="/work/.mirror")
    ap.add_argument("--table-only", action="store_true", help="print the tables of OUT/results.json again")
    a = ap.parse_args()
    if a.table_only:
        with open(os.path.join(a.out, "results.json")) as f:
            return tables(json.load(f), ("-", "-"))
    a.dtmap = os.path.abspath(a.dtmap)
    a.out = os.path.abspath(a.out)
    a.factors = [float(x) for x in a.factors.split(",")]
    a.verify = [x for x in a.verify.split(",") if x]
    parts = [x for x in a.parts.split(",") if x]
    bring(parts, a.parts_dir, a.mirrors)
    os.makedirs(a.out, exist_ok=True)
    load0 = open("/proc/loadavg").read().split()[0]
    results = []
    for name in parts:
        results.append(run_part(a, name))
        print("%s done" % name, file=sys.stderr, flush=True)
        with open(os.path.join(a.out, "results.json"), "w") as f:
            json.dump(results, f, indent=1)
    load1 = open("/proc/loadavg").read().split()[0]
    tables(results, (load0, load1))


if __name__ == "__main__":
    main()
