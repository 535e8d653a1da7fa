/* Decks with selective mass scaling (`dtmap deck --target T
 * --selective-mass`, issue 44): each solver's own selective scaling set
 * to reach the target, and dtmap's prediction, by that solver's rule, of
 * what it adds. Selective scaling adds to an element a mass matrix whose
 * rows sum to zero: the model's translational (rigid-body) mass is
 * unchanged, and only the element's deformation modes get heavier.
 * - CalculiX 2.20 (Debian's calculix-ccx source, calcstabletimeincvol.f and
 *   e_c3d.f, read for the rule): with ALPHA=0 its element step is
 *   0.98 h elemfac / c_d before its safety factor 0.8, so the deck's "own"
 *   estimate (0.8 of it) is what it compares. When the *DYNAMIC minimum
 *   increment T is above that estimate, it scales every element whose own
 *   estimate dt_e is below T by beta_e = (T / dt_e)^2 - 1, adding
 *   beta_e m_e / (n (n - 1)) (n I - 1 1^T) per direction (n nodes, m_e the
 *   element's mass; trace beta_e m_e), and runs at T. Elements its rule
 *   does not cover (springs, mass elements) keep an estimate of zero there:
 *   ccx counts them as scaled (beta infinite) but adds them no mass.
 * - LS-DYNA: IMSCL < 0 on *CONTROL_TIMESTEP's second card makes its DT2MS
 *   scaling selective on a part set; the deck's DT2MS prediction
 *   (lsdyna.c) is the conventional figure for the same elements.
 * - Abaqus/Explicit has no selective scaling: the deck keeps dtmap's mass
 *   at the nodes for the target, and says so. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deck-impl.h"

#define SMS_SET "DTMAP_SMS_SCALED" /* CalculiX: the elements its scaling reaches */

int deck_sms_scaled(const deck_ctx *c, const dtm_block *b, size_t e, size_t i) {
  return c->w->own(c, b, e, i, &c->parts[c->part[i]]) < c->info->step;
}

/* Nodes that get a CalculiX MASS element: a truss's (its lumped mass) or
 * one the mesh carries a point mass at. */
static size_t mass_nodes(const deck_ctx *c) {
  size_t n = 0, i = 0;
  char *has = calloc(c->m->nnodes, 1);
  if (!has) return 0;
  for (size_t v = 0; v < c->m->nnodes; v++) has[v] = c->carried && c->carried[v] > 0;
  for (int k = 0; k < c->m->nblocks; k++)
    for (size_t e = 0; e < c->m->blocks[k].n; e++, i++)
      if (c->parts[c->part[i]].kind == DTM_SECTION_TRUSS)
        for (int a = 0; a < c->m->blocks[k].nn; a++) has[c->m->blocks[k].conn[e * c->m->blocks[k].nn + a]] = 1;
  for (size_t v = 0; v < c->m->nnodes; v++) n += has[v];
  free(has);
  return n;
}

/* CalculiX's rule: beta_e, the trace of the added matrix and the count. */
static void predict_calculix(deck_ctx *c) {
  dtm_deck_info *in = c->info;
  double T = in->step, model = 0.0, added = 0.0;
  size_t i = 0, n = 0, other = 0;
  for (int k = 0; k < c->m->nblocks; k++)
    for (size_t e = 0; e < c->m->blocks[k].n; e++, i++) {
      const dtm_block *b = &c->m->blocks[k];
      const deck_part *p = &c->parts[c->part[i]];
      double m = deck_element_mass(c, b, e, p), t = c->w->own(c, b, e, i, p);
      model += m;
      if (!isfinite(t))
        other++;
      else if (t < T)
        added += m * ((T / t) * (T / t) - 1.0), n++;
    }
  int on = isfinite(in->own) && in->own < T; /* ccx switches it on only then */
  in->sms_added = on ? added : 0.0, in->sms_elements = on ? n : 0;
  in->sms_beta_max = on ? (T / in->own) * (T / in->own) - 1.0 : NAN;
  in->sms_counted = on ? other + mass_nodes(c) : 0;
  if (isnan(in->model_mass)) in->model_mass = model;
  snprintf(in->sms_note, sizeof in->sms_note,
           on ? "ccx runs at the deck's minimum increment, its step, with its own selective mass scaling (its "
                "estimate is below it)"
              : "ccx's own estimate is at or above the deck's step: it runs at that step without mass scaling");
}

void deck_sms_predict(deck_ctx *c) {
  dtm_deck_info *in = c->info;
  const char *M = dtm_scene_mass_unit(c->s, dtm_analysis_mesh(c->a)->dim);
  in->sms_solver = strcmp(c->w->name, "abaqus") != 0;
  if (!strcmp(c->w->name, "calculix")) {
    predict_calculix(c);
  } else if (in->sms_solver) {
    int on = isfinite(in->dt2ms);
    in->sms_added = on ? in->solver_added : 0.0, in->sms_elements = on ? in->solver_added_elements : 0;
    snprintf(in->sms_note, sizeof in->sms_note, "%s",
             on ? "LS-DYNA scales every part selectively (IMSCL) where an element's step is below |DT2MS|"
                : "the step is at most 0.9 x LS-DYNA's estimate: no mass scaling, selective or not");
  } else {
    snprintf(in->sms_note, sizeof in->sms_note,
             "Abaqus/Explicit has no selective mass scaling: conventional mass at the nodes instead, %.6g %s at %zu "
             "nodes (%.3g %% of the model's %.6g %s)",
             in->added, M, in->added_nodes, in->model_mass > 0 ? 100 * in->added / in->model_mass : 0.0, in->model_mass,
             M);
  }
}

static void header_calculix(const deck_ctx *c, const char *cm, const char *M) {
  const dtm_deck_info *in = c->info;
  FILE *f = c->f;
  if (!(in->sms_elements > 0)) {
    fprintf(f, "%s selective mass scaling (--selective-mass): %s\n", cm, in->sms_note);
    return;
  }
  fprintf(f,
          "%s selective mass scaling (--selective-mass): the *DYNAMIC minimum increment is the step, %.10g s,\n"
          "%s above CalculiX's own estimate %.10g s, so ccx 2.20 switches on its selective mass scaling and runs at\n"
          "%s that step (it prints \"Selective Mass Scaling is active\"). Its rule: each element whose own step\n"
          "%s dt_e is below the step T gets beta_e = (T / dt_e)^2 - 1 and the added mass\n"
          "%s beta_e m_e / (n (n - 1)) (n I - 1 1^T) per direction (n nodes, m_e its mass): rows sum to zero,\n"
          "%s so the model's translational mass, %.10g %s, is unchanged. With equal nodal masses the element's\n"
          "%s deformation modes get n / (n - 1) x beta_e of its mass, more than the beta_e its rule asks for.\n",
          cm, in->step, cm, in->own, cm, cm, cm, cm, in->model_mass, M, cm);
  fprintf(f,
          "%s predicted by that rule: beta_e up to %.6g (ccx prints it as the maximum beta) at %zu elements\n"
          "%s (element set " SMS_SET "); their trace sum beta_e m_e %.10g %s per direction, %.4g %% of the\n"
          "%s model's mass\n",
          cm, in->sms_beta_max, in->sms_elements, cm, in->sms_added, M, 100 * in->sms_added / in->model_mass, cm);
  if (in->sms_counted)
    fprintf(f,
            "%s ccx also counts %zu springs and mass elements as scaled (its rule gives them no step): it adds them\n"
            "%s no mass; so its count of scaled elements is %zu\n",
            cm, in->sms_counted, cm, in->sms_elements + in->sms_counted);
}

static void header_lsdyna(const deck_ctx *c, const char *cm, const char *M) {
  const dtm_deck_info *in = c->info;
  FILE *f = c->f;
  if (!isfinite(in->dt2ms)) {
    fprintf(f, "%s selective mass scaling (--selective-mass): %s; IMSCL is not written\n", cm, in->sms_note);
    return;
  }
  fprintf(f,
          "%s selective mass scaling (--selective-mass): *CONTROL_TIMESTEP's second card sets IMSCL to minus\n"
          "%s the part set DTMAP_SMS_PARTS (every part), so LS-DYNA's DT2MS scaling is selective there: each\n"
          "%s element whose own step is below |DT2MS| gets an added mass matrix that leaves its translational\n"
          "%s (rigid-body) mass unchanged and brings its step to |DT2MS| (RMSCL 0: rotations not scaled).\n",
          cm, cm, cm, cm);
  fprintf(f,
          "%s dtmap's prediction by the conventional DT2MS rule: %.10g %s at %zu elements, %.4g %% of the model's\n"
          "%s %.10g %s: what conventional scaling would add to the same elements; the selective form adds none\n"
          "%s of it to the translational mass (0 %s), only inertia against the elements' deformation. How\n"
          "%s LS-DYNA accounts for it in its output was not checked (no LS-DYNA here).\n",
          cm, in->sms_added, M, in->sms_elements, 100 * in->sms_added / in->model_mass, cm, in->model_mass, M, cm, M,
          cm);
}

static void header_abaqus(const deck_ctx *c, const char *cm, const char *M) {
  const dtm_deck_info *in = c->info;
  fprintf(c->f,
          "%s selective mass scaling (--selective-mass): Abaqus/Explicit has none. The deck reaches the target\n"
          "%s with conventional mass at the nodes instead (dtmap's --target path, the mass elements below):\n"
          "%s %.10g %s at %zu nodes, %.4g %% of the model's %.10g %s. That mass changes the model's\n"
          "%s translational mass and moves its low frequencies; the CalculiX and LS-DYNA decks scale selectively.\n",
          cm, cm, cm, in->added, M, in->added_nodes, 100 * in->added / in->model_mass, in->model_mass, M, cm);
}

void deck_sms_header(const deck_ctx *c, const char *cm) {
  const char *M = dtm_scene_mass_unit(c->s, dtm_analysis_mesh(c->a)->dim);
  if (!strcmp(c->w->name, "calculix"))
    header_calculix(c, cm, M);
  else if (!strcmp(c->w->name, "lsdyna"))
    header_lsdyna(c, cm, M);
  else
    header_abaqus(c, cm, M);
}

void deck_sms_elset(deck_ctx *c) {
  size_t i = 0, n = 0;
  if (!(c->info->sms_elements > 0)) return;
  fputs("*ELSET, ELSET=" SMS_SET "\n", c->f);
  for (int k = 0; k < c->m->nblocks; k++)
    for (size_t e = 0; e < c->m->blocks[k].n; e++, i++)
      if (deck_sms_scaled(c, &c->m->blocks[k], e, i))
        fprintf(c->f, "%zu%s", c->m->blocks[k].tags[e], ++n % 16 == 0 || n == c->info->sms_elements ? "\n" : ", ");
}
