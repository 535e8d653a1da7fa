#!/usr/bin/env bash
# What the accuracy measures cost in a whole `dtmap run` on a mesh of about
# a million elements read from a .msh (the case where they weigh most: no
# meshing in the run): Gmsh meshes the bundled box (tet4, 0.9e6) and the
# Brazilian disc (tri3, 1.5e6) once, then dtmap runs each scene on its .msh
# with --report; the report's timings give each stage, the measures among
# them (timings.measures), beside the run's wall time. Work files in
# BENCH_WORK (default /tmp/dtmap-accuracy-run).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
work=${BENCH_WORK:-/tmp/dtmap-accuracy-run}
mkdir -p "$work"
cp "$root"/geometries/{brazilian_disc,box}.{geo,xml} "$work"/
cd "$work"
[ -f box1m.msh ] || gmsh box.geo -3 -clmax 1.65e-3 -clmin 1e-3 -algo hxt -nt "$(nproc)" -o box1m.msh > box1m.log
[ -f disc1m.msh ] || gmsh brazilian_disc.geo -2 -clmax 7e-5 -clmin 7e-5 -nt "$(nproc)" -o disc1m.msh > disc1m.log
for name in box disc; do
  geo=$([ $name = box ] && echo box || echo brazilian_disc)
  sed "s|<geometry file=\"$geo.geo\"/>|<mesh file=\"${name}1m.msh\"/>|; /<meshing/d" "$geo.xml" > "${name}1m.xml"
done
/usr/bin/python3 - "$build/dtmap" <<'PY'
import json, subprocess, sys, time
for name in ("box", "disc"):
    for run in range(3):
        t0 = time.perf_counter()
        subprocess.run([sys.argv[1], "run", name + "1m.xml", "-o", "out_%s.msh" % name, "--report", name + ".json", "-q"],
                       check=True)
        wall = time.perf_counter() - t0
        r = json.load(open(name + ".json"))
        t = r["timings"]
        stages = " ".join("%s %.3f" % (k, v) for k, v in t.items() if k != "threads")
        print("%-5s %8d elements  wall %.2f s  measures %.3f s = %.1f %% of the run  (%s)"
              % (name, r["mesh"]["elements"], wall, t["measures"], 100 * t["measures"] / wall, stages), flush=True)
PY
