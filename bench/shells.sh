#!/usr/bin/env bash
# Regenerate docs/shells-bench.md: what shell and beam sections cost against
# the same mesh analysed as membranes and trusses (no rotations). The
# bundled stiffened panel (geometries/stiffened_panel.geo) is meshed once
# per size with Gmsh's Python API into BENCH_WORK (default
# /tmp/dtmap-shells-bench); each scene is run with `dtmap run` and
# `dtmap run --posterior`, alternating, BENCH_REPS times (default 3); the
# table gives the medians of the wall time and of the report's stage
# timings. SHELLS_SIZES (default "0.004 0.002") lists the mesh sizes, m.
# A benchmark, not a test.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build-bench}
export BENCH_WORK=${BENCH_WORK:-/tmp/dtmap-shells-bench}
export BENCH_REPS=${BENCH_REPS:-3}
sizes=${SHELLS_SIZES:-0.004 0.002}
bash "$root/bench/setup.sh" >/dev/null
bash "$root/scripts/build.sh" -DDTM_MPI=OFF >/dev/null
mkdir -p "$BENCH_WORK"
/usr/bin/python3 "$root/bench/shells.py" "$root" "$BENCH_WORK" "$BUILD_DIR/dtmap" "$BENCH_REPS" $sizes \
  >"$root/docs/shells-bench.md.tmp"
mv "$root/docs/shells-bench.md.tmp" "$root/docs/shells-bench.md"
cat "$root/docs/shells-bench.md"
