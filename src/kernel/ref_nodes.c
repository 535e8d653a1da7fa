/* Reference coordinates (u, v, w) of the nodes of every supported type, in
 * Gmsh's node ordering (Gmsh reference manual, "Node ordering"; the edge
 * and face orders are those of Gmsh's MTetrahedron, MHexahedron, MPrism
 * and MPyramid tables, which dtm_elem_topology follows). One table per
 * family: a linear type's corners and a serendipity type's nodes are the
 * first rows of the complete second-order table (Gmsh numbers corners,
 * then mid-edge nodes in the parent's edge order, then quadrilateral face
 * centres in the parent's facet order, then the element centre):
 *   triangle      tri3 < tri6;
 *   quadrangle    quad4 < quad8 < quad9 (8: centre);
 *   tetrahedron   tet4 < tet10;
 *   hexahedron    hex8 < hex20 < hex27 (20..25: centres of the faces
 *                 0-3-2-1, 0-1-5-4, 0-4-7-3, 1-2-6-5, 2-3-7-6, 4-5-6-7;
 *                 26: centre);
 *   prism         prism6 < prism15 < prism18 (15..17: centres of the
 *                 faces 0-1-4-3, 0-3-5-2, 1-2-5-4);
 *   pyramid       pyr5 < pyr13 < pyr14 (13: centre of the base).
 * tests/t105 checks every mid-edge and face node against the parent's
 * topology tables. dtm_ref_node returns pyramid nodes in collapsed rule
 * coordinates (a = u/(1 - w), b = v/(1 - w); the apex at a = b = 0). */
#include <string.h>

#include "kernel-impl.h"

#define H 0.5

static const double line_n[2][3] = {{-1, 0, 0}, {1, 0, 0}};

static const double tri_n[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {H, 0, 0}, {H, H, 0}, {0, H, 0}};

static const double quad_n[9][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, /* corners */
                                    {0, -1, 0},  {1, 0, 0},  {0, 1, 0}, {-1, 0, 0}, /* 0-1 1-2 2-3 3-0 */
                                    {0, 0, 0}};

static const double tet_n[10][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, /* corners */
                                    {H, 0, 0}, {H, H, 0}, {0, H, 0},            /* 0-1 1-2 2-0 */
                                    {0, 0, H}, {0, H, H}, {H, 0, H}};           /* 3-0 3-2 3-1 */

static const double hex_n[27][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1},  {-1, 1, -1}, /* corners */
                                    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},   {-1, 1, 1},
                                    {0, -1, -1},  {-1, 0, -1}, {-1, -1, 0}, /* 0-1 0-3 0-4 */
                                    {1, 0, -1},   {1, -1, 0},               /* 1-2 1-5 */
                                    {0, 1, -1},   {1, 1, 0},                /* 2-3 2-6 */
                                    {-1, 1, 0},                             /* 3-7 */
                                    {0, -1, 1},   {-1, 0, 1},               /* 4-5 4-7 */
                                    {1, 0, 1},                              /* 5-6 */
                                    {0, 1, 1},                              /* 6-7 */
                                    {0, 0, -1},   {0, -1, 0},  {-1, 0, 0},  /* faces */
                                    {1, 0, 0},    {0, 1, 0},   {0, 0, 1},   {0, 0, 0}};

static const double prism_n[18][3] = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}, /* corners */
                                      {0, 0, 1},  {1, 0, 1},  {0, 1, 1},
                                      {H, 0, -1}, {0, H, -1}, {0, 0, 0},  /* 0-1 0-2 0-3 */
                                      {H, H, -1}, {1, 0, 0},              /* 1-2 1-4 */
                                      {0, 1, 0},                          /* 2-5 */
                                      {H, 0, 1},  {0, H, 1},              /* 3-4 3-5 */
                                      {H, H, 1},                          /* 4-5 */
                                      {H, 0, 0},  {0, H, 0},  {H, H, 0}}; /* faces */

static const double pyr_n[14][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0},   {-1, 1, 0}, {0, 0, 1}, /* corners */
                                    {0, -1, 0},  {-1, 0, 0}, {-H, -H, H},                        /* 0-1 0-3 0-4 */
                                    {1, 0, 0},   {H, -H, H},                                     /* 1-2 1-4 */
                                    {0, 1, 0},   {H, H, H},                                      /* 2-3 2-4 */
                                    {-H, H, H},                                                  /* 3-4 */
                                    {0, 0, 0}};                                                  /* base */

const double (*dtm_ref_nodes(int type))[3] {
  switch (dtm_elem_parent(type)) {
  case DTM_LINE2: return line_n;
  case DTM_TRI3: return tri_n;
  case DTM_QUAD4: return quad_n;
  case DTM_TET4: return tet_n;
  case DTM_HEX8: return hex_n;
  case DTM_PRISM6: return prism_n;
  case DTM_PYR5: return pyr_n;
  default: return NULL;
  }
}

void dtm_ref_node_uvw(int type, int a, double p[3]) {
  const double(*t)[3] = dtm_ref_nodes(type);
  p[0] = p[1] = p[2] = 0;
  if (t) memcpy(p, t[a], sizeof(double[3]));
}

void dtm_ref_node(int type, int a, double p[3]) {
  dtm_ref_node_uvw(type, a, p);
  if (dtm_elem_parent(type) != DTM_PYR5 || p[2] >= 1) return;
  p[0] /= 1 - p[2]; /* collapse: only the apex has w = 1 */
  p[1] /= 1 - p[2];
}
