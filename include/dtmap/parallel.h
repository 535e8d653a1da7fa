/* The distributed run: `mpirun -n P dtmap run SCENE.xml`. Each MPI rank
 * reads one part of a mesh partitioned by Gmsh (METIS) and analyses only
 * that part; what crosses parts (the nodal bound's per-node sums, the size
 * suggestion, the minima behind the recommendation, the global estimate by
 * SLEPc on a PETSc matrix-free operator with ghost exchange on the
 * interface nodes) goes through MPI, so every figure equals the serial
 * run's. The scene names either the part files Gmsh wrote
 * (<mesh file="model.msh" partitions="P"/> reads model_1.msh ...
 * model_P.msh, or file="model_{part}.msh"), or one mesh or geometry, which
 * rank 0 then partitions through Gmsh into part files beside the output.
 * Each rank writes its own part of the output (OUT_1.msh ... OUT_P.msh,
 * views tagged with their partition so that Gmsh merges the parts into one
 * view), and rank 0 writes one JSON report with the global figures and the
 * per-part ones. Built with the CMake option DTM_MPI; without it these
 * functions only refuse (DTM_ERR_INPUT saying how to build it). */
#ifndef DTMAP_PARALLEL_H
#define DTMAP_PARALLEL_H

#include "dtmap/export.h"
#include "dtmap/scene.h"

/* What the CLI passes to a distributed run. */
typedef struct {
  const char *out;    /* output mesh: the parts are its dtm_scene_part_path names
                         (OUT.msh: OUT_1.msh ...) */
  const char *report; /* JSON report, or NULL: none */
  int posterior;      /* also the global estimate (SLEPc) */
  double tol;         /* its relative residual */
  int max_products;   /* its operator products at most */
  int threads;        /* OpenMP threads per rank (0: 1) */
  int verbosity;      /* 0 quiet, 1 summary (rank 0), 2 also Gmsh's messages and tracebacks */
  double t_scene;     /* reading the scene, s (the caller's stage) */
  int format;         /* the parts' encoding: DTM_MSH_AUTO (binary above DTM_BINARY_ABOVE
                         elements per part), DTM_MSH_ASCII or DTM_MSH_BINARY */
  int views_only;     /* 1: the parts' views only, for Gmsh to merge on top of the
                         input parts (or the input mesh) */
  int top;            /* elements the report lists as the smallest steps; 0: 10, < 0: none */
} dtm_parallel_opts;

/* 1 when scene s is to be run distributed: this process is one of several
 * an MPI launcher started, or the scene names partition files. */
DTM_EXPORT int dtm_parallel_wanted(const dtm_scene *s);
/* 1 when an MPI launcher started this process as one of several (the
 * commands that do not run distributed refuse then). */
DTM_EXPORT int dtm_parallel_launched(void);
/* Run scene s distributed, collectively over every rank the launcher
 * started, and write the parts, the report and (rank 0, verbosity > 0) the
 * summary. Initialises MPI, PETSc and SLEPc (once per process; they stay up
 * until dtm_parallel_finish). Every rank returns the same code (0, or the
 * error code of the first rank that failed); the error stays pending on
 * the rank where it arose, for the caller to print, and is cleared on the
 * others; nothing is written when any rank fails. */
DTM_EXPORT int dtm_parallel_run(const dtm_scene *s, const dtm_parallel_opts *o);
/* After dtm_parallel_run and after printing its error: wait until every
 * rank has got here, then finalise SLEPc, PETSc and MPI. A rank that exits
 * first would make the launcher kill the others, perhaps before the one
 * with the error has printed it. Does nothing when MPI is not running. */
DTM_EXPORT void dtm_parallel_finish(void);

#endif
