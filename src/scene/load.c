/* The scene reader's entry points: dtm_scene_load walks the validated XML
 * tree (see scene_xml.c) element by element and fills a dtm_scene: the
 * geometry or mesh source (extension and existence checked), the meshing
 * options, the materials (scene_material.c), the effects (scene_effects.c),
 * the time options and the output paths. Paths are resolved against the
 * scene file's directory. dtm_scene_destroy frees all of it. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <libxml/parser.h>

#include "dtmap/units.h"
#include "scene-impl.h"

static const char *extension(const char *file) {
  const char *slash = strrchr(file, '/');
  const char *dot = strrchr(slash ? slash + 1 : file, '.');
  return dot ? dot : "";
}

static int is_geometry_ext(const char *ext) {
  static const char *const ok[] = {".geo", ".step", ".stp", ".brep", ".iges", ".igs"};
  for (size_t i = 0; i < sizeof ok / sizeof *ok; i++)
    if (!strcasecmp(ext, ok[i])) return 1;
  return 0;
}

static int check_extension(const dtm_scene *s, const xmlNode *n, const char *file, int is_mesh) {
  const char *ext = extension(file);
  if (is_mesh && strcasecmp(ext, ".msh")) return DTM_SCENE_ERR(s, n, "mesh file '%s' is not a Gmsh .msh file", file);
  if (!is_mesh && !strcasecmp(ext, ".msh"))
    return DTM_SCENE_ERR(s, n, "geometry file '%s' is a mesh; use <mesh file=\"%s\"/>", file, file);
  if (!is_mesh && !is_geometry_ext(ext))
    return DTM_SCENE_ERR(s, n,
                         "geometry file '%s' has an unsupported extension (use .geo, "
                         ".step, .stp, .iges, .igs or .brep, or <mesh file=\"x.msh\"/>)",
                         file);
  return DTM_OK;
}

static int check_exists(const dtm_scene *s, const xmlNode *n, const char *kind, const char *file,
                        const char *resolved) {
  struct stat st;
  if (stat(resolved, &st) == 0 && S_ISDIR(st.st_mode))
    return DTM_SCENE_ERR(s, n, "%s file '%s' is a directory", kind, resolved);
  if (access(resolved, R_OK) == 0) return DTM_OK;
  if (errno != ENOENT && errno != ENOTDIR)
    return DTM_SCENE_ERR(s, n, "%s file '%s' cannot be read: %s", kind, resolved, strerror(errno));
  if (!strcmp(file, resolved)) return DTM_SCENE_ERR(s, n, "%s file '%s' not found", kind, file);
  return DTM_SCENE_ERR(s, n, "%s file '%s' not found (looked for '%s')", kind, file, resolved);
}

static int read_int(const dtm_scene *s, const xmlNode *n, const char *key, int lo, int hi, int *out);

/* <mesh partitions="P">: the part files are looked for by each rank of the
 * distributed run (its own only); "{part}" in the file needs partitions. */
static int read_partitions(dtm_scene *s, const xmlNode *n, const char *file) {
  DTM_CHECK(read_int(s, n, "partitions", 1, 1 << 24, &s->partitions));
  if (strstr(file, "{part}") && !s->partitions)
    return DTM_SCENE_ERR(s, n, "mesh file '%s' names {part} but <mesh> has no partitions=\"P\"", file);
  return DTM_OK;
}

/* The length units a file may be declared in (<geometry unit>, <mesh unit>). */
static const struct {
  const char *name; /* as written */
  double metres;    /* metres per unit */
} length_units[] = {{"mm", 1e-3}, {"cm", 1e-2}, {"m", 1.0}, {"in", 0.0254}};

/* <geometry unit> or <mesh unit>: a .geo draws with its own numbers and sets
 * its own sizes, which dtmap cannot scale together, so it takes none. */
static int read_unit(dtm_scene *s, const xmlNode *n, const char *file) {
  char *text;
  DTM_CHECK(dtm_scene_attr(n, "unit", &text));
  if (!text) return DTM_OK;
  for (size_t i = 0; i < sizeof length_units / sizeof *length_units; i++)
    if (!strcmp(text, length_units[i].name))
      s->source_unit = length_units[i].name, s->source_unit_m = length_units[i].metres;
  int rc = !s->source_unit ? DTM_SCENE_ERR(s, n, "<%s> unit=\"%s\" is not mm, cm, m or in", (const char *)n->name, text)
           : !strcasecmp(extension(file), ".geo")
               ? DTM_SCENE_ERR(s, n,
                               "<geometry> unit=\"%s\" on the .geo file '%s': a .geo sets its own sizes in its own "
                               "numbers, which dtmap cannot scale with it; write the .geo in the scene's length unit "
                               "(Geometry.OCCTargetUnit or Geometry.OCCScaling convert the files it merges)",
                               text, file)
               : DTM_OK;
  free(text);
  return rc;
}

static int read_source(dtm_scene *s, const xmlNode *n) {
  int is_mesh = dtm_scene_is(n, "mesh");
  const char *kind = is_mesh ? "mesh" : "geometry";
  char **dst = is_mesh ? &s->mesh : &s->geometry;
  char *file;
  if (s->geometry || s->mesh || s->model) return DTM_SCENE_ERR(s, n, "a second <%s>; give one source", kind);
  s->source_line = dtm_scene_line(n);
  DTM_CHECK(dtm_scene_attr(n, "file", &file));
  if (!file || !*file) {
    free(file);
    return DTM_SCENE_ERR(s, n, "<%s> needs a file=\"...\"", kind);
  }
  int rc = check_extension(s, n, file, is_mesh);
  if (!rc) rc = read_unit(s, n, file);
  if (!rc && is_mesh) rc = read_partitions(s, n, file);
  if (!rc) rc = dtm_scene_resolve(s, file, dst);
  if (!rc && !s->partitions) rc = check_exists(s, n, kind, file, *dst);
  free(file);
  return rc ? dtm_error_trace(rc, __FILE__, __LINE__, __func__) : DTM_OK;
}

/* <model/>: the current Gmsh model of the program that loads the scene. */
static int read_model(dtm_scene *s, const xmlNode *n) {
  if (s->geometry || s->mesh || s->model) return DTM_SCENE_ERR(s, n, "a second source <model/>; give one source");
  s->model = 1;
  s->source_line = dtm_scene_line(n);
  return DTM_OK;
}

int dtm_scene_use_model(dtm_scene *s) {
  free(s->geometry);
  free(s->mesh);
  s->geometry = s->mesh = NULL;
  s->model = 1;
  return DTM_OK;
}

static int read_int(const dtm_scene *s, const xmlNode *n, const char *key, int lo, int hi, int *out) {
  char *text;
  double v;
  DTM_CHECK(dtm_scene_attr(n, key, &text));
  if (!text) return DTM_OK;
  int bad = dtm_scene_parse_double(text, &v) || v != floor(v) || v < lo || v > hi;
  int rc = bad ? DTM_SCENE_ERR(s, n,
                               "<%s> %s=\"%s\" is not admissible (need an integer "
                               "from %d to %d)",
                               (const char *)n->name, key, text, lo, hi)
               : DTM_OK;
  if (!bad) *out = (int)v;
  free(text);
  return rc;
}

static const struct {
  const char *name; /* <meshing algorithm> */
  int code;         /* Gmsh's Mesh.Algorithm3D */
} algorithms[] = {{"delaunay", 1}, {"frontal", 4}, {"mmg3d", 7}, {"rtree", 9}, {"hxt", 10}};

const char *dtm_scene_algorithm_name(int code) {
  for (size_t i = 0; i < sizeof algorithms / sizeof *algorithms; i++)
    if (algorithms[i].code == code) return algorithms[i].name;
  return code ? "other" : "read";
}

/* <meshing algorithm> as Gmsh's Mesh.Algorithm3D code (the schema admits
 * only the names of the table). */
static int read_algorithm(dtm_scene *s, const xmlNode *n) {
  char *text;
  DTM_CHECK(dtm_scene_attr(n, "algorithm", &text));
  for (size_t i = 0; text && i < sizeof algorithms / sizeof *algorithms; i++)
    if (!strcmp(text, algorithms[i].name)) s->mesh_algorithm = algorithms[i].code;
  int bad = text && !s->mesh_algorithm;
  int rc = bad ? DTM_SCENE_ERR(s, n, "<meshing> algorithm=\"%s\" is not delaunay, frontal, mmg3d, rtree or hxt", text)
               : DTM_OK;
  free(text);
  return rc;
}

static int read_meshing(dtm_scene *s, const xmlNode *n) {
  s->meshing_line = dtm_scene_line(n);
  DTM_CHECK(dtm_scene_attr_positive(s, n, "size", 0, &s->mesh_size));
  DTM_CHECK(dtm_scene_attr_positive(s, n, "min-size", 0, &s->mesh_min_size));
  DTM_CHECK(read_int(s, n, "order", 1, 2, &s->mesh_order));
  DTM_CHECK(read_int(s, n, "dim", 1, 3, &s->mesh_dim));
  DTM_CHECK(read_int(s, n, "threads", 1, 4096, &s->mesh_threads));
  DTM_CHECK(read_algorithm(s, n));
  if (s->mesh_size > 0 && s->mesh_min_size > s->mesh_size)
    return DTM_SCENE_ERR(s, n, "<meshing> min-size=%g is larger than size=%g", s->mesh_min_size, s->mesh_size);
  return DTM_OK;
}

static int read_time(dtm_scene *s, const xmlNode *n) {
  s->time_line = dtm_scene_line(n);
  DTM_CHECK(dtm_scene_attr_positive(s, n, "cost-per-element-step", 0, &s->cost_per_element_step));
  DTM_CHECK(dtm_scene_attr_positive(s, n, "safety", 0.9, &s->safety));
  if (s->safety > 1) return DTM_SCENE_ERR(s, n, "<time> safety=%g is not admissible (need 0 < safety <= 1)", s->safety);
  DTM_CHECK(dtm_scene_attr_positive(s, n, "target", 0, &s->target));
  DTM_CHECK(dtm_scene_attr_positive(s, n, "duration", 0, &s->duration));
  DTM_CHECK(dtm_scene_attr_positive(s, n, "f-max", 0, &s->f_max));
  DTM_CHECK(dtm_scene_attr_bool(s, n, "posterior", &s->posterior));
  DTM_CHECK(dtm_scene_attr_percent(s, n, "max-added-mass", &s->max_added_mass));
  return dtm_scene_attr_positive(s, n, "elements-per-wavelength", DTM_SCENE_PER_WAVELENGTH,
                                 &s->elements_per_wavelength);
}

static int read_output_path(dtm_scene *s, const xmlNode *n, const char *key, char **dst) {
  char *file;
  DTM_CHECK(dtm_scene_attr(n, key, &file));
  if (!file) return DTM_OK;
  int rc = DTM_OK;
  if (!*file)
    rc = DTM_SCENE_ERR(s, n, "<output> %s=\"\" names no file", key);
  else if (dst == &s->out_mesh && strcasecmp(extension(file), ".msh"))
    rc = DTM_SCENE_ERR(s, n, "<output> mesh=\"%s\" must be a Gmsh .msh file", file);
  if (!rc) rc = dtm_scene_resolve(s, file, dst);
  free(file);
  return rc;
}

/* <output format="auto|ascii|binary"> (the schema admits only these). */
static int read_format(dtm_scene *s, const xmlNode *n) {
  char *text;
  DTM_CHECK(dtm_scene_attr(n, "format", &text));
  s->out_format = !text                     ? DTM_MSH_AUTO
                  : !strcmp(text, "ascii")  ? DTM_MSH_ASCII
                  : !strcmp(text, "binary") ? DTM_MSH_BINARY
                                            : DTM_MSH_AUTO;
  free(text);
  return DTM_OK;
}

static int read_output(dtm_scene *s, const xmlNode *n) {
  s->out_line = dtm_scene_line(n);
  DTM_CHECK(read_format(s, n));
  DTM_CHECK(read_output_path(s, n, "mesh", &s->out_mesh));
  return read_output_path(s, n, "report", &s->out_report);
}

typedef int (*element_reader)(dtm_scene *s, const xmlNode *n);

static element_reader reader_for(const xmlNode *n) {
  static const struct {
    const char *tag;     /* element name under <dtmap-scene> */
    element_reader read; /* what reads it */
  } table[] = {{"geometry", read_source},
               {"mesh", read_source},
               {"model", read_model},
               {"meshing", read_meshing},
               {"material", dtm_scene_read_material},
               {"section", dtm_scene_read_section},
               {"effects", dtm_scene_read_effects},
               {"time", read_time},
               {"output", read_output}};
  for (size_t i = 0; i < sizeof table / sizeof *table; i++)
    if (dtm_scene_is(n, table[i].tag)) return table[i].read;
  return NULL;
}

static int count_tag(const xmlNode *root, const char *tag) {
  int count = 0;
  for (const xmlNode *c = root->children; c; c = c->next) count += dtm_scene_is(c, tag);
  return count;
}

/* <dtmap-scene units>: SI, or mm-t-s (mm, tonne, s; N, MPa, t/mm^3). */
static int read_units(dtm_scene *s, const xmlNode *root) {
  char *text;
  DTM_CHECK(dtm_scene_attr(root, "units", &text));
  int rc = DTM_OK;
  if (text && !strcmp(text, "mm-t-s"))
    s->units = "mm-t-s", s->unit_length = 1e-3, s->unit_mass = 1e3;
  else if (text && strcmp(text, "SI"))
    rc = DTM_SCENE_ERR(s, root, "<dtmap-scene> units=\"%s\" is not SI or mm-t-s", text);
  free(text);
  if (rc == DTM_OK) dtm_units_set_messages(s->units); /* the library's messages follow the scene loaded */
  return rc;
}

static int read_document(dtm_scene *s, const xmlNode *root) {
  if (!root) return DTM_ERR(DTM_ERR_INPUT, "%s: the scene file has no root element", s->path);
  DTM_CHECK(read_units(s, root));
  DTM_CHECK(dtm_scene_read_plausible(s, root, &s->no_plausible_check));
  int nmat = count_tag(root, "material");
  DTM_CHECK(dtm_scene_build_catalogue(s, root));
  s->materials = nmat ? calloc((size_t)nmat, sizeof *s->materials) : NULL;
  if (nmat && !s->materials) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int nsec = count_tag(root, "section");
  s->sections = nsec ? calloc((size_t)nsec, sizeof *s->sections) : NULL;
  if (nsec && !s->sections) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (const xmlNode *c = root->children; c; c = c->next) {
    if (c->type != XML_ELEMENT_NODE) continue;
    element_reader read = reader_for(c);
    if (!read) return DTM_SCENE_ERR(s, c, "unknown element <%s>", (const char *)c->name);
    DTM_CHECK(read(s, c));
  }
  if (!s->geometry && !s->mesh && !s->model)
    return DTM_SCENE_ERR(s, root, "the scene needs <geometry file=...> or <mesh file=...>");
  if (!nmat) return DTM_SCENE_ERR(s, root, "the scene defines no <material>");
  if (!s->effects) return DTM_SCENE_ERR(s, root, "the scene has no <effects>");
  DTM_CHECK(dtm_scene_check_properties(s, NULL, 0));
  return dtm_scene_check_plausible(s);
}

static int scene_dir(const char *path, char **dir) {
  const char *slash = strrchr(path, '/');
  if (!slash) return dtm_scene_strdup(".", dir);
  *dir = strndup(path, slash == path ? 1 : (size_t)(slash - path));
  return *dir ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
}

static int scene_new(const char *path, dtm_scene **out) {
  dtm_scene *s = calloc(1, sizeof *s);
  *out = s;
  if (!s) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  s->mesh_order = 1;
  s->safety = 0.9;
  s->max_added_mass = NAN;
  s->elements_per_wavelength = DTM_SCENE_PER_WAVELENGTH;
  s->units = "SI", s->unit_length = 1.0, s->unit_mass = 1.0;
  DTM_CHECK(dtm_scene_strdup(path, &s->path));
  return scene_dir(path, &s->dir);
}

/* The scene of the parsed document doc (freed here), named path. */
static int load_doc(const char *path, xmlDoc *doc, dtm_scene **out) {
  dtm_scene *s = NULL;
  int rc = scene_new(path, &s);
  if (!rc) rc = read_document(s, xmlDocGetRootElement(doc));
  xmlFreeDoc(doc);
  if (rc) {
    dtm_scene_destroy(&s);
    return dtm_error_trace(rc, __FILE__, __LINE__, __func__);
  }
  *out = s;
  return DTM_OK;
}

int dtm_scene_load(const char *path, dtm_scene **out) {
  xmlDoc *doc;
  if (!out) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_scene_load: out is NULL");
  *out = NULL;
  if (!path) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_scene_load: path is NULL");
  DTM_CHECK(dtm_scene_xml_read(path, &doc));
  return load_doc(path, doc, out);
}

int dtm_scene_load_memory(const char *text, size_t len, const char *name, dtm_scene **out) {
  xmlDoc *doc;
  if (!out) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_scene_load_memory: out is NULL");
  *out = NULL;
  if (!text || !name) return DTM_ERR(DTM_ERR_INTERNAL, "dtm_scene_load_memory: text or name is NULL");
  DTM_CHECK(dtm_scene_xml_parse(name, text, len, &doc));
  return load_doc(name, doc, out);
}

static void free_effect(dtm_scene_effect *e) {
  free(e->name);
  free(e->library);
  dtm_scene_free_strings(e->nattr, e->keys);
  dtm_scene_free_strings(e->nattr, e->values);
}

void dtm_scene_destroy(dtm_scene **s) {
  if (!s || !*s) return;
  dtm_scene *p = *s;
  for (int i = 0; i < p->nmaterials; i++) {
    free(p->materials[i].m.name);
    free(p->materials[i].m.prop);
    dtm_scene_free_strings(p->materials[i].ngroups, p->materials[i].groups);
  }
  for (int i = 0; i < p->nsections; i++) dtm_scene_free_strings(p->sections[i].ngroups, p->sections[i].groups);
  free(p->sections);
  for (int i = 0; i < p->neffects; i++) free_effect(&p->effects[i]);
  dtm_scene_free_strings(p->nprops, p->prop_names);
  free(p->materials);
  free(p->effects);
  free(p->path);
  free(p->dir);
  free(p->geometry);
  free(p->mesh);
  free(p->out_mesh);
  free(p->out_report);
  free(p);
  *s = NULL;
}
