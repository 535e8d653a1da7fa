/* The prediction of one plane wave (dtm_measures_phase_along), the figure
 * `dtmap verify --accuracy` checks by simulation (src/study/wave.c): the
 * fully discrete error of one branch along one direction at one frequency
 * and step, from the same model the measures use for each element type and
 * material (dtm_acc_table):
 * - the mesh's own shapes (tri3, quad4, hex8): the wave's Rayleigh quotient
 *   over the summed plane-wave matrices (dtm_dispersion_element) of one
 *   material's elements;
 * - a structured mesh: a lattice's Bloch branch whose eigenvector overlaps
 *   most with the polarisation, exact; a grid of one node class summed as
 *   own shapes (its plane wave is a Bloch mode of every cell);
 * - the measured table (unstructured tet4, tet10): its direction class
 *   nearest the wave's, at the root mean square of the elements' mean
 *   edges (the table's own abscissa);
 * - the regular lattice (bar, tri6): the polarised Bloch branch at each
 *   element's lattice spacing;
 * the others' errors averaged with the element masses as weights (a plane
 * wave's frequency shift is the energy-weighted mean of the local ones to
 * first order). The worst is the worst single element's own error. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "accuracy-impl.h"
#include "dispersion-impl.h"
#include "dtmap/cost.h"
#include "dtmap/kernel.h"
#include "dtmap/topology.h"

#define PI 3.14159265358979323846

/* The model of one element type and material. */
typedef struct {
  int type, mat;        /* the pair */
  int have;             /* 1: a model applies */
  dtm_dispersion t;     /* its table */
  dtm_disp_lattice *L;  /* a structured mesh's patch (DTM_LATTICE_MESH, a lattice), else NULL */
  double kh, err;       /* its last Bloch evaluation (the elements of a lattice share their spacing) */
  double w, wh2;        /* the measured table: the elements' masses and mass-weighted squared mean edges */
  size_t count;         /* the measured table: its elements */
  dtm_elastic_moduli m; /* the measured table: the material's moduli */
} along_model;

typedef struct {
  int n;              /* models in use */
  along_model *m[64]; /* owned */
} model_set;

static void models_free(model_set *s) {
  for (int i = 0; i < s->n; i++) free(s->m[i]->L), free(s->m[i]);
}

/* The model of type and material mat (r its mu / M), built on first use. */
static int model_get(model_set *s, const dtm_mesh *mesh, int type, int mat, double r, along_model **out) {
  for (int i = 0; i < s->n; i++)
    if (s->m[i]->type == type && s->m[i]->mat == mat) return *out = s->m[i], DTM_OK;
  if (s->n == 64) return DTM_ERR(DTM_ERR_INPUT, "more than 64 element type and material pairs");
  along_model *md = calloc(1, sizeof *md);
  if (!md) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  md->type = type, md->mat = mat, md->kh = NAN;
  s->m[s->n++] = md;
  DTM_CHECK(dtm_acc_table(mesh, type, mat, r, &md->t, &md->have));
  if (md->have && md->t.shape == DTM_LATTICE_MESH) { /* a lattice's patch; a grid's elements are summed as own shapes */
    dtm_disp_structure st;
    DTM_CHECK(dtm_disp_structure_find(mesh, type, mat, &st));
    md->L = st.lattice;
  }
  *out = md;
  return DTM_OK;
}

/* The semi-discrete error of a lattice model along n (the branch along pol,
 * else P or the worse S branch); NaN when it fails. */
static double lattice_along(along_model *md, int shape, double r, double kh, const double n[3], const double *pol,
                            int mode) {
  double err[2] = {NAN, NAN};
  int rc;
  if (shape == DTM_LATTICE_MESH && md->L)
    rc = pol ? dtm_disp_lattice_polarised(md->L, r, kh, n, pol, mode, &err[mode])
             : dtm_disp_lattice_space(md->L, r, kh, n, err);
  else
    rc = pol && r > 0 ? dtm_dispersion_polarised(md->type, shape, r, kh, n, pol, mode, &err[mode])
                      : dtm_dispersion_space(md->type, shape, r, kh, n, err);
  if (rc) dtm_error_clear();
  return rc ? NAN : err[mode];
}

/* One element's fully discrete error of branch mode along n at frequency f
 * and step dt, at spacing h of its model; NaN when unresolved. */
static double element_along(along_model *md, const dtm_elastic_moduli *m, double h, double f, double dt,
                            const double n[3], const double *pol, int mode) {
  double c = mode ? sqrt(m->mu / m->rho) : m->cd, kh = 2 * PI * f * h / c, s, r = m->mu / m->modulus;
  if (m->form == DTM_FORM_BAR) r = 0;
  if (!(kh <= PI)) return NAN;
  if (md->t.shape == DTM_LATTICE_MEASURED)
    s = dtm_dispersion_at(&md->t, mode, dtm_disp_measured_class(n), kh);
  else if (md->t.shape == DTM_LATTICE_MESH && kh == md->kh)
    s = md->err;
  else
    s = lattice_along(md, md->t.shape == DTM_LATTICE_MESH ? DTM_LATTICE_MESH : DTM_LATTICE_REGULAR, r, kh, n, pol,
                      mode);
  md->kh = kh, md->err = s;
  return dtm_dispersion_time(s, (1 + s) * PI * f * dt);
}

/* The plane wave's own-shape sums: dynamic matrix and mass. */
typedef struct {
  double D[9], mass; /* sum of the elements' dynamic matrices (N/m) and masses (kg) */
  int d;             /* their dimension */
} wave_sum;

/* The fully discrete error of branch mode from a dynamic matrix D over
 * mass, along pol (else n for P, the worse transverse branch for S). */
static double own_error(int d, const double *D, double mass, const dtm_elastic_moduli *m, double f, double dt,
                        const double n[3], const double *pol, int mode) {
  double c = mode ? sqrt(m->mu / m->rho) : m->cd, k = 2 * PI * f / c, A[9], w[3], e[3] = {0};
  for (int i = 0; i < 9; i++) A[i] = D[i] / mass;
  dtm_dispersion_branches(d, A, pol ? pol : n, w);
  for (int i = 0; i < d; i++) e[i] = sqrt(fmax(w[i], 0)) / (c * k) - 1;
  double space = pol || !mode ? e[0] : d == 3 && fabs(e[2]) > fabs(e[1]) ? e[2] : e[1];
  return dtm_dispersion_time(space, (1 + space) * PI * f * dt);
}

/* One own-shape element into the sums; its own error into *err (NaN when
 * unresolved: fewer than 2 lattice cells per wavelength). */
static void own_along(const dtm_block *bl, const double *x, double meas, double h, const dtm_elastic_moduli *m,
                      double f, double dt, const double n[3], const double *pol, int mode, wave_sum *ws, double *err) {
  double D[9], c = mode ? sqrt(m->mu / m->rho) : m->cd, k = 2 * PI * f / c;
  double kv[3] = {k * n[0], k * n[1], k * n[2]};
  *err = NAN;
  if (!(k * h <= PI)) return;
  if (dtm_dispersion_element(bl->type, x, m->modulus - 2 * m->mu, m->mu, kv, D)) return;
  ws->d = bl->dim, ws->mass += m->rho * meas;
  for (int i = 0; i < 9; i++) ws->D[i] += D[i];
  *err = own_error(bl->dim, D, m->rho * meas, m, f, dt, n, pol, mode);
}

/* What one call accumulates. */
typedef struct {
  double f, dt;            /* frequency (Hz) and step (s) */
  const double *n, *pol;   /* direction and polarisation (NULL: by branch) */
  int mode, mat;           /* branch; material (-1: all) */
  double wsum, sum;        /* mass-weighted sum of the errors */
  wave_sum ws;             /* the own-shape sums */
  dtm_elastic_moduli mown; /* the moduli of the own-shape elements */
} along_run;

/* Element e of block bl into the run. */
static void element_into(const dtm_mesh *mesh, const dtm_block *bl, size_t e, along_model *md,
                         const dtm_elastic_moduli *m, along_run *r, dtm_phase_along *out) {
  double x[3 * DTM_MAX_NODES], err;
  dtm_mesh_gather_one(mesh, bl, e, x);
  double meas = fabs(dtm_elem_measure(bl->type, x)), w = m->rho * meas;
  double h = dtm_acc_spacing(&md->t, bl->dim, meas, dtm_elem_mean_edge(bl->type, x));
  int own = md->t.shape == DTM_LATTICE_OWN || (md->t.shape == DTM_LATTICE_MESH && !md->L);
  out->speed = r->mode ? sqrt(m->mu / m->rho) : m->cd, out->model = md->t.shape;
  if (own)
    own_along(bl, x, meas, h, m, r->f, r->dt, r->n, r->pol, r->mode, &r->ws, &err), r->mown = *m;
  else
    err = element_along(md, m, h, r->f, r->dt, r->n, r->pol, r->mode);
  if (md->t.shape == DTM_LATTICE_MEASURED) { /* the mesh's mean edge, as the table was measured: below */
    md->w += w, md->wh2 += w * h * h, md->m = *m, md->count++;
    if (fabs(err) > fabs(out->worst)) out->worst = err; /* NaN: this element alone past 2 per wavelength */
    return;
  }
  if (isnan(err)) {
    out->unresolved++;
    return;
  }
  out->elements++;
  if (!own || r->mat < 0) r->wsum += w, r->sum += w * err; /* one material's own shapes are summed below */
  if (fabs(err) > fabs(out->worst)) out->worst = err;
}

/* The measured table's share of the mean: each model's error at the root
 * mean square of its elements' mean edges (the table's abscissa), with
 * their mass as weight; its elements are unresolved when that is. */
static void measured_into(model_set *models, along_run *r, dtm_phase_along *out) {
  for (int i = 0; i < models->n; i++) {
    along_model *md = models->m[i];
    if (!(md->w > 0)) continue;
    double err = element_along(md, &md->m, sqrt(md->wh2 / md->w), r->f, r->dt, r->n, r->pol, r->mode);
    *(isnan(err) ? &out->unresolved : &out->elements) += md->count;
    if (!isnan(err)) r->wsum += md->w, r->sum += md->w * err;
  }
}

static int check_along(const dtm_analysis *a, double f, double dt, int mode, int *k) {
  for (*k = 0; *k < dtm_analysis_neffects(a) && strcmp(dtm_analysis_effect(a, *k)->name, "elastic"); (*k)++)
    ;
  if (*k == dtm_analysis_neffects(a)) return DTM_ERR(DTM_ERR_INPUT, "phase error: the scene has no elastic effect");
  if (!(f > 0) || !(dt > 0) || (mode != 0 && mode != 1))
    return DTM_ERR(DTM_ERR_INPUT, "phase error: f = %g Hz, dt = %g s, branch %d", f, dt, mode);
  return DTM_OK;
}

int dtm_measures_phase_along(const dtm_analysis *a, double f, double dt, const double n[3], const double pol[3],
                             int mode, int mat, dtm_phase_along *out) {
  const dtm_mesh *mesh = dtm_analysis_mesh(a);
  int k;
  DTM_CHECK(check_along(a, f, dt, mode, &k));
  dtm_formulation form = dtm_acc_formulation(a, k);
  memset(out, 0, sizeof *out);
  out->model = -1;
  along_run r = {.f = f, .dt = dt, .n = n, .pol = pol, .mode = mode, .mat = mat};
  model_set models = {0};
  int rc = DTM_OK;
  for (int b = 0; b < mesh->nblocks && !rc; b++)
    for (size_t e = 0; e < mesh->blocks[b].n && !rc; e++) {
      const dtm_block *bl = &mesh->blocks[b];
      dtm_elastic_moduli m;
      along_model *md = NULL;
      if (bl->mat[e] < 0 || (mat >= 0 && bl->mat[e] != mat) || (bl->section && bl->section[e] >= 0) ||
          dtm_acc_moduli(a, bl->mat[e], form, &m))
        continue;
      rc = model_get(&models, mesh, bl->type, bl->mat[e], form == DTM_FORM_BAR ? 0 : m.mu / m.modulus, &md);
      if (!rc && md->have) element_into(mesh, bl, e, md, &m, &r, out);
    }
  measured_into(&models, &r, out);
  models_free(&models);
  DTM_CHECK(rc);
  if (r.ws.mass > 0 && mat >= 0) /* one material's own-shape elements as one: the wave's Rayleigh quotient */
    r.sum += r.ws.mass * own_error(r.ws.d, r.ws.D, r.ws.mass, &r.mown, f, dt, n, pol, mode), r.wsum += r.ws.mass;
  out->mean = r.wsum > 0 && !out->unresolved ? r.sum / r.wsum : NAN;
  return DTM_OK;
}
