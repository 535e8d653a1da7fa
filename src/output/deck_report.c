/* The report's "deck" object (dtmap deck --report): the solver and the
 * file, the step the deck fixes with its basis beside dtmap's recommended
 * step, the solver's own estimate for the same mesh by its rule and the
 * ratio of the two, LS-DYNA's TSSFAC, the duration, what was written
 * (nodes, elements, sets) and the mass added at the nodes, and the
 * warnings on the solver's elements. */
#include <cJSON.h>
#include <math.h>

#include "output-impl.h"
#include "report.h"

/* deck.selective_mass (--selective-mass): what the solver does and what
 * its selective scaling adds by its rule, as dtmap predicts it. */
static cJSON *selective_json(const dtm_deck_info *d) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddBoolToObject(o, "solver_scales", d->sms_solver);
  cJSON_AddStringToObject(o, "note", d->sms_note);
  if (d->sms_solver) cJSON_AddNumberToObject(o, "added_mass", isnan(d->sms_added) ? 0.0 : d->sms_added);
  if (d->sms_solver) cJSON_AddNumberToObject(o, "elements", (double)d->sms_elements);
  if (!isnan(d->sms_beta_max)) cJSON_AddNumberToObject(o, "beta_max", d->sms_beta_max);
  if (d->sms_counted) cJSON_AddNumberToObject(o, "counted_without_mass", (double)d->sms_counted);
  return o;
}

static cJSON *deck_json(const dtm_deck_info *d) {
  cJSON *o = cJSON_CreateObject(), *w = cJSON_CreateArray();
  cJSON_AddStringToObject(o, "solver", d->solver);
  cJSON_AddStringToObject(o, "file", d->path);
  cJSON_AddNumberToObject(o, "step", d->step);
  cJSON_AddStringToObject(o, "basis", d->basis);
  cJSON_AddNumberToObject(o, "recommended", d->recommended);
  if (!isnan(d->own)) cJSON_AddNumberToObject(o, "own_estimate", d->own);
  if (!isnan(d->own)) cJSON_AddNumberToObject(o, "own_element", (double)d->own_element);
  cJSON_AddStringToObject(o, "own_rule", d->own_rule);
  if (!isnan(d->own)) cJSON_AddNumberToObject(o, "ratio", d->step / d->own);
  if (isfinite(d->tssfac)) cJSON_AddNumberToObject(o, "tssfac", d->tssfac);
  if (isfinite(d->tssfac)) cJSON_AddStringToObject(o, "lsdyna_step", d->lsdyna_proven ? "proven" : "conventional");
  if (isfinite(d->dt2ms)) cJSON_AddNumberToObject(o, "dt2ms", d->dt2ms);
  if (isfinite(d->dt2ms)) cJSON_AddNumberToObject(o, "solver_added_mass", d->solver_added);
  if (isfinite(d->dt2ms)) cJSON_AddNumberToObject(o, "solver_added_elements", (double)d->solver_added_elements);
  cJSON_AddNumberToObject(o, "duration", d->duration);
  cJSON_AddNumberToObject(o, "nodes", (double)d->nodes);
  cJSON_AddNumberToObject(o, "elements", (double)d->elements);
  cJSON_AddNumberToObject(o, "element_sets", d->element_sets);
  cJSON_AddNumberToObject(o, "node_sets", d->node_sets);
  cJSON_AddNumberToObject(o, "carried_mass", d->carried);
  cJSON_AddNumberToObject(o, "carried_nodes", (double)d->carried_nodes);
  cJSON_AddNumberToObject(o, "added_mass", d->added);
  cJSON_AddNumberToObject(o, "added_nodes", (double)d->added_nodes);
  if (isfinite(d->model_mass)) cJSON_AddNumberToObject(o, "model_mass", d->model_mass);
  if (d->selective) cJSON_AddItemToObject(o, "selective_mass", selective_json(d));
  for (int i = 0; i < d->nwarnings; i++) cJSON_AddItemToArray(w, cJSON_CreateString(d->warnings[i]));
  cJSON_AddItemToObject(o, "warnings", w);
  cJSON_AddNumberToObject(o, "seconds", d->seconds);
  return o;
}

int dtm_report_write_deck(const dtm_results *r, const dtm_deck_info *d, const char *path) {
  cJSON *root = dtm_report_json(r);
  cJSON *deck = deck_json(d);
  dtm_report_units(deck, r->analysis, 0);
  cJSON_AddItemToObject(root, "deck", deck);
  return dtm_json_write(root, path, "JSON report");
}
