/* The post-processing sections of a Gmsh .msh file ($ElementData and
 * $NodeData, format 4.1), written directly from dtmap's arrays instead of
 * creating a Gmsh view per array, filling it, writing it and removing it
 * again (which costs a heap allocation per value and a pass over the model
 * per view). The layout is the one Gmsh's own view writer uses
 * (Post/PViewDataGModelIO.cpp in its sources) and reads back:
 *   $ElementData / 1 string tag (the name) / 1 real tag (time 0) /
 *   3 integer tags (time step 0, 1 component, number of records; a 4th,
 *   the part number, for a part of a partitioned result) /
 *   records / $EndElementData,
 * a record being "tag value" (ASCII, here %.17g so that the value reads back
 * bit for bit) or, in a binary file, a 4-byte int tag and an 8-byte double
 * in the machine's byte order, followed by a newline after the last record.
 * Gmsh reads the tag as an int, so tags above INT_MAX cannot be written. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "dtmap/gmsh.h"
#include "gmsh-impl.h"

#define RECORDS_PER_WRITE 4096 /* binary records packed per fwrite */

int dtm_msh_header(FILE *f, int binary) {
  int one = 1;
  fprintf(f, "$MeshFormat\n4.1 %d %d\n", binary ? 1 : 0, (int)sizeof(double));
  if (binary) fwrite(&one, sizeof one, 1, f), fputc('\n', f);
  fprintf(f, "$EndMeshFormat\n");
  return ferror(f) ? -1 : 0;
}

static double value(const dtm_view *v, size_t i) { return v->ivalues ? (double)v->ivalues[i] : v->values[i]; }
static int kept(const dtm_view *v, size_t i) { return !v->finite_only || isfinite(value(v, i)); }

size_t dtm_msh_view_records(const dtm_view *v) {
  size_t n = 0;
  for (size_t i = 0; i < v->n; i++) n += kept(v, i);
  return n;
}

/* The head of a section; a part of a partitioned result adds its part
 * number as a fourth integer tag (Gmsh merges the parts' views by it). */
static void section_head(FILE *f, const dtm_view *v, const char *kind, int partition) {
  fprintf(f, "$%s\n1\n\"%s\"\n1\n0\n%d\n0\n1\n%zu\n", kind, v->name, partition ? 4 : 3, dtm_msh_view_records(v));
  if (partition) fprintf(f, "%d\n", partition);
}

static void records_binary(FILE *f, const dtm_view *v) {
  char buf[RECORDS_PER_WRITE * 12];
  size_t k = 0;
  for (size_t i = 0; i < v->n; i++) {
    if (!kept(v, i)) continue;
    int tag = (int)v->tags[i];
    double x = value(v, i);
    memcpy(buf + 12 * k, &tag, 4);
    memcpy(buf + 12 * k + 4, &x, 8);
    if (++k == RECORDS_PER_WRITE) fwrite(buf, 12, k, f), k = 0;
  }
  fwrite(buf, 12, k, f);
  fputc('\n', f);
}

static void records_ascii(FILE *f, const dtm_view *v) {
  for (size_t i = 0; i < v->n; i++)
    if (kept(v, i)) fprintf(f, "%zu %.17g\n", v->tags[i], value(v, i));
}

static int check_tags(const dtm_view *v) {
  for (size_t i = 0; i < v->n; i++)
    if (v->tags[i] > INT_MAX)
      return DTM_ERR(DTM_ERR_INPUT, "view '%s': %s tag %zu is above %d, which Gmsh's view format cannot hold", v->name,
                     v->node_data ? "node" : "element", v->tags[i], INT_MAX);
  return DTM_OK;
}

int dtm_msh_write_view(FILE *f, const dtm_view *v, int binary, int partition) {
  const char *kind = v->node_data ? "NodeData" : "ElementData";
  DTM_CHECK(check_tags(v));
  section_head(f, v, kind, partition);
  if (binary)
    records_binary(f, v);
  else
    records_ascii(f, v);
  fprintf(f, "$End%s\n", kind);
  return ferror(f) ? DTM_ERR(DTM_ERR_INPUT, "cannot write view '%s'", v->name) : DTM_OK;
}
