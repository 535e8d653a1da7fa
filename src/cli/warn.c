/* Warnings the CLI prints on stderr after an analysis (even with -q): the
 * elements dtmap analysed although they are inverted at a node (valid at
 * every integration point; see dtm_mesh_check), the first 20 by tag, group,
 * centroid and smallest scaled Jacobian, and how many in all; the curved
 * second-order elements whose step depends on the integration rule; the
 * numbers that look like a unit error (src/output/plausible.c). */
#include <stdio.h>

#include "cli-impl.h"
#include "dtmap/analysis.h"
#include "dtmap/output.h"

#define WARN_LISTED 20 /* flagged elements named on the terminal */

void dtm_cli_warn_flagged(const dtm_analysis *a) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  if (!m->nflagged) return;
  fprintf(stderr,
          "dtmap: warning: %zu element%s inverted at a node but valid at every integration point: analysed, "
          "and flagged in the view 'invalid elements' and the report's invalid_elements\n",
          m->nflagged, m->nflagged == 1 ? " is" : "s are");
  for (size_t i = 0; i < m->nflagged && i < WARN_LISTED; i++) {
    const dtm_flagged *f = &m->flagged[i];
    char place[256];
    dtm_mesh_element_place(m, f->block, f->index, place, sizeof place);
    fprintf(stderr, "  %s: smallest scaled Jacobian %.3g\n", place, f->min_jacobian);
  }
  if (m->nflagged > WARN_LISTED) fprintf(stderr, "  ... and %zu more\n", m->nflagged - WARN_LISTED);
}

void dtm_cli_warn_curved(const dtm_analysis *a) {
  const dtm_curvature_summary *s = dtm_analysis_curvature(a);
  if (!s->sensitive) return;
  fprintf(stderr,
          "dtmap: warning: %zu curved element%s a step that changes by more than 1e-3 with the integration rule "
          "(up to %.2g); the steps are for the %s integration (view 'curvature', report's curvature)\n",
          s->sensitive, s->sensitive == 1 ? " has" : "s have", s->max_dependence,
          s->model == DTM_INTEGRATION_FULL ? "full-rule" : dtm_integration_name(s->model));
}

void dtm_cli_warn_units(const dtm_analysis *a) { dtm_output_warn_plausibility(a, stderr); }
