#!/usr/bin/env bash
# Regenerate docs/performance.md: dtmap end to end against Gmsh's own
# read + write and meshing, and the global estimate against scipy's eigsh,
# side by side in one run (bench/perf.py). Takes 10-20 minutes on 2 cores;
# meshes are kept in BENCH_WORK (default /tmp/dtmap-perf) for the next run.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build}
bash "$root/bench/setup.sh" >/dev/null
bash "$root/scripts/build.sh" >/dev/null
/usr/bin/python3 "$root/bench/perf.py" > "$root/docs/performance.md.tmp"
mv "$root/docs/performance.md.tmp" "$root/docs/performance.md"
cat "$root/docs/performance.md"
