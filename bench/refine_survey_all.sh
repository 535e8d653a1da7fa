#!/bin/bash
# The four surveys of docs/refine-survey.md, two at a time: refine on
# Gmsh's tutorials and demos at 1.3x the nodal-bound step (mesh alone, and
# with --posterior), and at 1.3x the input's global-basis step with
# --posterior (mesh alone, and with --max-added-mass 2). Writes each mode's
# table to OUTDIR/survey-MODE.md, then prints the joined table and the
# counts (bench/refine_survey_table.py).
# Usage: bench/refine_survey_all.sh DTMAP OUTDIR [EXAMPLES_DIR]
set -u
DTMAP=${1:?usage: refine_survey_all.sh DTMAP OUTDIR [EXAMPLES_DIR]}
OUT=${2:?usage: refine_survey_all.sh DTMAP OUTDIR [EXAMPLES_DIR]}
EX=${3:-/usr/share/doc/gmsh-doc/doc/gmsh}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
for pair in "bound posterior" "global global-mass"; do
  for mode in $pair; do
    bash "$HERE/refine_survey.sh" "$DTMAP" "$mode" 1.3 "$EX" > "$OUT/survey-$mode.md" &
  done
  wait
done
/usr/bin/python3 "$HERE/refine_survey_table.py" "$OUT/survey-bound.md" "$OUT/survey-posterior.md" \
  "$OUT/survey-global.md" "$OUT/survey-global-mass.md"
