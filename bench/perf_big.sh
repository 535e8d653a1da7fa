#!/usr/bin/env bash
# Regenerate docs/performance-big.md: 1e7 tets from a .msh and 1e6 tets
# from a geometry (HXT, 2 threads), dtmap before and after a change side by
# side with Gmsh, with page faults and peak RSS (bench/perf_big.py). Set
# DTMAP_BEFORE to the dtmap of a build of main for the before columns.
# About 10-20 minutes on 2 cores and 3 GB of memory; meshes are kept in
# BENCH_WORK (default /tmp/dtmap-perf), shared with bench/perf.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build-bench}
bash "$root/scripts/build.sh" -DDTM_MPI=OFF >/dev/null
/usr/bin/python3 "$root/bench/perf_big.py" > "$root/docs/performance-big.md.tmp"
mv "$root/docs/performance-big.md.tmp" "$root/docs/performance-big.md"
cat "$root/docs/performance-big.md"
