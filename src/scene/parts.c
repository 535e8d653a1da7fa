/* Partitioned files: where part k of a scene's <mesh partitions="P"> (or
 * of a distributed run's output) is. Gmsh, told to write model.msh split
 * into P files (Mesh.PartitionSplitMeshFiles), writes model_1.msh ...
 * model_P.msh; a file name holding "{part}" puts the number there
 * instead. */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "scene-impl.h"

int dtm_scene_part_path(const char *file, int part, char *buf, size_t len) {
  const char *f = file ? file : "", *at = strstr(f, "{part}");
  size_t n = strlen(f);
  int w;
  if (at)
    w = snprintf(buf, len, "%.*s%d%s", (int)(at - f), f, part, at + 6);
  else if (n >= 4 && !strcasecmp(f + n - 4, ".msh"))
    w = snprintf(buf, len, "%.*s_%d%s", (int)(n - 4), f, part, f + n - 4);
  else
    w = snprintf(buf, len, "%s_%d", f, part);
  if (w < 0 || (size_t)w >= len) return DTM_ERR(DTM_ERR_INPUT, "%s: the path of part %d is too long", f, part);
  return DTM_OK;
}
