/* Reading a scene file into a libxml2 tree and validating it against the
 * schema embedded at build time (schema/dtmap-scene.xsd). libxml2 reports
 * through callbacks and, by default, prints to stderr; here every report is
 * captured instead and the first error becomes a DTM_ERR_INPUT message
 * "file:line: malformed XML: ..." or "file:line: schema: ...". The file is
 * read into memory by hand so that a missing or unreadable file gets the
 * system's reason, and the network is never used. */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libxml/SAX2.h>
#include <libxml/parser.h>
#include <libxml/xmlerror.h>
#include <libxml/xmlschemas.h>

#include "scene-impl.h"

extern const unsigned char dtm_scene_xsd[];
extern const size_t dtm_scene_xsd_len;

#define SCENE_MAX_BYTES (64 << 20) /* a scene is a few kB; refuse the absurd */

/* The first error libxml2 reported during one stage. */
typedef struct {
  int have;      /* an error was captured */
  int line;      /* its line, 0 if unknown */
  char msg[512]; /* its text, trailing white space removed */
  int top;       /* it is about the order of <dtmap-scene>'s children */
} xml_capture;

/* libxml2's process-wide (per-thread) handlers, saved while we capture. */
typedef struct {
  xmlStructuredErrorFunc serror; /* structured handler */
  void *sctx;                    /* its context */
  xmlGenericErrorFunc gerror;    /* printf-style handler */
  void *gctx;                    /* its context */
} xml_handlers;

#if LIBXML_VERSION >= 21200
typedef const xmlError *xml_error_ptr;
#else
typedef xmlErrorPtr xml_error_ptr;
#endif

static void trim_right(char *s) {
  size_t n = strlen(s);
  while (n > 0 && (s[n - 1] == '\n' || s[n - 1] == ' ' || s[n - 1] == '\r')) s[--n] = '\0';
}

static void on_error(void *data, xml_error_ptr e) {
  xml_capture *c = data;
  if (c->have || !e || e->level < XML_ERR_ERROR) return;
  c->have = 1;
  c->line = e->line;
  if (c->line <= 0 && e->node) c->line = (int)xmlGetLineNo((xmlNode *)e->node);
  snprintf(c->msg, sizeof c->msg, "%s", e->message ? e->message : "unknown error");
  trim_right(c->msg);
  const xmlNode *n = e->domain == XML_FROM_SCHEMASV ? e->node : NULL;
  int root = n && n->type == XML_ELEMENT_NODE && !strcmp((const char *)n->name, "dtmap-scene");
  int child =
      n && n->parent && n->parent->type == XML_ELEMENT_NODE && !strcmp((const char *)n->parent->name, "dtmap-scene");
  c->top = (root || child) && strstr(c->msg, "xpected");
}

static void on_generic(void *ctx, const char *msg, ...) {
  (void)ctx;
  (void)msg;
}

static void handlers_push(xml_handlers *saved, xml_capture *c) {
  saved->serror = xmlStructuredError;
  saved->sctx = xmlStructuredErrorContext;
  saved->gerror = xmlGenericError;
  saved->gctx = xmlGenericErrorContext;
  xmlSetStructuredErrorFunc(c, on_error);
  xmlSetGenericErrorFunc(NULL, on_generic);
}

static void handlers_pop(const xml_handlers *saved) {
  xmlSetStructuredErrorFunc(saved->sctx, saved->serror);
  xmlSetGenericErrorFunc(saved->gctx, saved->gerror);
}

static int report(const char *path, const xml_capture *c, const char *what) {
  char order[512], msg[1100];
  snprintf(msg, sizeof msg, "%s", c->have ? c->msg : "the document was rejected");
  if (c->top && !dtm_scene_child_order(order, sizeof order))
    snprintf(msg + strlen(msg), sizeof msg - strlen(msg), " (<dtmap-scene> holds, in this order: %s)", order);
  if (c->line > 0) return DTM_ERR(DTM_ERR_INPUT, "%s:%d: %s: %s", path, c->line, what, msg);
  return DTM_ERR(DTM_ERR_INPUT, "%s: %s: %s", path, what, msg);
}

static int read_fail(const char *path, FILE *f, int err, char *buf) {
  free(buf);
  if (f) fclose(f);
  return DTM_ERR(DTM_ERR_INPUT, "%s: cannot read scene file: %s", path, strerror(err));
}

/* The whole file into *buf (malloc'd, caller frees) of *len bytes. */
static int read_all(const char *path, char **buf, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f) return read_fail(path, NULL, errno, NULL);
  size_t cap = 4096, n = 0, got;
  char *b = malloc(cap);
  if (!b) return read_fail(path, f, ENOMEM, NULL);
  while ((got = fread(b + n, 1, cap - n, f)) > 0) {
    n += got;
    if (n > SCENE_MAX_BYTES) return read_fail(path, f, EFBIG, b);
    if (n < cap) continue;
    char *bigger = realloc(b, cap *= 2);
    if (!bigger) return read_fail(path, f, ENOMEM, b);
    b = bigger;
  }
  if (ferror(f)) return read_fail(path, f, errno ? errno : EIO, b);
  fclose(f);
  *buf = b;
  *len = n;
  return DTM_OK;
}

/* libxml2 gives an element the line where its start tag ends; a multi-line
 * <material .../> should be reported where it starts. Attribute values
 * cannot hold '<', so the start is the last '<' before the parser's cursor. */
static void fix_start_line(xmlParserCtxt *ctxt) {
  xmlNode *n = ctxt->node;
  const xmlParserInput *in = ctxt->input;
  if (!n || !in || !in->base || !in->cur || in->line <= 0 || in->line >= 65535) return;
  int newlines = 0;
  for (const xmlChar *p = in->cur; p > in->base;) {
    if (*--p == '<') {
      n->line = (unsigned short)(in->line - newlines);
      return;
    }
    newlines += *p == '\n';
  }
}

static void on_start_element(void *ctx, const xmlChar *name, const xmlChar *prefix, const xmlChar *uri, int nns,
                             const xmlChar **ns, int nattr, int ndefaulted, const xmlChar **attr) {
  xmlSAX2StartElementNs(ctx, name, prefix, uri, nns, ns, nattr, ndefaulted, attr);
  fix_start_line(ctx);
}

static int parse(const char *path, const char *buf, size_t len, xmlDoc **doc) {
  xml_capture c = {0};
  xml_handlers saved;
  handlers_push(&saved, &c);
  xmlParserCtxt *ctxt = xmlNewParserCtxt();
  if (ctxt) ctxt->sax->startElementNs = on_start_element;
  *doc = ctxt ? xmlCtxtReadMemory(ctxt, buf, (int)len, path, NULL,
                                  XML_PARSE_NONET | XML_PARSE_BIG_LINES | XML_PARSE_NOCDATA)
              : NULL;
  xmlFreeParserCtxt(ctxt);
  handlers_pop(&saved);
  if (!ctxt) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (*doc && !c.have) return DTM_OK;
  xmlFreeDoc(*doc);
  *doc = NULL;
  return report(path, &c, "malformed XML");
}

static xmlSchema *load_schema(xml_capture *c) {
  xmlSchemaParserCtxt *pc = xmlSchemaNewMemParserCtxt((const char *)dtm_scene_xsd, (int)dtm_scene_xsd_len);
  if (!pc) return NULL;
  xmlSchemaSetParserStructuredErrors(pc, on_error, c);
  xmlSchema *schema = xmlSchemaParse(pc);
  xmlSchemaFreeParserCtxt(pc);
  return schema;
}

static int run_validation(xmlSchema *schema, xmlDoc *doc, xml_capture *c) {
  xmlSchemaValidCtxt *vc = xmlSchemaNewValidCtxt(schema);
  if (!vc) return -1;
  xmlSchemaSetValidStructuredErrors(vc, on_error, c);
  int rc = xmlSchemaValidateDoc(vc, doc);
  xmlSchemaFreeValidCtxt(vc);
  return rc;
}

static int validate(const char *path, xmlDoc *doc) {
  xml_capture c = {0};
  xml_handlers saved;
  handlers_push(&saved, &c);
  xmlSchema *schema = load_schema(&c);
  int rc = schema ? run_validation(schema, doc, &c) : -1;
  xmlSchemaFree(schema);
  handlers_pop(&saved);
  if (!schema)
    return DTM_ERR(DTM_ERR_INTERNAL, "the embedded scene schema does not load: %s", c.have ? c.msg : "unknown error");
  if (rc < 0 && !c.have) return DTM_ERR(DTM_ERR_INTERNAL, "%s: schema validation failed internally", path);
  return rc == 0 ? DTM_OK : report(path, &c, "schema");
}

int dtm_scene_xml_read(const char *path, xmlDoc **doc) {
  char *buf = NULL;
  size_t len = 0;
  *doc = NULL;
  DTM_CHECK(read_all(path, &buf, &len));
  int rc = dtm_scene_xml_parse(path, buf, len, doc);
  free(buf);
  return rc;
}

int dtm_scene_xml_parse(const char *name, const char *buf, size_t len, xmlDoc **doc) {
  *doc = NULL;
  if (len > SCENE_MAX_BYTES || len > (size_t)INT_MAX)
    return DTM_ERR(DTM_ERR_INPUT, "%s: the scene is %zu bytes; a scene is a few kB", name, len);
  xmlInitParser();
  int rc = parse(name, buf, len, doc);
  if (!rc) rc = validate(name, *doc);
  if (rc) {
    xmlFreeDoc(*doc);
    *doc = NULL;
    return dtm_error_trace(rc, __FILE__, __LINE__, __func__);
  }
  return DTM_OK;
}
