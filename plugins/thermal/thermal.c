/* The thermal effect: heat conduction integrated by explicit forward Euler
 * with lumped heat capacity. Conductivity k, capacity rho c, diffusivity
 * alpha = k/(rho c); dt_e = 2/lambda_max(Ce^-1 Ke), which on simplices is
 * 2/((d+1) alpha s_max). The step scales with the square of the size. */
#include <math.h>

#include "common/diffusion.h"

static const dtm_property properties[] = {
    {"conductivity", "W/(m K)", 0, HUGE_VAL, DTM_OPEN_LO, 1, "thermal conductivity k"},
    {"heat-capacity", "J/(kg K)", 0, HUGE_VAL, DTM_OPEN_LO, 1, "specific heat capacity c"},
    {"rho", "kg/m^3", 0, HUGE_VAL, DTM_OPEN_LO, 1, "density"},
    {NULL, NULL, 0, 0, 0, 0, NULL}};

/* k = conductivity, capacity per volume = rho c. */
static void thermal_combine(const double v[3], double *k, double *c) { *k = v[0], *c = v[2] * v[1]; }

DTM_DIFFUSION_EFFECT(dtm_effect_thermal, "thermal", "heat conduction, forward Euler with lumped capacity", properties,
                     thermal_combine);
