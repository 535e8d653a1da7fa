#!/usr/bin/env bash
# What the benchmarks need beyond scripts/setup.sh (not the tests): scipy
# for the eigsh comparison, Gmsh's Python API for reading meshes there,
# CalculiX (ccx) for the cost calibration (bench/ccx_calibrate.py), and
# what bench/ccx_fixed_inc.sh builds CalculiX's sources with (the
# fixed-increment ccx of bench/ccx_c3d10.py and bench/deck_ccx.py):
# gfortran, SPOOLES, ARPACK, LAPACK.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup.sh"
missing=()
for p in python3-scipy python3-gmsh calculix-ccx gfortran libspooles-dev libarpack2-dev liblapack-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
