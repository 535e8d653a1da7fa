/* The hydraulic effect: pore-fluid diffusion integrated by explicit forward
 * Euler with lumped storage. Conductivity permeability/viscosity, capacity
 * storage, so D = permeability / (viscosity storage); the kernel is the
 * thermal one (plugins/common/diffusion.c). */
#include <math.h>

#include "common/diffusion.h"

static const dtm_property properties[] = {
    {"permeability", "m^2", 0, HUGE_VAL, DTM_OPEN_LO, 1, "intrinsic permeability"},
    {"viscosity", "Pa s", 0, HUGE_VAL, DTM_OPEN_LO, 1, "dynamic viscosity of the pore fluid"},
    {"storage", "1/Pa", 0, HUGE_VAL, DTM_OPEN_LO, 1, "specific storage"},
    {NULL, NULL, 0, 0, 0, 0, NULL}};

/* k = permeability / viscosity, capacity = storage. */
static void hydraulic_combine(const double v[3], double *k, double *c) { *k = v[0] / v[1], *c = v[2]; }

DTM_DIFFUSION_EFFECT(dtm_effect_hydraulic, "hydraulic", "pore-fluid diffusion, forward Euler with lumped storage",
                     properties, hydraulic_combine);
