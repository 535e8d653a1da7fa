#!/usr/bin/env bash
# Run a libFuzzer target of tests/fuzz/ for a given time:
#   bash scripts/fuzz.sh [TARGET] [SECONDS] [--merge]
# TARGET is a fuzz target name (default: scene; the corpus is
# tests/data/fuzz/TARGET/), SECONDS the run time (default 600). The targets
# are built with clang, -fsanitize=fuzzer,address,undefined, into
# build-fuzz/. New inputs go to build-fuzz/corpus/TARGET/, findings to
# build-fuzz/findings/TARGET/ (replay one with build-fuzz/tests/fuzz-TARGET
# FILE). With --merge, the run's corpus is minimised into the committed one
# (tests/data/fuzz/TARGET/), which ctest replays. Extra libFuzzer flags can
# be passed in FUZZ_FLAGS, e.g. FUZZ_FLAGS="-jobs=2 -workers=2".
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
target=${1:-scene}
seconds=${2:-600}
merge=${3:-}
build=${FUZZ_BUILD_DIR:-$root/build-fuzz}
bash "$root/scripts/setup.sh"
CC=clang cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDTM_TESTS=ON -DDTM_FUZZ=ON >/dev/null
cmake --build "$build" -j"$(nproc)" --target "fuzz-$target"
corpus=$root/tests/data/fuzz/$target
work=$build/corpus/$target
findings=$build/findings/$target
mkdir -p "$work" "$findings"
seeds=("$corpus")
[ "$target" = scene ] && seeds+=("$root/tests/data/scenes/fuzz" "$root/geometries")
dict=()
[ -f "$root/tests/fuzz/$target.dict" ] && dict=(-dict="$root/tests/fuzz/$target.dict")
max_len=16384
limits=()
if [ "$target" = msh ]; then
  # Gmsh answers a header announcing 2^40 elements by asking for that much
  # memory and handling the failure (std::bad_alloc -> "Error loading").
  # Let such requests fail as they do outside the sanitizer instead of being
  # reported; what Gmsh or dtmap really uses is still bounded by the RSS limit.
  max_len=65536
  export ASAN_OPTIONS="allocator_may_return_null=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
  limits=(-malloc_limit_mb=1000000)
fi
# Gmsh, OpenCASCADE and OpenMP keep allocations for the process lifetime.
export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0"
# shellcheck disable=SC2086
"$build/tests/fuzz-$target" "${dict[@]}" "${limits[@]}" -max_total_time="$seconds" -max_len=$max_len -timeout=20 \
  -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$findings/" ${FUZZ_FLAGS:-} "$work" "${seeds[@]}"
if [ "$merge" = --merge ]; then
  "$build/tests/fuzz-$target" -merge=1 "${dict[@]}" -max_len=$max_len "$corpus" "$work"
  echo "fuzz: $(ls "$corpus" | wc -l) inputs in $corpus"
fi
