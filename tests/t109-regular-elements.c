/* The well-shaped element of every supported type (dtm_elem_regular), the
 * reference the advice compares an element's step with: its mean edge
 * length is h, and its measure is the closed form of its shape: bar h,
 * equilateral triangle sqrt(3)/4 h^2, square h^2, regular tetrahedron
 * h^3/(6 sqrt 2), cube h^3, prism on an equilateral triangle with square
 * sides sqrt(3)/4 h^3, pyramid with all edges h h^3/(3 sqrt 2); the
 * second-order types are straight-sided, so theirs are the same. h = 0.37
 * (not a power of two); tolerance 1e-14 relative: a handful of roundings in
 * the map and the measure. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/topology.h"
#include "reference.h"

static double closed_form(int parent, double h) {
  switch (parent) {
  case DTM_LINE2: return h;
  case DTM_TRI3: return sqrt(3.0) / 4 * h * h;
  case DTM_QUAD4: return h * h;
  case DTM_TET4: return h * h * h / (6 * sqrt(2.0));
  case DTM_HEX8: return h * h * h;
  case DTM_PRISM6: return sqrt(3.0) / 4 * h * h * h;
  default: return h * h * h / (3 * sqrt(2.0)); /* pyramid */
  }
}

static void check(int type, int parent) {
  const double h = 0.37;
  double x[DTM_MAX_NODES * 3];
  assert_int_equal(dtm_elem_regular(type, h, x), 0);
  double mean = dtm_elem_mean_edge(type, x), v = dtm_elem_measure(type, x), want = closed_form(parent, h);
  if (fabs(mean - h) > 1e-14 * h) fail_msg("%s: mean edge %.17g, want %.17g", dtm_elem_name(type), mean, h);
  if (fabs(v - want) > 1e-14 * want) fail_msg("%s: measure %.17g, want %.17g", dtm_elem_name(type), v, want);
}

static void all_types(void **unused) {
  static const int types[][2] = {{DTM_LINE2, DTM_LINE2},    {DTM_TRI3, DTM_TRI3},      {DTM_TRI6, DTM_TRI3},
                                 {DTM_QUAD4, DTM_QUAD4},    {DTM_QUAD8, DTM_QUAD4},    {DTM_QUAD9, DTM_QUAD4},
                                 {DTM_TET4, DTM_TET4},      {DTM_TET10, DTM_TET4},     {DTM_HEX8, DTM_HEX8},
                                 {DTM_HEX20, DTM_HEX8},     {DTM_HEX27, DTM_HEX8},     {DTM_PRISM6, DTM_PRISM6},
                                 {DTM_PRISM15, DTM_PRISM6}, {DTM_PRISM18, DTM_PRISM6}, {DTM_PYR5, DTM_PYR5},
                                 {DTM_PYR13, DTM_PYR5},     {DTM_PYR14, DTM_PYR5}};
  for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) check(types[i][0], types[i][1]);
  double x[DTM_MAX_NODES * 3];
  assert_int_equal(dtm_elem_regular(29, 1.0, x), DTM_ERR_INPUT); /* third-order triangle: not supported */
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(all_types)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
