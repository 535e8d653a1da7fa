#!/usr/bin/env bash
# Install the Debian 12 packages dtmap needs to build, test and run, when
# they are missing. Needs root (or sudo). Safe to run again. The Python
# module's companions (python3-gmsh, python3-numpy) and python3-jsonschema
# (the report schema) are for scripting dtmap and for its tests; man-db
# reads the generated man page; gmsh-doc holds Gmsh's tutorials and demos.
set -euo pipefail
# The last four are for the distributed run (cmake -DDTM_MPI=ON): Open MPI,
# PETSc and SLEPc; a build without DTM_MPI does not need them.
packages=(build-essential cmake pkg-config clang clang-format libgmsh-dev gmsh libxml2-dev libxml2-utils
          libcjson-dev libcmocka-dev libplplot-dev plplot-driver-cairo fonts-dejavu-core libpng-dev
          xvfb xfonts-base xfonts-75dpi  # Gmsh draws dtmap's PNG snapshots on a virtual display, its
                                         # text in X's core Helvetica (xfonts-75dpi; without it a small
                                         # fixed font without spaces)
          python3 python3-gmsh python3-numpy python3-scipy python3-jsonschema man-db
          libsuitesparse-dev  # CHOLMOD: the factorisation that proves the global bound (src/spectral/certify.c)
          libopenblas0-serial  # the BLAS under CHOLMOD (Debian's alternatives pick it over the reference
                               # BLAS): 6x faster certificates. Single-threaded on purpose: the OpenMP
                               # build (libopenblas0-openmp) spins when loaded under ulimit -d (t309);
                               # if a threaded OpenBLAS is installed too it outranks this one
                               # (update-alternatives --display libblas.so.3-x86_64-linux-gnu)
          calculix-ccx  # ccx 2.20 runs the decks of dtmap deck (tests/t371)
          gmsh-doc  # Gmsh's tutorials and demos: tests/t318 reruns bench/surface_models.py on one
          openmpi-bin libopenmpi-dev libpetsc-real-dev libslepc-real-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all packages present"
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "setup: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
