/* In-memory fixtures for effect tests (see fixtures.h). */
#include "dtmap/analysis.h"
#include "fixtures.h"
#include "kernel-impl.h"
#include "dtmap/operator.h"
#include "dtmap/registry.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
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
  tu_scene_catalogue(&f->scene);
  const dtm_effect_class *cls = NULL;
  if (dtm_registry_find(name, &cls)) dtm_error_clear(), cls = NULL;
  f->args = (dtm_effect_args){&f->scene, &f->se, &f->mesh, cls};
}

#define MAX_PROPS 64     /* catalogue entries */
#define MAX_MATERIALS 64 /* materials a test program builds */

static char *names[MAX_PROPS];
static int nnames = -1;

static void catalogue(void) {
  if (nnames >= 0) return;
  int n;
  const dtm_property *const *p = dtm_registry_properties(&n);
  for (nnames = 0; nnames < n && nnames < MAX_PROPS; nnames++) names[nnames] = (char *)p[nnames]->name;
}

void tu_scene_catalogue(dtm_scene *s) {
  catalogue();
  s->nprops = s->nknown = nnames;
  s->prop_names = names;
}

void tu_material(dtm_material *m, const char *name, ...) {
  static double pool[MAX_MATERIALS][MAX_PROPS];
  static int used;
  catalogue();
  memset(m, 0, sizeof *m);
  m->name = (char *)name;
  m->file = "fixture.xml";
  m->line = 3;
  m->nprops = nnames;
  m->prop_names = names;
  m->prop = pool[used++ % MAX_MATERIALS];
  for (int i = 0; i < nnames; i++) m->prop[i] = NAN;
  va_list ap;
  va_start(ap, name);
  for (const char *key; (key = va_arg(ap, const char *));) {
    double v = va_arg(ap, double);
    int i = dtm_material_index(m, key);
    if (i < 0) fprintf(stderr, "tu_material: '%s' is no built-in property\n", key), abort();
    m->prop[i] = v;
  }
  va_end(ap);
}

dtm_batch tu_batch1(int type, const double *x, const dtm_material **m) {
  static const size_t tag = 1;
  static const int group = 0;
  int dim = 0, nn = 0;
  dtm_elem_info(type, &dim, &nn);
  return (dtm_batch){type, dim, nn, 1, x, &tag, &group, NULL, m, NULL, NULL};
}

dtm_mesh *tu_bar_mesh(int n, const double *len, const int *group, const int *mat) {
  dtm_mesh *m = calloc(1, sizeof *m);
  size_t ne = (size_t)n;
  m->dim = 1, m->nnodes = ne + 1;
  m->node_tags = malloc((ne + 1) * sizeof *m->node_tags);
  m->xyz = calloc(3 * (ne + 1), sizeof *m->xyz);
  for (size_t i = 0; i <= ne; i++) m->node_tags[i] = i + 1, m->xyz[3 * i] = i ? m->xyz[3 * (i - 1)] + len[i - 1] : 0;
  m->nblocks = 1;
  m->blocks = calloc(1, sizeof *m->blocks);
  dtm_block *b = m->blocks;
  *b = (dtm_block){DTM_LINE2,
                   1,
                   2,
                   ne,
                   malloc(ne * sizeof(size_t)),
                   malloc(2 * ne * sizeof(size_t)),
                   malloc(ne * sizeof(int)),
                   malloc(ne * sizeof(int)),
                   NULL,
                   NULL,
                   NULL};
  for (size_t e = 0; e < ne; e++) {
    b->tags[e] = e + 1, b->conn[2 * e] = e, b->conn[2 * e + 1] = e + 1;
    b->group[e] = group ? group[e] : -1, b->mat[e] = mat ? mat[e] : 0;
  }
  return m;
}

void tu_bar_scene(dtm_scene *s, dtm_scene_effect *se, dtm_scene_material *sm, double target) {
  static char *keys[] = {"formulation"}, *vals[] = {"bar"};
  *se = (dtm_scene_effect){"elastic", NULL, 5, 1, keys, vals};
  *sm = (dtm_scene_material){0};
  tu_material(&sm->m, "steel", "E", 200e9, "rho", 8000.0, NULL);
  sm->is_default = 1;
  *s = (dtm_scene){0};
  tu_scene_catalogue(s);
  s->path = "mem.xml", s->nmaterials = 1, s->materials = sm, s->neffects = 1, s->effects = se;
  s->safety = 0.9, s->target = target;
}

struct dtm_analysis *tu_bar_analysis(const dtm_scene *s, int n, const double *len, const int *group, int ngroups) {
  static const char *const names[] = {"a", "b", "c", "d"};
  dtm_mesh *m = tu_bar_mesh(n, len, group, NULL);
  m->ngroups = ngroups;
  m->groups = ngroups ? calloc((size_t)ngroups, sizeof *m->groups) : NULL;
  for (int g = 0; g < ngroups && g < 4; g++) m->groups[g] = (dtm_group){1, g + 1, strdup(names[g])};
  dtm_effect *ef = NULL;
  int ne = 0;
  dtm_analysis *a = NULL;
  if (dtm_effects_create(s, m, &ef, &ne) || dtm_analysis_compute(s, m, ef, ne, &a)) {
    fprintf(stderr, "tu_bar_analysis: %s\n", dtm_error_message());
    abort();
  }
  return a;
}

int tu_random_element(int type, double curve, double (*urand)(void), double *x) {
  int d, nn, nc, parent = dtm_elem_parent(type);
  dtm_elem_info(type, &d, &nn);
  dtm_elem_info(parent, NULL, &nc);
  int r = dtm_elem_regular(type, 1.0, x);
  if (r) return r;
  for (int i = 0; i < 3 * nc; i++) x[i] += (d == 2 && i % 3 == 2) ? 0 : 0.15 * urand();
  for (int a = nc; a < nn; a++) {
    double p[3], N[DTM_K_NODES], dN[DTM_K_NODES][3];
    dtm_ref_node(type, a, p);
    dtm_ref_eval(parent, p, N, dN);
    for (int i = 0; i < 3; i++) {
      x[3 * a + i] = 0;
      for (int c = 0; c < nc; c++) x[3 * a + i] += N[c] * x[3 * c + i];
      if (d == 3 || i < 2) x[3 * a + i] += curve * urand();
    }
  }
  return DTM_OK;
}

double *tu_operator_dense(const struct dtm_operator *op, int sym) {
  size_t n = dtm_operator_ndof(op);
  double *a = malloc((n ? n * n : 1) * sizeof *a), *e = calloc(n + 1, sizeof *e);
  if (!a || !e) abort();
  for (size_t j = 0; j < n; j++) {
    e[j] = 1;
    (sym ? dtm_operator_apply_sym : dtm_operator_apply)(op, e, a + j * n);
    e[j] = 0;
  }
  free(e);
  return a;
}
