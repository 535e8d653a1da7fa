#!/usr/bin/env bash
# Test: the installed package works on its own. `cmake --install` into a
# temporary prefix, which is then moved (so nothing may point at where it
# was installed, nor into the build tree), and from the moved prefix, in an
# environment without the build tree (env -i, no LD_LIBRARY_PATH):
#   - the files are there; libdtmap has SONAME libdtmap.so.MAJOR and no
#     RUNPATH, dtmap the relative RUNPATH $ORIGIN/../LIBDIR;
#   - dtmap --version and dtmap run work, and the report follows the
#     installed JSON Schema;
#   - a C client builds with pkg-config and with find_package(dtmap) and
#     prints the same recommended step as dtmap run; find_package refuses
#     another major version;
#   - the example effect builds from share/dtmap/examples against the
#     installed headers and the installed dtmap loads it;
#   - the Python module imports from the prefix (whose folder is on
#     python3's path for /usr/local), finds the prefix's libdtmap, and the
#     example script prints the recommended step of `dtmap run` on the same
#     mesh, digit for digit (as far as the report keeps them);
#   - `man dtmap` finds the page with PREFIX/bin on PATH, and the bash
#     completion completes.
# Arguments: SRC BUILD WORK CC PYTHON LIBDIR PYDIR [SANITIZER_FLAGS as a CMake list]
# (PY_PRELOAD in the environment: sanitizer runtimes python3 must preload).
set -euo pipefail
src=$1 build=$2 work=$3 cc=$4 python=$5 libdir=$6 pydir=$7
san=${8:-}
san=${san//;/ }
fail() {
  echo "t003-install: $*" >&2
  exit 1
}

rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/staged" >"$work/install.log" || fail "cmake --install failed"
cp -a "$work/staged" "$work/prefix"
rm -rf "$work/staged"
P=$work/prefix
L=$P/$libdir

# ---- the files ----
for f in bin/dtmap "$libdir/libdtmap.so" "$libdir/libdtmap.so.0" "$libdir/cmake/dtmap/dtmapConfig.cmake" \
  "$libdir/cmake/dtmap/dtmapConfigVersion.cmake" "$libdir/cmake/dtmap/dtmapTargets.cmake" \
  "$libdir/pkgconfig/dtmap.pc" share/dtmap/dtmap-scene.xsd share/dtmap/dtmap-report.schema.json \
  share/dtmap/examples/courant_effect.c share/dtmap/examples/box.py share/man/man1/dtmap.1 \
  share/bash-completion/completions/dtmap "$pydir/dtmap/__init__.py" "$pydir/dtmap/_install.py"; do
  [ -e "$P/$f" ] || fail "not installed: $f"
done
for h in "$src"/include/dtmap/*.h; do
  cmp -s "$h" "$P/include/dtmap/$(basename "$h")" || fail "header not installed as is: $(basename "$h")"
done
if grep -rIl -e "$build" -e "$work/staged" "$P" >"$work/stale.txt"; then
  fail "installed text files name the build tree or the install location: $(tr '\n' ' ' <"$work/stale.txt")"
fi
readelf -d "$L/libdtmap.so.0" >"$work/lib.dyn"
grep -q 'SONAME.*\[libdtmap\.so\.0\]' "$work/lib.dyn" || fail "libdtmap has no SONAME libdtmap.so.0"
! grep -qE 'RPATH|RUNPATH' "$work/lib.dyn" || fail "libdtmap has a RUNPATH: $(grep -E 'RPATH|RUNPATH' "$work/lib.dyn")"
readelf -d "$P/bin/dtmap" >"$work/bin.dyn"
grep -qF "RUNPATH" "$work/bin.dyn" && grep -qF "[\$ORIGIN/../$libdir]" "$work/bin.dyn" ||
  fail "dtmap's RUNPATH is not \$ORIGIN/../$libdir: $(grep -E 'RPATH|RUNPATH' "$work/bin.dyn" || echo none)"

# ---- a clean environment: no build tree, no library path ----
clean=(env -i PATH=/usr/bin:/bin HOME="$work" LANG=C.UTF-8)
[ -n "${ASAN_OPTIONS:-}" ] && clean+=(ASAN_OPTIONS="$ASAN_OPTIONS")
[ -n "${LSAN_OPTIONS:-}" ] && clean+=(LSAN_OPTIONS="$LSAN_OPTIONS")
cd "$work"
loaded=$("${clean[@]}" ldd "$P/bin/dtmap" | sed -n 's/.*libdtmap\.so\.0 => \([^ ]*\) .*/\1/p')
[ "$(readlink -f "$loaded")" = "$(readlink -f "$L/libdtmap.so.0")" ] || fail "dtmap loads libdtmap from '$loaded'"
"${clean[@]}" "$P/bin/dtmap" --version >version.txt || fail "dtmap --version failed"
grep -qE '^dtmap [0-9]+\.[0-9]+\.[0-9]+ \(libdtmap ' version.txt || fail "no dtmap version: $(cat version.txt)"
grep -qE '^Gmsh [0-9]+\.[0-9]+\.[0-9]+ ' version.txt || fail "no Gmsh version: $(cat version.txt)"
grep -qE '^effect API [0-9]+' version.txt || fail "no effect API version: $(cat version.txt)"
"${clean[@]}" "$P/bin/dtmap" run "$src/geometries/plate_with_hole.xml" -q -o plate.msh --report plate.json ||
  fail "the installed dtmap cannot run a scene"
"$python" "$src/tests/common/report_schema.py" "$P/share/dtmap/dtmap-report.schema.json" plate.json ||
  fail "the report does not follow the installed schema"
recommended() { "$python" -c "import json,sys; print(repr(json.load(open(sys.argv[1]))['dt']['recommended']))" "$1"; }
rec=$(recommended plate.json)
# The same double, as the report holds it: cJSON prints 15 significant digits whenever they
# read back within DBL_EPSILON relative, so a report value is one unit in the last place at most.
same_double() {
  "$python" -c "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]);
sys.exit(abs(a - b) > sys.float_info.epsilon * max(abs(a), abs(b)))" "$1" "$2"
}

# ---- C clients: pkg-config and find_package ----
cat >client.c <<'EOF'
/* A program built against the installed dtmap: analyse a scene and print
 * the versions and the recommended step. */
#include <dtmap/analysis.h>
#include <dtmap/effect.h>
#include <dtmap/error.h>
#include <dtmap/gmsh.h>
#include <dtmap/version.h>
#include <stdio.h>

int main(int argc, char **argv) {
  dtm_scene *s = NULL;
  dtm_analysis *a = NULL;
  if (argc != 2 || dtm_scene_load(argv[1], &s) || dtm_gmsh_start(0) || dtm_analysis_run(s, &a)) {
    fprintf(stderr, "client: %s\n", dtm_error_message());
    return 2;
  }
  printf("%s %d %.17g\n", dtm_version(), DTM_EFFECT_API_VERSION, dtm_analysis_recommended(a));
  dtm_analysis_destroy(&a);
  dtm_gmsh_stop();
  dtm_scene_destroy(&s);
  return 0;
}
EOF
export PKG_CONFIG_PATH=$L/pkgconfig
pc_cflags=$(pkg-config --cflags dtmap) && pc_libs=$(pkg-config --libs dtmap) || fail "pkg-config does not know dtmap"
pc_libdir=$(pkg-config --variable=libdir dtmap)
[ "$(cd "$pc_libdir" && pwd -P)" = "$(cd "$L" && pwd -P)" ] || fail "pkg-config's libdir $pc_libdir is not $L"
# shellcheck disable=SC2086
"$cc" $san -std=c11 -Wall -Wextra -Werror client.c $pc_cflags $pc_libs -Wl,-rpath,"$pc_libdir" -o client-pc ||
  fail "a client does not build with pkg-config ($pc_cflags $pc_libs)"
check_client() {
  local out
  out=$("${clean[@]}" "$1" "$src/geometries/plate_with_hole.xml" 2>/dev/null | tail -1) || fail "$1 failed"
  same_double "$(echo "$out" | cut -d' ' -f3)" "$rec" || fail "$1 printed '$out'; dtmap run recommends $rec"
}
check_client ./client-pc

mkdir -p cm
cat >cm/CMakeLists.txt <<'EOF'
cmake_minimum_required(VERSION 3.18)
project(client C)
find_package(dtmap 0.1 REQUIRED)
add_executable(client ../client.c)
target_link_libraries(client PRIVATE dtmap::dtmap)
if(NOT EXISTS ${dtmap_DATA_DIR}/dtmap-report.schema.json)
  message(FATAL_ERROR "dtmap_DATA_DIR ${dtmap_DATA_DIR} has no report schema")
endif()
EOF
"${clean[@]}" cmake -S cm -B cm/build -DCMAKE_PREFIX_PATH="$P" -DCMAKE_C_FLAGS="$san" \
  -DCMAKE_EXE_LINKER_FLAGS="$san" >cm.log 2>&1 || fail "find_package(dtmap) failed: $(cat cm.log)"
"${clean[@]}" cmake --build cm/build >>cm.log 2>&1 || fail "the find_package client does not build: $(cat cm.log)"
check_client cm/build/client
mkdir -p cm2
sed 's/find_package(dtmap 0.1 REQUIRED)/find_package(dtmap 1 REQUIRED)/' cm/CMakeLists.txt >cm2/CMakeLists.txt
if "${clean[@]}" cmake -S cm2 -B cm2/build -DCMAKE_PREFIX_PATH="$P" >cm2.log 2>&1; then
  fail "find_package(dtmap 1) accepted dtmap $(head -1 version.txt)"
fi

# ---- an external effect from the installed example and headers ----
# shellcheck disable=SC2086
"$cc" $san -std=c11 -Wall -Wextra -Werror -shared -fPIC $pc_cflags "$P/share/dtmap/examples/courant_effect.c" \
  $pc_libs -o libcourant.so || fail "the example effect does not build against the installed headers"
cat >courant.xml <<EOF
<dtmap-scene version="1">
  <geometry file="$src/geometries/plate_with_hole.geo"/>
  <meshing size="5e-3" dim="2"/>
  <material name="aluminium" groups="plate" E="70e9" nu="0.33" rho="2700"/>
  <effects><effect library="$work/libcourant.so" name="courant" speed="5000"/></effects>
</dtmap-scene>
EOF
"${clean[@]}" "$P/bin/dtmap" run courant.xml -q -o courant.msh --report courant.json ||
  fail "the installed dtmap cannot run the example effect"
"$python" -c "import json; assert json.load(open('courant.json'))['effects'] == ['courant']" ||
  fail "courant.json does not name the courant effect"

# ---- the Python module from the prefix ----
pyenv=("${clean[@]}" PYTHONPATH="$P/$pydir" PYTHONDONTWRITEBYTECODE=1)
[ -n "${PY_PRELOAD:-}" ] && pyenv+=(LD_PRELOAD="$PY_PRELOAD" ASAN_OPTIONS=detect_leaks=0)
"$python" -c "import sys; sys.exit('/usr/local/$pydir' not in sys.path)" ||
  fail "$python would not find the module installed under /usr/local/$pydir"
lib=$("${pyenv[@]}" "$python" -c "import dtmap; print(dtmap.LIBRARY)") || fail "import dtmap fails from the prefix"
[ "$(readlink -f "$lib")" = "$(readlink -f "$L/libdtmap.so.0")" ] || fail "dtmap's Python module loaded $lib"
mkdir -p py
(cd py && "${pyenv[@]}" "$python" "$P/share/dtmap/examples/box.py" >box.out 2>box.err) ||
  fail "the example script failed: $(cat py/box.err)"
cat >py/box.xml <<'EOF'
<dtmap-scene version="1">
  <mesh file="box.msh"/>
  <material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic/></effects>
</dtmap-scene>
EOF
(cd py && "${clean[@]}" "$P/bin/dtmap" run box.xml -q -o box_dt.msh --report box.json) || fail "dtmap run on box.msh"
py_rec=$(sed -n 's/^recommended step \([^ ]*\) s.*/\1/p' py/box.out)
[ -n "$py_rec" ] || fail "the example script printed no step: $(cat py/box.out)"
same_double "$py_rec" "$(recommended py/box.json)" ||
  fail "the Python script printed $py_rec, dtmap run recommends $(recommended py/box.json)"

# ---- the man page and the completion ----
# man finds the page from PATH alone (PREFIX/bin -> PREFIX/share/man)
env -i PATH="$P/bin:/usr/bin:/bin" HOME="$work" LANG=C.UTF-8 MANPAGER=cat MANWIDTH=100 man dtmap >man.txt 2>man.err ||
  fail "man dtmap with $P/bin on PATH: $(cat man.err)"
grep -q "dtmap run SCENE.xml" man.txt && grep -q "EXIT\|Exit codes" man.txt || fail "man dtmap shows: $(head man.txt)"
words=$("${clean[@]}" bash -c "source '$P/share/bash-completion/completions/dtmap';
  COMP_WORDS=(dtmap r); COMP_CWORD=1; _dtmap; echo \${COMPREPLY[*]}")
[ "$words" = "run refine" ] || fail "completing 'dtmap r' gives '$words'"
echo "t003-install: the package installed in $P works on its own (recommended step $rec s)"
