/* The kill switches: inputs that cannot fit in this machine's memory are
 * refused with the figures before anything is allocated for them, instead
 * of ending in the OOM killer or a half-read mesh.
 *  - A .msh: its headers' node and element counts (msh_scan.c) must fit in
 *    the file (at least 8 bytes a node and 4 an element in ASCII, more in
 *    binary: fewer means a truncated or corrupt file whose headers lie),
 *    and reading and analysing them must fit in dtm_memory_limit().
 *  - A geometry: <meshing size=h> gives at least c_d M / h^d elements of
 *    dimension d, M the measure of the model's entities of that dimension
 *    (OpenCASCADE's for OCC entities, else the product of the d largest
 *    extents of each entity's bounding box), c_d the elements a Gmsh mesh
 *    of size h puts in h^d (measured on box.geo: 4.5 tetrahedra; 2.3
 *    triangles for an equilateral tiling; 1 segment), rounded down. The
 *    size is the largest Gmsh may use (Mesh.MeshSizeMax); smaller sizes
 *    from the geometry only add elements, so this is a lower bound. When
 *    the size does not fit, the refusal names the unit that would make it
 *    fit: the model drawn in mm, in or cm but read in metres (<geometry
 *    unit>), or in a mm-t-s scene a size written in metres.
 *  - Tags: Gmsh's views index their data by node or element tag (a pointer
 *    per tag number up to the largest, for each view), so a mesh whose
 *    tags go up to 10^15 crashes Gmsh when dtmap writes its views, though
 *    Gmsh reads it: the largest tag counts 8 B for each of at least 8 views.
 * Bytes per element and node were measured with /usr/bin/time (peak RSS,
 * dtmap run -j 1, tet4): 445 B per element, nodes included, reading a
 * .msh; 620 B per element meshing a .geo. The constants below are lower
 * (the switch must never refuse what fits); second order triples them. */
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "base.h"
#include "gmsh-impl.h"

#define READ_PER_ELEMENT 300.0 /* bytes, reading and analysing a .msh */
#define READ_PER_NODE 150.0    /* bytes */
#define MESH_PER_ELEMENT 450.0 /* bytes, meshing and analysing */

static const double per_hd[4] = {0, 1.0, 2.0, 4.0}; /* elements per h^d, rounded down */

static int too_big_hint(const char *what, double need, const char *hint) {
  char a[32], b[32];
  double limit = dtm_memory_limit();
  if (!(need > limit)) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT,
                 "%s, which need about %s of memory; this machine allows %s (memory, cgroup and ulimit)%s%s", what,
                 dtm_bytes_text(need, a, sizeof a), dtm_bytes_text(limit, b, sizeof b), hint[0] ? "; " : "", hint);
}

static int too_big(const char *what, double need) { return too_big_hint(what, need, ""); }

int dtm_gmsh_check_msh(const char *path) {
  dtm_msh_head h;
  char what[4300], sz[32];
  if (dtm_msh_scan(path, &h)) return DTM_OK;
  if (h.problem[0] && h.problem_line) return DTM_ERR(DTM_ERR_INPUT, "%s:%lld: %s", path, h.problem_line, h.problem);
  if (h.problem[0]) return DTM_ERR(DTM_ERR_INPUT, "%s: %s", path, h.problem);
  double per_node = h.binary ? 24.0 + (h.version >= 4 ? h.dsize : 4) : 8.0, per_el = h.binary ? 8.0 : 4.0;
  double least = (double)h.nodes * per_node + (double)h.elements * per_el;
  if (least > (double)h.bytes)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s: its headers announce %zu nodes and %zu elements, more than the %s file can hold: it is "
                   "truncated or corrupt",
                   path, h.nodes, h.elements, dtm_bytes_text((double)h.bytes, sz, sizeof sz));
  snprintf(what, sizeof what, "%s: the mesh has %zu elements and %zu nodes", path, h.elements, h.nodes);
  return too_big(what, (double)h.elements * READ_PER_ELEMENT + (double)h.nodes * READ_PER_NODE);
}

#define VIEW_BYTES_PER_TAG (8.0 * 8) /* a pointer per tag number in each of 8 views */

int dtm_gmsh_check_tags(const char *src, const char *what, size_t max_tag, size_t count) {
  char text[4400];
  snprintf(text, sizeof text,
           "%s: %s tags go up to %zu for %zu %ss (renumber them densely); the views dtmap writes index their data by "
           "tag",
           src, what, max_tag, count, what);
  return too_big(text, VIEW_BYTES_PER_TAG * (double)max_tag);
}

/* Measure of entity (dim, tag), m^dim: OpenCASCADE's when it is one of
 * its entities (occ lists them), else from its bounding box. */
static double entity_measure(int dim, int tag, const int *occ, size_t nocc) {
  int ierr = 0;
  double m = 0, b[6], e[3];
  for (size_t i = 0; i + 1 < nocc; i += 2)
    if (occ[i] == dim && occ[i + 1] == tag) {
      gmshModelOccGetMass(dim, tag, &m, &ierr);
      if (!ierr && m > 0) return m;
    }
  gmshModelGetBoundingBox(dim, tag, &b[0], &b[1], &b[2], &b[3], &b[4], &b[5], &ierr);
  for (int i = 0; i < 3; i++) e[i] = ierr ? 0 : fabs(b[i + 3] - b[i]);
  for (int i = 0; i < 2; i++) /* sort the extents, largest first */
    for (int j = i + 1; j < 3; j++)
      if (e[j] > e[i]) m = e[i], e[i] = e[j], e[j] = m;
  m = 1;
  for (int i = 0; i < dim; i++) m *= e[i];
  return m;
}

static double model_measure(int dim) {
  int *ents = NULL, *occ = NULL, ierr = 0;
  size_t n = 0, nocc = 0;
  double m = 0;
  gmshModelGetEntities(&ents, &n, dim, &ierr);
  gmshModelOccGetEntities(&occ, &nocc, dim, &ierr);
  for (size_t i = 0; i + 1 < n; i += 2) m += entity_measure(dim, ents[i + 1], occ, nocc);
  gmshFree(ents);
  gmshFree(occ);
  return m;
}

/* When n elements do not fit, the unit that would make them fit: the
 * geometry drawn in mm, in or cm but read in the scene's length unit, or
 * (a mm-t-s scene) a size written in metres. Appended to what[len]. */
static void unit_hint(const dtm_scene *s, int dim, double n, double per, char *hint, size_t len) {
  static const struct {
    const char *name;
    double metres;
  } units[] = {{"mm", 1e-3}, {"in", 0.0254}, {"cm", 1e-2}};
  double L = s->unit_length > 0 ? s->unit_length : 1.0, b[6];
  int ierr = 0, geo = !strcasecmp(strrchr(s->geometry, '.') ? strrchr(s->geometry, '.') : "", ".geo");
  hint[0] = '\0';
  gmshModelGetBoundingBox(-1, -1, &b[0], &b[1], &b[2], &b[3], &b[4], &b[5], &ierr);
  double span = fmax(b[3] - b[0], fmax(b[4] - b[1], b[5] - b[2]));
  if (L != 1.0 && n * pow(1e-3, dim) * per <= dtm_memory_limit()) {
    snprintf(hint, len,
             "the size looks like metres: the scene's units are mm-t-s, so sizes are in mm: size=\"%g\" would give "
             "about %.3g elements",
             s->mesh_size * 1e3, n * pow(1e-3, dim));
    return;
  }
  for (size_t i = 0; i < sizeof units / sizeof *units && L == 1.0; i++) {
    double k = units[i].metres, nk = n * pow(k, dim);
    if (nk * per > dtm_memory_limit()) continue;
    if (geo)
      snprintf(hint, len,
               "the model spans %.4g m, which looks like %s taken as metres: a .geo is read in metres, and drawn in "
               "metres it would be %.4g m across and give about %.3g elements",
               span, units[i].name, span * k, nk);
    else
      snprintf(hint, len,
               "the model spans %.4g m, which looks like %s taken as metres: with <geometry unit=\"%s\"> it would be "
               "%.4g m across and give about %.3g elements",
               span, units[i].name, units[i].name, span * k, nk);
    return;
  }
}

int dtm_gmsh_check_meshing(const dtm_scene *s, int dim) {
  if (!(s->mesh_size > 0) || dim < 1 || dim > 3) return DTM_OK;
  char what[4400], hint[400];
  double measure = model_measure(dim), per = MESH_PER_ELEMENT * (s->mesh_order > 1 ? 3 : 1);
  double n = per_hd[dim] * measure / pow(s->mesh_size, dim);
  snprintf(what, sizeof what,
           "%s:%d: <meshing size=\"%g\"> on %s (measure %.3g %s^%d in dimension %d) gives at least %.3g elements",
           s->path, s->meshing_line, s->mesh_size, s->geometry, measure,
           s->unit_length > 0 && s->unit_length != 1.0 ? "mm" : "m", dim, dim, n);
  hint[0] = '\0';
  if (n * per > dtm_memory_limit()) unit_hint(s, dim, n, per, hint, sizeof hint);
  return too_big_hint(what, n * per, hint);
}
