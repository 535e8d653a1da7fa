/* The Abaqus/Explicit deck (Abaqus Keywords Reference; Analysis User's
 * Guide, "Explicit dynamic analysis"). Elements: C3D4, C3D10M (the
 * 10-node tetrahedron Abaqus/Explicit has; its lumping is not published,
 * so the step is that of dtmap's model), C3D8 (its volumetric term is
 * integrated at one point in Abaqus/Explicit, which can only lower the
 * element's top eigenvalue: dtmap's fully integrated step is on the safe
 * side), CPE3/CPE4R/CPE6M and CPS*, M3D3/M3D4, S3R/S4, T3D2, B31 with a
 * general section (A, I11 = the section's I_y, I22 = I_z, J; n1 along the
 * section's y). The step is fixed with *DYNAMIC, EXPLICIT, DIRECT USER
 * CONTROL (increment, time period) for the whole step; the header says it
 * was proven for the undeformed mesh. Abaqus's own estimate is
 * element-by-element from each element's highest (dilatational) frequency:
 * for the elements of this deck that is dtmap's element bound (the map's
 * smallest step), which is what it shows. */
#include <math.h>
#include <stdio.h>

#include "deck-impl.h"

static const int c3d10[] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8}; /* Gmsh's last two mid-edge nodes swap */

static const deck_elem_row rows[] = {{DTM_SECTION_SOLID, DTM_TET4, "C3D4", 0, NULL},
                                     {DTM_SECTION_SOLID, DTM_TET10, "C3D10M", 0, c3d10},
                                     {DTM_SECTION_SOLID, DTM_HEX8, "C3D8", 0, NULL},
                                     {DTM_SECTION_PLANE_STRAIN, DTM_TRI3, "CPE3", 0, NULL},
                                     {DTM_SECTION_PLANE_STRAIN, DTM_QUAD4, "CPE4R", 0, NULL},
                                     {DTM_SECTION_PLANE_STRAIN, DTM_TRI6, "CPE6M", 0, NULL},
                                     {DTM_SECTION_PLANE_STRESS, DTM_TRI3, "CPS3", 0, NULL},
                                     {DTM_SECTION_PLANE_STRESS, DTM_QUAD4, "CPS4R", 0, NULL},
                                     {DTM_SECTION_PLANE_STRESS, DTM_TRI6, "CPS6M", 0, NULL},
                                     {DTM_SECTION_MEMBRANE, DTM_TRI3, "M3D3", 0, NULL},
                                     {DTM_SECTION_MEMBRANE, DTM_QUAD4, "M3D4", 0, NULL},
                                     {DTM_SECTION_SHELL, DTM_TRI3, "S3R", 0, NULL},
                                     {DTM_SECTION_SHELL, DTM_QUAD4, "S4", 0, NULL},
                                     {DTM_SECTION_TRUSS, DTM_LINE2, "T3D2", 0, NULL},
                                     {DTM_SECTION_BEAM, DTM_LINE2, "B31", 0, NULL}};

static int element(deck_ctx *c, deck_part *p) {
  char lbl[160];
  DTM_CHECK(deck_element_from(c, p, rows, sizeof rows / sizeof *rows));
  if (p->type == DTM_TET10)
    deck_warn(c,
              "%s: Abaqus does not publish the lumping of C3D10M; the step is that of dtmap's model (HRZ); keep "
              "the safety factor",
              deck_part_label(c, p, lbl, sizeof lbl));
  deck_warn_quad4(c, p, p->elem);
  return DTM_OK;
}

/* Abaqus's element-by-element estimate: the element's own (elastic) step. */
static double own(const deck_ctx *c, const dtm_block *b, size_t e, size_t i, const deck_part *p) {
  (void)b, (void)e, (void)p;
  return dtm_analysis_effect_dt(c->a, c->elastic)[i];
}

static int section_beam(deck_ctx *c, const deck_part *p, int *done) {
  if (p->kind != DTM_SECTION_BEAM) return DTM_OK;
  *done = 1;
  const dtm_section *s = &c->s->sections[p->section];
  double E, nu, rho, v[3];
  deck_elastic(c, p->mat, &E, &nu, &rho);
  deck_beam_orientation(c, p, v);
  fprintf(c->f, "*BEAM GENERAL SECTION, ELSET=%s, SECTION=GENERAL, DENSITY=%.14g\n", p->set, rho);
  deck_inp_reals(c, 5, (double[]){s->area, s->iy, 0.0, s->iz, s->jt});
  deck_inp_reals(c, 3, v);
  deck_inp_reals(c, 2, (double[]){E, E / (2 * (1 + nu))});
  return DTM_OK;
}

static int write(deck_ctx *c) {
  FILE *f = c->f;
  snprintf(c->proven, sizeof c->proven,
           "The step was proven for the undeformed mesh. DIRECT USER CONTROL fixes the increment at\n"
           "%.10g s for the whole step: Abaqus does not shorten it as elements deform, so a run whose\n"
           "elements shrink or distort needs a margin of its own (or Abaqus's own stable increment).",
           c->info->step);
  deck_header(c, "**");
  fprintf(f, "*HEADING\ndtmap deck of %s\n", c->s->path);
  DTM_CHECK(deck_inp_nodes(c));
  DTM_CHECK(deck_inp_elements(c));
  DTM_CHECK(deck_inp_sets(c));
  DTM_CHECK(deck_inp_materials(c, 1));
  DTM_CHECK(deck_inp_sections(c, section_beam));
  DTM_CHECK(deck_inp_masses(c, NULL));
  deck_inp_slot(c, "model", "boundary and initial conditions, contact (model data)");
  fputs("*STEP\n*DYNAMIC, EXPLICIT, DIRECT USER CONTROL\n", f);
  deck_inp_reals(c, 2, (double[]){c->info->step, c->info->duration});
  deck_inp_slot(c, "step", "loads and output requests (history data)");
  fputs("*END STEP\n", f);
  return DTM_OK;
}

const deck_writer dtm_deck_abaqus = {"abaqus", "Abaqus/Explicit",
                                     ".inp",   "each element's highest frequency: dtmap's element bound",
                                     element,  own,
                                     NULL,     NULL,
                                     NULL,     write};
