#!/usr/bin/env bash
# The sweep figures of docs/accuracy.md: error against hours on the bundled
# Brazilian disc (2D, tri3), the notched beam with a cohesive zone in the
# beam (3D, tet4; the scene as bundled plus <cohesive groups="beam"/>) and
# the box (3D, tet4), each with the scene's own <time> (no f-max: the
# sweep's default frequency). Writes docs/images/sweep_*.png and prints the
# tables; the CSVs stay in BENCH_WORK (default /tmp/dtmap-accuracy).
# Then what the measures add to the analysis (bench_accuracy_cost).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
work=${BENCH_WORK:-/tmp/dtmap-accuracy}
mkdir -p "$work"
cp "$root"/geometries/{brazilian_disc,notched_beam,box}.{geo,xml} "$work"/
sed 's|<elastic formulation="3d" length="eigen"/>|&\n    <cohesive groups="beam"/>|' \
  "$root/geometries/notched_beam.xml" > "$work/notched_beam_cohesive.xml"
cd "$work"
run() { # scene sizes image
  "$build/dtmap" sweep "$1" --sizes "$2" --csv "${3%.png}.csv" --plot "$root/docs/images/$3"
}
run brazilian_disc.xml 4e-3,2e-3,1e-3,7e-4,5e-4 sweep_brazilian_disc.png
run notched_beam_cohesive.xml 16e-3,12e-3,8e-3,6e-3 sweep_notched_beam.png
run box.xml 16e-3,10e-3,8e-3,5e-3,4e-3 sweep_box.png
[ "${SKIP_OVERHEAD:-0}" = 1 ] || "$build/bench/bench_accuracy_cost" box.xml 8e-3 4e-3 2e-3
