/* Sections from dtmap's ONELAB panel, driven by Gmsh's own machinery as in
 * t802 (the test process is the Gmsh session; gmshOnelabRun launches `dtmap
 * -onelab dtmap SOCKET` against its in-process ONELAB server, as the GUI's
 * Run button does). The model, written here, is a box with a line (physical
 * curve "bar") and a small square (physical surface "sheet") embedded in it.
 * Checked: the panel offers a section menu for the curve and the surface
 * groups only (none by default, truss with its area, membrane with its
 * thickness, and a material only once a section is chosen), for a 2D model
 * a truss for its curve groups, and takes its defaults from the scene beside
 * the model (the bundled reinforced block); a truss chosen in the panel
 * brings the bar's line elements into the views that come back (and the
 * sheet's triangles only once it is a membrane), the saved panel scene
 * holds the sections, and the .opt draws the trusses as tubes and the
 * sections opaque inside the faint skin, while an output without them is
 * styled as before; an area <= 0 is refused with the scene reader's own
 * message, as for a scene file, and the line of the panel's scene it is
 * about goes to Gmsh's console. The menus also offer a beam (with the
 * radius of a circular profile) for curves and a shell (thickness) for
 * surfaces: chosen, their elements come back in the views and the saved
 * scene holds the circle's A and I exactly; a beam the scene beside the
 * model gives (the bundled stiffened panel) keeps its rectangular profile
 * and orientation (no radius field), and its shell the skin's thickness. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "dtmap/scene.h"
#include "onelab.h"
#include "testutil.h"

static char dir[512], geo[600], out[600], opt[610];

/* The box (0.2 x 0.2 x 0.6 m) with the bar along z through its middle and
 * the sheet at mid-height beside it (they do not touch). */
static const char *const box_geo = "SetFactory(\"OpenCASCADE\");\n"
                                   "Box(1) = {0, 0, 0, 0.2, 0.2, 0.6};\n"
                                   "Point(100) = {0.1, 0.1, 0.05}; Point(101) = {0.1, 0.1, 0.55};\n"
                                   "Line(100) = {100, 101};\n"
                                   "Rectangle(100) = {0.02, 0.02, 0.3, 0.06, 0.06};\n"
                                   "Curve{100} In Volume{1};\n"
                                   "Surface{100} In Volume{1};\n"
                                   "Physical Volume(\"block\") = {1};\n"
                                   "Physical Curve(\"bar\") = {100};\n"
                                   "Physical Surface(\"sheet\") = {100};\n"
                                   "Mesh.MeshSizeMax = 0.05;\n";

/* A 2D wall with a tie along its middle. */
static const char *const wall_geo = "SetFactory(\"OpenCASCADE\");\n"
                                    "Rectangle(1) = {0, 0, 0, 1.0, 0.5};\n"
                                    "Point(10) = {0.1, 0.25, 0}; Point(11) = {0.9, 0.25, 0};\n"
                                    "Line(10) = {10, 11};\n"
                                    "Curve{10} In Surface{1};\n"
                                    "Physical Surface(\"wall\") = {1};\n"
                                    "Physical Curve(\"tie\") = {10};\n"
                                    "Mesh.MeshSizeMax = 0.1;\n";

static int setup(void **state) {
  (void)state;
  char path[700];
  snprintf(dir, sizeof dir, "%s/sections", tu_tmpdir());
  snprintf(geo, sizeof geo, "%s/rebar_box.geo", dir);
  snprintf(out, sizeof out, "%s/rebar_box_dt.msh", dir);
  snprintf(opt, sizeof opt, "%s.opt", out);
  int r = tu_run(NULL,
                 "mkdir -p %s/wall %s/block %s/panel && cp %s/geometries/reinforced_block.geo "
                 "%s/geometries/reinforced_block.xml %s/block/ && cp %s/geometries/stiffened_panel.geo "
                 "%s/geometries/stiffened_panel.xml %s/panel/",
                 dir, dir, dir, tu_src(), tu_src(), dir, tu_src(), tu_src(), dir);
  tu_write(geo, box_geo);
  snprintf(path, sizeof path, "%s/wall/wall.geo", dir);
  tu_write(path, wall_geo);
  return r;
}

/* The ONELAB parameter called name, as the server writes it in JSON; NULL
 * when the server has none. */
static cJSON *parameter(const char *name) {
  char *json = NULL;
  int ierr = 0;
  gmshOnelabGet(&json, name, "json", &ierr);
  cJSON *p = json && json[0] ? cJSON_Parse(json) : NULL;
  gmshFree(json);
  return p;
}

static int is_visible(const cJSON *p) { return cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(p, "visible")); }

/* The value the menu p gives the choice labelled label, or NaN. */
static double choice_value(const cJSON *p, const char *label) {
  const cJSON *l = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(p, "valueLabels"), label);
  return cJSON_IsNumber(l) ? l->valuedouble : NAN;
}

static const char *units(const cJSON *p) {
  const cJSON *u = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(p, "attributes"), "Units");
  return cJSON_IsString(u) ? u->valuestring : "";
}

/* A section menu: none (0, the value given) and kind (1), visible. */
static void assert_section_menu(const char *name, const char *kind, double value) {
  cJSON *p = parameter(name);
  assert_non_null(p);
  assert_true(is_visible(p));
  assert_true(choice_value(p, "none (not analysed)") == 0);
  assert_true(choice_value(p, kind) == 1);
  assert_true(tu_onelab_get_number(name) == value);
  cJSON_Delete(p);
}

/* A parameter that exists, with its visibility and units. */
static void assert_parameter(const char *name, int visible, const char *unit) {
  cJSON *p = parameter(name);
  assert_non_null(p);
  assert_int_equal(is_visible(p), visible);
  if (unit) assert_string_equal(units(p), unit);
  cJSON_Delete(p);
}

/* The panel of the box: a section menu for bar (truss, area) and sheet
 * (membrane, thickness), none for the volume; with no section, the
 * measure, the material and its properties are hidden. */
static void test_panel_names(void **state) {
  (void)state;
  tu_onelab_session(geo, "t804");
  tu_onelab_run("check");
  assert_section_menu("dtmap/4Materials/bar/00section", "truss", 0);
  assert_section_menu("dtmap/4Materials/sheet/00section", "membrane", 0);
  assert_parameter("dtmap/4Materials/bar/01area", 0, "m^2");
  assert_parameter("dtmap/4Materials/sheet/01thickness", 0, "m");
  assert_parameter("dtmap/4Materials/bar/0material", 0, NULL);
  assert_parameter("dtmap/4Materials/bar/1E", 0, "Pa");
  assert_parameter("dtmap/4Materials/block/0material", 1, NULL);
  assert_null(parameter("dtmap/4Materials/block/00section"));
  /* a truss chosen: its area, material and properties appear */
  tu_onelab_set_number("dtmap/4Materials/bar/00section", 1);
  tu_onelab_run("check");
  assert_parameter("dtmap/4Materials/bar/01area", 1, "m^2");
  assert_parameter("dtmap/4Materials/bar/0material", 1, NULL);
  assert_parameter("dtmap/4Materials/bar/1E", 1, "Pa");
  assert_parameter("dtmap/4Materials/sheet/0material", 0, NULL);
  tu_gmsh_end();
}

/* A 2D model: its curve group gets the truss; its surfaces take the plane
 * kinds from the elastic formulation, as before (no section menu). */
static void test_panel_2d(void **state) {
  (void)state;
  char wall[700];
  snprintf(wall, sizeof wall, "%s/wall/wall.geo", dir);
  tu_onelab_session(wall, "t804");
  tu_onelab_run("check");
  assert_section_menu("dtmap/4Materials/tie/00section", "truss", 0);
  assert_null(parameter("dtmap/4Materials/wall/00section"));
  cJSON *f = parameter("dtmap/1Effects/1elastic formulation");
  assert_non_null(f);
  assert_true(choice_value(f, "plane-strain") == 1 && choice_value(f, "plane-stress") == 2);
  assert_true(tu_onelab_get_number("dtmap/1Effects/1elastic formulation") == 1);
  cJSON_Delete(f);
  tu_gmsh_end();
}

/* The scene beside the model gives the defaults: the bundled reinforced
 * block's rebar truss (3.1e-4 m^2) and plate membrane (0.01 m), steel. */
static void test_scene_defaults(void **state) {
  (void)state;
  char model[700];
  snprintf(model, sizeof model, "%s/block/reinforced_block.geo", dir);
  tu_onelab_session(model, "t804");
  tu_onelab_run("check");
  assert_section_menu("dtmap/4Materials/rebar/00section", "truss", 1);
  assert_section_menu("dtmap/4Materials/plate/00section", "membrane", 1);
  assert_true(tu_onelab_get_number("dtmap/4Materials/rebar/01area") == 3.1e-4);
  assert_true(tu_onelab_get_number("dtmap/4Materials/plate/01thickness") == 0.01);
  cJSON *m = parameter("dtmap/4Materials/rebar/0material");
  assert_non_null(m);
  assert_true(choice_value(m, "steel (scene)") == tu_onelab_get_number("dtmap/4Materials/rebar/0material"));
  cJSON_Delete(m);
  tu_gmsh_end();
}

/* Element tags of the physical group (dim, name) of the model open. */
static size_t group_elements(int dim, const char *name, size_t **tags) {
  int *dt = NULL, ierr = 0;
  size_t ndt = 0, n = 0;
  *tags = NULL;
  gmshModelGetPhysicalGroups(&dt, &ndt, dim, &ierr);
  for (size_t g = 0; g + 1 < ndt; g += 2) {
    char *gname = NULL;
    gmshModelGetPhysicalName(dim, dt[g + 1], &gname, &ierr);
    int *ents = NULL;
    size_t nents = 0;
    if (!strcmp(gname, name)) gmshModelGetEntitiesForPhysicalGroup(dim, dt[g + 1], &ents, &nents, &ierr);
    for (size_t e = 0; e < nents; e++) {
      int *types = NULL;
      size_t **et = NULL, *etn = NULL, ntypes = 0, nnt = 0, **nt = NULL, *ntn = NULL;
      gmshModelMeshGetElements(&types, &ntypes, &et, &etn, &ntypes, &nt, &ntn, &nnt, dim, ents[e], &ierr);
      for (size_t t = 0; t < ntypes; t++) {
        *tags = realloc(*tags, (n + etn[t]) * sizeof **tags);
        memcpy(*tags + n, et[t], etn[t] * sizeof **tags), n += etn[t];
        gmshFree(et[t]), gmshFree(nt[t]);
      }
      gmshFree(types), gmshFree(et), gmshFree(etn), gmshFree(nt), gmshFree(ntn);
    }
    gmshFree(ents), gmshFree(gname);
  }
  gmshFree(dt);
  return n;
}

/* The output's elements of the block (tets), the bar (lines), the sheet
 * (triangles), read in a session of their own. */
typedef struct {
  size_t n[3], *tags[3];
} groups;
static const char *const group_names[3] = {"block", "bar", "sheet"};
static const int group_dims[3] = {3, 1, 2};

static void read_groups(groups *g) {
  int ierr = 0;
  tu_gmsh_begin();
  gmshOpen(out, &ierr);
  assert_int_equal(ierr, 0);
  for (int k = 0; k < 3; k++) g->n[k] = group_elements(group_dims[k], group_names[k], &g->tags[k]);
  tu_gmsh_end();
  assert_true(g->n[0] > 100 && g->n[1] >= 8 && g->n[2] >= 2);
}

static void free_groups(groups *g) {
  for (int k = 0; k < 3; k++) free(g->tags[k]);
}

static int has_tag(const tu_view *v, size_t tag) {
  for (size_t i = 0; i < v->n; i++)
    if (v->tags[i] == tag) return 1;
  return 0;
}

/* How many of tags[n] the view covers. */
static size_t covered(const tu_view *v, const size_t *tags, size_t n) {
  size_t k = 0;
  for (size_t i = 0; i < n; i++) k += has_tag(v, tags[i]);
  return k;
}

static char *read_text(const char *path) {
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  char *buf = calloc(1, 1 << 16);
  size_t n = fread(buf, 1, (1 << 16) - 1, f);
  fclose(f);
  buf[n] = '\0';
  return buf;
}

/* Run the box with the bar as a truss (and the sheet as a membrane when
 * membrane): the dt view that comes back covers the tets, the bar's lines,
 * the sheet's triangles exactly when it is a membrane, and nothing else. */
static void run_sections(int membrane, groups *g) {
  unlink(out);
  tu_onelab_session(geo, "t804");
  tu_onelab_run("check");
  tu_onelab_set_number("dtmap/4Materials/bar/00section", 1);
  tu_onelab_set_number("dtmap/4Materials/bar/01area", 3.1e-4);
  if (membrane) tu_onelab_set_number("dtmap/4Materials/sheet/00section", 1);
  if (membrane) tu_onelab_set_number("dtmap/4Materials/sheet/01thickness", 0.002);
  tu_onelab_run("compute");
  tu_view dt;
  assert_int_equal(tu_view_read_last("dt", &dt), 0);
  double published = tu_onelab_get_number("dtmap/9Results/6elements");
  tu_gmsh_end();
  read_groups(g);
  assert_int_equal(covered(&dt, g->tags[0], g->n[0]), g->n[0]);
  assert_int_equal(covered(&dt, g->tags[1], g->n[1]), g->n[1]);
  assert_int_equal(covered(&dt, g->tags[2], g->n[2]), membrane ? g->n[2] : 0);
  size_t all = g->n[0] + g->n[1] + (membrane ? g->n[2] : 0);
  assert_int_equal(dt.n, all);
  assert_true(published == (double)all);
  tu_view_free(&dt);
}

static double view_number(int index, const char *what) {
  char name[96];
  double v = NAN;
  int ierr = 0;
  snprintf(name, sizeof name, "View[%d].%s", index, what);
  gmshOptionGetNumber(name, &v, &ierr);
  return v;
}

/* Whether every element of the view called name is a solid (3D) one: the
 * view is model data (a script reads it with gmsh.view.getModelData). */
static int solid_elements_only(const char *name) {
  tu_view v;
  int read = tu_view_read(name, &v) == 0, solid = read && v.n > 0;
  for (size_t i = 0; solid && i < v.n; i++) {
    int type = 0, ierr = 0, dim = 0, order = 0, nn = 0, npn = 0;
    size_t *nodes = NULL, nnodes = 0;
    double *local = NULL;
    size_t nlocal = 0;
    char *tname = NULL;
    gmshModelMeshGetElement(v.tags[i], &type, &nodes, &nnodes, &ierr);
    gmshModelMeshGetElementProperties(type, &tname, &dim, &order, &nn, &local, &nlocal, &npn, &ierr);
    solid = !ierr && dim == 3;
    gmshFree(nodes), gmshFree(tname), gmshFree(local);
  }
  if (read) tu_view_free(&v);
  return solid;
}

/* The output opened as a user opens it (its .opt merged): one view called
 * dt, drawing the sections alone, opaque, with the colour bar, and one
 * called "dt skin" (dt over the solid elements, an ElementData view of the
 * .msh), the faint skin of the solid alone; lines as 4-pixel tubes in
 * every view of the result. */
static void assert_opened_styling(void) {
  int ierr = 0, ndt = 0, nskin = 0, first = -1, second = -1;
  tu_gmsh_begin();
  gmshOpen(out, &ierr);
  assert_int_equal(ierr, 0);
  int nviews = tu_view_count();
  for (int i = 0; i < nviews; i++) {
    char name[64], *s = NULL;
    snprintf(name, sizeof name, "View[%d].Name", i);
    gmshOptionGetString(name, &s, &ierr);
    if (!strcmp(s, "dt")) ndt++, first = i;
    if (!strcmp(s, "dt skin")) nskin++, second = i;
    if (strcmp(s, "dtmap")) assert_true(view_number(i, "LineType") == 1 && view_number(i, "LineWidth") == 4);
    gmshFree(s);
  }
  assert_int_equal(ndt, 1);
  assert_int_equal(nskin, 1);
  assert_true(view_number(first, "ColormapAlpha") == 1 && view_number(first, "DrawTetrahedra") == 0);
  assert_true(view_number(first, "DrawLines") == 1 && view_number(first, "ShowScale") == 1);
  assert_true(fabs(view_number(second, "ColormapAlpha") - 0.2) < 1e-12);
  assert_true(view_number(second, "DrawSkinOnly") == 1 && view_number(second, "DrawTetrahedra") == 1);
  assert_true(solid_elements_only("dt skin"));
  assert_true(view_number(first, "Visible") == 1 && view_number(second, "Visible") == 1);
  tu_gmsh_end();
}

/* The bar as a truss: its line elements are in the views; the .opt styles
 * them; the saved panel scene holds the section. */
static void test_truss(void **state) {
  (void)state;
  groups g;
  run_sections(0, &g);
  free_groups(&g);
  char *text = read_text(opt);
  assert_non_null(strstr(text, ".LineType = 1; // trusses as tubes, seen inside the solid\n"));
  assert_non_null(strstr(text, ".LineWidth = 4;\n"));
  assert_null(strstr(text, "Plugin(")); /* no view made by the .opt: a list-based one aborts getModelData */
  assert_non_null(strstr(text, "].DrawTetrahedra = 0;\n"));
  free(text);
  assert_opened_styling();
}

/* A session of model whose panel saves its scene to saved (removed
 * first), its panel declared. */
static void saving_session(const char *model, const char *saved) {
  char *file[] = {(char *)saved};
  int ierr = 0;
  unlink(saved);
  tu_onelab_session(model, "t804");
  gmshOnelabSetString("dtmap/5Scene/1file", file, 1, &ierr);
  assert_int_equal(ierr, 0);
  tu_onelab_set_number("dtmap/5Scene/0save", 1);
  tu_onelab_run("check");
}

/* Both sections, and the panel saved as a scene: the triangles of the
 * sheet come back too, and the saved scene reads back with the two
 * sections and their values exactly (17 digits). */
static void test_truss_and_membrane(void **state) {
  (void)state;
  char saved[700];
  snprintf(saved, sizeof saved, "%s/saved.xml", dir);
  unlink(out);
  saving_session(geo, saved);
  tu_onelab_set_number("dtmap/4Materials/bar/00section", 1);
  tu_onelab_set_number("dtmap/4Materials/bar/01area", 3.1e-4);
  tu_onelab_set_number("dtmap/4Materials/sheet/00section", 1);
  tu_onelab_set_number("dtmap/4Materials/sheet/01thickness", 0.002);
  tu_onelab_run("compute");
  tu_view dt;
  assert_int_equal(tu_view_read_last("dt", &dt), 0);
  tu_gmsh_end();
  groups g;
  read_groups(&g);
  for (int k = 0; k < 3; k++) assert_int_equal(covered(&dt, g.tags[k], g.n[k]), g.n[k]);
  assert_int_equal(dt.n, g.n[0] + g.n[1] + g.n[2]);
  tu_view_free(&dt);
  free_groups(&g);
  dtm_scene *s = NULL;
  assert_int_equal(dtm_scene_load(saved, &s), 0);
  assert_int_equal(s->nsections, 2);
  for (int i = 0; i < 2; i++) {
    const dtm_section *sec = &s->sections[i];
    assert_int_equal(sec->ngroups, 1);
    int bar = !strcmp(sec->groups[0], "bar");
    assert_int_equal(sec->kind, bar ? DTM_SECTION_TRUSS : DTM_SECTION_MEMBRANE);
    assert_true(bar ? sec->area == 3.1e-4 : sec->thickness == 0.002);
  }
  dtm_scene_destroy(&s);
}

/* The section of group name in scene s (NULL when none). */
static const dtm_section *section_of(const dtm_scene *s, const char *name) {
  for (int i = 0; i < s->nsections; i++)
    if (s->sections[i].ngroups == 1 && !strcmp(s->sections[i].groups[0], name)) return &s->sections[i];
  return NULL;
}

/* A beam of radius 0.01 m on the bar and a 2 mm shell on the sheet, chosen
 * in the panel (choice 2 of each menu): all elements come back in the dt
 * view; the saved scene holds a beam of A = pi r^2, I_y = I_z = pi r^4/4
 * (1e-15 relative: the panel writes the radius, the reader computes them)
 * and the shell's thickness. */
static void test_shell_and_beam(void **state) {
  (void)state;
  char saved[700];
  snprintf(saved, sizeof saved, "%s/saved_sb.xml", dir);
  unlink(out);
  saving_session(geo, saved);
  cJSON *p = parameter("dtmap/4Materials/bar/00section");
  assert_true(choice_value(p, "beam") == 2);
  cJSON_Delete(p);
  p = parameter("dtmap/4Materials/sheet/00section");
  assert_true(choice_value(p, "shell") == 2);
  cJSON_Delete(p);
  tu_onelab_set_number("dtmap/4Materials/bar/00section", 2);
  tu_onelab_set_number("dtmap/4Materials/bar/01radius", 0.01);
  tu_onelab_set_number("dtmap/4Materials/sheet/00section", 2);
  tu_onelab_set_number("dtmap/4Materials/sheet/01thickness", 0.002);
  tu_onelab_run("check");
  assert_parameter("dtmap/4Materials/bar/01radius", 1, "m");
  assert_parameter("dtmap/4Materials/bar/01area", 0, "m^2");
  tu_onelab_run("compute");
  tu_view dt;
  assert_int_equal(tu_view_read_last("dt", &dt), 0);
  tu_gmsh_end();
  groups g;
  read_groups(&g);
  for (int k = 0; k < 3; k++) assert_int_equal(covered(&dt, g.tags[k], g.n[k]), g.n[k]);
  tu_view_free(&dt);
  free_groups(&g);
  dtm_scene *s = NULL;
  assert_int_equal(dtm_scene_load(saved, &s), 0);
  const dtm_section *beam = section_of(s, "bar"), *shell = section_of(s, "sheet");
  assert_non_null(beam);
  assert_non_null(shell);
  assert_int_equal(beam->kind, DTM_SECTION_BEAM);
  assert_int_equal(shell->kind, DTM_SECTION_SHELL);
  double pi = 3.14159265358979323846, a = pi * 1e-4, i = pi * 1e-8 / 4;
  assert_true(fabs(beam->area - a) <= 1e-15 * a && fabs(beam->iy - i) <= 1e-15 * i && beam->iz == beam->iy);
  assert_true(shell->thickness == 0.002);
  dtm_scene_destroy(&s);
}

/* The stiffened panel with its scene beside it: the stiffener's menu
 * defaults to its beam (no radius field: the scene's 10 x 40 mm profile is
 * kept); the skin is of the analysed dimension (no section menu) and keeps
 * the scene's shell; the saved scene has the same profile, orientation and
 * shell. */
static void test_scene_beam_kept(void **state) {
  (void)state;
  char model[700], saved[700], orig[700];
  snprintf(model, sizeof model, "%s/panel/stiffened_panel.geo", dir);
  snprintf(saved, sizeof saved, "%s/panel/saved.xml", dir);
  snprintf(orig, sizeof orig, "%s/panel/stiffened_panel.xml", dir);
  saving_session(model, saved);
  assert_true(tu_onelab_get_number("dtmap/4Materials/stiffener/00section") == 2);
  assert_null(parameter("dtmap/4Materials/skin/00section"));
  assert_null(parameter("dtmap/4Materials/stiffener/01radius"));
  tu_onelab_run("compute");
  tu_gmsh_end();
  dtm_scene *s = NULL, *o = NULL;
  assert_int_equal(dtm_scene_load(saved, &s), 0);
  assert_int_equal(dtm_scene_load(orig, &o), 0);
  const dtm_section *got = section_of(s, "stiffener"), *want = section_of(o, "stiffener");
  assert_non_null(got);
  assert_int_equal(got->kind, DTM_SECTION_BEAM);
  assert_true(got->area == want->area && got->iy == want->iy && got->iz == want->iz && got->jt == want->jt);
  for (int k = 0; k < 3; k++) assert_true(got->orient[k] == want->orient[k]);
  assert_int_equal(section_of(s, "skin")->kind, DTM_SECTION_SHELL);
  assert_true(section_of(s, "skin")->thickness == 0.005);
  dtm_scene_destroy(&s);
  dtm_scene_destroy(&o);
}

/* No section chosen: only the tets are analysed, and the .opt is the one a
 * solid output always had (no line, alias or element-type option). */
static void test_no_section(void **state) {
  (void)state;
  unlink(out);
  tu_onelab_session(geo, "t804");
  tu_onelab_run("compute");
  tu_view dt;
  assert_int_equal(tu_view_read_last("dt", &dt), 0);
  tu_gmsh_end();
  groups g;
  read_groups(&g);
  assert_int_equal(dt.n, g.n[0]);
  assert_int_equal(covered(&dt, g.tags[0], g.n[0]), g.n[0]);
  tu_view_free(&dt);
  free_groups(&g);
  char *text = read_text(opt);
  assert_null(strstr(text, "Line"));
  assert_null(strstr(text, "Alias"));
  assert_null(strstr(text, ".DrawTetrahedra"));
  assert_null(strstr(text, ".DrawLines"));
  free(text);
}

/* What `dtmap run` says about a scene file with this area, after its
 * "file:line: " (into msg). */
static void scene_file_message(const char *area, char *msg, size_t n) {
  char xml[700], text[2048], *said = NULL;
  snprintf(xml, sizeof xml, "%s/bad_area.xml", dir);
  snprintf(text, sizeof text,
           "<dtmap-scene version=\"1\">\n<geometry file=\"rebar_box.geo\"/>\n"
           "<material name=\"steel\" groups=\"block bar\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
           "<section groups=\"bar\" kind=\"truss\" area=\"%s\"/>\n<effects><elastic/></effects>\n</dtmap-scene>\n",
           area);
  tu_write(xml, text);
  assert_int_equal(tu_run(&said, "%s run %s -q -o %s/bad_area.msh 2>&1", tu_cli(), xml, dir), 2);
  const char *at = strstr(said, "bad_area.xml:4: ");
  assert_non_null(at);
  snprintf(msg, n, "%.*s", (int)strcspn(at + 16, "\n"), at + 16);
  free(said);
}

/* An area <= 0 in the panel: Gmsh gets the scene reader's own error (the
 * same text as for a scene file), and the line of the panel's scene it is
 * about; nothing is written. */
static void test_bad_area(void **state) {
  (void)state;
  static const double areas[] = {0, -1e-4};
  static const char *const texts[] = {"0", "-0.0001"};
  for (int k = 0; k < 2; k++) {
    char expect[1024], quote[200], **log = NULL;
    size_t nlog = 0;
    int ierr = 0, said = 0, quoted = 0;
    scene_file_message(texts[k], expect, sizeof expect);
    snprintf(quote, sizeof quote, "of the panel's scene: <section groups=\"bar\" kind=\"truss\" area=\"%s\"/>",
             texts[k]);
    unlink(out);
    tu_onelab_session(geo, "t804");
    tu_onelab_run("check");
    tu_onelab_set_number("dtmap/4Materials/bar/00section", 1);
    tu_onelab_set_number("dtmap/4Materials/bar/01area", areas[k]);
    gmshLoggerStart(&ierr);
    tu_onelab_run("compute");
    gmshLoggerGet(&log, &nlog, &ierr);
    for (size_t i = 0; i < nlog; i++) {
      said |= strstr(log[i], expect) != NULL;
      quoted |= strstr(log[i], quote) != NULL;
      gmshFree(log[i]);
    }
    gmshFree(log);
    gmshLoggerStop(&ierr);
    tu_gmsh_end();
    if (!said || !quoted) fprintf(stderr, "expected in Gmsh's log: '%s' and '%s'\n", expect, quote);
    assert_true(said && quoted);
    assert_false(tu_exists(out));
  }
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_panel_names),        cmocka_unit_test(test_panel_2d),
      cmocka_unit_test(test_scene_defaults),     cmocka_unit_test(test_truss),
      cmocka_unit_test(test_truss_and_membrane), cmocka_unit_test(test_no_section),
      cmocka_unit_test(test_bad_area),           cmocka_unit_test(test_shell_and_beam),
      cmocka_unit_test(test_scene_beam_kept),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
