/* Whether an MPI launcher started this process as one of several, from
 * the environment the launchers set (Open MPI's mpirun, MPICH's Hydra,
 * Slurm's srun), so that dtmap can tell before initialising MPI. Built
 * with and without MPI. */
#include <stdlib.h>

#include "dtmap/parallel.h"

int dtm_parallel_launched(void) {
  static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS", "SLURM_STEP_NUM_TASKS"};
  for (size_t i = 0; i < sizeof vars / sizeof *vars; i++) {
    const char *v = getenv(vars[i]);
    if (v && atoi(v) > 1) return 1;
  }
  return 0;
}

int dtm_parallel_wanted(const dtm_scene *s) { return s->partitions > 0 || dtm_parallel_launched(); }
