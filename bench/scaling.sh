#!/usr/bin/env bash
# Strong and weak scaling of the distributed run (mpirun -n P dtmap run) on
# this machine, as Markdown tables for docs/scaling.md. Builds the MPI build
# into build-mpi/ (or BUILD_DIR). Arguments: the box sizes (m) of the
# strong-scaling mesh and of the weak-scaling meshes for 1, 2 and 4 ranks.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build-mpi}
bash "$root/scripts/build.sh" -DDTM_MPI=ON >/dev/null
work=$(mktemp -d /tmp/dtmap-scaling-XXXXXX)
trap 'rm -rf "$work"' EXIT
strong=${1:-2e-3} w1=${2:-3.2e-3} w2=${3:-2.5e-3} w4=${4:-2e-3}
# Open MPI as root, 4 ranks on fewer cores, no cross-process memory copy
# (containers often forbid it), shared memory only.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_btl=self,vader
echo "Measured by \`bench/scaling.sh $strong $w1 $w2 $w4\` on $(nproc) cores, $(date -u +%Y-%m-%d);"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)."
echo
"$BUILD_DIR/bench/bench_scaling" "$BUILD_DIR/dtmap" "mpirun --bind-to none" "$root" "$work" "$strong" "$w1" "$w2" "$w4"
echo
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)."
