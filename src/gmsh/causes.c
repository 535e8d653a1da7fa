/* What a model holds that decides its sizes where a size field cannot, for
 * the causes refine names when it stops short of its target: Gmsh's size
 * options (which clamp every field; the remesh lifts them), curves whose node
 * count the model fixes and refine does not set (the Layers of an Extrude,
 * and Transfinite Curve when refine keeps the model's counts; found by
 * src/gmsh/counts.c), recombined surfaces and structured volumes (their
 * element types), periodic entities (which copy their master's mesh) and
 * embedded entities. For fixed curves the fix is the node count the size
 * suggestion implies along the curve, or the layers the target needs, as a
 * line a user can paste into the .geo. */
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "dtmap/units.h"
#include "gmsh-impl.h"

static const char *const dim_name[] = {"Point", "Curve", "Surface", "Volume"};

static void name_entity(dtm_cause *c, int dim, int tag) {
  if (c->nent < DTM_CAUSE_ENTITIES) c->dim[c->nent] = dim, c->tag[c->nent] = tag;
  c->nent++;
}

/* "Curve 3, Curve 7, ..." of c's entities into buf. */
static void entity_list(const dtm_cause *c, char *buf, size_t len) {
  buf[0] = '\0';
  int n = c->nent < DTM_CAUSE_ENTITIES ? c->nent : DTM_CAUSE_ENTITIES;
  for (int i = 0; i < n && strlen(buf) + 40 < len; i++) {
    size_t used = strlen(buf);
    snprintf(buf + used, len - used, "%s%s %d", i ? ", " : "", dim_name[c->dim[i]], c->tag[i]);
  }
  if (c->nent > n || (n && strlen(buf) + 40 >= len)) strncat(buf, ", ...", len - strlen(buf) - 1);
}

static void append(char *buf, size_t len, const char *line) {
  size_t used = strlen(buf);
  if (used + strlen(line) + 2 < len) snprintf(buf + used, len - used, "%s%s", used ? "\n" : "", line);
}

static double option(const char *name, double fallback) {
  double v = fallback;
  int ierr = 0;
  gmshOptionGetNumber(name, &v, &ierr);
  return ierr ? fallback : v;
}

static void finite_range(const double *size, size_t n, double *lo, double *hi) {
  *lo = INFINITY, *hi = 0;
  for (size_t v = 0; v < n; v++)
    if (isfinite(size[v]) && size[v] > 0) *lo = fmin(*lo, size[v]), *hi = fmax(*hi, size[v]);
}

/* Mesh.MeshSizeMin/Max/Factor that would clamp a size field, unless they
 * are just the scene's own <meshing size min-size> (the user set those). */
static void size_options(const dtm_scene *s, const dtm_mesh *m, const double *size, dtm_cause *c, int *found) {
  double mn = option("Mesh.MeshSizeMin", 0), mx = option("Mesh.MeshSizeMax", 1e22),
         f = option("Mesh.MeshSizeFactor", 1), lo, hi;
  int scene_min = s && s->mesh_min_size > 0 && mn == s->mesh_min_size,
      scene_max = s && s->mesh_size > 0 && mx == s->mesh_size;
  *found = (mn > 0 && !scene_min) || (mx < 1e22 && !scene_max) || f != 1;
  if (!*found) return;
  finite_range(size, m->nnodes, &lo, &hi);
  snprintf(c->kind, sizeof c->kind, "size-options");
  snprintf(c->text, sizeof c->text,
           "Gmsh's size options Mesh.MeshSizeMin = %g, Mesh.MeshSizeMax = %g, Mesh.MeshSizeFactor = %g (from the "
           "geometry file or the scene's <meshing>) clamp every size field; refine lifted them for its remeshes "
           "(0, 1e22 and 1); the size suggestion spans %.4g to %.4g %s",
           mn, mx, f, lo, hi, dtm_units_name(s ? s->units : NULL, DTM_UNIT_LENGTH));
  if (lo < mn * f || hi > mx * f)
    snprintf(c->fix, sizeof c->fix, "Mesh.MeshSizeMin = %.4g;\nMesh.MeshSizeMax = %.4g;\nMesh.MeshSizeFactor = 1;",
             fmin(mn, lo), fmax(mx, hi));
}

/* The mean suggested size on the nodes inside curve tag (NaN: none). */
static double curve_size(const dtm_geo *g, const double *size, int tag) {
  double sum = 0;
  size_t n = 0;
  for (size_t v = 0; v < g->nnodes; v++)
    if (g->node_dim[v] == 1 && g->node_tag[v] == tag && isfinite(size[v])) sum += size[v], n++;
  return n ? sum / n : NAN;
}

/* The line a user pastes for fixed curve f: a transfinite count from the
 * size the suggestion implies along it, or the Layers{} an extrusion needs
 * for the size its entities' nodes need. */
static void fixed_fix(const dtm_geo *g, const double *size, const dtm_fixed_curve *f, int transfinite, dtm_cause *c) {
  char line[200];
  if (transfinite) {
    double h = curve_size(g, size, f->tag);
    if (!isfinite(h) || !(h > 0)) return;
    long nodes = lround(f->length / h) + 1;
    snprintf(line, sizeof line, "Transfinite Curve{%d} = %ld; // now %d", f->tag, nodes < 2 ? 2 : nodes, f->nodes);
  } else {
    long layers = f->need > 0 ? (long)floor(f->length / f->need) : f->nodes - 1;
    snprintf(line, sizeof line, "// Curve %d: Layers{%ld} in the Extrude that makes it (now %d)", f->tag,
             layers < 1 ? 1 : layers, f->nodes - 1);
  }
  append(c->fix, sizeof c->fix, line);
}

/* The curves whose count the model fixes and refine does not set: the
 * layers of extrusions, and the transfinite curves when it keeps them. */
static void fixed_curves(const dtm_geo *g, const double *size, const dtm_structure *st, int keep_counts, dtm_cause *c,
                         int *found) {
  dtm_fixed_curve f[DTM_CAUSE_ENTITIES];
  *found = 0;
  for (int tf = 0; tf <= keep_counts; tf++) {
    int n = dtm_gmsh_fixed_curves(st, tf, f, DTM_CAUSE_ENTITIES);
    for (int i = 0; i < n; i++) {
      name_entity(c, 1, i < DTM_CAUSE_ENTITIES ? f[i].tag : 0);
      if (i < DTM_CAUSE_ENTITIES) fixed_fix(g, size, &f[i], tf, c);
    }
    *found += n;
  }
  if (!*found) return;
  char list[400];
  snprintf(c->kind, sizeof c->kind, "fixed-node-count");
  entity_list(c, list, sizeof list);
  snprintf(c->text, sizeof c->text,
           "%d curve(s) have a node count the model fixes (%s), which no size field changes: %s; the counts the "
           "size suggestion implies follow",
           *found,
           keep_counts ? "Transfinite Curve, kept by --keep-counts, or the Layers of an Extrude"
                       : "the Layers of an Extrude, which Gmsh's API cannot set",
           list);
}

static int has_type(int dim, int tag, const int *types, int ntypes) {
  int *t = NULL, ierr = 0, hit = 0;
  size_t n = 0;
  gmshModelMeshGetElementTypes(&t, &n, dim, tag, &ierr);
  for (size_t i = 0; i < n; i++)
    for (int k = 0; k < ntypes; k++) hit |= t[i] == types[k];
  gmshFree(t);
  return hit;
}

static void model_entities(int dim, int **dt, size_t *n) {
  int ierr = 0;
  *dt = NULL, *n = 0;
  gmshModelGetEntities(dt, n, dim, &ierr);
}

/* Surfaces of quadrangles and volumes of hexahedra, prisms or pyramids. */
static void recombined(dtm_cause *c, int *found) {
  static const int quad[] = {3, 10, 16}, solid[] = {5, 6, 7, 12, 13, 14, 17, 18, 19};
  for (int dim = 2; dim <= 3; dim++) {
    int *dt;
    size_t n;
    model_entities(dim, &dt, &n);
    for (size_t i = 0; i < n; i += 2)
      if (dim == 2 ? has_type(2, dt[i + 1], quad, 3) : has_type(3, dt[i + 1], solid, 9)) name_entity(c, dim, dt[i + 1]);
    gmshFree(dt);
  }
  *found = c->nent;
  if (!*found) return;
  char list[400];
  entity_list(c, list, sizeof list);
  snprintf(c->kind, sizeof c->kind, "recombined");
  snprintf(c->text, sizeof c->text,
           "recombined or structured entities (quadrangles, hexahedra, prisms: Recombine, Transfinite or a "
           "recombined Extrude) follow their curves' node counts: %s",
           list);
}

/* Entities whose mesh copies another's (Periodic). */
static void periodic(dtm_cause *c, int *found) {
  char masters[400] = "";
  for (int dim = 1; dim <= 2; dim++) {
    int *dt, ierr = 0, master = 0;
    size_t n;
    model_entities(dim, &dt, &n);
    for (size_t i = 0; i < n; i += 2) {
      size_t *a = NULL, *b = NULL, na, nb, nt;
      double *t = NULL;
      gmshModelMeshGetPeriodicNodes(dim, dt[i + 1], &master, &a, &na, &b, &nb, &t, &nt, 0, &ierr);
      gmshFree(a), gmshFree(b), gmshFree(t);
      if (ierr || master <= 0 || master == dt[i + 1]) continue;
      name_entity(c, dim, dt[i + 1]);
      size_t used = strlen(masters);
      if (used + 60 < sizeof masters)
        snprintf(masters + used, sizeof masters - used, "%s%s %d copies %s %d", used ? ", " : "", dim_name[dim],
                 dt[i + 1], dim_name[dim], master);
    }
    gmshFree(dt);
  }
  *found = c->nent;
  if (!*found) return;
  snprintf(c->kind, sizeof c->kind, "periodic");
  snprintf(c->text, sizeof c->text,
           "periodic entities take their master's mesh, so the size field on them is not theirs: %s", masters);
}

/* Entities embedded in surfaces or volumes (their nodes stay in every mesh). */
static void embedded(dtm_cause *c, int *found) {
  for (int dim = 2; dim <= 3; dim++) {
    int *dt;
    size_t n;
    model_entities(dim, &dt, &n);
    for (size_t i = 0; i < n; i += 2) {
      int *e = NULL, ierr = 0;
      size_t ne = 0;
      gmshModelMeshGetEmbedded(dim, dt[i + 1], &e, &ne, &ierr);
      for (size_t k = 0; !ierr && k < ne; k += 2) name_entity(c, e[k], e[k + 1]);
      gmshFree(e);
    }
    gmshFree(dt);
  }
  *found = c->nent;
  if (!*found) return;
  char list[400];
  entity_list(c, list, sizeof list);
  snprintf(c->kind, sizeof c->kind, "embedded");
  snprintf(c->text, sizeof c->text,
           "embedded entities keep their nodes in every mesh and small elements around them: %s", list);
}

int dtm_gmsh_size_causes(const dtm_scene *s, const dtm_mesh *m, const dtm_geo *g, const double *size,
                         const dtm_structure *st, int keep_counts, dtm_cause *out, int max, int *n) {
  int found = 0;
  if (*n >= max) return DTM_OK;
  memset(&out[*n], 0, sizeof out[*n]);
  size_options(s, m, size, &out[*n], &found);
  if (found && ++*n >= max) return DTM_OK;
  if (g && st) {
    memset(&out[*n], 0, sizeof out[*n]);
    fixed_curves(g, size, st, keep_counts, &out[*n], &found);
    if (found && ++*n >= max) return DTM_OK;
  }
  void (*const probes[])(dtm_cause *, int *) = {recombined, periodic, embedded};
  for (int k = 0; k < 3 && *n < max; k++) {
    memset(&out[*n], 0, sizeof out[*n]);
    probes[k](&out[*n], &found);
    if (found) ++*n;
  }
  return DTM_OK;
}
