#!/usr/bin/env bash
# Regenerate the roofline table of the element kernels (bench/roofline.py,
# bench/roofline.c) and put it in docs/performance.md in place of the
# section "## Roofline of the element kernels" (appended when absent).
# With ROOFLINE_BEFORE=path of another build's bench_roofline (the code
# before a change), its rows run in the same alternation. About a minute.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build-bench}
if [ ! -x "$BUILD_DIR/bench/bench_roofline" ]; then BUILD_DIR=$BUILD_DIR bash "$root/scripts/build.sh" -DDTM_MPI=OFF >/dev/null; fi
table=$(/usr/bin/python3 "$root/bench/roofline.py")
/usr/bin/python3 - "$root/docs/performance.md" "$table" <<'PY'
import sys
path, table = sys.argv[1], sys.argv[2].rstrip("\n") + "\n"
text = open(path).read()
head = "## Roofline of the element kernels"
if head in text:
    start = text.index(head)
    nxt = text.find("\n## ", start + len(head))
    text = text[:start] + table + (text[nxt:] if nxt >= 0 else "")
else:
    text = text.rstrip("\n") + "\n\n" + table
open(path + ".tmp", "w").write(text)
PY
mv "$root/docs/performance.md.tmp" "$root/docs/performance.md"
echo "$table"
