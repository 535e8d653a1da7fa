"""How far the deterministic certificate of the global bound reaches
(src/spectral/certify.c, CHOLMOD, with the budget of src/analysis/global.c):
Gmsh tet4 meshes of the unit box, steel, 3D elasticity, at increasing
sizes, each run by the built dtmap with `run --posterior`. Per size:
unknowns (3 x nodes), the wall time of the run before the certificate (the
report's timings mesh + extract + effects + nodal: the budget's basis) and
of the element map alone (effects), the certificate (the report's
lanczos.certificate), CHOLMOD's predicted flops and memory and the flops
allowed (the summary's line), the certificate's wall time (analysis,
assembly, every factorisation), the whole run's wall time, its CPU time
(user + system over all threads, wait4: on a loaded machine the wall time
grows, the CPU time much less) and the process's peak resident memory
(wait4). Where dtmap refuses (too dear) up
to FORCE_TO unknowns, a second run with DTMAP_BENCH_CERT_BUDGET=1e15
measures what the factorisation would have cost (the forced columns).
The certificate's seconds are, where refused, the prediction's (CHOLMOD's
ordering and analysis).

Usage: certify_reach.py BUILD_DIR [UNKNOWNS ...]   (default 1e3 1e4 3e4 1e5 3e5)
Prints a Markdown table and the load average before and after
(docs/certificate.md keeps one)."""
import json
import os
import re
import subprocess
import sys
import tempfile
import time

import gmsh

STEEL = 'E="210e9" nu="0.3" rho="7850"'
FORCE_TO = 1.2e5  # refused factorisations are run anyway up to this many unknowns


def box_mesh(path, unknowns):
    """A Delaunay tet4 mesh of the unit box with about unknowns / 3 nodes."""
    h = (unknowns / 3 / 1.0) ** (-1 / 3) * 0.93
    gmsh.initialize(["certify_reach", "-v", "0"])
    try:
        gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [1]), "block")
        gmsh.option.setNumber("Mesh.MeshSizeMin", h)
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.model.mesh.generate(3)
        gmsh.write(path)
    finally:
        gmsh.finalize()


def peak_rss_run(cmd, cwd, env=None):
    """(wall s, CPU s, peak RSS MB, stdout) of cmd, stdout through a file."""
    with tempfile.TemporaryFile("w+") as out:
        t0 = time.perf_counter()
        p = subprocess.Popen(cmd, cwd=cwd, stdout=out, stderr=subprocess.PIPE, env=dict(os.environ, **(env or {})))
        _, status, ru = os.wait4(p.pid, 0)
        t = time.perf_counter() - t0
        err = p.stderr.read().decode()
        p.stderr.close()
        if os.waitstatus_to_exitcode(status) != 0:
            sys.exit("failed: %s\n%s" % (" ".join(cmd), err))
        out.seek(0)
        return t, ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024.0, out.read()


def certify(dtmap, work, env=None):
    """One run --posterior of box.xml: its report's figures and the summary's certificate line."""
    wall, cpu, rss, out = peak_rss_run([dtmap, "run", "box.xml", "-o", "out.msh", "--report", "rep.json", "--posterior"],
                                  work, env)
    with open(os.path.join(work, "rep.json")) as f:
        rep = json.load(f)
    lz = rep["effect_minima"][0]["lanczos"]
    # the global line and the three under it (the proof in words, the factorisation's figures)
    lines = out.splitlines()
    at = next(i for i, l in enumerate(lines) if l.startswith("global"))
    line = " ".join(lines[at:at + 4])
    proven = re.search(r"factorisation of ([0-9.e+]+) flops, ([0-9.e+]+) MB, ([0-9.]+) s", line)
    dear = re.search(r"too dear: ([0-9.e+]+) flops and ([0-9.e+]+) MB predicted, ([0-9.e+]+) flops allowed "
                     r"\(([0-9.]+) s to predict", line)
    huge = re.search(r"too dear: the mesh is too large to order, ([0-9.e+]+) flops allowed \(([0-9.]+) s", line)
    if huge:  # refused before any ordering: nothing predicted
        dear = huge
    tm = rep["timings"]
    return {
        "unknowns": 3 * rep["mesh"]["nodes"],
        "elements": rep["mesh"]["elements"],
        "before": tm["mesh"] + tm["extract"] + tm["effects"] + tm["nodal"],
        "map": tm["effects"],
        "certificate": lz.get("deterministic", lz.get("certificate")),
        "cert_s": float(proven.group(3)) if proven else float(dear.groups()[-1]) if dear else None,
        "predicted": None if huge else (float(dear.group(1)), float(dear.group(2))) if dear else
                     (float(proven.group(1)), float(proven.group(2))) if proven else None,
        "allowed": float(dear.groups()[-2]) if dear else None,
        "wall": wall,
        "cpu": cpu,
        "rss": rss,
    }


def one(dtmap, work, unknowns, force_to):
    """The run at dtmap's own budget and, when it is too dear and the size is
    at most force_to unknowns, a second run whose budget lets it factor."""
    box_mesh(os.path.join(work, "box.msh"), unknowns)
    with open(os.path.join(work, "box.xml"), "w") as f:
        f.write('<?xml version="1.0"?>\n<dtmap-scene version="1">\n<mesh file="box.msh"/>\n'
                '<material name="steel" groups="block" %s/>\n<effects><elastic formulation="3d"/></effects>\n'
                '</dtmap-scene>\n' % STEEL)
    own = certify(dtmap, work)
    forced = own
    if own["certificate"] == "too dear" and own["unknowns"] <= force_to:
        forced = certify(dtmap, work, {"DTMAP_BENCH_CERT_BUDGET": "1e15"})
    return own, forced


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    dtmap = os.path.abspath(os.path.join(sys.argv[1], "dtmap"))
    sizes = [float(s) for s in sys.argv[2:]] or [1e3, 1e4, 3e4, 1e5, 3e5]
    print("load before: %s" % open("/proc/loadavg").read().strip())
    print("| unknowns | tet4 | run before s | element map s | certificate | predicted flops | predicted MB |"
          " allowed flops | certificate s | run s | run CPU s | peak RSS MB | forced: certificate s |"
          " forced: run s | forced: run CPU s | forced: peak RSS MB |")
    print("|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as work:
        for n in sizes:
            own, f = one(dtmap, work, n, FORCE_TO)
            pred = own["predicted"] or (float("nan"), float("nan"))
            forced = ("%.2f | %.2f | %.2f | %.0f" % (f["cert_s"], f["wall"], f["cpu"], f["rss"])
                      if f is not own else " | | | ")
            print("| %d | %d | %.3f | %.3f | %s | %.3g | %.0f | %s | %.2f | %.2f | %.2f | %.0f | %s |" %
                  (own["unknowns"], own["elements"], own["before"], own["map"], own["certificate"], pred[0], pred[1],
                   "%.3g" % own["allowed"] if own["allowed"] else "", own["cert_s"] or 0, own["wall"], own["cpu"],
                   own["rss"], forced), flush=True)
    print("load after: %s" % open("/proc/loadavg").read().strip())
    print("forced: a second run whose budget (DTMAP_BENCH_CERT_BUDGET=1e15) lets the refused factorisation run")


if __name__ == "__main__":
    main()
