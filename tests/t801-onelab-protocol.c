/* The ONELAB client's text forms, without Gmsh: a number and a string
 * parameter survive encode -> decode with every field dtmap uses; a reply
 * laid out field by field as ONELAB 1.3 sends it (with attributes, clients
 * and value labels dtmap skips) decodes to the right value and choices; a
 * truncated or foreign-version message is refused; and the views-only copy
 * of a result keeps $MeshFormat and the data sections and drops the mesh. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "onelab-impl.h"
#include "testutil.h"

static void test_number_round_trip(void **state) {
  (void)state;
  ol_param p, q;
  dtm_ol_number(&p, "dtmap/2Time/0safety", 0.123456789012345678, "safety factor");
  dtm_ol_attr(&p, "Units", "s");
  dtm_ol_choice(&p, 0, "custom"), dtm_ol_choice(&p, 1, "steel");
  p.read_only = 1;
  char *msg;
  size_t len;
  assert_int_equal(dtm_ol_encode(&p, &msg, &len), 0);
  assert_int_equal(dtm_ol_decode(msg, len, &q), 0);
  free(msg);
  assert_string_equal(q.name, p.name);
  assert_string_equal(q.label, p.label);
  assert_int_equal(q.read_only, 1);
  /* 16 significant digits are written, as ONELAB's own writer does */
  assert_true(q.value == 0.1234567890123457);
  assert_int_equal(q.nattrs, 1);
  assert_string_equal(q.attr_val[0], "s");
  assert_int_equal(q.nchoices, 2);
  assert_string_equal(q.choice_label[1], "steel");
}

static void test_string_round_trip(void **state) {
  (void)state;
  ol_param p, q;
  dtm_ol_string(&p, "dtmap/5Scene/1file", "/tmp/a b.xml", "scene file");
  snprintf(p.kind, sizeof p.kind, "file");
  char *msg;
  size_t len;
  assert_int_equal(dtm_ol_encode(&p, &msg, &len), 0);
  assert_int_equal(dtm_ol_decode(msg, len, &q), 0);
  free(msg);
  assert_true(q.is_string);
  assert_string_equal(q.svalue, "/tmp/a b.xml");
  assert_string_equal(q.kind, "file");
}

/* A reply as Gmsh's server writes it: one attribute, two clients, two
 * values (the first counts), choices 0 and 1 with one label. */
static void test_decode_server_reply(void **state) {
  (void)state;
  static const char msg[] = "1.3\0number\0dtmap/x\0label\0help\0"
                            "31\0"
                            "1\0"
                            "0\0"
                            "1\0Highlight\0Pink\0"
                            "2\0Gmsh\0"
                            "1\0dtmap\0"
                            "0\0"
                            "2\0"
                            "2.5\0"
                            "7\0"
                            "-1e+200\0"
                            "1e+200\0"
                            "0\0"
                            "-1\0"
                            "2\0"
                            "0\0"
                            "1\0"
                            "1\0"
                            "1\0on\0";
  ol_param p;
  assert_int_equal(dtm_ol_decode(msg, sizeof msg - 1, &p), 0);
  assert_true(p.value == 2.5);
  assert_int_equal(p.nchoices, 2);
  assert_string_equal(p.choice_label[1], "on");
  assert_string_equal(p.attr_key[0], "Highlight");
  assert_int_not_equal(dtm_ol_decode(msg, 40, &p), 0);                /* truncated */
  assert_int_not_equal(dtm_ol_decode("1.2\0number\0x\0", 13, &p), 0); /* another version */
}

static void test_views_only(void **state) {
  (void)state;
  char in[600], out[600], opt[640], *text = NULL;
  snprintf(in, sizeof in, "%s/r.msh", tu_tmpdir());
  snprintf(out, sizeof out, "%s/v.msh", tu_tmpdir());
  tu_write(in, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 0\n$EndEntities\n$Nodes\n0 0 0 0\n$EndNodes\n"
               "$ElementData\n1\n\"dt\"\n1\n0\n3\n0\n1\n1\n7 2.5\n$EndElementData\n"
               "$NodeData\n1\n\"size suggestion\"\n1\n0\n3\n0\n1\n1\n3 0.1\n$EndNodeData\n");
  snprintf(opt, sizeof opt, "%s.opt", in);
  tu_write(opt, "View[0].Visible = 1;\n");
  assert_int_equal(dtm_ol_views_only(in, out), 0);
  char *o = NULL;
  assert_int_equal(tu_run(&o, "cat %s", out), 0);
  text = o;
  assert_non_null(strstr(text, "$MeshFormat"));
  assert_non_null(strstr(text, "7 2.5\n$EndElementData"));
  assert_non_null(strstr(text, "$EndNodeData"));
  assert_null(strstr(text, "$Nodes"));
  assert_null(strstr(text, "$Entities"));
  free(o);
  snprintf(opt, sizeof opt, "%s.opt", out);
  assert_true(tu_exists(opt));
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_number_round_trip),
      cmocka_unit_test(test_string_round_trip),
      cmocka_unit_test(test_decode_server_reply),
      cmocka_unit_test(test_views_only),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
