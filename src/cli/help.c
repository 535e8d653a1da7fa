/* The documentation of the dtmap command, all of it printed from the same
 * command tables (main.c) and texts: `dtmap --help`, `dtmap CMD --help`,
 * and for the build (`dtmap --generate man|bash-completion`, run by
 * cmake/install.cmake) the man page dtmap.1 and the bash completion, so
 * that the help, the manual and the completion never disagree. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/version.h"

static const char summary[] =
    "dtmap tells an explicit solver's user the critical time step before the run: it meshes the\n"
    "scene's geometry with Gmsh (or reads its .msh), computes every element's critical step for\n"
    "only the physical effects the scene names, and writes a dt map and a size suggestion back\n"
    "into the .msh as Gmsh views, plus a JSON report.";

static const char effects_line[] = "list the effects a scene can name";
static const char onelab_usage[] = "[run] [SCENE.xml] [-v|-q] [-j N] -onelab NAME ADDRESS";
static const char onelab_line[] = "(as Gmsh's ONELAB solver)";

/* Sections after the commands: a title and its text, preformatted (a
 * table kept as printed) or a paragraph. */
static const struct {
  const char *title; /* printed as "title:" in --help, a section in the manual */
  const char *text;  /* lines ending in \n */
  int table;         /* 1: keep the lines as they are */
} sections[] = {{"Element step of the elastic effect, <elastic length=...>",
                 "  eigen         2/sqrt(lambda_max(Me^-1 Ke)), lumped mass (default; provably safe)\n"
                 "  safe          2/sqrt(d+1) (sum_a h_a^-2)^-1/2 / C_D on simplices (safe for nu >= 0)\n"
                 "  min-edge      shortest edge / C_D            UNSAFE: up to 17x too large on slivers\n"
                 "  min-altitude  smallest altitude / C_D        UNSAFE on needles (1.06-1.13x)\n"
                 "  inradius      2 x inradius / C_D             UNSAFE on needle triangles (1.05x)\n"
                 "  volume-area   V / A_max / C_D                UNSAFE on hex and quad (1.04-1.21x)\n",
                 1},
                {"Exit codes",
                 "0 success, 1 target or verification not met, 2 bad input or usage,\n"
                 "3 internal error.\n",
                 0}};
#define NSECTIONS (sizeof sections / sizeof sections[0])

/* ---- plain text ---- */

void dtm_cli_print_usage(void *stream) {
  FILE *f = stream;
  for (const cli_command *c = dtm_cli_commands; c->name; c++)
    fprintf(f, "%s dtmap %s %s\n", c == dtm_cli_commands ? "usage:" : "      ", c->name, c->args);
  fprintf(f, "       dtmap effects        %s\n", effects_line);
  fprintf(f, "       dtmap --help | --version\n");
  fprintf(f, "       dtmap %s   %s\n", onelab_usage, onelab_line);
}

int dtm_cli_print_overview(void) {
  dtm_cli_print_usage(stdout);
  printf("\n%s\n", summary);
  for (const cli_command *c = dtm_cli_commands; c->name; c++) printf("\n%-6s %s\n", c->name, c->about);
  printf("\nEach command's options: dtmap CMD --help.\n");
  for (size_t i = 0; i < NSECTIONS; i++) printf("\n%s:\n%s", sections[i].title, sections[i].text);
  return 0;
}

/* "NAME VALUE" of an option, as the help and the manual show it. */
static const char *option_head(const cli_option *p, char *buf, size_t len) {
  snprintf(buf, len, "%s%s%s", p->name, p->value ? " " : "", p->value ? p->value : "");
  return buf;
}

void dtm_cli_print_help(const cli_command *c, void *stream) {
  FILE *f = stream;
  char head[64];
  fprintf(f, "usage: dtmap %s %s\n\n%s\n", c->name, c->args, c->about);
  if (c->options && c->options->name) fprintf(f, "\noptions:\n");
  for (const cli_option *p = c->options; p && p->name; p++)
    fprintf(f, "  %-18s %s\n", option_head(p, head, sizeof head), p->help);
}

/* ---- the man page (roff) ---- */

/* text as roff: backslashes and minus signs escaped, and a line that would
 * start with a control character ('.' or ') protected. */
static void roff(FILE *f, const char *text) {
  for (const char *p = text; *p; p++) {
    if ((p == text || p[-1] == '\n') && (*p == '.' || *p == '\'')) fputs("\\&", f);
    if (*p == '\\')
      fputs("\\e", f);
    else if (*p == '-')
      fputs("\\-", f);
    else
      fputc(*p, f);
  }
}

static void man_synopsis(FILE *f) {
  fputs(".SH SYNOPSIS\n.nf\n", f);
  for (const cli_command *c = dtm_cli_commands; c->name; c++) {
    fprintf(f, "\\fBdtmap %s\\fR ", c->name);
    roff(f, c->args);
    fputc('\n', f);
  }
  fputs("\\fBdtmap effects\\fR\n\\fBdtmap \\-\\-help\\fR | \\fB\\-\\-version\\fR\n\\fBdtmap\\fR ", f);
  roff(f, onelab_usage);
  fputs("   ", f);
  roff(f, onelab_line);
  fputs("\n.fi\n", f);
}

static void man_command(FILE *f, const cli_command *c) {
  char head[64];
  fprintf(f, ".SS %s\n.B dtmap %s\n", c->name, c->name);
  roff(f, c->args);
  fputs("\n.PP\n", f);
  roff(f, c->about);
  fputc('\n', f);
  for (const cli_option *p = c->options; p && p->name; p++) {
    fputs(".TP\n.B ", f);
    roff(f, option_head(p, head, sizeof head));
    fputc('\n', f);
    roff(f, p->help);
    fputc('\n', f);
  }
}

/* `dtmap effects`'s listing, kept as printed. */
static void man_effects(FILE *f) {
  char *text = NULL;
  size_t len = 0;
  FILE *m = open_memstream(&text, &len);
  if (m) dtm_cli_print_effects_to(m), fclose(m);
  fprintf(f, ".SS effects\n.B dtmap effects\n.PP\n");
  roff(f, effects_line);
  fputs(":\n.nf\n", f);
  if (text) roff(f, text);
  fputs(".fi\n", f);
  free(text);
}

static void man_sections(FILE *f) {
  for (size_t i = 0; i < NSECTIONS; i++) {
    fputs(".SH \"", f);
    roff(f, sections[i].title);
    fputs(sections[i].table ? "\"\n.nf\n" : "\"\n", f);
    roff(f, sections[i].text);
    if (sections[i].table) fputs(".fi\n", f);
  }
}

static int print_man(FILE *f) {
  fprintf(f, ".\\\" Generated by `dtmap --generate man` from the tables of src/cli/main.c; do not edit.\n");
  fprintf(f, ".TH DTMAP 1 \"\" \"dtmap %s\" \"User Commands\"\n.nh\n.ad l\n", dtm_version());
  fputs(".SH NAME\ndtmap \\- critical explicit time steps of Gmsh meshes, as views\n", f);
  man_synopsis(f);
  fputs(".SH DESCRIPTION\n", f);
  roff(f, summary);
  fputs("\n.PP\nEach command's options: dtmap CMD \\-\\-help.\n.SH COMMANDS\n", f);
  for (const cli_command *c = dtm_cli_commands; c->name; c++) man_command(f, c);
  man_effects(f);
  man_sections(f);
  fputs(".SH FILES\n.TP\n.I PREFIX/share/dtmap/\nthe scene schema (dtmap-scene.xsd), the report's JSON Schema\n"
        "(dtmap-report.schema.json) and examples (an external effect, a Python script)\n"
        ".SH \"SEE ALSO\"\n.BR gmsh (1)\n",
        f);
  return 0;
}

/* ---- the bash completion ---- */

/* What a value of option p completes to: files with the extension of its
 * placeholder (OUT.msh -> *.msh), any file, or nothing (numbers, lists). */
static void completion_value(FILE *f, const cli_option *p) {
  const char *dot = p->value ? strrchr(p->value, '.') : NULL;
  fprintf(f, "        %s) ", p->name);
  if (p->kind != CLI_STRING || (p->value && strchr(p->value, ',')))
    fputs("return ;;\n", f);
  else if (dot && isalpha((unsigned char)dot[1]))
    fprintf(f, "_dtmap_files '%s'; return ;;\n", dot + 1);
  else
    fputs("_dtmap_files ''; return ;;\n", f);
}

/* The extension of a command's positional argument (SCENE.xml -> xml). */
static int positional_ext(const cli_command *c, char *ext, size_t len) {
  size_t n = strcspn(c->args, " ");
  const char *dot = memchr(c->args, '.', n);
  return snprintf(ext, len, "%.*s", dot ? (int)(c->args + n - dot - 1) : 0, dot ? dot + 1 : "");
}

static void completion_command(FILE *f, const cli_command *c) {
  char ext[16];
  positional_ext(c, ext, sizeof ext);
  fprintf(f, "    %s)\n      ext='%s'\n      case $prev in\n", c->name, ext);
  for (const cli_option *p = c->options; p && p->name; p++)
    if (p->kind != CLI_FLAG) completion_value(f, p);
  fprintf(f, "      esac\n      opts='--help");
  for (const cli_option *p = c->options; p && p->name; p++) fprintf(f, " %s", p->name);
  fprintf(f, "' ;;\n");
}

static int print_completion(FILE *f) {
  fputs("# bash completion for dtmap, generated by `dtmap --generate bash-completion`\n"
        "# from the command tables of src/cli/main.c; do not edit.\n"
        "_dtmap_files() { # files ending in .$1 and folders, or any file\n"
        "  local IFS=$'\\n'\n"
        "  if [ -n \"$1\" ]; then COMPREPLY=($(compgen -d -- \"$cur\") $(compgen -f -X \"!*.$1\" -- \"$cur\"))\n"
        "  else COMPREPLY=($(compgen -f -- \"$cur\")); fi\n"
        "}\n"
        "_dtmap() {\n"
        "  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]} opts='' ext=''\n"
        "  if [ \"$COMP_CWORD\" -eq 1 ]; then\n"
        "    COMPREPLY=($(compgen -W '",
        f);
  for (const cli_command *c = dtm_cli_commands; c->name; c++) fprintf(f, "%s ", c->name);
  fputs("effects --help --version' -- \"$cur\"))\n    return\n  fi\n  case ${COMP_WORDS[1]} in\n", f);
  for (const cli_command *c = dtm_cli_commands; c->name; c++) completion_command(f, c);
  fputs("    *) COMPREPLY=(); return ;;\n  esac\n"
        "  if [[ $cur == -* ]]; then COMPREPLY=($(compgen -W \"$opts\" -- \"$cur\"))\n"
        "  else _dtmap_files \"$ext\"; fi\n"
        "}\n"
        "complete -o filenames -F _dtmap dtmap\n",
        f);
  return 0;
}

int dtm_cli_generate(const char *what) {
  if (what && !strcmp(what, "man")) return print_man(stdout);
  if (what && !strcmp(what, "bash-completion")) return print_completion(stdout);
  fprintf(stderr, "dtmap --generate: give man or bash-completion\n");
  return 2;
}
