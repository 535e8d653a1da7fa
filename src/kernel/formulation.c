/* Which elastic formulation suits which element dimension: 3D solids need
 * DTM_FORM_3D, 2D elements plane strain or plane stress, 1D elements the
 * bar. A mismatch is a scene error, reported with both names. */
#include "dtmap/error.h"
#include "kernel-impl.h"

static const char *form_name(int f) {
  switch (f) {
  case DTM_FORM_3D: return "3d";
  case DTM_FORM_PLANE_STRAIN: return "plane-strain";
  case DTM_FORM_PLANE_STRESS: return "plane-stress";
  case DTM_FORM_BAR: return "bar";
  default: return "unknown";
  }
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
                 dtm_elem_name(type), d, form_name(f),
                 d == 3   ? "3d"
                 : d == 2 ? "plane-strain or plane-stress"
                          : "bar");
}
