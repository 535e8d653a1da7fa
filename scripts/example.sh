#!/usr/bin/env bash
# README command 1: install what is missing, build dtmap as a user would
# (a plain CMake build: no tests, no benchmarks), and run it on the bundled
# Brazilian disc. Writes brazilian_disc_dt.msh (+ .opt) and
# brazilian_disc_dt.json in the current directory.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup.sh"
cmake -S "$root" -B "$root/build" >/dev/null
cmake --build "$root/build" -j"$(nproc)"
"$root/build/dtmap" run "$root/geometries/brazilian_disc.xml" \
  -o brazilian_disc_dt.msh --report brazilian_disc_dt.json
echo "open it with: gmsh brazilian_disc_dt.msh"
