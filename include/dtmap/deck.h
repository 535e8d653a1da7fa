/* Solver input decks (src/deck/): the analysed mesh handed to an explicit
 * solver with the step dtmap proved. One deck holds the nodes, every
 * analysed element in the solver's own element type (the one whose
 * integration and lumping match the step), one element set and one node set
 * per physical group (node sets also for the groups below the analysed
 * dimension, where loads and supports go), the materials and the sections
 * of the scene, the step fixed as the solver's increment (CalculiX,
 * Abaqus) or as the scale of the solver's own estimate (LS-DYNA's TSSFAC),
 * the duration, any mass added at the nodes to reach a target, and
 * commented *INCLUDE slots for what the scene does not describe (loads,
 * boundary conditions, contact, output requests). Each solver's format is
 * one small writer behind one table of operations, chosen by name
 * (src/deck/list.h). The deck is written atomically: a failed write
 * leaves the old file whole. */
#ifndef DTMAP_DECK_H
#define DTMAP_DECK_H

#include <stddef.h>

#include "dtmap/analysis.h"
#include "dtmap/export.h"

#define DTM_DECK_WARN_MAX 8 /* warnings a deck keeps */

/* What to write. */
typedef struct {
  const char *solver; /* a name of dtm_deck_solvers() */
  const char *path;   /* the deck (written atomically; not owned) */
  double target;      /* > 0: the step to reach with mass added at the nodes, s; 0: none */
  double max_added;   /* the added mass may reach this percent of the model's mass; NaN: no limit */
  int lsdyna_proven;  /* LS-DYNA: 1 writes dtmap's proven step as TSSFAC (above 1 where its estimate is
                         lower) with dtmap's nodal masses for a target; 0 (default) keeps TSSFAC <= 0.9
                         and reaches the step with LS-DYNA's own mass scaling (DT2MS < 0) */
  int selective_mass; /* 1: reach the target with the solver's own selective mass scaling (needs target > 0):
                         CalculiX's (its minimum increment at the target), LS-DYNA's (IMSCL with DT2MS < 0);
                         Abaqus/Explicit has none: mass at the nodes instead, as without it */
} dtm_deck_opts;

/* The step a solver will take with dtmap's deck and the hours the scene's
 * duration then takes: element-steps x that solver's cost per
 * element-step (CalculiX: measured on its own runs, src/cost/ccx_cost.inc;
 * LS-DYNA and Abaqus: the scene's <time cost-per-element-step> or not
 * known; never CalculiX's figure for another solver). */
typedef struct {
  double step;           /* the step the solver takes, s */
  char basis[160];       /* why ("ccx's own estimate: it takes the smaller of it and the deck's increment") */
  double element_steps;  /* elements x ceil(duration / step) (NaN without <time duration>) */
  double cost;           /* s per element-step (NaN: not known) */
  char cost_source[320]; /* where that figure comes from, or why it is not known */
  double hours;          /* element_steps x cost / 3600 (NaN: not known) */
} dtm_solver_run;

/* What was written, for the terminal and the report. */
typedef struct dtm_deck_info {
  char solver[16];                       /* its name ("calculix") */
  char title[48];                        /* the solver as the deck names it ("CalculiX 2.20") */
  char path[4096];                       /* the deck written */
  double step;                           /* the increment the deck fixes, s */
  double recommended;                    /* dt.recommended of the analysis, s */
  char basis[48];                        /* what the step rests on ("nodal bound", "target with added mass") */
  double own;                            /* the solver's own element-by-element estimate, s */
  size_t own_element;                    /* Gmsh tag of the element that sets it */
  char own_rule[200];                    /* that rule, in words */
  double tssfac;                         /* LS-DYNA's TSSFAC (NaN for the others) */
  double dt2ms;                          /* LS-DYNA's DT2MS, negative: its conventional mass scaling to
                                            |DT2MS|, s (NaN: none) */
  double solver_added;                   /* the mass LS-DYNA adds at its start by its DT2MS rule, kg (0: none) */
  size_t solver_added_elements;          /* the elements it adds it to */
  int lsdyna_proven;                     /* LS-DYNA: 1 when written with --lsdyna-step proven */
  double duration;                       /* the step's duration (<time duration>; else 1000 steps), s */
  size_t nodes;                          /* nodes written */
  size_t elements;                       /* elements written (mass elements not counted) */
  int element_sets;                      /* element sets (physical groups of the analysed elements) */
  int node_sets;                         /* node sets (those groups and the groups below them) */
  double model_mass;                     /* mass of the analysed elements, kg (2D: per unit thickness) */
  double carried;                        /* point masses the mesh carries (a refined mesh), kg: written too */
  size_t carried_nodes;                  /* nodes that carry one */
  double added;                          /* mass added at the nodes, kg */
  size_t added_nodes;                    /* nodes that receive it */
  double seconds;                        /* writing the deck, s */
  int nwarnings;                         /* warnings kept */
  char warnings[DTM_DECK_WARN_MAX][480]; /* one sentence each */
  dtm_solver_run run;                    /* the step the solver takes with this deck, and the hours */
  int selective;                         /* 1: written with selective_mass */
  int sms_solver;                        /* 1: the solver scales selectively (CalculiX, LS-DYNA); 0: it cannot
                                            (Abaqus: the target's mass at the nodes instead) */
  double sms_added;                      /* the mass the solver's selective scaling adds by its rule, as dtmap
                                            predicts it, kg: CalculiX sum of beta_e m_e (the trace of its added
                                            matrix per direction), LS-DYNA its DT2MS rule's figure; the model's
                                            translational mass is unchanged (NaN: none) */
  size_t sms_elements;                   /* the elements it scales */
  double sms_beta_max;                   /* CalculiX: the largest beta_e, as ccx prints it (NaN otherwise) */
  size_t sms_counted;                    /* CalculiX: the elements ccx counts as scaled (its rule covers none
                                            of them: springs, mass elements) beside sms_elements */
  char sms_note[480];                    /* what the solver does with the deck, one sentence */
} dtm_deck_info;

/* The solvers, "calculix, abaqus, lsdyna" (static). */
DTM_EXPORT const char *dtm_deck_solvers(void);
/* 0 when name is a solver (and *ext, when not NULL, its file extension:
 * ".inp", ".k"); DTM_ERR_INPUT naming it and listing the solvers. */
DTM_EXPORT int dtm_deck_solver(const char *name, const char **ext);
/* The solver name likely meant by a name that is none ("ls-dyna",
 * "CalculiX" -> "lsdyna", "calculix"; static), NULL when none is near. */
DTM_EXPORT const char *dtm_deck_solver_near(const char *name);
/* Prepare scene s for the solver's elements before it is analysed: for
 * CalculiX the elastic effect takes integration="calculix" (its C3D10), so
 * that the step is the one of the solver's element. note[len] receives one
 * sentence on what was changed ("" when nothing). */
DTM_EXPORT int dtm_deck_adapt(dtm_scene *s, const char *solver, char *note, size_t len);
/* Write the deck of analysis a (its mesh, scene and recommended step) as
 * o says, filling *info. DTM_ERR_INPUT for an element kind the solver
 * lacks (naming the kind and the group), a scene without the elastic
 * effect, or a write that fails (the old file stays whole);
 * DTM_ERR_TARGET when the mass the target needs is above o->max_added
 * percent of the model's (nothing is written). */
DTM_EXPORT int dtm_deck_write(const dtm_analysis *a, const dtm_deck_opts *o, dtm_deck_info *info);

/* Each element's step by one solver's own element rule (the rule whose
 * smallest value a deck's header gives as the solver's estimate), for the
 * views of `run --solver-rule`. */
typedef struct {
  char solver[16];    /* its name ("lsdyna") */
  char title[48];     /* the solver as a deck names it ("LS-DYNA") */
  char rule[200];     /* the rule, in words */
  double *dt;         /* [nel] in the analysis' element order, s; NaN where the rule covers
                         none (CalculiX's springs) (owned: dtm_deck_steps_free) */
  double min;         /* the smallest, s (NaN when the rule covers no element) */
  size_t element;     /* Gmsh tag of the element that has it */
  double centroid[3]; /* that element's centroid (mean of its corners), m */
  dtm_solver_run run; /* the step it takes with dtmap's deck (no target), and the hours */
} dtm_deck_steps;

/* Fill *out for solver (a name of dtm_deck_solvers()) on analysis a: the
 * same parts, elements and rule as dtm_deck_write, so out->min is the
 * deck's estimate. DTM_ERR_INPUT for an unknown solver, a scene without
 * the elastic effect or an element kind the solver lacks (as the deck). */
DTM_EXPORT int dtm_deck_own_steps(const dtm_analysis *a, const char *solver, dtm_deck_steps *out);
DTM_EXPORT void dtm_deck_steps_free(dtm_deck_steps *s);

#endif
