#!/bin/sh
# Build a CalculiX whose explicit increment can be fixed, for
# bench/ccx_c3d10.py (docs/curved.md). CalculiX 2.20 chooses the explicit
# increment itself: its Courant estimate, or, when the minimum increment asked
# for is larger, selective mass scaling, which changes the mass matrix. Neither
# lets a run sit at 0.999x of the exact step. This builds CalculiX from a
# source tree (SRC: the src/ directory of a CalculiX checkout, e.g. of the
# GitHub mirror Dhondtguido/CalculiX at 35fcfa1, September 2022, just after
# 2.20) with one change in nonlingeo.c: when CCX_FIXED_INC is set, the
# selected explicit increment is that value (at the start and where the
# increment is re-selected). Element routines, lumping and the time scheme
# are untouched. Needs gfortran, libspooles-dev, libarpack2-dev, liblapack-dev.
#
# Usage: sh bench/ccx_fixed_inc.sh SRC OUTDIR   -> OUTDIR/ccx_fixed
set -eu
src=$1
out=$2
mkdir -p "$out/src"
cp -r "$src"/. "$out/src/"
cd "$out/src"
python3 - <<'PY'
s = open("nonlingeo.c").read()
a = '      printf(" SELECTED time increment:%e\\n\\n",*tinc);'
b = '\t    dtime=dtvol;\n\t  }'
assert s.count(a) == 1 and s.count(b) == 1, "nonlingeo.c is not the expected version"
s = s.replace(a, '      if(getenv("CCX_FIXED_INC")){*tinc=atof(getenv("CCX_FIXED_INC"));dtheta=(*tinc)/(*tper);dthetaref=dtheta;}\n' + a)
s = s.replace(b, b + '\n\t  if(getenv("CCX_FIXED_INC")) dtime=atof(getenv("CCX_FIXED_INC"));')
open("nonlingeo.c", "w").write(s)
PY
cat > Makefile.fixed <<'MK'
CFLAGS = -O1 -w -I /usr/include/spooles -DARCH="Linux" -DSPOOLES -DARPACK -DMATRIXSTORAGE -DNETWORKOUT -fopenmp
FFLAGS = -O1 -w -fopenmp -fallow-argument-mismatch
CC=cc
FC=gfortran
.c.o :
	$(CC) $(CFLAGS) -c $<
.f.o :
	$(FC) $(FFLAGS) -c $<
include Makefile.inc
OBJ = CalculiX.o $(SCCXF:.f=.o) $(filter-out CalculiXstep.o,$(SCCXC:.c=.o))
ccx_fixed: $(OBJ)
	$(FC) -fopenmp -o $@ $(OBJ) -lspooles -larpack -llapack -lblas -lpthread -lm -lc
MK
make -f Makefile.fixed -j"${JOBS:-2}" ccx_fixed
cp ccx_fixed "$out/ccx_fixed"
echo "$out/ccx_fixed"
