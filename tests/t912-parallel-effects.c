/* Everything a scene asks for gives the same numbers distributed as
 * serial, on the Brazilian disc (granite and steel): (a) elastic waves with
 * Rayleigh damping in the scene and a damping ratio of the steel's own,
 * cohesive springs in the rock and a wavelength bound, from one .msh that
 * rank 0 splits with Gmsh (mpirun -n 4 on a one-mesh scene); (b) heat and
 * pore-fluid diffusion next to the elastic waves, without a target (so the
 * view of the 1 % smallest steps rests on the whole mesh's quantile), from
 * part files Gmsh wrote. Every view of the serial output is in the
 * merged parts: element views bit-identical, node views and the element
 * views that read them (the own step below the target, the added mass)
 * within 1e-14 (the added mass: of its largest value); each effect's
 * element, nodal and global minima, the recommendation, the cost, the
 * subcycling counts, the mass-scaling totals, the smallest steps, the
 * cohesive zones and the damping factors agree; so do the shape-limited
 * elements from the one mesh (t915 compares them in detail). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parts.h"

#define NP 4

static char dir[512];

static const char granite[] = "<material name=\"granite\" groups=\"rock\" E=\"60e9\" nu=\"0.25\" rho=\"2700\" "
                              "conductivity=\"3\" heat-capacity=\"790\" permeability=\"1e-15\" viscosity=\"1e-3\" "
                              "storage=\"1e-9\" fracture-energy=\"50\" strength=\"10e6\"/>\n";
static const char steel[] = "<material name=\"steel\" groups=\"platen_top platen_bottom\" E=\"210e9\" nu=\"0.3\" "
                            "rho=\"7850\" xi=\"0.2\" conductivity=\"45\" heat-capacity=\"460\" permeability=\"1e-18\" "
                            "viscosity=\"1e-3\" storage=\"1e-10\"/>\n";
static const char waves[] = "<effects><elastic formulation=\"plane-strain\"/><damping alpha=\"2e3\" beta=\"2e-9\"/>"
                            "<cohesive groups=\"rock\" stiffness=\"1e16\"/></effects>\n"
                            "<time safety=\"0.8\" target=\"8e-8\" duration=\"1e-4\" f-max=\"1e6\"/>\n";
static const char diffusion[] = "<effects><thermal/><hydraulic/><elastic formulation=\"plane-strain\"/></effects>\n"
                                "<time duration=\"1e-3\"/>\n";

static void write_scene(const char *name, const char *source, const char *effects) {
  char path[1024], text[4096];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  snprintf(text, sizeof text, "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n%s\n%s%s%s</dtmap-scene>\n",
           source, granite, steel, effects);
  tu_write(path, text);
}

static int setup(void **state) {
  (void)state;
  snprintf(dir, sizeof dir, "%s", tu_tmpdir());
  tu_gmsh_begin();
  tu_mesh_and_split("brazilian_disc.geo", 2, 2e-3, dir, "disc", NP);
  write_scene("waves.xml", "<mesh file=\"disc.msh\"/>", waves);
  write_scene("diff.xml", "<mesh file=\"disc.msh\"/>", diffusion);
  write_scene("diff_parts.xml", "<mesh file=\"disc_parts.msh\" partitions=\"4\"/>", diffusion);
  return tu_run_pair(dir, NP, "waves.xml", "waves.xml", "waves") |
         tu_run_pair(dir, NP, "diff.xml", "diff_parts.xml", "diff");
}

static int teardown(void **state) {
  (void)state;
  tu_gmsh_end();
  return 0;
}

/* Every view of the serial output, in the parts merged by Gmsh. */
static void views(const char *tag) {
  char whole[1024], parts[1024], names[64][96];
  snprintf(whole, sizeof whole, "%s/%s_ser.msh", dir, tag);
  snprintf(parts, sizeof parts, "%s/%s_par.msh", dir, tag);
  int n = tu_view_list(whole, names, 64);
  assert_true(n >= 8);
  for (int i = 0; i < n; i++) {
    tu_view a, b;
    if (!strcmp(names[i], "dtmap")) continue;         /* the .opt's text view, not data */
    if (!strcmp(names[i], "shape limited")) continue; /* needs the whole model: not in a distributed run */
    tu_view_diff d;
    int found = tu_view_pair(whole, parts, NP, names[i], &a, &b);
    if (found) fprintf(stderr, "%s: view '%s' not in both outputs\n", tag, names[i]);
    assert_int_equal(found, 0);
    tu_view_compare(&a, &b, &d);
    int node = !strcmp(a.type, "NodeData") || !strcmp(names[i], "below target [s]");
    int added = !strcmp(names[i], "added mass"); /* m ((target/dt)^2 - 1): digits lost near the target */
    double worst = added ? d.scaled : d.worst;
    if (d.missing || (!node && !added && d.bitequal != a.n) || worst > 1e-14)
      fprintf(stderr, "%s: view '%s': %zu missing, %zu of %zu identical, worst %g, scaled %g\n", tag, names[i],
              d.missing, d.bitequal, a.n, d.worst, d.scaled);
    assert_int_equal(d.missing, 0);
    if (!node && !added) assert_int_equal(d.bitequal, a.n); /* element by element: the same kernels on the same nodes */
    assert_true(worst <= 1e-14);                            /* node sums in another order */
    tu_view_free(&a), tu_view_free(&b);
  }
}

static double rel(double a, double b) { return a == b ? 0 : fabs(a - b) / fabs(a); }

static double field(const cJSON *o, const char *key) {
  const cJSON *v = cJSON_GetObjectItem(o, key);
  return v && cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* Each effect's minima: the element one exact, the nodal one within 1e-14,
 * the global one (both at a residual of at most 1e-9 theta) within 1e-6. */
static void effect_minima(const cJSON *s, const cJSON *p) {
  const cJSON *ms = cJSON_GetObjectItem(s, "effect_minima"), *mp = cJSON_GetObjectItem(p, "effect_minima");
  assert_int_equal(cJSON_GetArraySize(ms), cJSON_GetArraySize(mp));
  for (int k = 0; k < cJSON_GetArraySize(ms); k++) {
    const cJSON *a = cJSON_GetArrayItem(ms, k), *b = cJSON_GetArrayItem(mp, k);
    assert_string_equal(cJSON_GetObjectItem(a, "name")->valuestring, cJSON_GetObjectItem(b, "name")->valuestring);
    assert_true(field(a, "min") == field(b, "min") || (isnan(field(a, "min")) && isnan(field(b, "min"))));
    assert_true(field(a, "element") == field(b, "element") || isnan(field(a, "element")));
    assert_true(rel(field(a, "nodal"), field(b, "nodal")) <= 1e-14 || isnan(field(a, "nodal")));
    assert_true(rel(field(a, "global"), field(b, "global")) <= 1e-6 || isnan(field(a, "global")));
    assert_true(isnan(field(a, "global")) == isnan(field(b, "global")));
  }
}

/* The same JSON text, numbers within tol (relative) of each other. */
static void same_json(const cJSON *a, const cJSON *b, double tol) {
  assert_non_null(a), assert_non_null(b);
  assert_int_equal(a->type, b->type);
  if (cJSON_IsNumber(a)) {
    if (rel(a->valuedouble, b->valuedouble) > tol) fprintf(stderr, "%.17g != %.17g\n", a->valuedouble, b->valuedouble);
    assert_true(rel(a->valuedouble, b->valuedouble) <= tol);
  } else if (cJSON_IsString(a)) {
    assert_string_equal(a->valuestring, b->valuestring);
  } else if (cJSON_IsArray(a) || cJSON_IsObject(a)) {
    assert_int_equal(cJSON_GetArraySize(a), cJSON_GetArraySize(b));
    for (const cJSON *x = a->child, *y = b->child; x; x = x->next, y = y->next) {
      if (x->string) assert_string_equal(x->string, y->string);
      same_json(x, y, tol);
    }
  }
}

static const cJSON *item(const cJSON *o, const char *key) { return cJSON_GetObjectItem(o, key); }

/* 1 when one of the report's warnings contains text. */
static int warns(const cJSON *r, const char *text) {
  const cJSON *w;
  cJSON_ArrayForEach(w, item(r, "warnings")) if (strstr(w->valuestring, text)) return 1;
  return 0;
}

/* The same elements listed under key (by tag, in order). */
static void same_tags(const cJSON *s, const cJSON *p, const char *key) {
  const cJSON *a = item(s, key), *b = item(p, key);
  assert_int_equal(cJSON_GetArraySize(a), cJSON_GetArraySize(b));
  for (const cJSON *x = a->child, *y = b->child; x; x = x->next, y = y->next)
    assert_true(tu_json_number(x, "element") == tu_json_number(y, "element"));
}

/* The advice: the same smallest steps (exact), below-target count, cohesive
 * zones (1e-15: R from one element's figures), damping factors and cost
 * (1e-6: they rest on the recommendation, the global estimate's tolerance).
 * Which elements below the target are shape-limited needs the whole model:
 * from one mesh (model 1; rank 0 keeps it from the split) the same ones as
 * the serial run's, and no warning; from part files (no model) none, and a
 * warning says so when elements are below the target. */
static void advice(const cJSON *s, const cJSON *p, int model) {
  same_json(item(s, "worst"), item(p, "worst"), 0.0);
  same_json(item(s, "cohesive"), item(p, "cohesive"), 1e-15);
  same_json(item(s, "damping"), item(p, "damping"), 1e-6);
  same_json(item(s, "cost"), item(p, "cost"), 1e-6);
  assert_true(tu_json_number(s, "below_target") == tu_json_number(p, "below_target"));
  if (model) {
    assert_true(tu_json_number(p, "shape_limited_count") == tu_json_number(s, "shape_limited_count"));
    same_tags(s, p, "shape_limited");
    same_tags(s, p, "thickness_limited");
    assert_false(warns(p, "shape-limited"));
    return;
  }
  assert_true(tu_json_number(p, "shape_limited_count") == 0);
  assert_true(warns(p, "shape-limited") == (tu_json_number(p, "below_target") > 0));
}

static void report(const char *tag, int model) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s_ser.json", dir, tag);
  cJSON *s = tu_json_load(path);
  snprintf(path, sizeof path, "%s/%s_par.json", dir, tag);
  cJSON *p = tu_json_load(path);
  assert_non_null(s), assert_non_null(p);
  assert_true(tu_json_number(s, "mesh.elements") == tu_json_number(p, "mesh.elements"));
  assert_true(tu_json_number(s, "mesh.nodes") == tu_json_number(p, "mesh.nodes"));
  assert_true(tu_json_number(s, "dt.min") == tu_json_number(p, "dt.min"));
  assert_true(rel(tu_json_number(s, "dt.recommended"), tu_json_number(p, "dt.recommended")) <= 1e-6);
  assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(s, "dt"), "basis")->valuestring,
                      cJSON_GetObjectItem(cJSON_GetObjectItem(p, "dt"), "basis")->valuestring);
  effect_minima(s, p);
  char *ls = cJSON_PrintUnformatted(cJSON_GetObjectItem(cJSON_GetObjectItem(s, "subcycling"), "levels"));
  char *lp = cJSON_PrintUnformatted(cJSON_GetObjectItem(cJSON_GetObjectItem(p, "subcycling"), "levels"));
  assert_string_equal(ls, lp); /* the same level for every element */
  free(ls), free(lp);
  double added = tu_json_number(s, "mass_scaling.total_added"); /* with a target */
  assert_true(isnan(added) == isnan(tu_json_number(p, "mass_scaling.total_added")));
  assert_true(isnan(added) || rel(added, tu_json_number(p, "mass_scaling.total_added")) <= 1e-12); /* ~5000 terms */
  assert_true(isnan(added) ||
              tu_json_number(s, "mass_scaling.elements_scaled") == tu_json_number(p, "mass_scaling.elements_scaled"));
  assert_true(tu_json_number(s, "accuracy.under_resolved") == tu_json_number(p, "accuracy.under_resolved") ||
              isnan(tu_json_number(s, "accuracy.under_resolved")));
  advice(s, p, model);
  cJSON_Delete(s), cJSON_Delete(p);
}

static void waves_damping_cohesive(void **state) {
  (void)state;
  views("waves");
  report("waves", 1);
}

static void thermal_hydraulic(void **state) {
  (void)state;
  views("diff");
  report("diff", 0);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(waves_damping_cohesive),
      cmocka_unit_test(thermal_hydraulic),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
