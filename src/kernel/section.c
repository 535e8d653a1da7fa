/* Section kinds: their scene names, the element dimension each applies to,
 * the elastic formulation each implies and the measure factor (thickness or
 * area) that scales an element's stiffness and lumped mass alike; and the
 * bounds and lumped masses of one shell or beam element under its section's
 * rotary-inertia convention, from the structural kernels (structural.h). */
#include <math.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/section.h"
#include "structural.h"

static const char *const names[] = DTM_SECTION_NAMES;

const char *dtm_section_kind_name(int k) {
  return k >= DTM_SECTION_SOLID && k <= DTM_SECTION_BEAM ? names[k] : "unknown";
}

int dtm_section_dim(int k) {
  return k == DTM_SECTION_SOLID ? 3 : k == DTM_SECTION_TRUSS || k == DTM_SECTION_BEAM ? 1 : 2;
}

int dtm_section_has_rotations(int k) { return k == DTM_SECTION_SHELL || k == DTM_SECTION_BEAM; }

dtm_formulation dtm_section_formulation(int k) {
  switch (k) {
  case DTM_SECTION_SOLID: return DTM_FORM_3D;
  case DTM_SECTION_PLANE_STRAIN: return DTM_FORM_PLANE_STRAIN;
  case DTM_SECTION_TRUSS:
  case DTM_SECTION_BEAM: return DTM_FORM_BAR;
  default: return DTM_FORM_PLANE_STRESS;
  }
}

double dtm_section_factor(const dtm_section *s) {
  if (!s || s->kind == DTM_SECTION_SOLID) return 1.0;
  return s->kind == DTM_SECTION_TRUSS || s->kind == DTM_SECTION_BEAM ? s->area : s->thickness;
}

/* Translational and rotary masses of each node from the frame diagonal m
 * (6 unknowns per node), the rotary ones times scale. */
static void node_masses(int nn, const double *m, double scale, dtm_section_bounds *out) {
  out->nn = nn;
  for (int a = 0; a < nn; a++) out->mt[a] = m[6 * a], out->mr[a] = m[6 * a + 3] * scale;
}

static int shell_bounds(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                        dtm_section_bounds *out) {
  dtm_shell_section sh = {E, nu, rho, s->thickness, s->shear};
  dtm_shell_lambda l;
  dtm_struct_matrices mat;
  DTM_CHECK(dtm_kernel_shell_lambda(type, &sh, x, &l));
  DTM_CHECK(dtm_kernel_shell_matrices(type, &sh, x, DTM_ROTARY_PHYSICAL, &mat));
  int scaled = s->rotary == DTM_ROTARY_SCALED_INERTIA;
  if (scaled && !isfinite(l.scale))
    return DTM_ERR(DTM_ERR_INPUT, "shell: no finite rotary inertia scale brings the element to its membrane step");
  out->lambda = scaled ? l.lambda_scaled : l.lambda_physical;
  out->lambda_physical = l.lambda_physical, out->lambda_reference = l.lambda_membrane;
  out->scale = scaled ? l.scale : 1.0;
  node_masses(mat.nn, mat.m, out->scale, out);
  return DTM_OK;
}

/* The kernel's beam section of s with material E, nu, rho. */
static dtm_beam_section beam_of(const dtm_section *s, double E, double nu, double rho) {
  dtm_beam_section b = {E, nu, rho, s->area, s->iy, s->iz, s->jt, s->shear, {0, 0, 0}, 1};
  memcpy(b.ref, s->orient, sizeof b.ref);
  return b;
}

static int beam_bounds(const dtm_section *s, double E, double nu, double rho, const double *x,
                       dtm_section_bounds *out) {
  dtm_beam_section b = beam_of(s, E, nu, rho);
  dtm_beam_lambda l;
  dtm_struct_matrices mat;
  DTM_CHECK(dtm_kernel_beam_lambda(&b, x, &l));
  DTM_CHECK(dtm_kernel_beam_matrices(&b, x, DTM_ROTARY_PHYSICAL, &mat));
  int scaled = s->rotary == DTM_ROTARY_SCALED_INERTIA;
  if (scaled && !isfinite(l.scale))
    return DTM_ERR(DTM_ERR_INPUT, "beam: no finite rotary inertia scale brings the element to its axial step "
                                  "(k G >= E)");
  out->lambda = scaled ? l.lambda_scaled : l.lambda_physical;
  out->lambda_physical = l.lambda_physical, out->lambda_reference = l.lambda_axial;
  out->scale = scaled ? l.scale : 1.0;
  node_masses(2, mat.m, out->scale, out);
  return DTM_OK;
}

int dtm_section_element(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                        dtm_section_bounds *out) {
  memset(out, 0, sizeof *out);
  if (s && s->kind == DTM_SECTION_SHELL && (type == DTM_TRI3 || type == DTM_QUAD4))
    return shell_bounds(s, type, E, nu, rho, x, out);
  if (s && s->kind == DTM_SECTION_BEAM && type == DTM_LINE2) return beam_bounds(s, E, nu, rho, x, out);
  return DTM_ERR(DTM_ERR_INPUT, "a %s section does not take %s elements (shells: tri3, quad4; beams: line2)",
                 s ? dtm_section_kind_name(s->kind) : "missing", dtm_elem_name(type));
}

int dtm_section_matrices(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                         dtm_struct_matrices *out) {
  dtm_rotary_convention c = s->rotary == DTM_ROTARY_SCALED_INERTIA ? DTM_ROTARY_SCALED : DTM_ROTARY_PHYSICAL;
  if (s->kind == DTM_SECTION_SHELL) {
    dtm_shell_section sh = {E, nu, rho, s->thickness, s->shear};
    return dtm_kernel_shell_matrices(type, &sh, x, c, out);
  }
  dtm_beam_section b = beam_of(s, E, nu, rho);
  return dtm_kernel_beam_matrices(&b, x, c, out);
}
