/* The named materials the ONELAB panel offers for each physical group, in SI
 * units (the panel shows them converted into the scene's system of units:
 * dtm_ol_prop_si), with the source of their values (docs/materials.md
 * explains each entry). NaN marks a property the library does not give: a
 * material chosen for an effect that needs it is an error naming the group,
 * as in a scene. */
#include <math.h>

#include "dtmap/units.h"
#include "onelab-impl.h"

/* Columns: E (Pa), nu, rho (kg/m^3), conductivity (W/(m K)), heat capacity
 * (J/(kg K)), permeability (m^2), viscosity (Pa s), storage (1/Pa), fracture
 * energy (J/m^2), strength (Pa); damping (xi, alpha, beta) is the damping
 * effect's, not a material's. */
#define ROW(e, nu, rho, k, cp, perm, visc, stor, gc, ft)                                                               \
  { e, nu, rho, k, cp, perm, visc, stor, gc, ft }

const char *const dtm_ol_prop_names[OL_NPROPS] = {
    "E",       "nu", "rho", "conductivity", "heat-capacity", "permeability", "viscosity", "storage", "fracture-energy",
    "strength"};
/* The unit of each property in SI and in mm-t-s (docs/units.md: the system's
 * derived units, energy in mJ = N mm), and the SI value of one mm-t-s unit:
 * MPa (1e6 Pa), t/mm^3 (1e12 kg/m^3), mW/(mm K) (= W/(m K)), mJ/(t K)
 * (1e-6 J/(kg K)), mm^2, MPa s, 1/MPa (1e-6 /Pa), N/mm (1e3 J/m^2). */
static const char *const si_unit[OL_NPROPS] = {"Pa",  "",     "kg/m^3", "W/(m K)", "J/(kg K)",
                                               "m^2", "Pa s", "1/Pa",   "J/m^2",   "Pa"};
static const char *const mm_unit[OL_NPROPS] = {"MPa",  "",      "t/mm^3", "mW/(mm K)", "mJ/(t K)",
                                               "mm^2", "MPa s", "1/MPa",  "N/mm",      "MPa"};
static const double mm_si[OL_NPROPS] = {1e6, 1, 1e12, 1, 1e-6, 1e-6, 1e6, 1e-6, 1e3, 1e6};

const char *dtm_ol_prop_unit(const char *system, int p) {
  if (p < 0 || p >= OL_NPROPS) return "";
  return dtm_units_mm(system) ? mm_unit[p] : si_unit[p];
}

double dtm_ol_prop_si(const char *system, int p) {
  if (p < 0 || p >= OL_NPROPS) return 1;
  return dtm_units_mm(system) ? mm_si[p] : 1;
}

const ol_material dtm_ol_materials[] = {
    {"steel", ROW(210e9, 0.30, 7850, 53.3, 440, NAN, NAN, NAN, NAN, NAN),
     "structural steel: EN 1993-1-1 (E, nu, rho); EN 1993-1-2 at 20 C (conductivity, heat capacity)"},
    {"aluminium", ROW(68.9e9, 0.33, 2700, 167, 896, NAN, NAN, NAN, NAN, NAN),
     "alloy 6061-T6: ASM Handbook vol. 2, typical values"},
    {"titanium", ROW(113.8e9, 0.342, 4430, 6.7, 526, NAN, NAN, NAN, NAN, NAN),
     "alloy Ti-6Al-4V: ASM Handbook vol. 2, typical values"},
    {"glass", ROW(72e9, 0.22, 2500, 1.0, 840, NAN, NAN, NAN, NAN, NAN), "soda-lime glass: typical handbook values"},
    {"granite", ROW(60e9, 0.25, 2650, 2.8, 790, NAN, NAN, NAN, 40, 10e6),
     "intact granite: Goodman (E, nu); Robertson, USGS 88-441 (thermal); K_Ic 1.5 MPa m^0.5 (fracture energy)"},
    {"concrete", ROW(33e9, 0.20, 2400, 1.6, 900, NAN, NAN, NAN, 140, 2.9e6),
     "normal-weight C30/37: EN 1992-1-1 (E, tensile strength), EN 1992-1-2 (thermal), fib Model Code 2010 (G_F)"},
    {"water-saturated sandstone", ROW(14.4e9, 0.20, 2340, 2.5, 1000, 1.9e-13, 1.0e-3, 1.0e-10, 15, 3e6),
     "Berea sandstone saturated with water at 20 C: Wang, Theory of Linear Poroelasticity (K, G, porosity, "
     "permeability, Biot modulus)"},
    {NULL, {0}, NULL}};

int dtm_ol_material_count(void) {
  int n = 0;
  while (dtm_ol_materials[n].name) n++;
  return n;
}
