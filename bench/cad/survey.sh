#!/bin/bash
# The real-CAD survey of docs/cad-corpus.md: brings the corpus of
# bench/cad/parts.tsv (bench/cad/corpus.py) if it is not there, runs
# bench/cad/survey.py on it under `nice -n 10`, and prints the tables of
# bench/cad/table.py. Restartable: results already in CAD_OUT are kept.
# Environment:
#   DTMAP        the dtmap binary (default build/dtmap of this tree)
#   CAD_DIR      where the parts are (default build/cad-parts)
#   CAD_OUT      where results go (default build/cad-survey)
#   CAD_PARTS    a subset of parts, space- or comma-separated (default all)
#   CAD_CONFIGS  a subset of 1.5-default 1.3-default 1.5-posterior 1.3-posterior (default all, in that order)
#   CAD_TIMEOUT  the time limit of each dtmap command in seconds (default 900)
#   CAD_MIRRORS  the git mirrors the parts are read from (default /work/.mirror)
# Usage: [DTMAP=...] [CAD_PARTS=...] [CAD_CONFIGS=...] bench/cad/survey.sh
set -eu
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
PY=/usr/bin/python3
DTMAP=${DTMAP:-$ROOT/build/dtmap}
CAD_DIR=${CAD_DIR:-$ROOT/build/cad-parts}
CAD_OUT=${CAD_OUT:-$ROOT/build/cad-survey}
CAD_CONFIGS=${CAD_CONFIGS:-1.5-default 1.3-default 1.5-posterior 1.3-posterior}
CAD_TIMEOUT=${CAD_TIMEOUT:-900}
[ -x "$DTMAP" ] || { echo "survey.sh: no dtmap binary at $DTMAP (set DTMAP)" >&2; exit 2; }
if [ ! -s "$CAD_DIR/parts.list" ]; then
  nice -n 10 $PY "$HERE/corpus.py" "$CAD_DIR" --mirrors "${CAD_MIRRORS:-/work/.mirror}"
fi
mkdir -p "$CAD_OUT"
"$DTMAP" --version > "$CAD_OUT/dtmap-version.txt" 2>&1 || true
nice -n 10 $PY "$HERE/survey.py" --dtmap "$DTMAP" --parts-dir "$CAD_DIR" --out "$CAD_OUT" \
  --parts "${CAD_PARTS:-}" --configs "$CAD_CONFIGS" --timeout "$CAD_TIMEOUT"
$PY "$HERE/table.py" "$CAD_OUT"
