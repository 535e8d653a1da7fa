/* `dtmap effects`: every built-in effect with what it declares (its scene
 * attributes, the material properties it reads, its scheme and accuracy
 * indicator), and how to name an external one. Printed to a stream, so the
 * man page (help.c) carries the same listing. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli-impl.h"
#include "dtmap/registry.h"

/* "[lo, hi]" style range of a number, or "" when unbounded. */
static void range_text(double lo, double hi, unsigned open, char *buf, size_t n) {
  buf[0] = '\0';
  if (isfinite(lo) && isfinite(hi))
    snprintf(buf, n, "%s%g, %g%s", open & DTM_OPEN_LO ? "(" : "[", lo, hi, open & DTM_OPEN_HI ? ")" : "]");
  else if (isfinite(lo))
    snprintf(buf, n, "%s %g", open & DTM_OPEN_LO ? ">" : ">=", lo);
  else if (isfinite(hi))
    snprintf(buf, n, "%s %g", open & DTM_OPEN_HI ? "<" : "<=", hi);
}

static void print_param(FILE *f, const dtm_param *p) {
  char what[256] = "";
  if (p->type == DTM_PARAM_NUMBER) range_text(p->lo, p->hi, p->open, what, sizeof what);
  for (int i = 0; p->type == DTM_PARAM_CHOICE && p->choices[i]; i++)
    snprintf(what + strlen(what), sizeof what - strlen(what), "%s%s", i ? "|" : "", p->choices[i]);
  if (p->type == DTM_PARAM_GROUPS) snprintf(what, sizeof what, "physical groups");
  fprintf(f, "    %-18s %s%s%s%s%s%s%s%s\n", p->name, what, p->unit && p->unit[0] ? " " : "", p->unit ? p->unit : "",
          p->def ? ", default " : "", p->def ? p->def : "", p->required ? ", required" : "", "; ", p->help);
}

static void print_property(FILE *f, const dtm_property *p) {
  char range[128];
  range_text(p->lo, p->hi, p->open, range, sizeof range);
  fprintf(f, "    %-18s %s%s%s%s; %s\n", p->name, range, p->unit[0] ? " " : "", p->unit,
          p->required ? ", required" : "", p->help);
}

static void print_effect(FILE *f, const dtm_effect_class *c) {
  static const char *const schemes[] = {"modifies the wave steps", "central differences", "forward Euler"};
  fprintf(f, "%s: %s\n  %s", c->name, c->summary, schemes[c->scheme]);
  if (c->role & DTM_ROLE_LIMITS) fprintf(f, ", dt ~ h^%g", c->exponent);
  fprintf(f, "\n");
  if (c->params && c->params->name) fprintf(f, "  attributes:\n");
  for (const dtm_param *p = c->params; p && p->name; p++) print_param(f, p);
  if (c->properties && c->properties->name) fprintf(f, "  material properties:\n");
  for (const dtm_property *p = c->properties; p && p->name; p++) print_property(f, p);
  if (c->indicator.name) fprintf(f, "  accuracy: view '%s' (%s)\n", c->indicator.view, c->indicator.help);
}

void dtm_cli_print_effects_to(void *stream) {
  FILE *f = stream;
  for (int i = 0; i < dtm_registry_count(); i++) print_effect(f, dtm_registry_get(i)), fprintf(f, "\n");
  fprintf(f, "effect: an external effect, <effect library=\"libX.so\" name=\"X\" .../>; its attributes and\n"
             "  properties are those its library declares (see docs/effects.md)\n");
}

int dtm_cli_print_effects(void) {
  dtm_cli_print_effects_to(stdout);
  return 0;
}
