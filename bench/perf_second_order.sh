#!/usr/bin/env bash
# Regenerate docs/performance-second-order.md: tet10 read from a binary .msh
# (about 1e5 and 1e6 elements) against Gmsh's own read + write, and a ball
# of curved tet10 against its straight-sided twin, as the median of 5
# alternating pairs (bench/perf_second_order.py). With DTMAP_BEFORE=path of
# another build's dtmap (DTMAP_BEFORE_NAME: what it is, in words), its rows
# run in the same alternation. BENCH_SIZES, BENCH_REPS: the box sizes and
# the pairs (default "1e5 1e6", 5). About 10-20
# minutes on 2 cores; meshes are kept in BENCH_WORK (default
# /tmp/dtmap-perf-second-order) for the next run.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build-bench}
if [ ! -x "$BUILD_DIR/dtmap" ]; then bash "$root/scripts/build.sh" -DDTM_MPI=OFF >/dev/null; fi
/usr/bin/python3 "$root/bench/perf_second_order.py" > "$root/docs/performance-second-order.md.tmp"
mv "$root/docs/performance-second-order.md.tmp" "$root/docs/performance-second-order.md"
cat "$root/docs/performance-second-order.md"
