/* The "compute" action of the ONELAB client: the panel's scene is read back
 * through dtmap's scene reader, analysed, written (mesh with views, .opt,
 * the report when the scene asks for one), its figures published under
 * NAME/9Results and its summary sent to Gmsh's console, and the result is
 * handed to Gmsh to merge: the whole .msh (a new model beside the one the
 * user opened), or, when Gmsh already holds the very mesh analysed, only the
 * views, so that they land on it. An error at a line of the panel's scene
 * (a section's area <= 0, a material without a property an effect needs)
 * is the scene reader's or the analysis' own, as for a scene file; that
 * line of the scene, which the user does not see, goes to Gmsh's console
 * first, so that the group and the value it is about can be read. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dtmap/analysis.h"
#include "dtmap/cost.h"
#include "dtmap/error.h"
#include "dtmap/output.h"
#include "dtmap/util.h"
#include "onelab-impl.h"

/* The scene file (or the model) without its extension: *len characters. */
static const char *stem(const ol_model *m, int *len) {
  const char *base = m->scene[0] ? m->scene : m->model;
  const char *dot = strrchr(base, '.'), *slash = strrchr(base, '/');
  *len = dot && (!slash || dot > slash) ? (int)(dot - base) : (int)strlen(base);
  return base;
}

/* The scene name the panel's scene is read under: messages then name the
 * model's scene, and relative paths resolve beside the model. */
static void panel_name(const ol_model *m, char *out, size_t n) {
  int len;
  const char *base = stem(m, &len);
  snprintf(out, n, "%.*s.xml (dtmap panel)", len, base);
}

static void default_output(const ol_model *m, char *out, size_t n) {
  if (m->base && m->base->out_mesh) {
    snprintf(out, n, "%s", m->base->out_mesh);
    return;
  }
  int len;
  const char *base = stem(m, &len);
  snprintf(out, n, "%.*s_dt.msh", len, base);
}

/* The terminal summary, one INFO line each, into Gmsh's message console. */
static int send_summary(ol_conn *c, const dtm_results *res) {
  char *text = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&text, &len);
  if (!f) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  dtm_summary_print(res, f);
  fclose(f);
  int r = DTM_OK;
  for (char *line = strtok(text, "\n"); line && r == DTM_OK; line = strtok(NULL, "\n"))
    r = dtm_ol_send_text(c, OL_INFO, line);
  free(text);
  return r;
}

static int result_number(ol_conn *c, const char *rest, const char *label, const char *units, double v) {
  ol_param p;
  char name[256];
  snprintf(name, sizeof name, "%s/9Results/%s", c->name, rest);
  dtm_ol_number(&p, name, v, label);
  p.read_only = 1;
  if (units) dtm_ol_attr(&p, "Units", units);
  dtm_ol_attr(&p, "Highlight", "AliceBlue");
  return dtm_ol_set(c, &p);
}

static int result_string(ol_conn *c, const char *rest, const char *label, const char *v) {
  ol_param p;
  char name[256];
  snprintf(name, sizeof name, "%s/9Results/%s", c->name, rest);
  dtm_ol_string(&p, name, v, label);
  p.read_only = 1;
  dtm_ol_attr(&p, "Highlight", "AliceBlue");
  return dtm_ol_set(c, &p);
}

static int publish(ol_conn *c, const dtm_analysis *a, const char *out) {
  size_t e = 0;
  double dmin = dtm_analysis_dt_min(a, &e);
  char buf[32];
  const char *group = dtm_mesh_group_label(dtm_analysis_mesh(a), dtm_analysis_group(a, e), buf, sizeof buf);
  DTM_CHECK(result_number(c, "0recommended", "recommended step", "s", dtm_analysis_recommended(a)));
  DTM_CHECK(result_string(c, "1basis", "recommended from", dtm_analysis_basis(a)));
  DTM_CHECK(result_number(c, "2dt min", "smallest element step", "s", dmin));
  DTM_CHECK(result_number(c, "3element", "at element (Gmsh tag)", NULL, (double)dtm_analysis_tag(a, e)));
  DTM_CHECK(result_string(c, "4group", "in physical group", group));
  DTM_CHECK(result_string(c, "5effect", "limited by", dtm_analysis_effect(a, dtm_analysis_limiting(a)[e])->name));
  DTM_CHECK(result_number(c, "6elements", "elements", NULL, (double)dtm_analysis_nelements(a)));
  return result_string(c, "7output", "output mesh", out);
}

static int same_file(const char *a, const char *b) {
  struct stat sa, sb;
  return !stat(a, &sa) && !stat(b, &sb) && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* Hand the result to Gmsh: the whole file, or its views only when Gmsh
 * holds the same mesh; wait until Gmsh has merged it. */
static int hand_over(ol_conn *c, const ol_model *m, const char *out) {
  if (!(m->source_is_mesh && same_file(m->source, m->model))) {
    DTM_CHECK(dtm_ol_send_text(c, OL_MERGE_FILE, out));
    return dtm_ol_sync(c);
  }
  char dir[] = "/tmp/dtmap-onelab-XXXXXX", views[64];
  if (!mkdtemp(dir)) return DTM_ERR(DTM_ERR_INTERNAL, "cannot create a temporary directory in /tmp");
  snprintf(views, sizeof views, "%s/views.msh", dir);
  int r = dtm_ol_views_only(out, views);
  if (r == DTM_OK) r = dtm_ol_send_text(c, OL_MERGE_FILE, views);
  if (r == DTM_OK) r = dtm_ol_sync(c);
  char opt[80];
  snprintf(opt, sizeof opt, "%s.opt", views);
  unlink(views), unlink(opt), rmdir(dir);
  return r;
}

/* Whether the user pressed Gmsh's Stop (NAME/Action is "stop"; Gmsh's own
 * example clients poll it the same way): *stop is set, and Gmsh is told
 * what was not done. A run cannot be stopped inside a stage (Gmsh's
 * meshing has no way to), only between them; Gmsh's Kill ends it at once
 * (its temporaries go at the next run's clean-up). */
static int stop_asked(ol_conn *c, const char *before, int *stop) {
  char action[64];
  DTM_CHECK(dtm_ol_action(c, action, sizeof action));
  *stop = !strcmp(action, "stop");
  if (!*stop) return DTM_OK;
  char line[200];
  snprintf(line, sizeof line, "stopped from Gmsh before %s: nothing written", before);
  return dtm_ol_send_text(c, OL_INFO, line);
}

static int analyse(ol_conn *c, const dtm_scene *s, int posterior, dtm_analysis **a, dtm_cost **cost, int *stop) {
  DTM_CHECK(dtm_ol_send_text(c, OL_PROGRESS,
                             s->mesh ? "reading the mesh and computing steps" : "meshing and computing steps"));
  DTM_CHECK(dtm_analysis_run(s, a));
  if (posterior) DTM_CHECK(stop_asked(c, "the global estimate", stop));
  if (posterior && !*stop) {
    DTM_CHECK(dtm_ol_send_text(c, OL_PROGRESS, "global estimate (Lanczos)"));
    DTM_CHECK(dtm_analysis_estimate_global(*a, 1e-4, 400, DTM_GLOBAL_BASIS)); /* as run --posterior */
  }
  return dtm_cost_create(*a, cost);
}

static int write_and_send(ol_conn *c, const ol_model *m, dtm_results *res) {
  char out[DTM_PATH_MAX];
  default_output(m, out, sizeof out);
  DTM_CHECK(dtm_ol_send_text(c, OL_PROGRESS, "writing the result"));
  double t0 = dtm_wtime();
  DTM_CHECK(dtm_output_write(res, out));
  res->t_output = dtm_wtime() - t0;
  if (m->base && m->base->out_report) DTM_CHECK(dtm_report_write(res, m->base->out_report));
  DTM_CHECK(send_summary(c, res));
  DTM_CHECK(publish(c, res->analysis, out));
  return hand_over(c, m, out);
}

static int save_scene(ol_conn *c, const ol_panel *pn, const char *xml) {
  if (!pn->save_scene) return DTM_OK;
  DTM_CHECK(dtm_atomic_write_text(pn->scene_out, xml, 0));
  char line[4200];
  snprintf(line, sizeof line, "saved the panel as the scene %s", pn->scene_out);
  return dtm_ol_send_text(c, OL_INFO, line);
}

/* The line of the panel's scene xml (read as name) that the pending error
 * names ("name:LINE: ..."), sent to Gmsh's console; nothing when it names
 * none. */
static void quote_line(ol_conn *c, const char *name, const char *xml) {
  const char *msg = dtm_error_message();
  size_t n = strlen(name);
  int line = strncmp(msg, name, n) || msg[n] != ':' ? 0 : atoi(msg + n + 1);
  const char *at = line > 0 ? xml : NULL;
  for (int i = 1; at && i < line; i++) at = strchr(at, '\n'), at = at ? at + 1 : NULL;
  while (at && (*at == ' ' || *at == '\t')) at++;
  if (!at || !*at) return;
  char text[1200];
  snprintf(text, sizeof text, "line %d of the panel's scene: %.*s", line, (int)strcspn(at, "\n"), at);
  (void)dtm_ol_send_text(c, OL_INFO, text); /* a lost connection is what the report then says */
}

int dtm_ol_compute(ol_conn *c, const ol_model *m, const ol_panel *pn, int posterior) {
  char *xml = NULL, name[4200];
  dtm_scene *s = NULL;
  dtm_analysis *a = NULL;
  dtm_cost *cost = NULL;
  panel_name(m, name, sizeof name);
  int r = dtm_ol_scene_text(m, pn, &xml);
  double t0 = dtm_wtime(), t_scene = 0;
  if (r == DTM_OK) r = dtm_scene_load_memory(xml, strlen(xml), name, &s);
  t_scene = dtm_wtime() - t0;
  int stop = 0;
  if (r == DTM_OK) r = stop_asked(c, "the analysis", &stop);
  if (r == DTM_OK && !stop) r = analyse(c, s, posterior || pn->posterior, &a, &cost, &stop);
  if (r == DTM_OK && !stop) r = stop_asked(c, "writing the result", &stop);
  if (r == DTM_OK && !stop) {
    dtm_results res = {a, cost, NULL, t_scene, 0.0, 0, 0, {NULL}, {NULL}, NULL, NULL};
    r = write_and_send(c, m, &res);
  }
  if (r == DTM_OK && !stop) r = save_scene(c, pn, xml);
  if (r && xml) quote_line(c, name, xml);
  dtm_cost_destroy(&cost);
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
  free(xml);
  return r;
}
