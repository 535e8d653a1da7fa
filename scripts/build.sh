#!/usr/bin/env bash
# The developer build: configure and build dtmap into BUILD_DIR (default
# build/) with the test suite, the benchmarks and -Werror (what CI and
# scripts/test.sh use; a plain `cmake -S . -B build` is a user build without
# them, see cmake/options.cmake). Extra arguments go to cmake's configure
# step, e.g. -DDTM_SANITIZE=ON.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DDTM_TESTS=ON -DDTM_BENCHMARKS=ON -DDTM_WERROR=ON -DDTM_PLOT=ON "$@" >/dev/null
cmake --build "$build" -j"$(nproc)"
