#!/usr/bin/env bash
# Regenerate docs/performance.md: dtmap end to end against Gmsh's own
# read + write and meshing, supervised against one process, the global
# estimate against scipy's eigsh, 1e7 tets, shells against membranes and
# curved tet10 against straight-sided, every row side by side in one run
# (bench/perf.py). Takes about 7 minutes on 2 cores once its meshes exist
# (making them the first time takes much longer) and about 3 GB of memory
# (the 1e7 rows); meshes are kept in BENCH_WORK (default /tmp/dtmap-perf)
# for the next run.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# The default (serial) build, what `cmake -S . -B build` gives a user: an
# MPI build also loads PETSc, SLEPc and Open MPI (some 190 shared
# libraries), which costs 70 ms at every start.
export BUILD_DIR=${BUILD_DIR:-$root/build-bench}
bash "$root/bench/setup.sh" >/dev/null
bash "$root/scripts/build.sh" -DDTM_MPI=OFF >/dev/null
doc=$root/docs/performance.md
/usr/bin/python3 "$root/bench/perf.py" > "$doc.tmp"
# The sections below the marker come from other scripts (each names its
# own): they are kept as they are.
if [ -f "$doc" ] && grep -q '^<!-- bench/perf.sh regenerates' "$doc"; then
  printf '\n' >> "$doc.tmp"
  sed -n '/^<!-- bench\/perf.sh regenerates/,$p' "$doc" >> "$doc.tmp"
fi
mv "$doc.tmp" "$doc"
cat "$root/docs/performance.md"
