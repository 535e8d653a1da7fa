#!/usr/bin/env bash
# The curved ball's element map against its straight-sided twin, for two
# builds side by side (issue 46): the `effects` stage (the level search, the
# element map and the curvature pass) of `dtmap run --views-only` on
# bench/perf.py's ball_curved.xml and ball_straight.xml (996,455 tet10,
# 83,911 curved), both builds alternated ROUNDS times (default 5), and the
# ratio curved / straight of each build in each round, then the medians.
# The balls are those bench/perf.sh makes in BENCH_WORK (default
# /tmp/dtmap-perf); BENCH_THREADS (default 2) threads. A benchmark, not a
# test: about 20 s a round.
# Usage: bench/curved_map_ab.sh BEFORE_DTMAP AFTER_DTMAP [ROUNDS]
set -euo pipefail
before=$(realpath "$1") after=$(realpath "$2") rounds=${3:-5}
work=${BENCH_WORK:-/tmp/dtmap-perf} threads=${BENCH_THREADS:-2}
for s in ball_curved ball_straight; do
  [ -f "$work/$s.xml" ] || { echo "curved_map_ab.sh: $work/$s.xml not found (bench/perf.sh makes it)" >&2; exit 2; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$work"
for r in $(seq "$rounds"); do
  for b in before after; do
    bin=$before
    [ $b = after ] && bin=$after
    for k in curved straight; do
      "$bin" run "ball_$k.xml" -q --views-only -j "$threads" -o "$tmp/o.msh" --report "$tmp/${r}_${b}_$k.json"
    done
  done
done
/usr/bin/python3 - "$tmp" "$rounds" "$threads" <<'PY'
import json, statistics, sys
tmp, rounds, threads = sys.argv[1], int(sys.argv[2]), sys.argv[3]
def eff(r, b, k):
    return json.load(open(f"{tmp}/{r}_{b}_{k}.json"))["timings"]["effects"]
print(f"element map (`effects`, s, {threads} threads): curved / straight = ratio, {rounds} alternating rounds")
rat = {"before": [], "after": []}
for r in range(1, rounds + 1):
    cells = []
    for b in ("before", "after"):
        c, s = eff(r, b, "curved"), eff(r, b, "straight")
        rat[b].append(c / s)
        cells.append(f"{b} {c:.2f} / {s:.2f} = {c / s:.3f}")
    print("  ".join(cells))
for b in ("before", "after"):
    print(f"{b}: median {statistics.median(rat[b]):.3f} (range {min(rat[b]):.3f}-{max(rat[b]):.3f})")
PY
