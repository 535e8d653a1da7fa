#!/usr/bin/env bash
# README command 2: install what is missing, check the formatting
# (clang-format, .clang-format), build, and run the whole ctest suite twice:
# an optimised build, then an AddressSanitizer + UndefinedBehaviorSanitizer
# build of the same tests. The optimised build is the MPI build
# (-DDTM_MPI=ON) when Open MPI, PETSc and SLEPc are installed (setup.sh
# installs them), so it also runs the distributed tests (t9xx, real
# mpirun); the sanitizer build stays serial, which keeps a dtmap without
# MPI tested too.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup.sh"
jobs=$(nproc)
echo "== format (clang-format, .clang-format)"
(cd "$root" && git ls-files '*.c' '*.h' | xargs clang-format --dry-run -Werror)
mpi=OFF
if command -v mpirun >/dev/null && pkg-config --exists petsc slepc; then mpi=ON; fi
echo "== optimised build (DTM_MPI=$mpi)"
BUILD_DIR="$root/build" bash "$root/scripts/build.sh" -DDTM_MPI=$mpi
# A failure here does not stop the sanitizer half: both halves run and
# the script fails at the end if either did, so one slow or failing test
# on a loaded machine never hides the other build's results.
status=0
(cd "$root/build" && ctest --output-on-failure -j"$jobs") || status=$?
echo "== sanitizer build (ASan + UBSan)"
BUILD_DIR="$root/build-asan" bash "$root/scripts/build.sh" -DDTM_SANITIZE=ON -DDTM_MPI=OFF
# Gmsh and OpenMP runtimes keep allocations for the process lifetime; leaks
# in dtmap's own code are still reported through the suppressions file.
export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
(cd "$root/build-asan" && ctest --output-on-failure -j"$jobs") || status=$?
if [ "$status" -ne 0 ]; then echo "== the suite failed (see above)"; fi
exit "$status"
