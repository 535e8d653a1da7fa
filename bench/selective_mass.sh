#!/bin/bash
# The tables of docs/selective-mass.md: bench/selective_mass.py on the thin-walled
# parts of the real-CAD corpus (bench/cad/parts.tsv), under `nice -n 10`.
# Environment:
#   DTMAP      the dtmap binary (default build/dtmap of this tree)
#   CAD_DIR    where the parts are (brought there when missing; default build/cad-parts)
#   SMS_OUT    where reports go (default build/sms-bench)
#   SMS_PARTS  a comma-separated subset of parts (default the script's six)
#   SMS_STEPS  verify's steps (default 2000)
# Usage: [DTMAP=...] bench/selective_mass.sh
set -eu
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
DTMAP=${DTMAP:-$ROOT/build/dtmap}
[ -x "$DTMAP" ] || { echo "selective_mass.sh: no dtmap binary at $DTMAP (set DTMAP)" >&2; exit 2; }
ARGS=()
[ -n "${SMS_PARTS:-}" ] && ARGS+=(--parts "$SMS_PARTS")
exec nice -n 10 /usr/bin/python3 "$HERE/selective_mass.py" --dtmap "$DTMAP" \
  --parts-dir "${CAD_DIR:-$ROOT/build/cad-parts}" --out "${SMS_OUT:-$ROOT/build/sms-bench}" \
  --steps "${SMS_STEPS:-2000}" --mirrors "${CAD_MIRRORS:-/work/.mirror}" "${ARGS[@]}"
