/* The ONELAB session helpers of onelab.h: Gmsh's C API calls the ONELAB
 * tests (t804, t805) make around each panel action, with cmocka's checks
 * of every error code. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "onelab.h"
#include "testutil.h"

void tu_onelab_session(const char *model, const char *test) {
  int ierr = 0;
  char sock[96];
  tu_gmsh_begin();
  snprintf(sock, sizeof sock, ".gmshsock-%s-%ld-", test, (long)getpid());
  gmshOptionSetString("Solver.SocketName", sock, &ierr);
  gmshOnelabClear("", &ierr);
  gmshOpen(model, &ierr);
  assert_int_equal(ierr, 0);
}

void tu_onelab_run(const char *action) {
  int ierr = 0;
  char *a[] = {(char *)action};
  gmshOnelabSetString("dtmap/Action", a, 1, &ierr);
  gmshOnelabRun("dtmap", tu_cli(), &ierr);
  assert_int_equal(ierr, 0);
}

void tu_onelab_set_number(const char *name, double v) {
  int ierr = 0;
  gmshOnelabSetNumber(name, &v, 1, &ierr);
  assert_int_equal(ierr, 0);
}

double tu_onelab_get_number(const char *name) {
  double *v = NULL, r = NAN;
  size_t n = 0;
  int ierr = 0;
  gmshOnelabGetNumber(name, &v, &n, &ierr);
  if (n == 1) r = v[0];
  gmshFree(v);
  return r;
}

void tu_onelab_assert_units(const char *name, const char *unit) {
  char *json = NULL;
  int ierr = 0;
  gmshOnelabGet(&json, name, "json", &ierr);
  cJSON *p = json && json[0] ? cJSON_Parse(json) : NULL;
  gmshFree(json);
  assert_non_null(p);
  const cJSON *u = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(p, "attributes"), "Units");
  if (!cJSON_IsString(u) || strcmp(u->valuestring, unit))
    fprintf(stderr, "%s: units '%s', expected '%s'\n", name, cJSON_IsString(u) ? u->valuestring : "", unit);
  assert_true(cJSON_IsString(u) && !strcmp(u->valuestring, unit));
  cJSON_Delete(p);
}

char *tu_onelab_compute_saved(const char *saved, double *rec, double *dmin) {
  tu_onelab_set_number("dtmap/5Scene/0save", 1);
  int ierr = 0;
  char *file[] = {(char *)saved};
  gmshOnelabSetString("dtmap/5Scene/1file", file, 1, &ierr);
  unlink(saved);
  tu_onelab_run("compute");
  *rec = tu_onelab_get_number("dtmap/9Results/0recommended");
  *dmin = tu_onelab_get_number("dtmap/9Results/2dt min");
  tu_gmsh_end();
  char *text = NULL;
  assert_int_equal(tu_run(&text, "cat %s", saved), 0);
  return text;
}
