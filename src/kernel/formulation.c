/* The elastic formulations: their scene names, the default of each
 * dimension, and which suits which element dimension (3D solids need
 * DTM_FORM_3D, 2D elements plane strain or plane stress, 1D elements the
 * bar). A mismatch is a scene error, reported with both names. */
#include "dtmap/error.h"
#include "kernel-impl.h"

static const char *const names[] = DTM_FORMULATION_NAMES;

const char *dtm_formulation_name(int f) { return f >= DTM_FORM_3D && f <= DTM_FORM_BAR ? names[f] : "unknown"; }

dtm_formulation dtm_formulation_default(int dim) {
  return dim == 3 ? DTM_FORM_3D : dim == 2 ? DTM_FORM_PLANE_STRAIN : DTM_FORM_BAR;
}

static int suits(int d, int f) {
  if (d == 3) return f == DTM_FORM_3D;
  if (d == 2) return f == DTM_FORM_PLANE_STRAIN || f == DTM_FORM_PLANE_STRESS;
  return f == DTM_FORM_BAR;
}

int dtm_form_check(int type, int d, int f) {
  if (suits(d, f)) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s elements (dimension %d) cannot use the %s elastic "
                 "formulation: use %s",
                 dtm_elem_name(type), d, dtm_formulation_name(f),
                 d == 3   ? "3d"
                 : d == 2 ? "plane-strain or plane-stress"
                          : "bar");
}
