#!/usr/bin/env bash
# What the converged integration of curved tet10 costs (issue 21): runs
# bench/curved_cost.py on a ball of CURVED_TARGET (default 2e5) tet10 in
# BENCH_WORK (default /tmp/dtmap-curved-bench; the mesh is kept), BENCH_REPS
# (default 3) runs per integration, and prints the table quoted in
# docs/curved.md. A benchmark, not a test.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build-bench}
bash "$root/scripts/build.sh" -DDTM_MPI=OFF >/dev/null
/usr/bin/python3 "$root/bench/curved_cost.py" "$BUILD_DIR/dtmap" "${BENCH_WORK:-/tmp/dtmap-curved-bench}" \
  "${CURVED_TARGET:-2e5}" "${BENCH_REPS:-3}"
