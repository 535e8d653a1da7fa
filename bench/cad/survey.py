"""Refine on the real-CAD corpus (bench/cad/parts.tsv), as a new user would.

For each part (its wrapper .geo from bench/cad/corpus.py, in metres): steel
(E = 210e9, nu = 0.3, rho = 7850), 3D elastic, duration 1 ms, safety 0.9. A
uniform size is chosen from the part's volume so that Gmsh gives 3e3-2e4
tetrahedra (checked with `dtmap run`, up to 4 tries; where Gmsh fails, the
first size x 0.75, 1.3, 0.6 are tried), and `dtmap run` on it
gives the recommended step R (nodal bound). Then, per configuration F-BASIS
(F = 1.3 or 1.5; BASIS default or posterior):

    dtmap refine SCENE --target F x R --max-iter 3 [--posterior]

Exit 0 is "met" (with the kept mesh's element-steps over the input's). On
exit 1, uniform coarser meshes (the input size x 1.25, 1.5, 2, 3, 4, 6; each
`dtmap run`, with --posterior for that basis) are tried: if one reaches the
target at no more element-steps than the input, the stop is "wrong" (its
size factor and cost ratio are kept), else "true". Exit 3, a signal or the
time limit is a "crash"; exit 2 "refused".

Restartable: each result is a JSON file OUT/PART/CONFIG.json, and every
`dtmap run` report is kept, so a second call does only what is missing.
Each command runs under a time limit in its own process group (killed with
it on time-out).

Usage: survey.py --dtmap D --parts-dir P --out O [--parts A,B] [--configs C,D] [--timeout S]
"""

import argparse
import json
import os
import signal
import subprocess
import sys
import time

CONFIGS = ["1.5-default", "1.3-default", "1.5-posterior", "1.3-posterior"]
UNIFORM = [1.25, 1.5, 2.0, 3.0, 4.0, 6.0]
TETS_LO, TETS_HI, TETS_AIM = 3000, 20000, 8000

SCENE = """<?xml version="1.0" encoding="UTF-8"?>
<dtmap-scene version="1">
  <geometry file="{geo}"/>
  <meshing dim="3" size="{size:.6g}"/>
  <material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic formulation="3d" length="eigen"/></effects>
  <time safety="0.9" duration="1e-3"/>
</dtmap-scene>
"""


def command(cmd, cwd, timeout):
    """Run cmd in its own process group; (exit code or 'signal N' or 'timeout', seconds, stderr tail)."""
    t0 = time.time()
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
    try:
        _, err = p.communicate(timeout=timeout)
        rc = p.returncode if p.returncode >= 0 else "signal %d" % -p.returncode
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        _, err = p.communicate()
        rc = "timeout"
    tail = " ".join(err.decode("utf-8", "replace").split())[-400:]
    return rc, time.time() - t0, tail


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def remove(msh):
    """Drop a mesh written by dtmap and Gmsh's .opt beside it: the reports are what is kept."""
    for f in (msh, msh + ".opt"):
        try:
            os.remove(f)
        except OSError:
            pass


def save(path, obj):
    with open(path + ".tmp", "w") as f:
        json.dump(obj, f, indent=1)
    os.replace(path + ".tmp", path)


class Part:
    def __init__(self, args, name, volume_mm3):
        self.a, self.name = args, name
        self.geo = os.path.join(os.path.abspath(args.parts_dir), name + ".geo")
        self.dir = os.path.join(args.out, name)
        self.volume = volume_mm3 * 1e-9
        os.makedirs(self.dir, exist_ok=True)

    def run(self, size, posterior):
        """`dtmap run` at a uniform size (cached): dict with rc, elements, rec, cost."""
        tag = "run_%s_%.6g" % ("posterior" if posterior else "default", size)
        cached = load(os.path.join(self.dir, tag + ".json"))
        if cached is not None:
            return cached
        scene = os.path.join(self.dir, "s_%.6g.xml" % size)
        with open(scene, "w") as f:
            f.write(SCENE.format(geo=self.geo, size=size))
        rep = os.path.join(self.dir, tag + ".report.json")
        cmd = [self.a.dtmap, "run", scene, "-q", "--report", rep, "-o", os.path.join(self.dir, tag + ".msh")]
        rc, sec, tail = command(cmd + (["--posterior"] if posterior else []), self.dir, self.a.timeout)
        out = {"size": size, "rc": rc, "seconds": round(sec, 2)}
        j = load(rep) if rc == 0 else None
        if j:
            out.update(elements=j["mesh"]["elements"], rec=j["dt"]["recommended"], basis=j["dt"]["basis"],
                       cost=j["cost"]["element_steps"])
        else:
            out["error"] = tail
        remove(os.path.join(self.dir, tag + ".msh"))
        save(os.path.join(self.dir, tag + ".json"), out)
        return out

    def input(self):
        """The input mesh: a uniform size giving 3e3-2e4 tets, its default run."""
        path = os.path.join(self.dir, "input.json")
        cached = load(path)
        if cached is not None:
            return cached
        size = first = (8.5 * self.volume / TETS_AIM) ** (1 / 3)
        tries, failed = [], 0
        for _ in range(4):
            r = self.run(size, False)
            tries.append(r)
            if r["rc"] == 0 and TETS_LO <= r["elements"] <= TETS_HI:
                break
            if r["rc"] != 0:  # Gmsh may fail at one size and not another
                failed += 1
                size = first * (0.75, 1.3, 0.6)[min(failed, 3) - 1]
            else:
                size *= min(3.0, max(0.4, (r["elements"] / TETS_AIM) ** (1 / 3)))
        ok = [t for t in tries if t["rc"] == 0]
        if ok:
            best = min(ok, key=lambda t: 0 if TETS_LO <= t["elements"] <= TETS_HI else
                       abs(t["elements"] - TETS_AIM))
        else:
            best = tries[-1]
        best = dict(best, tries=[(t["size"], t.get("elements"), t["rc"]) for t in tries])
        save(path, best)
        return best

    def refine(self, config, inp):
        path = os.path.join(self.dir, config + ".json")
        cached = load(path)
        if cached is not None:
            return cached
        factor, basis = config.split("-")
        posterior = basis == "posterior"
        target = float(factor) * inp["rec"]
        scene = os.path.join(self.dir, "s_%.6g.xml" % inp["size"])
        rep = os.path.join(self.dir, config + ".report.json")
        msh = os.path.join(self.dir, config + ".msh")
        cmd = [self.a.dtmap, "refine", scene, "-q", "--target", "%.6e" % target, "--max-iter", "3",
               "--report", rep, "-o", msh] + (["--posterior"] if posterior else [])
        rc, sec, tail = command(cmd, self.dir, self.a.timeout)
        res = {"part": self.name, "config": config, "target": target, "input_size": inp["size"],
               "input_elements": inp["elements"], "rc": rc, "seconds": round(sec, 1)}
        j = load(rep) if rc in (0, 1) else None
        if j and "refine" in j:
            r = j["refine"]
            res.update(met=r.get("met"), met_by=r.get("met_by"), stopped=r.get("stopped"),
                       causes=[c.get("kind", "?") for c in r.get("causes") or []],
                       cause_text=(r.get("causes") or [{}])[0].get("message", "")[:300])
            try:  # a report of another dtmap may lack these: the outcome stands on the exit code
                rounds = r["rounds"]
                res.update(remeshes=sum(1 for x in rounds if x.get("kind") == "mesh"),
                           cost_ratio=rounds[r["best"]]["element_steps"] / rounds[0]["element_steps"])
            except (KeyError, IndexError, TypeError, ZeroDivisionError) as e:
                res["report_error"] = "refine.rounds unreadable: %r" % e
        if rc not in (0, 1) or not j:
            res["error"] = tail
        if rc == 0:
            res["outcome"] = "met"
        elif rc == 1:
            res["outcome"] = "stop"
            res.update(self.uniform_check(inp, posterior, target))
        elif rc == 2:
            res["outcome"] = "refused"
        else:
            res["outcome"] = "crash"
        remove(msh)
        save(path, res)
        return res

    def uniform_check(self, inp, posterior, target):
        base = self.run(inp["size"], posterior)
        if base["rc"] != 0:
            return {"wrong": None, "uniform": [], "uniform_error": "input run failed"}
        tried = []
        for m in UNIFORM:
            r = self.run(inp["size"] * m, posterior)
            row = {"factor": m, "rc": r["rc"]}
            if r["rc"] == 0:
                row.update(elements=r["elements"], reach=r["rec"] / target, cost_ratio=r["cost"] / base["cost"])
            tried.append(row)
            if r["rc"] == 0 and r["rec"] >= target * (1 - 1e-12) and r["cost"] <= base["cost"]:
                return {"wrong": True, "uniform": tried, "uniform_factor": m, "uniform_cost_ratio": r["cost"] / base["cost"]}
        return {"wrong": False, "uniform": tried}


def parts_list(parts_dir):
    out = []
    for line in open(os.path.join(parts_dir, "parts.list")):
        c = line.rstrip("\n").split("\t")
        out.append((c[0], float(c[4])))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dtmap", required=True)
    ap.add_argument("--parts-dir", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--parts", default="")
    ap.add_argument("--configs", default=",".join(CONFIGS))
    ap.add_argument("--timeout", type=float, default=900)
    a = ap.parse_args()
    a.dtmap = os.path.abspath(a.dtmap)
    a.out = os.path.abspath(a.out)
    parts = parts_list(a.parts_dir)
    if a.parts:
        want = a.parts.replace(",", " ").split()
        unknown = set(want) - {n for n, _ in parts}
        if unknown:
            sys.exit("unknown parts: %s" % " ".join(sorted(unknown)))
        parts = [p for p in parts if p[0] in want]
    configs = a.configs.replace(",", " ").split()
    for c in configs:
        if c not in CONFIGS:
            sys.exit("unknown configuration %s (one of %s)" % (c, " ".join(CONFIGS)))
    for config in configs:  # every part at one configuration before the next
        for name, vol in parts:
            p = Part(a, name, vol)
            inp = p.input()
            if inp["rc"] != 0:
                print("%-18s %-14s input run exit %s" % (name, config, inp["rc"]), flush=True)
                continue
            r = p.refine(config, inp)
            extra = ""
            if r["outcome"] == "met":
                extra = "cost x%.2f" % r.get("cost_ratio", float("nan"))
            elif r["outcome"] == "stop":
                extra = "%s; %s" % (",".join(r.get("causes", [])) or r.get("stopped"),
                                    "WRONG: uniform x%s meets at cost x%.2f" % (r["uniform_factor"], r["uniform_cost_ratio"])
                                    if r.get("wrong") else "no uniform coarser mesh meets")
            print("%-18s %-14s %5s tets %-7s %6.1fs %s" % (name, config, inp["elements"], r["outcome"], r["seconds"], extra),
                  flush=True)


if __name__ == "__main__":
    main()
