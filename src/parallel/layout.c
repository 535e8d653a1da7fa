/* How the parts of a distributed run meet. A node on the interface of
 * several parts is in each of their files under the same Gmsh tag; the
 * lowest rank holding it owns it. Owners are found with a PetscSF whose
 * roots are the tags (spread evenly over the ranks, a directory) and whose
 * leaves are each rank's nodes: a min-reduction of the ranks to the roots,
 * then a broadcast back. Owned nodes are numbered rank by rank (the
 * ownership ranges of a PETSc Vec), the owners' numbers go to the other
 * holders the same way, and the part's nodes are renumbered owned first,
 * ghosts last, so that a ghosted Vec's local form is indexed like the
 * mesh's nodes. The same directory, over element tags, finds elements that
 * two part files both hold, and a forward scatter of the owners'
 * coordinates finds shared nodes that are not at the same place: both mean
 * that the part files do not come from one partitioning of one mesh. */
#include <petscsf.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parallel-impl.h"

/* The file of part k (1 ...) for messages. */
static const char *part_file(const dtm_par *p, int k, char *buf, size_t len) {
  if (p->scene->partitions && dtm_scene_part_path(p->scene->mesh, k, buf, len) == DTM_OK) return buf;
  dtm_error_clear();
  snprintf(buf, len, "part %d", k);
  return buf;
}

/* The tag directory: roots 0 .. maxtag-1 over the ranks, leaf i at tags[i]-1. */
static int tag_sf(const dtm_par *p, const size_t *tags, size_t n, PetscSF *sf) {
  unsigned long long mx = 0, all = 0;
  for (size_t i = 0; i < n; i++) mx = tags[i] > mx ? tags[i] : mx;
  MPI_Allreduce(&mx, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, p->comm);
  if (all >= (unsigned long long)PETSC_MAX_INT)
    return DTM_ERR(DTM_ERR_INPUT, "Gmsh tags up to %llu need PETSc with 64-bit indices (libpetsc64-real-dev)", all);
  PetscInt *g = malloc((n + 1) * sizeof *g);
  if (!g) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < n; i++) g[i] = (PetscInt)tags[i] - 1;
  PetscLayout lay;
  PAR_PETSC(PetscLayoutCreate(p->comm, &lay));
  PAR_PETSC(PetscLayoutSetSize(lay, (PetscInt)all));
  PAR_PETSC(PetscLayoutSetUp(lay));
  PAR_PETSC(PetscSFCreate(p->comm, sf));
  PAR_PETSC(PetscSFSetGraphLayout(*sf, lay, (PetscInt)n, NULL, PETSC_COPY_VALUES, g));
  PAR_PETSC(PetscSFSetUp(*sf));
  PAR_PETSC(PetscLayoutDestroy(&lay));
  free(g);
  return DTM_OK;
}

/* out[i] = op over the ranks holding leaf i's tag of their in[i]; init is
 * op's neutral value. */
static int through_roots(PetscSF sf, const PetscInt *in, PetscInt *out, MPI_Op op, PetscInt init) {
  PetscInt nroots;
  PAR_PETSC(PetscSFGetGraph(sf, &nroots, NULL, NULL, NULL));
  PetscInt *root = malloc(((size_t)nroots + 1) * sizeof *root);
  if (!root) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (PetscInt i = 0; i < nroots; i++) root[i] = init;
  PAR_PETSC(PetscSFReduceBegin(sf, MPIU_INT, in, root, op));
  PAR_PETSC(PetscSFReduceEnd(sf, MPIU_INT, in, root, op));
  PAR_PETSC(PetscSFBcastBegin(sf, MPIU_INT, root, out, MPI_REPLACE));
  PAR_PETSC(PetscSFBcastEnd(sf, MPIU_INT, root, out, MPI_REPLACE));
  free(root);
  return DTM_OK;
}

/* Owner (lowest rank holding it) and global number of every node. */
static int owners_and_numbers(dtm_par *p, PetscSF sf, size_t n, PetscInt *owner, PetscInt *gnum) {
  for (size_t i = 0; i < n; i++) gnum[i] = p->rank;
  DTM_CHECK(through_roots(sf, gnum, owner, MPI_MIN, PETSC_MAX_INT));
  PetscInt mine = 0, first = 0;
  for (size_t i = 0; i < n; i++) mine += owner[i] == p->rank;
  MPI_Exscan(&mine, &first, 1, MPIU_INT, MPI_SUM, p->comm);
  p->first = p->rank ? first : 0;
  p->nowned = (size_t)mine;
  PetscInt *own = malloc((n + 1) * sizeof *own), k = p->first;
  if (!own) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t i = 0; i < n; i++) own[i] = owner[i] == p->rank ? k++ : -1;
  int r = through_roots(sf, own, gnum, MPI_MAX, -1);
  free(own);
  return r;
}

/* Elements that another part file holds too. */
static int check_overlap(dtm_par *p) {
  const dtm_mesh *m = p->mesh;
  size_t n = dtm_mesh_nelements(m), i = 0;
  size_t *tags = malloc((n + 1) * sizeof *tags);
  PetscInt *in = malloc((n + 1) * sizeof *in), *lo = malloc((n + 1) * sizeof *lo), *hi = malloc((n + 1) * sizeof *hi);
  int r = dtm_par_agree(p, tags && in && lo && hi ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
  for (int b = 0; b < m->nblocks && r == DTM_OK; b++)
    for (size_t e = 0; e < m->blocks[b].n; e++) tags[i] = m->blocks[b].tags[e], in[i++] = p->rank;
  PetscSF sf = NULL;
  if (r == DTM_OK) r = tag_sf(p, tags, n, &sf);
  if (r == DTM_OK) r = through_roots(sf, in, lo, MPI_MIN, PETSC_MAX_INT);
  if (r == DTM_OK) r = through_roots(sf, in, hi, MPI_MAX, -1);
  for (i = 0; i < n && r == DTM_OK; i++) {
    if (lo[i] == hi[i]) continue;
    char other[4096];
    int k = (int)(lo[i] == p->rank ? hi[i] : lo[i]) + 1;
    r = DTM_ERR(DTM_ERR_INPUT,
                "%s: element %zu is also in %s: the part files overlap (they come from different "
                "partitionings or meshes)",
                p->part_path, tags[i], part_file(p, k, other, sizeof other));
  }
  PetscSFDestroy(&sf);
  free(tags), free(in), free(lo), free(hi);
  return r;
}

static void permute_nodes(dtm_mesh *m, const size_t *newi, size_t *tags, double *xyz) {
  for (size_t i = 0; i < m->nnodes; i++) {
    tags[newi[i]] = m->node_tags[i];
    memcpy(xyz + 3 * newi[i], m->xyz + 3 * i, 3 * sizeof *xyz);
  }
  for (int b = 0; b < m->nblocks; b++)
    for (size_t k = 0; k < m->blocks[b].n * (size_t)m->blocks[b].nn; k++)
      m->blocks[b].conn[k] = newi[m->blocks[b].conn[k]];
  free(m->node_tags), free(m->xyz);
  m->node_tags = tags, m->xyz = xyz;
}

/* Owned nodes first (in their order), then the ghosts; p->ghosts and
 * ghost_owner[] (ranks) in the new order. */
static int renumber(dtm_par *p, const PetscInt *owner, const PetscInt *gnum, PetscInt *ghost_owner) {
  dtm_mesh *m = p->mesh;
  size_t n = m->nnodes, k = 0, g = p->nowned;
  size_t *newi = malloc((n + 1) * sizeof *newi), *tags = malloc((n + 1) * sizeof *tags);
  double *xyz = malloc((3 * n + 1) * sizeof *xyz);
  p->nghost = n - p->nowned;
  p->ghosts = malloc((p->nghost + 1) * sizeof *p->ghosts);
  if (!newi || !tags || !xyz || !p->ghosts) {
    free(newi), free(tags), free(xyz);
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  for (size_t i = 0; i < n; i++) {
    if (owner[i] == p->rank)
      newi[i] = k++;
    else
      ghost_owner[g - p->nowned] = owner[i], p->ghosts[g - p->nowned] = gnum[i], newi[i] = g++;
  }
  permute_nodes(m, newi, tags, xyz);
  free(newi);
  return DTM_OK;
}

/* Shared nodes must be where their owner has them. */
static int check_positions(dtm_par *p, const PetscInt *ghost_owner) {
  const dtm_mesh *m = p->mesh;
  Vec v;
  double *x = malloc((3 * m->nnodes + 1) * sizeof *x);
  int r = dtm_par_agree(p, x ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
  if (r) return free(x), r;
  memcpy(x, m->xyz, 3 * m->nnodes * sizeof *x);
  r = dtm_par_vec(p, 3, &v);
  if (r == DTM_OK) r = dtm_par_combine(v, x, 3 * m->nnodes, INSERT_VALUES), VecDestroy(&v);
  for (size_t i = p->nowned; i < m->nnodes && r == DTM_OK; i++) {
    const double *a = m->xyz + 3 * i, *b = x + 3 * i;
    char other[4096];
    if (a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) continue;
    r = DTM_ERR(DTM_ERR_INPUT,
                "%s: node %zu is at (%.17g, %.17g, %.17g) here but at (%.17g, %.17g, %.17g) in %s, which "
                "shares it: the part files come from different meshes",
                p->part_path, m->node_tags[i], a[0], a[1], a[2], b[0], b[1], b[2],
                part_file(p, (int)ghost_owner[i - p->nowned] + 1, other, sizeof other));
  }
  free(x);
  return r;
}

/* Every part must name the same physical groups (mass scaling sums by group). */
static int check_groups(dtm_par *p) {
  uint64_t h = 1469598103934665603ull, lo, hi;
  for (int g = 0; g < p->mesh->ngroups; g++) {
    const dtm_group *gr = &p->mesh->groups[g];
    h = (h ^ (uint64_t)(gr->dim * 1000003 + gr->tag)) * 1099511628211ull;
    for (const char *c = gr->name; *c; c++) h = (h ^ (unsigned char)*c) * 1099511628211ull;
  }
  MPI_Allreduce(&h, &lo, 1, MPI_UINT64_T, MPI_MIN, p->comm);
  MPI_Allreduce(&h, &hi, 1, MPI_UINT64_T, MPI_MAX, p->comm);
  if (lo == hi) return DTM_OK;
  return DTM_ERR(DTM_ERR_INPUT, "%s: the part files name different physical groups (they come from different meshes)",
                 p->part_path);
}

static int node_layout(dtm_par *p, PetscInt *owner, PetscInt *gnum, PetscInt *ghost_owner) {
  PetscSF sf = NULL;
  int r = tag_sf(p, p->mesh->node_tags, p->mesh->nnodes, &sf);
  if (r == DTM_OK) r = owners_and_numbers(p, sf, p->mesh->nnodes, owner, gnum);
  PetscSFDestroy(&sf);
  if (r == DTM_OK) r = renumber(p, owner, gnum, ghost_owner);
  return r;
}

int dtm_par_layout(dtm_par *p) {
  size_t n = p->mesh->nnodes + 1;
  PetscInt *owner = malloc(n * sizeof *owner), *gnum = malloc(n * sizeof *gnum), *gown = malloc(n * sizeof *gown);
  int r = dtm_par_agree(p, owner && gnum && gown ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"));
  if (r == DTM_OK) r = dtm_par_agree(p, node_layout(p, owner, gnum, gown));
  if (r == DTM_OK) r = dtm_par_agree(p, check_positions(p, gown));
  if (r == DTM_OK) r = check_overlap(p);
  r = dtm_par_agree(p, r);
  if (r == DTM_OK) r = dtm_par_agree(p, check_groups(p));
  if (r == DTM_OK) r = dtm_par_agree(p, dtm_par_vec(p, 1, &p->node));
  free(owner), free(gnum), free(gown);
  return r;
}

void dtm_par_layout_destroy(dtm_par *p) {
  if (p->node) VecDestroy(&p->node);
  free(p->ghosts);
  p->ghosts = NULL;
}

int dtm_par_vec(const dtm_par *p, int bs, Vec *v) {
  PAR_PETSC(
      VecCreateGhostBlock(p->comm, bs, bs * (PetscInt)p->nowned, PETSC_DECIDE, (PetscInt)p->nghost, p->ghosts, v));
  return DTM_OK;
}

int dtm_par_combine(Vec g, double *v, size_t n, InsertMode mode) {
  Vec l;
  PetscScalar *a;
  PAR_PETSC(VecGhostGetLocalForm(g, &l));
  PAR_PETSC(VecGetArray(l, &a));
  memcpy(a, v, n * sizeof *a);
  PAR_PETSC(VecRestoreArray(l, &a));
  if (mode != INSERT_VALUES) {
    PAR_PETSC(VecGhostUpdateBegin(g, mode, SCATTER_REVERSE));
    PAR_PETSC(VecGhostUpdateEnd(g, mode, SCATTER_REVERSE));
  }
  PAR_PETSC(VecGhostUpdateBegin(g, INSERT_VALUES, SCATTER_FORWARD));
  PAR_PETSC(VecGhostUpdateEnd(g, INSERT_VALUES, SCATTER_FORWARD));
  PAR_PETSC(VecGetArray(l, &a));
  memcpy(v, a, n * sizeof *a);
  PAR_PETSC(VecRestoreArray(l, &a));
  PAR_PETSC(VecGhostRestoreLocalForm(g, &l));
  return DTM_OK;
}
