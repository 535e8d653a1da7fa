#!/bin/bash
# What Gmsh's optimisers pay in refine: one remesh (--max-iter 1) at 1.3x the
# recommended step of each model, with each set of passes (--optimise), the
# same size field every time. Prints per model and set the first round's
# recommended step over that of the remesh without any pass (the lift: what
# the pass does to the worst element), and the round's time (remesh and
# analysis, from the report) over that without any pass (the cost), then
# the median of each over the models of each dimension. Models: the bundled
# scenes and Gmsh's demos in 2D (plane stress) and 3D, meshed by Gmsh's
# default mesher on one thread (the same mesh for the same field).
# Usage: bench/refine_optimisers.sh DTMAP [EXAMPLES_DIR]
set -u
DTMAP=${1:?usage: refine_optimisers.sh DTMAP [EXAMPLES_DIR]}
EX=${2:-/usr/share/doc/gmsh-doc/doc/gmsh}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
PY=/usr/bin/python3
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cp -r "$EX" "$WORK/examples"
find "$WORK/examples" -name '*.gz' -exec gunzip -f {} +
cp "$ROOT"/geometries/*.geo "$ROOT"/geometries/*.xml "$WORK/"
sets2=(none relocate laplace relocate,laplace)
sets3=(none gmsh gmsh,relocate gmsh,netgen,relocate)
models=(bundled:plate_with_hole bundled:brazilian_disc bundled:notched_beam bundled:box
        tutorial/t1.geo tutorial/t2.geo tutorial/t5.geo tutorial/t10.geo demos/boolean/fillet_chamfer.geo
        demos/boolean/compsolid2.geo demos/boolean/simple2.geo demos/simple_geo/piece.geo)

scene_of() { # model -> scene path, and its dimension in $dim
  local m=$1 name
  if [[ $m == bundled:* ]]; then
    name=${m#bundled:}
    dim=$(grep -o 'dim="[0-9]"' "$WORK/$name.xml" | head -1 | tr -dc 0-9)
    echo "$WORK/$name.xml"
    return
  fi
  name=$(echo "$m" | tr '/' '_' | sed 's/\.geo$//')
  dim=$(cd "$(dirname "$WORK/examples/$m")" && $PY -c "
import gmsh; gmsh.initialize(); gmsh.option.setNumber('General.Terminal', 0)
gmsh.open('$(basename "$m")'); print(gmsh.model.getDimension())" 2>/dev/null | tail -1)
  [ "$dim" = 2 ] || dim=3
  local form=3d
  [ "$dim" = 2 ] && form=plane-stress
  cat > "$WORK/$name.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dtmap-scene version="1">
  <geometry file="$WORK/examples/$m"/>
  <meshing dim="$dim"/>
  <material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic formulation="$form"/></effects>
  <time safety="0.9" duration="1e-3"/>
</dtmap-scene>
XML
  echo "$WORK/$name.xml"
}

echo "| model | dim | passes | round-1 step / no pass | round time / no pass |"
echo "|---|---|---|---|---|"
: > "$WORK/rows"
for m in "${models[@]}"; do
  dim=3
  scene=$(scene_of "$m")
  dim=$(grep -o 'dim="[0-9]"' "$scene" | head -1 | tr -dc 0-9)
  (cd "$WORK" && "$DTMAP" run "$scene" -q -j 1 --report r.json -o r.msh) || continue
  target=$($PY -c "import json; print('%.6e' % (1.3 * json.load(open('$WORK/r.json'))['dt']['recommended']))")
  if [ "$dim" = 2 ]; then sets=("${sets2[@]}"); else sets=("${sets3[@]}"); fi
  base_step="" base_time=""
  for s in "${sets[@]}"; do
    (cd "$WORK" && "$DTMAP" refine "$scene" -q -j 1 --target "$target" --max-iter 1 --optimise "$s" \
       --report o.json -o o.msh >/dev/null 2>&1)
    read -r step secs < <($PY -c "
import json; r = json.load(open('$WORK/o.json'))['refine']['rounds']
print(r[1]['recommended'] if len(r) > 1 else 'nan', r[1]['seconds'] if len(r) > 1 else 'nan')")
    [ -z "$base_step" ] && base_step=$step base_time=$secs
    lift=$($PY -c "print('%.3f' % ($step / $base_step))")
    cost=$($PY -c "print('%.2f' % ($secs / $base_time))")
    echo "| $m | $dim | $s | $lift | $cost |"
    echo "$dim $s $lift $cost" >> "$WORK/rows"
  done
done
echo
echo "| dim | passes | median step / no pass | median time / no pass |"
echo "|---|---|---|---|"
$PY - "$WORK/rows" <<'PYEOF'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
for key in sorted({(r[0], r[1]) for r in rows}):
    sel = [r for r in rows if (r[0], r[1]) == key]
    print("| %s | %s | %.3f | %.2f |" % (key[0], key[1], statistics.median(float(r[2]) for r in sel),
                                      statistics.median(float(r[3]) for r in sel)))
PYEOF
