#!/usr/bin/env bash
# Regenerate docs/performance-shells.md (issue 38: shells at most 2x
# membranes): bench/perf_shells.py runs the stiffened panel at 5 mm as
# shells and beams against membranes and trusses, by two builds: BEFORE
# (default: main's code, exported with git archive into
# BENCH_MAIN_SRC=/tmp/dtmap-perf-shells-main and built there) and AFTER
# (default: this tree's BUILD_DIR, $root/build). BENCH_REPS alternating pairs
# (default 5); BENCH_WORK holds the mesh and the runs. Run it under nice on
# a shared machine. A benchmark, not a test.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
main_src=${BENCH_MAIN_SRC:-/tmp/dtmap-perf-shells-main}
if [ -z "${BEFORE:-}" ]; then
  if [ ! -x "$main_src/build/dtmap" ]; then
    mkdir -p "$main_src"
    git -C "$root" archive main | tar -x -C "$main_src"
    BUILD_DIR="$main_src/build" bash "$main_src/scripts/build.sh" -DDTM_MPI=OFF >/dev/null
  fi
  BEFORE="$main_src/build/dtmap"
fi
export BEFORE
export AFTER=${AFTER:-${BUILD_DIR:-$root/build}/dtmap}
[ -x "$AFTER" ] || BUILD_DIR=$(dirname "$AFTER") bash "$root/scripts/build.sh" -DDTM_MPI=OFF >/dev/null
/usr/bin/python3 "$root/bench/perf_shells.py" >"$root/docs/performance-shells.md.tmp"
mv "$root/docs/performance-shells.md.tmp" "$root/docs/performance-shells.md"
cat "$root/docs/performance-shells.md"
