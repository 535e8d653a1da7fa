#!/bin/bash
# Refine on Gmsh's own tutorials and demos (Debian's gmsh-doc examples), as a
# new user would: each .geo gets a scene (steel, elastic, default material,
# the model's own dimension, 3 when Gmsh's Python module cannot tell),
# `dtmap run` gives its recommended step, and `dtmap refine --target F x rec.
# --max-iter 3` runs on it. MODE picks the survey:
#   bound        F x the nodal-bound step, refine on the nodal bound (mesh only)
#   posterior    F x the nodal-bound step, refine --posterior
#   global       F x the input's global-basis step (run --posterior), refine --posterior
#   global-mass  the same with --max-added-mass 2
# Prints one markdown row per model: outcome (exit code or signal), how the
# target was met (input, mesh, mesh and point masses), the first cause the
# report names, the kept mesh's cost over the input's, the remeshes run, and
# the point masses added (% of the mass), or the share they would need
# beyond the limit.
# Usage: bench/refine_survey.sh DTMAP MODE [FACTOR] [EXAMPLES_DIR] [MODEL...]
set -u
DTMAP=${1:?usage: refine_survey.sh DTMAP MODE [FACTOR] [EXAMPLES_DIR] [MODEL...]}
MODE=${2:?MODE: bound, posterior, global or global-mass}
FACTOR=${3:-1.3}
EX=${4:-/usr/share/doc/gmsh-doc/doc/gmsh}
shift 4 2>/dev/null || shift $#
PY=/usr/bin/python3
case "$MODE" in
  bound) run_opts=(); refine_opts=() ;;
  posterior) run_opts=(); refine_opts=(--posterior) ;;
  global) run_opts=(--posterior); refine_opts=(--posterior) ;;
  global-mass) run_opts=(--posterior); refine_opts=(--posterior --max-added-mass 2) ;;
  *) echo "unknown MODE $MODE" >&2; exit 2 ;;
esac
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
# Debian compresses some of the examples (t1.geo.gz, t13_data.stl.gz, ...):
# work on an uncompressed copy.
cp -r "$EX" "$WORK/examples"
find "$WORK/examples" -name '*.gz' -exec gunzip -f {} +
EX="$WORK/examples"
models=("$@")
if [ ${#models[@]} -eq 0 ]; then
  mapfile -t models < <(cd "$EX" && ls tutorial/*.geo demos/*/*.geo 2>/dev/null)
fi
echo "| model | outcome | met by | cause | cost ratio | rounds | mass % |"
echo "|---|---|---|---|---|---|---|"
for m in "${models[@]}"; do
  name=$(echo "$m" | tr '/' '_' | sed 's/\.geo$//')
  dim=$(cd "$(dirname "$EX/$m")" && timeout 120 $PY -c "
import gmsh,sys
gmsh.initialize(); gmsh.option.setNumber('General.Terminal',0)
gmsh.open('$(basename "$m")'); print(gmsh.model.getDimension())" 2>/dev/null | tail -1)
  case "$dim" in 2) form='formulation="plane-stress" ';; *) dim=3; form='formulation="3d" ';; esac
  cat > "$WORK/$name.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dtmap-scene version="1">
  <geometry file="$EX/$m"/>
  <meshing dim="$dim"/>
  <material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic ${form}length="eigen"/></effects>
  <time safety="0.9" duration="1e-3"/>
</dtmap-scene>
XML
  (cd "$WORK" && timeout 300 "$DTMAP" run "$name.xml" -q "${run_opts[@]}" --report "$name.run.json" -o "$name.run.msh" >/dev/null 2>"$name.run.err")
  rc=$?
  if [ $rc -ne 0 ]; then echo "| $m | run exit $rc: $(head -c 150 "$WORK/$name.run.err" | tr '\n|' ' /') | | | | | |"; continue; fi
  rec=$($PY -c "import json;print(json.load(open('$WORK/$name.run.json'))['dt']['recommended'])")
  target=$($PY -c "print('%.6e' % ($FACTOR*$rec))")
  (cd "$WORK" && timeout 600 "$DTMAP" refine "$name.xml" -q "${refine_opts[@]}" --target "$target" --max-iter 3 --report "$name.json" -o "$name.msh" >/dev/null 2>"$name.err")
  rc=$?
  if [ $rc -gt 128 ]; then out="signal $((rc - 128))"; elif [ $rc -eq 0 ]; then out="met"; else out="exit $rc"; fi
  row=$($PY - "$WORK/$name.json" <<'PYEOF'
import json, sys
try:
    j = json.load(open(sys.argv[1]))['refine']
except Exception:
    print('| | | | | |'); sys.exit()
causes = j.get('causes', [])
cause = causes[0]['kind'] if causes else j.get('stopped', '')
r = j['rounds']
mass = [x.get('added_percent', 0) for x in r if x.get('kind') == 'mass']
mesh = sum(1 for x in r if x.get('kind') == 'mesh')
need = j.get('mass_needed_percent')
mass_cell = '%.3g' % mass[0] if mass else ('needs %.3g' % need if need is not None else '')
print('| %s | %s | %.2f | %d | %s |' % (j.get('met_by', ''), cause, r[j['best']]['element_steps'] / r[0]['element_steps'],
                                       mesh, mass_cell))
PYEOF
)
  if [ "$out" != met ] && [ "$row" = "| | | | | |" ]; then row="| | $(head -c 160 "$WORK/$name.err" | tr '\n|' ' /') | | | |"; fi
  echo "| $m | $out $row"
done
