/* Elastic moduli of an isotropic material as each formulation sees them:
 * Lame parameters (lam, mu) from E and nu, the plane-stress reduction
 * lam* = 2 lam mu / (lam + 2 mu), the bar (modulus E, no shear), the
 * P-wave modulus lam + 2 mu and the dilatational wave speed. Computed once
 * per material and formulation, then read by every element kernel. */
#include <math.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/units.h"

static int check(dtm_formulation f, double E, double nu, double rho) {
  if (f < DTM_FORM_3D || f > DTM_FORM_BAR) return DTM_ERR(DTM_ERR_INPUT, "unknown elastic formulation %d", (int)f);
  char t[48];
  if (!isfinite(E) || !(E > 0))
    return DTM_ERR(DTM_ERR_INPUT, "Young's modulus E must be finite and > 0 (got %s)",
                   dtm_units_si_text(DTM_UNIT_MODULUS, E, 6, t, sizeof t));
  if (!isfinite(rho) || !(rho > 0))
    return DTM_ERR(DTM_ERR_INPUT, "density rho must be finite and > 0 (got %s)",
                   dtm_units_si_text(DTM_UNIT_DENSITY, rho, 6, t, sizeof t));
  if (!isfinite(nu) || !(nu > -1 && nu < 0.5))
    return DTM_ERR(DTM_ERR_INPUT, "Poisson's ratio nu must lie in (-1, 0.5) (got %g)", nu);
  return DTM_OK;
}

const char *dtm_integration_name(int model) {
  static const char *const names[] = {"converged", "full", "calculix"};
  return model >= 0 && model <= DTM_INTEGRATION_CALCULIX ? names[model] : "unknown";
}

int dtm_elastic_moduli_init(dtm_formulation f, double E, double nu, double rho, dtm_elastic_moduli *m) {
  DTM_CHECK(check(f, E, nu, rho));
  double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  m->form = f;
  m->rho = rho;
  m->integration = DTM_INTEGRATION_CONVERGED;
  if (f == DTM_FORM_BAR) {
    m->lam = m->mu = 0;
    m->modulus = E;
  } else {
    m->lam = f == DTM_FORM_PLANE_STRESS ? 2 * lam * mu / (lam + 2 * mu) : lam;
    m->mu = mu;
    m->modulus = m->lam + 2 * mu;
  }
  m->cd = sqrt(m->modulus / rho);
  return DTM_OK;
}
