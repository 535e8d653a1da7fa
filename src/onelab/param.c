/* ONELAB parameters in their text form, and the requests that carry them.
 * A parameter travels as fields each followed by a NUL byte: the protocol
 * version ("1.3"), the type ("number" or "string"), name, label, help, the
 * "changed" value, visible, read-only, the attributes (count, then key and
 * value), the clients (count, then name and flag); then for a number its
 * values (count, values), min, max, step, loop index, choices (count,
 * values) and value labels (count, then value and label); for a string its
 * values, kind and choices. Numbers are written with 16 significant digits. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "onelab-impl.h"

#define OL_UNBOUNDED 1e200 /* ONELAB's "no limit" */

static void copy(char *dst, size_t n, const char *src) { snprintf(dst, n, "%s", src ? src : ""); }

static void init(ol_param *p, const char *name, const char *label) {
  memset(p, 0, sizeof *p);
  copy(p->name, sizeof p->name, name);
  copy(p->label, sizeof p->label, label);
  p->visible = 1;
  p->min = -OL_UNBOUNDED, p->max = OL_UNBOUNDED;
  copy(p->kind, sizeof p->kind, "generic");
}

void dtm_ol_number(ol_param *p, const char *name, double value, const char *label) {
  init(p, name, label);
  p->value = value;
}

void dtm_ol_string(ol_param *p, const char *name, const char *value, const char *label) {
  init(p, name, label);
  p->is_string = 1;
  copy(p->svalue, sizeof p->svalue, value);
}

void dtm_ol_attr(ol_param *p, const char *key, const char *value) {
  if (p->nattrs >= OL_MAX_ATTRS) return;
  copy(p->attr_key[p->nattrs], sizeof p->attr_key[0], key);
  copy(p->attr_val[p->nattrs++], sizeof p->attr_val[0], value);
}

void dtm_ol_choice(ol_param *p, double value, const char *label) {
  if (p->nchoices >= OL_MAX_CHOICES) return;
  p->choice[p->nchoices] = value;
  copy(p->choice_label[p->nchoices++], sizeof p->choice_label[0], label);
}

/* A growing text buffer; fields are appended with their NUL separator. */
typedef struct {
  char *s;    /* the bytes */
  size_t n;   /* bytes used */
  size_t cap; /* bytes allocated */
  int failed; /* an allocation failed */
} ol_buf;

static void put(ol_buf *b, const char *field) {
  size_t k = strlen(field) + 1;
  if (b->n + k > b->cap) {
    size_t cap = 2 * (b->n + k) + 256;
    char *s = realloc(b->s, cap);
    if (!s) {
      b->failed = 1;
      return;
    }
    b->s = s, b->cap = cap;
  }
  memcpy(b->s + b->n, field, k); /* the NUL is the separator */
  b->n += k;
}

static void put_num(ol_buf *b, double v) {
  char t[40];
  snprintf(t, sizeof t, "%.16g", v);
  put(b, t);
}

static void put_common(ol_buf *b, const ol_param *p) {
  put(b, "1.3");
  put(b, p->is_string ? "string" : "number");
  put(b, p->name);
  put(b, p->label);
  put(b, p->help);
  put_num(b, p->never_changed ? 0 : 31);
  put_num(b, p->visible);
  put_num(b, p->read_only);
  put_num(b, p->nattrs);
  for (int i = 0; i < p->nattrs; i++) put(b, p->attr_key[i]), put(b, p->attr_val[i]);
  put(b, "0"); /* clients: the server adds this one */
}

static void put_number(ol_buf *b, const ol_param *p) {
  put(b, "1");
  put_num(b, p->value);
  put_num(b, p->min), put_num(b, p->max), put_num(b, p->step);
  put(b, "-1"); /* loop index: not in a loop */
  put_num(b, p->nchoices);
  for (int i = 0; i < p->nchoices; i++) put_num(b, p->choice[i]);
  int labels = 0;
  for (int i = 0; i < p->nchoices; i++) labels += p->choice_label[i][0] != '\0';
  put_num(b, labels);
  for (int i = 0; i < p->nchoices; i++)
    if (p->choice_label[i][0]) put_num(b, p->choice[i]), put(b, p->choice_label[i]);
}

static void put_string(ol_buf *b, const ol_param *p) {
  put(b, "1");
  put(b, p->svalue);
  put(b, p->kind);
  put_num(b, p->nchoices);
  for (int i = 0; i < p->nchoices; i++) put(b, p->choice_label[i]);
}

int dtm_ol_encode(const ol_param *p, char **out, size_t *len) {
  ol_buf b = {0};
  put_common(&b, p);
  if (p->is_string)
    put_string(&b, p);
  else
    put_number(&b, p);
  if (b.failed) return free(b.s), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  *out = b.s, *len = b.n;
  return DTM_OK;
}

/* Reading the fields back, in order. */
typedef struct {
  const char *s; /* the message */
  size_t n, at;  /* its length, the next field's start */
  int bad;       /* ran past the end */
} ol_reader;

static const char *next(ol_reader *r) {
  if (r->at >= r->n) return r->bad = 1, "";
  const char *f = r->s + r->at;
  const char *end = memchr(f, '\0', r->n - r->at);
  r->at = end ? (size_t)(end - r->s) + 1 : r->n;
  return f;
}

static double next_num(ol_reader *r) { return atof(next(r)); }

static void read_common(ol_reader *r, ol_param *p) {
  copy(p->name, sizeof p->name, next(r));
  copy(p->label, sizeof p->label, next(r));
  copy(p->help, sizeof p->help, next(r));
  p->never_changed = next_num(r) == 0;
  p->visible = (int)next_num(r);
  p->read_only = (int)next_num(r);
  int na = (int)next_num(r);
  for (int i = 0; i < na && !r->bad; i++) {
    const char *k = next(r);
    dtm_ol_attr(p, k, next(r));
  }
  int nc = (int)next_num(r);
  for (int i = 0; i < 2 * nc && !r->bad; i++) next(r);
}

static void read_number(ol_reader *r, ol_param *p) {
  int nv = (int)next_num(r);
  for (int i = 0; i < nv && !r->bad; i++) {
    double v = next_num(r);
    if (i == 0) p->value = v;
  }
  p->min = next_num(r), p->max = next_num(r), p->step = next_num(r);
  next(r); /* loop index */
  int nc = (int)next_num(r);
  for (int i = 0; i < nc && !r->bad; i++) dtm_ol_choice(p, next_num(r), "");
  int nl = (int)next_num(r);
  for (int i = 0; i < nl && !r->bad; i++) {
    double v = next_num(r);
    const char *label = next(r);
    for (int j = 0; j < p->nchoices; j++)
      if (p->choice[j] == v) copy(p->choice_label[j], sizeof p->choice_label[0], label);
  }
}

static void read_string(ol_reader *r, ol_param *p) {
  int nv = (int)next_num(r);
  for (int i = 0; i < nv && !r->bad; i++) {
    const char *v = next(r);
    if (i == 0) copy(p->svalue, sizeof p->svalue, v);
  }
  copy(p->kind, sizeof p->kind, next(r));
  int nc = (int)next_num(r);
  for (int i = 0; i < nc && !r->bad; i++) dtm_ol_choice(p, 0, next(r));
}

int dtm_ol_decode(const char *msg, size_t len, ol_param *p) {
  ol_reader r = {msg, len, 0, 0};
  const char *version = next(&r);
  if (strcmp(version, "1.3"))
    return DTM_ERR(DTM_ERR_INPUT, "ONELAB: protocol version '%s' (dtmap speaks 1.3)", version);
  const char *type = next(&r);
  int is_string = !strcmp(type, "string");
  if (!is_string && strcmp(type, "number")) return DTM_ERR(DTM_ERR_INPUT, "ONELAB: unknown parameter type '%s'", type);
  init(p, "", "");
  p->is_string = is_string;
  read_common(&r, p);
  if (is_string)
    read_string(&r, p);
  else
    read_number(&r, p);
  return r.bad ? DTM_ERR(DTM_ERR_INPUT, "ONELAB: truncated parameter '%s'", p->name) : DTM_OK;
}

int dtm_ol_set(ol_conn *c, const ol_param *p) {
  char *msg;
  size_t len;
  DTM_CHECK(dtm_ol_encode(p, &msg, &len));
  int r = dtm_ol_send(c, OL_PARAMETER, msg, len);
  free(msg);
  return r;
}

/* Read replies until the one to our query (Gmsh may interleave nothing
 * else on this connection, but skip stray INFO lines to be safe). */
static int await_reply(ol_conn *c, ol_param *p, int *found) {
  for (;;) {
    int type;
    char *body;
    size_t len;
    DTM_CHECK(dtm_ol_recv(c, &type, &body, &len));
    int r = DTM_OK, done = 1;
    if (type == OL_PARAMETER)
      r = dtm_ol_decode(body, len, p), *found = 1;
    else if (type == OL_NOT_FOUND)
      *found = 0;
    else
      done = 0;
    free(body);
    if (r || done) return r;
  }
}

int dtm_ol_get(ol_conn *c, const char *name, int is_string, ol_param *p, int *found) {
  ol_param q;
  if (is_string)
    dtm_ol_string(&q, name, "", "");
  else
    dtm_ol_number(&q, name, 0, "");
  char *msg;
  size_t len;
  DTM_CHECK(dtm_ol_encode(&q, &msg, &len));
  int r = dtm_ol_send(c, OL_QUERY, msg, len);
  free(msg);
  DTM_CHECK(r);
  *found = 0;
  return await_reply(c, p, found);
}

int dtm_ol_define(ol_conn *c, ol_param *p) {
  ol_param s;
  int found = 0;
  DTM_CHECK(dtm_ol_get(c, p->name, p->is_string, &s, &found));
  if (found && p->is_string) copy(p->svalue, sizeof p->svalue, s.svalue);
  if (found && !p->is_string && isfinite(s.value)) p->value = s.value;
  return dtm_ol_set(c, p);
}

int dtm_ol_sync(ol_conn *c) {
  ol_param p;
  int found;
  return dtm_ol_get(c, "General.Version", 1, &p, &found);
}

int dtm_ol_action(ol_conn *c, char *action, size_t n) {
  ol_param p;
  int found = 0;
  char name[200];
  snprintf(name, sizeof name, "%s/Action", c->name);
  DTM_CHECK(dtm_ol_get(c, name, 1, &p, &found));
  snprintf(action, n, "%.60s", found ? p.svalue : "");
  return DTM_OK;
}
