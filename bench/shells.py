"""Time the stiffened panel as shells and beams against the same mesh as
membranes and trusses; print docs/shells-bench.md (called by bench/shells.sh).

Arguments: ROOT WORK DTMAP REPS SIZE..."""
import json
import os
import statistics
import subprocess
import sys
import time

import gmsh

ROOT, WORK, DTMAP, REPS, SIZES = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), sys.argv[5:]
STEEL = 'name="steel" default="true" E="200e9" nu="0.3" rho="7850"'
SCENES = {
    "membrane + truss": '<section groups="skin" kind="membrane" thickness="0.005"/>\n'
                        '<section groups="stiffener" kind="truss" area="4e-4"/>',
    "shell + beam": '<section groups="skin" kind="shell" thickness="0.005"/>\n'
                    '<section groups="stiffener" kind="beam" width="0.01" height="0.04" orientation="1 0 0"/>',
}
STAGES = ("extract", "effects", "nodal", "global")


def mesh(size):
    path = os.path.join(WORK, "panel_%s.msh" % size)
    if not os.path.exists(path):
        gmsh.initialize(["shells", "-v", "0"])
        gmsh.open(os.path.join(ROOT, "geometries", "stiffened_panel.geo"))
        gmsh.option.setNumber("Mesh.MeshSizeMax", float(size))
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.Binary", 1)
        gmsh.write(path)
        gmsh.finalize()
    return path


def scene(size, name, body):
    path = os.path.join(WORK, "%s_%s.xml" % (name.split()[0], size))
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<dtmap-scene version="1">\n<mesh file="%s"/>\n<material %s/>\n%s\n'
                '<effects><elastic/></effects>\n</dtmap-scene>\n' % (os.path.basename(mesh(size)), STEEL, body))
    return path


def once(path, posterior):
    rep = path + ".json"
    args = [DTMAP, "run", path, "-q", "--views-only", "-o", path + ".msh", "--report", rep]
    if posterior:
        args += ["--posterior", "--tol", "1e-3"]
    t0 = time.perf_counter()
    p = subprocess.Popen(args, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("failed: " + " ".join(args))
    with open(rep) as f:
        r = json.load(f)
    return (wall, usage.ru_utime + usage.ru_stime), r["timings"], r["mesh"]["elements"], r["dt"]


def main():
    print("# Shell and beam sections: what the rotations cost\n")
    print("`bench/shells.sh` (a benchmark, not a test): the bundled stiffened panel meshed at each size, run as")
    print("membranes and trusses, then as shells and beams (three rotations per node), on the same .msh;")
    print("medians of %d alternating runs on this machine (%d cores), seconds: wall time and the CPU time of" %
          (REPS, os.cpu_count()))
    print("the process (user + system, all threads: less disturbed by other jobs on a shared machine), and")
    print("the report's stage timings (wall) of the `--posterior` runs. Load average at the start: %s.\n" %
          open("/proc/loadavg").read().split()[0])
    print("| size (m) | elements | sections | run wall (s) | run CPU (s) | --posterior wall (s) | --posterior CPU (s) "
          "| element map | nodal | global | dt min (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for size in SIZES:
        paths = {name: scene(size, name, body) for name, body in SCENES.items()}
        res = {name: {"run": [], "post": [], "run_cpu": [], "post_cpu": [], "t": {s: [] for s in STAGES}}
               for name in SCENES}
        for _ in range(REPS):
            for name, path in paths.items():
                (w, c), _, n, dt = once(path, False)
                res[name]["run"].append(w), res[name]["run_cpu"].append(c)
                (w, c), t, n, dt = once(path, True)
                res[name]["post"].append(w), res[name]["post_cpu"].append(c)
                for s in STAGES:
                    res[name]["t"][s].append(t.get(s, float("nan")))
                res[name]["n"], res[name]["dt"] = n, dt["min"]
        base = None
        for name in SCENES:
            r = res[name]
            med = {k: statistics.median(r[k]) for k in ("run", "post", "run_cpu", "post_cpu")}
            st = {s: statistics.median(r["t"][s]) for s in STAGES}
            rc = "" if base is None else " (%.2fx)" % (med["run_cpu"] / base["run_cpu"])
            pc = "" if base is None else " (%.2fx)" % (med["post_cpu"] / base["post_cpu"])
            base = base or med
            print("| %s | %d | %s | %.2f | %.2f%s | %.2f | %.2f%s | %.3f | %.3f | %.3f | %.4e |" % (
                size, r["n"], name, med["run"], med["run_cpu"], rc, med["post"], med["post_cpu"], pc, st["effects"],
                st["nodal"], st["global"], r["dt"]))


if __name__ == "__main__":
    main()
