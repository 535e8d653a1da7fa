"""Running a CalculiX deck of `dtmap deck` (tests/t360-deck-calculix.py,
bench/deck_ccx.py): the deck's two commented *INCLUDE slots are opened, the
model slot gets a node set of every node, the step slot a seeded random
force at every node, applied from the start (a step load excites every mode,
the top one included; CalculiX 2.20 passes point loads on to the solids it
builds from 2D and 1D elements, not initial velocities) and a print of the
displacements at the end, and the *DYNAMIC line a new duration (and,
for the fixed-increment CalculiX of bench/ccx_fixed_inc.sh, the increment
passed in CCX_FIXED_INC). Written from CalculiX 2.20's manual (*INCLUDE,
*INITIAL CONDITIONS TYPE=VELOCITY, *NODE PRINT, *DYNAMIC)."""

import os
import random
import re
import subprocess

DYNAMIC = "*DYNAMIC, EXPLICIT, ALPHA=0"


def inp_nodes(lines):
    """{node id: (x, y, z)} of the *NODE block of an Abaqus-style deck."""
    nodes, on = {}, False
    for line in lines:
        if line.startswith("*"):
            on = line.split(",")[0].strip().upper() == "*NODE"
            continue
        if on and line.strip() and not line.startswith("**"):
            v = [x.strip() for x in line.split(",")]
            nodes[int(v[0])] = tuple(float(x) for x in v[1:4])
    return nodes


def write_node_set(f, nodes):
    """*NSET DTMAPTEST_ALL of every node id of nodes, 16 a line, to the open file f; the ids sorted."""
    f.write("*NSET, NSET=DTMAPTEST_ALL\n")
    ids = sorted(nodes)
    for k in range(0, len(ids), 16):
        f.write(", ".join(str(n) for n in ids[k:k + 16]) + "\n")
    return ids


def prepare(deck, duration, seed=27, increment=None):
    """Write RUN.inp beside deck (RUN: deck's name + '_run') with the slots
    opened and filled; returns (run name without .inp, the deck's step)."""
    base = os.path.splitext(deck)[0]
    with open(deck) as f:
        lines = f.read().split("\n")
    nodes = inp_nodes(lines)
    dofs = (1, 2) if all(abs(p[2]) == 0 for p in nodes.values()) else (1, 2, 3)
    i = lines.index(DYNAMIC)
    v = [x.strip() for x in lines[i + 1].split(",")]
    step = float(v[0])
    inc = increment if increment else step
    lines[i + 1] = "%.14g, %.14g, 1e-30, %.14g" % (inc, duration, inc)
    out = []
    for line in lines:
        m = re.match(r"\*\* \*INCLUDE, INPUT=(.*)$", line)
        out.append("*INCLUDE, INPUT=" + m.group(1) if m else line)
    rng = random.Random(seed)
    with open(base + "_model.inp", "w") as f:
        ids = write_node_set(f, nodes)
    with open(base + "_step.inp", "w") as f:
        f.write("*CLOAD\n")
        for n in ids:
            for d in dofs:
                f.write("%d, %d, %.6g\n" % (n, d, rng.uniform(-1, 1)))
        f.write("*NODE PRINT, NSET=DTMAPTEST_ALL, FREQUENCY=1000000000\nU\n")
    run = base + "_run"
    with open(run + ".inp", "w") as f:
        f.write("\n".join(out))
    return run, step


def run(ccx, run_name, fixed=None, timeout=600):
    """Run ccx on RUN.inp (cwd: its folder, one thread); returns (exit code,
    log, largest |u| at the end (inf when not finite or missing), the
    estimate ccx printed, s, the increment it selected, s)."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    env.pop("LD_PRELOAD", None)
    if fixed:
        env["CCX_FIXED_INC"] = "%.14g" % fixed
    d, name = os.path.split(run_name)
    p = subprocess.run([ccx, "-i", name], cwd=d or ".", env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       timeout=timeout)
    log = p.stdout.decode(errors="replace")
    est = re.search(r"Volumetric COURANT initial stable time increment:\s*(\S+)", log)
    sel = re.search(r"SELECTED time increment:\s*(\S+)", log)
    return p.returncode, log, max_displacement(run_name + ".dat"), float(est.group(1)) if est else None, \
        float(sel.group(1)) if sel else None


def max_displacement(dat):
    """Largest |u| component printed in a .dat (inf when a value is not
    finite, or nothing was printed)."""
    u, seen = 0.0, False
    try:
        with open(dat) as f:
            lines = f.read().split("\n")
    except OSError:
        return float("inf")
    for line in lines:
        w = line.split()
        if len(w) == 4 and w[0].isdigit():
            try:
                vals = [abs(float(x)) for x in w[1:]]
            except ValueError:
                return float("inf")
            if any(x != x or x == float("inf") for x in vals):
                return float("inf")
            u, seen = max(u, max(vals)), True
    return u if seen else float("inf")
