#!/usr/bin/python3
"""What one element-step costs in a real explicit solver on this machine:
CalculiX (ccx) explicit dynamics (*DYNAMIC, EXPLICIT, DIRECT: central
differences at its own stable step) on the bundled geometries, one element type at
a time, one thread. Each case is run twice, for N1 and N2 steps, and the
cost per element-step is the difference of ccx's CPU times (user + system:
the machine is shared, so wall time would count the others' load) over
elements x (N2 - N1), so the reading and the set-up are not counted. The
step is ccx's own stable increment (read from a first, short run; with
DIRECT, ccx 2.20 selects an increment of 0 in explicit dynamics), and the
step time is (N + 1/2) of them, so ccx takes N + 1 increments. A non-uniform initial velocity keeps every element
strained. Prints a Markdown table and writes it as CSV (argv[1], default
ccx_calibration.csv). Needs ccx (bench/setup.sh) and Debian's python3-gmsh.

Usage: /usr/bin/python3 bench/ccx_calibrate.py [out.csv] [--quick] [--only=tet4,quad4,...]
Rows are appended to the CSV as each case finishes.
"""
import os
import resource
import shutil
import subprocess
import sys
import tempfile

import gmsh

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GEO = os.path.join(ROOT, "geometries")
# (label, dtmap name, ccx type, geometry, dim, order, recombine, size m)
CASES = [
    ("tet4", "tet4", "C3D4", "box.geo", 3, 1, False, 6e-3),
    ("tet10", "tet10", "C3D10", "box.geo", 3, 2, False, 1e-2),
    ("hex8", "hex8", "C3D8", "box.geo", 3, 1, True, 4e-3),
    ("tri3", "tri3", "CPE3", "brazilian_disc.geo", 2, 1, False, 6e-4),
    ("tri6", "tri6", "CPE6", "brazilian_disc.geo", 2, 2, False, 1.2e-3),
    ("quad4", "quad4", "CPE4", "brazilian_disc.geo", 2, 1, True, 8e-4),
]
GMSH_TYPE = {"C3D4": 4, "C3D10": 11, "C3D8": 5, "CPE3": 2, "CPE6": 9, "CPE4": 3}
# Gmsh -> CalculiX node order (C3D10: the last two mid-edge nodes swap)
ORDER = {"C3D10": [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]}


def mesh(case):
    label, _, ccx, geo, dim, order, recombine, size = case
    gmsh.clear()
    gmsh.open(os.path.join(GEO, geo))
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size / 4)
    if recombine and dim == 3:  # a structured grid of the cube
        gmsh.model.mesh.setTransfiniteAutomatic()
    gmsh.option.setNumber("Mesh.RecombineAll", 1 if recombine else 0)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1 if recombine and dim == 2 else 0)
    gmsh.model.mesh.generate(dim)
    gmsh.model.mesh.setOrder(order)
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    etags, conn = gmsh.model.mesh.getElementsByType(GMSH_TYPE[ccx])
    return tags, xyz, etags, conn


def write_inp(path, case, tags, xyz, etags, conn, dt, total):
    ccx = case[2]
    nn = len(conn) // len(etags)
    order = ORDER.get(ccx, list(range(nn)))
    with open(path, "w") as f:
        f.write("*NODE, NSET=NALL\n")
        for i, t in enumerate(tags):
            f.write("%d,%.9g,%.9g,%.9g\n" % (t, xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]))
        f.write("*ELEMENT, TYPE=%s, ELSET=EALL\n" % ccx)
        for e, t in enumerate(etags):
            nodes = [int(conn[e * nn + k]) for k in order]
            lines = [nodes[i:i + 15] for i in range(0, nn, 15)]
            f.write("%d," % t + ",\n".join(",".join(map(str, l)) for l in lines) + "\n")
        f.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850\n")
        f.write("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n%s" % ("1.\n" if case[4] == 2 else ""))
        f.write("*INITIAL CONDITIONS, TYPE=VELOCITY\n")
        for i, t in enumerate(tags):
            f.write("%d,1,%.6g\n" % (t, 10.0 * xyz[3 * i + 1] + 1.0))
        f.write("*STEP, INC=10000000\n*DYNAMIC, EXPLICIT\n%.9g, %.9g\n" % (dt, total))
        f.write("*NODE FILE, FREQUENCY=10000000\nU\n*END STEP\n")


def run(workdir, name):
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1", NUMBER_OF_CPUS="1")
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(["ccx", "-i", name], cwd=workdir, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    out = p.stdout.decode(errors="replace")
    if p.returncode or "ERROR" in out:
        sys.exit("ccx failed on %s:\n%s" % (name, out[-2000:]))
    return t, out


def stable_increment(out):
    for line in out.splitlines():
        if "stable time increment" in line:
            return float(line.split(":")[-1])
    sys.exit("ccx printed no stable increment")


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    quick = "--quick" in sys.argv
    out = args[0] if args else "ccx_calibration.csv"
    if not shutil.which("ccx"):
        sys.exit("ccx not found: run bench/setup.sh")
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    rows = []
    work = tempfile.mkdtemp(prefix="dtmap-ccx-")
    n1, n2 = (20, 120) if quick else (50, 450)
    only = [a.split("=", 1)[1].split(",") for a in sys.argv[1:] if a.startswith("--only=")]
    with open(out, "w") as f:
        f.write("type,ccx_type,elements,nodes,cpu_%d_steps_s,cpu_%d_steps_s,ns_per_element_step\n" % (n1, n2))
    for case in CASES:
        if only and case[0] not in only[0]:
            continue
        tags, xyz, etags, conn = mesh(case)
        write_inp(os.path.join(work, "c.inp"), case, tags, xyz, etags, conn, 1e-12, 1e-12)
        dt = stable_increment(run(work, "c")[1])
        times = []
        for steps in (n1, n2):
            write_inp(os.path.join(work, "c.inp"), case, tags, xyz, etags, conn, dt, (steps + 0.5) * dt)
            times.append(min(run(work, "c")[0] for _ in range(1 if quick else 2)))
        ns = (times[1] - times[0]) / (len(etags) * (n2 - n1)) * 1e9
        rows.append((case[0], case[2], len(etags), len(tags), times[0], times[1], ns))
        print("%-6s %-6s %8d elements %8d nodes  %6.2f s / %6.2f s CPU  %8.1f ns per element-step" % rows[-1], flush=True)
        with open(out, "a") as f:
            f.write("%s,%s,%d,%d,%.4f,%.4f,%.2f\n" % rows[-1])
    gmsh.finalize()
    shutil.rmtree(work)
    print("\n| type | CalculiX | elements | ns per element-step |\n|---|---|---|---|")
    for r in rows:
        print("| %s | %s | %d | %.0f |" % (r[0], r[1], r[2], r[6]))


if __name__ == "__main__":
    main()
