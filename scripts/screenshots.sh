#!/usr/bin/env bash
# The pictures in docs/images/, made with the project's own tools: dtmap's
# snapshots (Gmsh's renderer, `dtmap run --png`) of the notched beam and the
# Brazilian disc, and screenshots of Gmsh's GUI with dtmap as its ONELAB
# solver after Run on the notched beam and the reinforced block
# (scripts/gui_screenshot.py, Gmsh's Python API and Pillow under Xvfb).
# Builds dtmap first; needs root for the two Python packages.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup.sh"
for p in python3-gmsh python3-pil; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" ||
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$p" >/dev/null
done
build=${BUILD_DIR:-$root/build}
BUILD_DIR="$build" bash "$root/scripts/build.sh"
dtmap="$build/dtmap"
out="$root/docs/images"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
cp "$root"/geometries/notched_beam.* "$root"/geometries/brazilian_disc.* "$root"/geometries/reinforced_block.* "$work"/
"$dtmap" run "$work/notched_beam.xml" -q -o "$work/beam.msh" --png "$out/notched_beam" --width 800 --height 560
"$dtmap" run "$work/brazilian_disc.xml" -q -o "$work/disc.msh" --png "$work/disc" --width 800 --height 560
mv "$work/disc_dt.png" "$out/brazilian_disc_dt.png"
for m in notched_beam:gmsh_panel reinforced_block:reinforced_block_gui; do
  xvfb-run -a -s "-screen 0 1700x1000x24" /usr/bin/python3 "$root/scripts/gui_screenshot.py" \
    "$work/${m%%:*}.geo" "$dtmap" "$out/${m#*:}.png" >/dev/null 2>&1
done
ls -l "$out"
