/* In-memory fixtures for effect tests (see fixtures.h). */
#include "fixtures.h"

#include <stdarg.h>
#include <string.h>

void tu_fixture_init(tu_effect_fixture *f, const char *name, int dim, const char *const *attrs) {
  memset(f, 0, sizeof *f);
  f->scene.path = "fixture.xml";
  f->scene.safety = 0.9;
  f->se.name = (char *)name;
  f->se.line = 7;
  for (int i = 0; attrs && attrs[2 * i] && i < 8; i++) {
    f->keys[i] = (char *)attrs[2 * i];
    f->values[i] = (char *)attrs[2 * i + 1];
    f->se.nattr = i + 1;
  }
  f->se.keys = f->keys;
  f->se.values = f->values;
  f->group = (dtm_group){dim, 1, "rock"};
  f->mesh.dim = dim;
  f->mesh.ngroups = 1;
  f->mesh.groups = &f->group;
  f->args = (dtm_effect_args){&f->scene, &f->se, &f->mesh};
}

void tu_material(dtm_material *m, const char *name, ...) {
  memset(m, 0, sizeof *m);
  m->name = (char *)name;
  m->file = "fixture.xml";
  m->line = 3;
  va_list ap;
  va_start(ap, name);
  for (int p; (p = va_arg(ap, int)) >= 0;) {
    m->prop[p] = va_arg(ap, double);
    m->have |= DTM_PROP_BIT(p);
  }
  va_end(ap);
}

dtm_batch tu_batch1(int type, const double *x, const dtm_material **m) {
  static const size_t tag = 1;
  static const int group = 0;
  int dim = 0, nn = 0;
  dtm_elem_info(type, &dim, &nn);
  return (dtm_batch){type, dim, nn, 1, x, &tag, &group, NULL, m};
}
