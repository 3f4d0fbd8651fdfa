/* The absolute tolerances IDAS's Newton test gives the algebraic unknowns of a run whose
 * algebraic unknowns are out of the error test: never below the round-off with which the point's
 * algebraic equations determine them. Solving alg(x, z) = 0 for z in double precision leaves
 * |dz| <= eps |J_zz^-1| (|J_zx| |x| + |J_zz| |z|) (the componentwise bound of one evaluation's
 * round-off through the solve); a tolerance below it asks the Newton iteration for digits the
 * equations do not have, and its corrections stall above the tolerance until IDAS cuts h to
 * nothing (IDA_CONV_FAIL). Worked out at every restart, from the Jacobian there. */
#include "dyad_idas.h"

#include <sundials/sundials_dense.h>

/* the rows of the algebraic equations of jac_dyad_dae's block `k` (6: d alg/dx, 7: d alg/dz)
 * into the column-major nz x ncol array `out` */
static void alg_block(Driver *d, int k, int ncol, double *out) {
  const cs_int *sp = d->jac.sparsity_out(k);
  const double *v = d->jac.res[k];
  cs_int nrow = sp[0], c, e;
  memset(out, 0, (size_t)d->nz * ncol * sizeof(double));
  if (nrow == 0 || sp[1] == 0) return;
  if (sp[2] == 1) {                                    /* CasADi's compact dense form */
    memcpy(out, v, (size_t)nrow * ncol * sizeof(double));
    return;
  }
  for (c = 0; c < ncol; c++)
    for (e = sp[2 + c]; e < sp[3 + c]; e++) out[c * nrow + sp[3 + ncol + e]] = v[e];
}

int dyad_allocate_floors(Driver *d) {
  int n = d->nx + d->nz, k;
  d->atol = calloc(n + 1, sizeof(double));
  d->floor_tolerances = N_VNew_Serial(n, d->ctx);
  if (d->nz == 0 || d->nz > DYAD_FLOOR_MOST_UNKNOWNS) return d->atol && d->floor_tolerances ? 0 : -1;
  d->jzz = calloc((size_t)d->nz * d->nz, sizeof(double));
  d->jzx = calloc((size_t)d->nz * (d->nx + 1), sizeof(double));
  d->inverse_column = calloc(d->nz, sizeof(double));
  d->terms = calloc(d->nz, sizeof(double));
  d->jzz_columns = calloc(d->nz, sizeof(double *));
  d->pivots = calloc(d->nz, sizeof(sunindextype));
  if (!d->atol || !d->floor_tolerances || !d->jzz || !d->jzx || !d->inverse_column || !d->terms
      || !d->jzz_columns || !d->pivots) return -1;
  for (k = 0; k < d->nz; k++) d->jzz_columns[k] = d->jzz + (size_t)k * d->nz;
  return 0;
}

void dyad_free_floors(Driver *d) {
  free(d->atol); free(d->jzz); free(d->jzx); free(d->inverse_column); free(d->terms);
  free(d->jzz_columns); free(d->pivots);
  if (d->floor_tolerances) N_VDestroy(d->floor_tolerances);
}

/* the round-off floor of each algebraic unknown at (t, y) into floors[0..nz); -1 where it cannot
 * be worked out (too many unknowns, a singular J_zz, no Jacobian there): then there is none */
static int roundoff_floors(Driver *d, double t, const double *y, double *floors) {
  const double *x = y, *z = y + d->nx;
  int nx = d->nx, nz = d->nz, i, j, k;
  if (!d->jzz) return -1;
  memset(d->jac.arg, 0, 9 * sizeof(double *));
  d->jac.arg[0] = &t; d->jac.arg[1] = x; d->jac.arg[2] = z; d->jac.arg[3] = d->p;
  memset(d->jac.res, 0, d->jac.n_res * sizeof(double *));
  for (k = 0; k < 20; k++) d->jac.res[k] = d->jac_values[k];
  if (d->jac.eval(d->jac.arg, d->jac.res, d->jac.iw, d->jac.w, d->jac.mem)) return -1;
  alg_block(d, 6, nx, d->jzx);
  alg_block(d, 7, nz, d->jzz);
  for (i = 0; i < nz; i++) {           /* the size of the terms of equation i */
    double sum = 0.0;
    for (j = 0; j < nx; j++) sum += fabs(d->jzx[(size_t)j * nz + i] * x[j]);
    for (j = 0; j < nz; j++) sum += fabs(d->jzz[(size_t)j * nz + i] * z[j]);
    d->terms[i] = sum;
    floors[i] = 0.0;
  }
  if (SUNDlsMat_denseGETRF(d->jzz_columns, nz, nz, d->pivots) != 0) return -1;
  for (k = 0; k < nz; k++) {           /* column k of J_zz^-1, weighted by equation k's terms */
    memset(d->inverse_column, 0, nz * sizeof(double));
    d->inverse_column[k] = 1.0;
    SUNDlsMat_denseGETRS(d->jzz_columns, nz, d->pivots, d->inverse_column);
    for (i = 0; i < nz; i++) floors[i] += fabs(d->inverse_column[i]) * d->terms[k];
  }
  for (i = 0; i < nz; i++) {
    floors[i] *= DBL_EPSILON;
    if (!isfinite(floors[i])) return -1;
  }
  return 0;
}

/* IDAS's tolerances at a restart at (t, y): the set-up ones, the algebraic unknowns' raised to
 * their round-off floors there where the run keeps them out of the error test */
int dyad_floor_tolerances(Driver *d, double t, const double *y) {
  double *tol = N_VGetArrayPointer(d->floor_tolerances);
  int i, n = d->nx + d->nz;
  memcpy(tol, d->atol, n * sizeof(double));
  if (d->suppress_alg && roundoff_floors(d, t, y, tol + d->nx) == 0)
    for (i = d->nx; i < n; i++) tol[i] = fmax(tol[i], d->atol[i]);
  else
    memcpy(tol, d->atol, n * sizeof(double));
  return IDASVtolerances(d->ida, d->rtol, d->floor_tolerances);
}
