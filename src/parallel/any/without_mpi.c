/* The distributed run in a dtmap built without MPI (CMake option DTM_MPI
 * off): a scene that names partition files, or a dtmap started as one of
 * several processes by an MPI launcher, is refused with how to get the
 * MPI build, rather than run P times over the same files. */
#include "dtmap/error.h"
#include "dtmap/parallel.h"

int dtm_parallel_run(const dtm_scene *s, const dtm_parallel_opts *o) {
  (void)o;
  if (s->partitions > 0)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s:%d: the mesh is %d partition files, and this dtmap was built without MPI; "
                   "build it with cmake -DDTM_MPI=ON and run it with mpirun -n %d",
                   s->path, s->source_line, s->partitions, s->partitions);
  return DTM_ERR(DTM_ERR_INPUT, "this dtmap was built without MPI and an MPI launcher started several copies of it; "
                                "build it with cmake -DDTM_MPI=ON for mpirun, or run it without mpirun");
}

void dtm_parallel_finish(void) {}
