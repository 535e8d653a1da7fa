/* Private to src/parallel/ (the MPI build): the state of one rank in a
 * distributed run and the stages its files share. A rank analyses one part
 * of the mesh; the parts meet at interface nodes, which the lowest rank
 * holding them owns. The part's nodes are renumbered owned first, then the
 * ghosts (the nodes other ranks own), so that a PETSc ghosted Vec's local
 * form is indexed like the mesh's nodes. */
#ifndef DTM_PARALLEL_IMPL_H
#define DTM_PARALLEL_IMPL_H

#include <cJSON.h>
#include <mpi.h>
#include <petscvec.h>
#include <stddef.h>

#include "distributed.h"
#include "dtmap/cost.h"
#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "dtmap/parallel.h"
#include "dtmap/util.h"

/* Stages each rank times, s. */
enum { PAR_T_READ, PAR_T_EXTRACT, PAR_T_LAYOUT, PAR_T_EFFECTS, PAR_T_NODAL, PAR_T_GLOBAL, PAR_T_OUTPUT, PAR_T_COUNT };

/* A rank's outputs on their way: the part's mesh (+ .opt) under its own
 * name in a temporary directory rank 0 makes beside the output, and rank
 * 0's report beside its own; renamed into place when every rank is done. */
typedef struct {
  char dir[4096];                     /* the temporary directory (every rank's), "" until made */
  char mesh[4096], opt[4200];         /* where the part goes */
  char mesh_tmp[8200], opt_tmp[8300]; /* where it is written first */
  char report_tmp[4200];              /* the report's temporary, "" if none */
  dtm_output_file *file;              /* the part's mesh, written, awaiting its views */
} dtm_par_outputs;

typedef struct {
  MPI_Comm comm;           /* MPI_COMM_WORLD */
  int rank, size;          /* this rank, the number of ranks (= parts) */
  int quiet;               /* 1 when the failure agreed on is another rank's to print */
  const dtm_scene *scene;  /* the user's scene (not owned) */
  dtm_scene part;          /* a shallow copy whose <mesh> is this rank's part file */
  char part_path[4200];    /* this rank's part file */
  char tmpdir[4096];       /* part files rank 0 wrote for a one-mesh scene, or "" */
  int dim;                 /* dimension analysed */
  dtm_mesh *mesh;          /* this part (owned by the analysis once it exists) */
  size_t nowned, nghost;   /* owned nodes (first), ghost nodes (last) */
  PetscInt first;          /* global number of the first owned node */
  PetscInt *ghosts;        /* [nghost] global numbers of the ghosts */
  Vec node;                /* ghosted, one value per node of the part */
  dtm_exchange x;          /* the analysis's way to the other parts (ctx = this) */
  dtm_analysis *analysis;  /* this part's analysis */
  dtm_mesh *whole;         /* rank 0 of a one-mesh scene: the whole mesh, until classified */
  dtm_geo *whole_geo;      /* where it sits on the model, the same */
  dtm_analysis *advice;    /* rank 0: the whole mesh's shape-limited elements and layers, or NULL */
  dtm_cost *cost;          /* its cost (subcycling, mass scaling) */
  double t[PAR_T_COUNT];   /* stage times, s */
  dtm_mesher_info mesher;  /* how rank 0 got the mesh (read, or meshed a geometry) */
  int top;                 /* elements the report lists as the smallest steps (0: 10) */
  dtm_par_outputs out;     /* this rank's outputs */
  dtm_output_part outpart; /* what its part of the output takes from the whole mesh */
  long products;           /* operator products of the eigensolver */
  double product_cpu;      /* CPU time of this part's share of them, s */
  double exchange;         /* wall time of their ghost exchanges, s */
} dtm_par;

/* PETSc's error code as a dtmap error naming the call. */
int dtm_par_petsc_fail(PetscErrorCode e, const char *call, const char *file, int line, const char *func);
#define PAR_PETSC(call)                                                                                                \
  do {                                                                                                                 \
    PetscErrorCode par_e_ = (call);                                                                                    \
    if (par_e_) return dtm_par_petsc_fail(par_e_, #call, __FILE__, __LINE__, __func__);                                \
  } while (0)

/* comm.c: start and stop MPI, PETSc and SLEPc; agree on a status (the
 * highest code of any rank; a rank that was fine gets an error record
 * saying another part failed and is quiet); agree on a status every rank
 * computed alike (only rank 0 prints it). */
int dtm_par_init(dtm_par *p);
void dtm_par_finalize(void);
int dtm_par_agree(dtm_par *p, int status);
int dtm_par_agree_alike(dtm_par *p, int status);

/* load.c: this rank's part of the mesh, read and extracted into p->mesh
 * (rank 0 first partitions a one-mesh scene into p->tmpdir); remove what
 * rank 0 wrote. */
int dtm_par_load(dtm_par *p, const char *out);
void dtm_par_load_cleanup(dtm_par *p);

/* layout.c: owners and global numbers of the part's nodes, the owned-first
 * renumbering of p->mesh, the ghosted node Vec; refuses parts whose shared
 * nodes differ in position or whose elements overlap another part's. */
int dtm_par_layout(dtm_par *p);
void dtm_par_layout_destroy(dtm_par *p);
/* A ghosted Vec with bs values per node of the part. */
int dtm_par_vec(const dtm_par *p, int bs, Vec *v);
/* v[nnodes * bs] (node-major): nodes shared with other ranks get the sum
 * (ADD_VALUES), min or max over them. */
int dtm_par_combine(Vec g, double *v, size_t n, InsertMode mode);

/* exchange.c: p->x, the dtm_exchange the analysis uses. */
void dtm_par_exchange_init(dtm_par *p);

/* eigen.c: lambda_max of the whole mesh's M^-1 K (SLEPc on a PETSc shell
 * matrix around this part's operator). */
int dtm_par_eigen(dtm_par *p, const dtm_operator *op, double tol, int maxit, unsigned seed, dtm_lanczos_result *r);

/* Where a global minimum is: the rank holding it (ties to the smaller
 * Gmsh tag, then the lower rank) broadcasts its record. */
typedef struct {
  int found;              /* 0 when no rank holds a finite candidate */
  unsigned long long tag; /* Gmsh element or node tag */
  char group[64];         /* the element's physical group */
  double centroid[3];     /* the element's centroid, m */
  int effect;             /* its limiting effect (scene order) */
  char type[16];          /* its element type */
} dtm_par_where;

/* One rank's row of the per-part figures. */
enum {
  ROW_ELEMENTS,
  ROW_NODES,
  ROW_OWNED,
  ROW_GHOSTS,
  ROW_MEMORY,
  ROW_PRODUCT_CPU,
  ROW_EXCHANGE,
  ROW_T,
  ROW_COUNT = ROW_T + PAR_T_COUNT
};

/* The global figures of a distributed run, as a serial run would report
 * them, plus the per-part ones. */
typedef struct {
  double elements, nodes; /* of the whole mesh (nodes counted once) */
  dtm_par_where dt;       /* the smallest element step */
  dtm_par_where *element; /* [neffects] each effect's smallest element step */
  dtm_par_where *node;    /* [neffects] each effect's smallest nodal step */
  double under_resolved;  /* elements coarser than an accuracy bound */
  double conflicts;       /* elements whose size for the target exceeds the bound */
  double dt_cap;          /* smallest step the accuracy bounds allow (NaN: none) */
  dtm_par_where cap;      /* where */
  double cap_hmax;        /* its bound, m */
  int cap_effect;         /* the effect whose bound it is */
  dtm_subcycling sub;     /* subcycling: counts summed over the parts (no levels array) */
  dtm_mass_scaling *mass; /* mass scaling: totals and groups summed (no added array), or NULL */
  cJSON *under_list;      /* rank 0: the parts' first under-resolved elements, in rank order */
  cJSON *most_added;      /* rank 0: the elements with the most added mass */
  cJSON *worst;           /* rank 0: the smallest steps of every part, smallest first, top of them */
  cJSON *zones;           /* rank 0: the cohesive process zone per material (the parts' rows merged) */
  cJSON *damping;         /* rank 0: the damping factor per effect and material (element ranges widened) */
  double below;           /* elements whose own safe step is below the target */
  double *rows;           /* [size][ROW_COUNT] on rank 0, else NULL */
} dtm_par_figures;

/* figures.c: collect them (collective), and p->outpart from them; then
 * the per-part rows (collective, last: they hold the output times); free
 * them. */
int dtm_par_collect(dtm_par *p, dtm_par_figures *f);
int dtm_par_collect_rows(dtm_par *p, dtm_par_figures *f);
void dtm_par_figures_free(dtm_par_figures *f);
/* c (a copy of this part's cost) with the run time per element-step of
 * the whole mesh: the calibration's switch counts f->elements, every
 * part's (figures.c). */
void dtm_par_whole_cost(const dtm_par *p, const dtm_par_figures *f, dtm_cost *c);

/* report.c: the JSON report text on rank 0 (free()); the serial run's
 * warnings from the whole mesh's figures, and a note when elements below
 * the target are not classified (a scene of part files holds no model), as a JSON
 * array of strings. */
int dtm_par_report(const dtm_par *p, const dtm_parallel_opts *o, const dtm_par_figures *f, char **json);
cJSON *dtm_par_warnings(const dtm_par *p, const dtm_par_figures *f);
/* summary.c: the terminal summary, rank 0. */
void dtm_par_summary(const dtm_par *p, const dtm_parallel_opts *o, const dtm_par_figures *f);

/* write.c (collective): the part's mesh, as soon as it is extracted, then
 * Gmsh's model released; later its views, the figures into f and rank 0's
 * report, committed only when every rank succeeded; what is left of the
 * temporaries removed (cleanup: local; remove_dir: collective). */
int dtm_par_write_begin(dtm_par *p, const dtm_parallel_opts *o);
int dtm_par_write_finish(dtm_par *p, const dtm_parallel_opts *o, dtm_par_figures *f);
void dtm_par_write_cleanup(dtm_par *p);
void dtm_par_write_remove_dir(dtm_par *p);

#endif
