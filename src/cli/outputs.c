/* Where the CLI's commands write, decided once and checked before any work
 * (dtm_output_path_check): the mesh of run and refine (-o, else the scene's
 * <output mesh>, else SCENE_dt.msh here; refine's defaults carry _refined)
 * with its .opt, their report
 * (--report, else <output report>, if any; with -o, the report the scene
 * asks for is named after -o's mesh: X.msh -> X.json), and sweep's CSV and PNG. A
 * message says where a bad path came from: the option, the scene's
 * <output> line, or the default. Two outputs may not be one file. */
#include <stdio.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/output.h"
#include "dtmap/util.h"

/* path with suffix before its extension ("a/b.msh" -> "a/b_refined.msh"). */
static void with_suffix(const char *path, const char *suffix, char *buf, size_t len) {
  const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
  if (!dot || (slash && dot < slash)) dot = path + strlen(path);
  snprintf(buf, len, "%.*s%s%s", (int)(dot - path), path, suffix, dot);
}

/* The mesh: -o, else the scene's <output mesh>, else SCENE_dt.msh; with a
 * suffix (refine: "_refined") the scene's and the default names carry it
 * before their extension, so they never overwrite run's. */
static void mesh_name(const dtm_scene *s, const cli_opts *o, const char *suffix, cli_outputs *out) {
  char tail[64];
  snprintf(tail, sizeof tail, "%s.msh", suffix ? suffix : "_dt");
  if (o->out) {
    snprintf(out->mesh, sizeof out->mesh, "%s", o->out);
    snprintf(out->mesh_from, sizeof out->mesh_from, "-o");
  } else if (s->out_mesh) {
    if (suffix)
      with_suffix(s->out_mesh, suffix, out->mesh, sizeof out->mesh);
    else
      snprintf(out->mesh, sizeof out->mesh, "%s", s->out_mesh);
    snprintf(out->mesh_from, sizeof out->mesh_from, "%s:%d: <output mesh>", s->path, s->out_line);
  } else {
    dtm_cli_default_out(s->path, tail, out->mesh, sizeof out->mesh);
    snprintf(out->mesh_from, sizeof out->mesh_from, "default output");
  }
}

/* -o's mesh with the extension .json ("d/x.msh" -> "d/x.json"): the report
 * of that mesh, never another mesh's. */
static void named_after(const char *mesh, char *buf, size_t len) {
  const char *slash = strrchr(mesh, '/'), *dot = strrchr(mesh, '.');
  if (!dot || (slash && dot < slash)) dot = mesh + strlen(mesh);
  if (snprintf(buf, len, "%.*s.json", (int)(dot - mesh), mesh) >= (int)len)
    buf[0] = '\0'; /* too long: the check before any work names no file */
}

/* The report: --report, else, when the scene's <output report> asks for
 * one, that name (with the suffix), or with -o the name of -o's mesh
 * (X.msh -> X.json), so that two meshes written with -o keep a report
 * each; else none. */
static void report_name(const dtm_scene *s, const cli_opts *o, const char *suffix, cli_outputs *out) {
  if (o->report) {
    snprintf(out->report, sizeof out->report, "%s", o->report);
    snprintf(out->report_from, sizeof out->report_from, "--report");
  } else if (s->out_report) {
    if (o->out)
      named_after(o->out, out->report, sizeof out->report);
    else if (suffix)
      with_suffix(s->out_report, suffix, out->report, sizeof out->report);
    else
      snprintf(out->report, sizeof out->report, "%s", s->out_report);
    snprintf(out->report_from, sizeof out->report_from, "%s:%d: <output report>%s", s->path, s->out_line,
             o->out ? ", named after -o's mesh" : "");
  }
}

void dtm_cli_output_names(const dtm_scene *s, const cli_opts *o, const char *suffix, cli_outputs *out) {
  memset(out, 0, sizeof *out);
  mesh_name(s, o, suffix, out);
  report_name(s, o, suffix, out);
  if (o->png) {
    snprintf(out->pictures[0], sizeof out->pictures[0], "%.4000s_worst.png", o->png);
    snprintf(out->pictures[1], sizeof out->pictures[1], "%.4000s_dt.png", o->png);
  }
}

/* Two outputs given the same name: the second would replace the first. */
static int distinct(const char *a, const char *a_from, const char *b, const char *b_from) {
  if (!a[0] || !b[0] || strcmp(a, b)) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT, "%s %s and %s %s: two outputs with one name", a_from, a, b_from, b);
}

int dtm_cli_check_outputs(const dtm_scene *s, const cli_outputs *out) {
  char opt[DTM_PATH_MAX + 8];
  snprintf(opt, sizeof opt, "%s.opt", out->mesh);
  DTM_CHECK(dtm_output_path_check(s, out->mesh, ".msh", out->mesh_from));
  DTM_CHECK(dtm_output_path_check(s, opt, NULL, out->mesh_from));
  if (out->report[0]) DTM_CHECK(dtm_output_path_check(s, out->report, NULL, out->report_from));
  for (int i = 0; i < 2 && out->pictures[i][0]; i++)
    DTM_CHECK(dtm_output_path_check(s, out->pictures[i], NULL, "--png"));
  DTM_CHECK(distinct(out->mesh, out->mesh_from, out->report, out->report_from));
  return distinct(opt, out->mesh_from, out->report, out->report_from);
}
