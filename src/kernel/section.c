/* Section kinds: their scene names, the element dimension each applies to,
 * the elastic formulation each implies and the measure factor (thickness or
 * area) that scales an element's stiffness and lumped mass alike. */
#include "dtmap/section.h"

static const char *const names[] = DTM_SECTION_NAMES;

const char *dtm_section_kind_name(int k) {
  return k >= DTM_SECTION_SOLID && k <= DTM_SECTION_TRUSS ? names[k] : "unknown";
}

int dtm_section_dim(int k) { return k == DTM_SECTION_SOLID ? 3 : k == DTM_SECTION_TRUSS ? 1 : 2; }

dtm_formulation dtm_section_formulation(int k) {
  switch (k) {
  case DTM_SECTION_SOLID: return DTM_FORM_3D;
  case DTM_SECTION_PLANE_STRAIN: return DTM_FORM_PLANE_STRAIN;
  case DTM_SECTION_TRUSS: return DTM_FORM_BAR;
  default: return DTM_FORM_PLANE_STRESS;
  }
}

double dtm_section_factor(const dtm_section *s) {
  if (!s || s->kind == DTM_SECTION_SOLID) return 1.0;
  return s->kind == DTM_SECTION_TRUSS ? s->area : s->thickness;
}
