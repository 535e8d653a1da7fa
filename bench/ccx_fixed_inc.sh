#!/bin/sh
# Build a CalculiX whose explicit increment can be fixed, for
# bench/ccx_c3d10.py (docs/curved.md) and tests/t376-deck-ccx-fixed.py.
# CalculiX 2.20 chooses the explicit increment itself: its Courant estimate,
# or, when the minimum increment asked for is larger, selective mass scaling,
# which changes the mass matrix. Neither lets a run sit at 0.999x of the exact
# step.
#
# The sources are Debian's own: the calculix-ccx source package of the
# release this machine runs (apt-get source, as a user would), with Debian's
# patches applied by dpkg-source. The script adds a deb-src list of its own
# beside the machine's apt sources (the same archives, Types: deb-src) when
# none is there, installs the package's build dependencies (apt-get
# build-dep), and makes one change in nonlingeo.c: when CCX_FIXED_INC is set,
# every place where the explicit increment is selected (at the start, and
# where it is selected again after contact changes) takes that value.
# Element routines, lumping and the time scheme are untouched. It builds with
# Debian's own Makefile and flags (debian/rules: spooles, ARPACK, USE_MT).
# Needs root (apt-get).
#
# Usage: sh bench/ccx_fixed_inc.sh OUTDIR   -> OUTDIR/ccx_fixed
set -eu
out=$(mkdir -p "$1" && cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
list=/etc/apt/sources.list.d/dtmap-deb-src.sources
if ! grep -rqs '^Types:.*deb-src\|^deb-src' /etc/apt/sources.list /etc/apt/sources.list.d/; then
  # The machine's own archives, as source archives.
  sed 's/^Types: deb$/Types: deb-src/' /etc/apt/sources.list.d/debian.sources > "$list"
fi
apt-get update -qq
DEBIAN_FRONTEND=noninteractive apt-get build-dep -y -qq calculix-ccx >/dev/null
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3 >/dev/null
cd "$out"
rm -rf calculix-ccx-*
apt-get source -qq calculix-ccx 2>/dev/null
src=$(ls -d "$out"/calculix-ccx-*/ccx_*/src | head -n 1)
python3 "$here/ccx_fixed_inc_patch.py" "$src/nonlingeo.c"
ver=$(basename "$(dirname "$src")" | sed 's/^ccx_//')
# Debian's flags (debian/rules), with OpenMP for the threaded solver.
make -C "$src" -j"${JOBS:-2}" "ccx_$ver" \
  CFLAGS="-O2 -w -I/usr/include/spooles -DARCH=\"Linux\" -DSPOOLES -DARPACK -DMATRIXSTORAGE -DUSE_MT=1 -fopenmp" \
  FFLAGS="-O2 -w -fallow-argument-mismatch -fopenmp" >/dev/null
cp "$src/ccx_$ver" "$out/ccx_fixed"
echo "$out/ccx_fixed"
