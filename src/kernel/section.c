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

static int shell_bounds(const dtm_section *s, int type, double E, double nu, double rho, const double *x, double screen,
                        dtm_section_bounds *out) {
  dtm_shell_section sh = {E, nu, rho, s->thickness, s->shear};
  double l[3], m[DTM_STRUCT_DOF];
  int nn, scaled = s->rotary == DTM_ROTARY_SCALED_INERTIA;
  int need = DTM_STRUCT_NEED_PHYSICAL | (scaled ? DTM_STRUCT_NEED_SCALE : 0);
  DTM_CHECK(dtm_kernel_shell_bounds(type, &sh, x, need, scaled ? screen : 0, l, m, &nn));
  if (scaled && !isfinite(l[1]))
    return DTM_ERR(DTM_ERR_INPUT, "shell: no finite rotary inertia scale brings the element to its membrane step");
  out->lambda = scaled ? l[0] : l[2]; /* scaled: the membrane eigenvalue (structural.h) */
  out->lambda_physical = l[2], out->lambda_reference = l[0];
  out->scale = scaled ? l[1] : 1.0;
  node_masses(nn, m, out->scale, out);
  return DTM_OK;
}

/* The kernel's beam section of s with material E, nu, rho. */
static dtm_beam_section beam_of(const dtm_section *s, double E, double nu, double rho) {
  dtm_beam_section b = {E, nu, rho, s->area, s->iy, s->iz, s->jt, s->shear, {0, 0, 0}, 1};
  memcpy(b.ref, s->orient, sizeof b.ref);
  return b;
}

/* lambda under the scaled convention is the axial eigenvalue whenever the
 * scale is finite (structural.h). */
static int beam_bounds(const dtm_section *s, double E, double nu, double rho, const double *x, double screen,
                       dtm_section_bounds *out) {
  dtm_beam_section b = beam_of(s, E, nu, rho);
  double l[3], m[DTM_STRUCT_DOF];
  int scaled = s->rotary == DTM_ROTARY_SCALED_INERTIA;
  int need = DTM_STRUCT_NEED_PHYSICAL | (scaled ? DTM_STRUCT_NEED_SCALE : 0);
  DTM_CHECK(dtm_kernel_beam_bounds(&b, x, need, scaled ? screen : 0, l, m));
  if (scaled && !isfinite(l[1]))
    return DTM_ERR(DTM_ERR_INPUT, "beam: no finite rotary inertia scale brings the element to its axial step "
                                  "(k G >= E)");
  out->lambda = scaled ? l[0] : l[2];
  out->lambda_physical = l[2], out->lambda_reference = l[0];
  out->scale = scaled ? l[1] : 1.0;
  node_masses(2, m, out->scale, out);
  return DTM_OK;
}

static int refuse(const dtm_section *s, int type) {
  return DTM_ERR(DTM_ERR_INPUT, "a %s section does not take %s elements (shells: tri3, quad4; beams: line2)",
                 s ? dtm_section_kind_name(s->kind) : "missing", dtm_elem_name(type));
}

static int takes(const dtm_section *s, int type) {
  return s && ((s->kind == DTM_SECTION_SHELL && (type == DTM_TRI3 || type == DTM_QUAD4)) ||
               (s->kind == DTM_SECTION_BEAM && type == DTM_LINE2));
}

int dtm_section_element_screened(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                                 double screen, dtm_section_bounds *out) {
  memset(out, 0, sizeof *out);
  if (!takes(s, type)) return refuse(s, type);
  return s->kind == DTM_SECTION_SHELL ? shell_bounds(s, type, E, nu, rho, x, screen, out)
                                      : beam_bounds(s, E, nu, rho, x, screen, out);
}

int dtm_section_element(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                        dtm_section_bounds *out) {
  return dtm_section_element_screened(s, type, E, nu, rho, x, 0, out);
}

int dtm_section_element_known(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                              double lambda, dtm_section_bounds *out) {
  double m[DTM_STRUCT_DOF];
  int nn = 2;
  memset(out, 0, sizeof *out);
  if (!takes(s, type)) return refuse(s, type);
  if (s->rotary == DTM_ROTARY_SCALED_INERTIA) return dtm_section_element(s, type, E, nu, rho, x, out);
  if (s->kind == DTM_SECTION_SHELL) {
    dtm_shell_section sh = {E, nu, rho, s->thickness, s->shear};
    DTM_CHECK(dtm_kernel_shell_masses(type, &sh, x, m, &nn));
  } else {
    dtm_beam_section bm = beam_of(s, E, nu, rho);
    DTM_CHECK(dtm_kernel_beam_masses(&bm, x, m));
  }
  out->lambda = out->lambda_physical = lambda;
  out->lambda_reference = NAN;
  out->scale = 1.0;
  node_masses(nn, m, 1.0, out);
  return DTM_OK;
}

/* The scaled convention from the reference eigenvalue and the scale
 * alone: lambda_scaled = lambda_reference whenever the scale is finite. */
static int scaled_step(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                       dtm_section_bounds *out) {
  double b[2], m[DTM_STRUCT_DOF];
  int nn = 2;
  double l[3];
  if (s->kind == DTM_SECTION_SHELL) {
    dtm_shell_section sh = {E, nu, rho, s->thickness, s->shear};
    DTM_CHECK(dtm_kernel_shell_bounds(type, &sh, x, DTM_STRUCT_NEED_SCALE, 0, l, m, &nn));
  } else {
    dtm_beam_section bm = beam_of(s, E, nu, rho);
    DTM_CHECK(dtm_kernel_beam_bounds(&bm, x, DTM_STRUCT_NEED_SCALE, 0, l, m));
  }
  b[0] = l[0], b[1] = l[1];
  if (!isfinite(b[1]))
    return DTM_ERR(DTM_ERR_INPUT, "%s: no finite rotary inertia scale brings the element to its %s step",
                   dtm_section_kind_name(s->kind), s->kind == DTM_SECTION_SHELL ? "membrane" : "axial");
  out->lambda = out->lambda_reference = b[0];
  out->lambda_physical = NAN;
  out->scale = b[1];
  node_masses(nn, m, b[1], out);
  return DTM_OK;
}

int dtm_section_element_lambda(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                               double *lambda) {
  dtm_section_bounds b;
  if (!takes(s, type)) return refuse(s, type);
  double k = s->shear > 0 ? s->shear : 5.0 / 6.0;
  /* shells with k <= 1: the scale is finite (structural.h); beams go the
   * whole way, which also checks their orientation */
  if (s->kind != DTM_SECTION_SHELL || s->rotary != DTM_ROTARY_SCALED_INERTIA || !(k <= 1)) {
    DTM_CHECK(dtm_section_element_step(s, type, E, nu, rho, x, &b));
    *lambda = b.lambda;
    return DTM_OK;
  }
  dtm_elastic_moduli mod;
  DTM_CHECK(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, E, nu, rho, &mod));
  return dtm_kernel_elastic_lambda(type, &mod, x, lambda);
}

int dtm_section_element_step(const dtm_section *s, int type, double E, double nu, double rho, const double *x,
                             dtm_section_bounds *out) {
  if (!takes(s, type)) return memset(out, 0, sizeof *out), refuse(s, type);
  if (s->rotary != DTM_ROTARY_SCALED_INERTIA) return dtm_section_element(s, type, E, nu, rho, x, out);
  memset(out, 0, sizeof *out);
  return scaled_step(s, type, E, nu, rho, x, out);
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
