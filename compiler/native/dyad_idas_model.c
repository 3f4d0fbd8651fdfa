/* The model's side of the native IDAS driver: its CasADi-generated functions loaded from its
 * shared library (CasADi's public calling convention: f(arg, res, iw, w, mem), f_work,
 * f_sparsity_out) and evaluated as IDAS asks: the residual F = [x' - ode; alg] with y = [x; z],
 * the Jacobian dF/dy + cj dF/dy' scattered from the sparse blocks into a dense matrix, the
 * watched zero functions. */
#include "dyad_idas.h"

int dyad_load_function(Driver *d, Function *f, const char *name) {
  char symbol[128];
  cs_work work;
  cs_checkout checkout;
  cs_int sz_arg = 0, sz_res = 0, sz_iw = 0, sz_w = 0;
  f->eval = (cs_eval)dlsym(d->library, name);
  snprintf(symbol, sizeof symbol, "%s_work", name);
  work = (cs_work)dlsym(d->library, symbol);
  snprintf(symbol, sizeof symbol, "%s_sparsity_out", name);
  f->sparsity_out = (cs_sparsity)dlsym(d->library, symbol);
  snprintf(symbol, sizeof symbol, "%s_checkout", name);
  checkout = (cs_checkout)dlsym(d->library, symbol);
  snprintf(symbol, sizeof symbol, "%s_release", name);
  f->release = (cs_release)dlsym(d->library, symbol);
  if (!f->eval || !work || !f->sparsity_out) {
    snprintf(d->message, sizeof d->message, "the model's library has no function %s", name);
    return -1;
  }
  work(&sz_arg, &sz_res, &sz_iw, &sz_w);
  f->arg = calloc(sz_arg + 1, sizeof(double *));
  f->res = calloc(sz_res + 1, sizeof(double *));
  f->iw = calloc(sz_iw + 1, sizeof(cs_int));
  f->w = calloc(sz_w + 1, sizeof(double));
  f->n_res = (int)sz_res;
  f->mem = checkout ? checkout() : 0;
  return 0;
}

void dyad_free_function(Function *f) {
  if (f->release && f->eval) f->release(f->mem);
  free(f->arg); free(f->res); free(f->iw); free(f->w);
}

/* ode and alg at (t, x, z) with the call's parameters; nonzero where a value is not finite */
int dyad_eval_dae(Driver *d, double t, const double *x, const double *z) {
  int i;
  d->t_model = t;
  d->dae.arg[0] = &t; d->dae.arg[1] = x; d->dae.arg[2] = z; d->dae.arg[3] = d->p;
  d->dae.arg[4] = NULL;
  memset(d->dae.res, 0, d->dae.n_res * sizeof(double *));
  d->dae.res[0] = d->ode; d->dae.res[1] = d->alg;
  if (d->dae.eval(d->dae.arg, d->dae.res, d->dae.iw, d->dae.w, d->dae.mem)) return 1;
  for (i = 0; i < d->nx; i++) if (!isfinite(d->ode[i])) return 1;
  for (i = 0; i < d->nz; i++) if (!isfinite(d->alg[i])) return 1;
  return 0;
}

int dyad_residual(sunrealtype t, N_Vector y, N_Vector yp, N_Vector rr, void *data) {
  Driver *d = data;
  const double *yv = N_VGetArrayPointer(y), *ypv = N_VGetArrayPointer(yp);
  double *r = N_VGetArrayPointer(rr);
  int i;
  if (dyad_eval_dae(d, t, yv, yv + d->nx)) return 1;     /* recoverable: IDAS cuts the step */
  for (i = 0; i < d->nx; i++) r[i] = ypv[i] - d->ode[i];
  for (i = 0; i < d->nz; i++) r[d->nx + i] = d->alg[i];
  return 0;
}

/* add `sign` times the sparse block of output `k` at (row0, col0) of the dense matrix J */
static void scatter(Driver *d, SUNMatrix J, int k, double sign, int row0, int col0) {
  const cs_int *sp = d->jac.sparsity_out(k);
  const double *v = d->jac.res[k];
  cs_int nrow = sp[0], ncol = sp[1], c, e;
  if (nrow == 0 || ncol == 0) return;
  if (sp[2] == 1) {                                    /* CasADi's compact dense form */
    for (c = 0; c < ncol; c++)
      for (e = 0; e < nrow; e++)
        SM_ELEMENT_D(J, row0 + e, col0 + c) += sign * v[c * nrow + e];
    return;
  }
  for (c = 0; c < ncol; c++)
    for (e = sp[2 + c]; e < sp[3 + c]; e++)
      SM_ELEMENT_D(J, row0 + sp[3 + ncol + e], col0 + c) += sign * v[e];
}

/* outputs j * 5 + i of jac_dyad_dae (ccodegen.state_jacobian): d(ode, alg)/d(x, z) are j in
 * {0, 1}, i in {1, 2}; the others are structurally zero and not computed */
static int is_state_block(int k) { return k / 5 <= 1 && (k % 5 == 1 || k % 5 == 2); }

int dyad_jacobian(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector rr,
                    SUNMatrix J, void *data, N_Vector t1, N_Vector t2, N_Vector t3) {
  Driver *d = data;
  const double *yv = N_VGetArrayPointer(y);
  int i, k;
  (void)yp; (void)rr; (void)t1; (void)t2; (void)t3;
  memset(d->jac.arg, 0, 9 * sizeof(double *));
  d->jac.arg[0] = &t; d->jac.arg[1] = yv; d->jac.arg[2] = yv + d->nx; d->jac.arg[3] = d->p;
  memset(d->jac.res, 0, d->jac.n_res * sizeof(double *));
  for (k = 0; k < 20; k++) d->jac.res[k] = d->jac_values[k];
  if (d->jac.eval(d->jac.arg, d->jac.res, d->jac.iw, d->jac.w, d->jac.mem)) return 1;
  SUNMatZero(J);
  scatter(d, J, 1, -1.0, 0, 0);
  scatter(d, J, 2, -1.0, 0, d->nx);
  scatter(d, J, 6, 1.0, d->nx, 0);
  scatter(d, J, 7, 1.0, d->nx, d->nx);
  for (i = 0; i < d->nx; i++) SM_ELEMENT_D(J, i, i) += cj;
  return 0;
}

int dyad_allocate_jacobian(Driver *d) {
  int k;
  for (k = 0; k < 20; k++) {
    const cs_int *sp;
    if (!is_state_block(k)) continue;
    sp = d->jac.sparsity_out(k);
    if (!sp) return -1;
    d->jac_values[k] = calloc((sp[2] == 1 || sp[1] == 0 ? sp[0] * sp[1] : sp[2 + sp[1]]) + 1,
                              sizeof(double));
  }
  return 0;
}

/* the watched rows; an exact zero is taken as the side whose relation value it shares (`x > 0`
 * is false at zero: below; `x < 0` false: above), so that a row that starts at zero and leaves
 * it to where its relation changes is a sign change */
int dyad_roots(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype *g, void *data) {
  Driver *d = data;
  const double *yv = N_VGetArrayPointer(y);
  int i;
  (void)yp;
  d->watch.arg[0] = yv; d->watch.arg[1] = yv + d->nx; d->watch.arg[2] = d->p;
  d->watch.arg[3] = &t; d->watch.arg[4] = &d->watch_atol;
  memset(d->watch.res, 0, d->watch.n_res * sizeof(double *));
  d->watch.res[0] = g;
  if (d->watch.eval(d->watch.arg, d->watch.res, d->watch.iw, d->watch.w, d->watch.mem)) return -1;
  for (i = 0; i < d->nrows; i++) {
    if (!d->active[i]) g[i] = 1.0;
    else if (g[i] == 0.0) g[i] = d->zero_side[i] * DBL_MIN;
  }
  return 0;
}

/* LU with partial pivoting of the n x n column-major `a`, then the solution of a s = b into b;
 * nonzero where a pivot is zero or not finite */
static int solve_dense(double *a, double *b, int n) {
  int i, j, k;
  for (k = 0; k < n; k++) {
    int pivot = k;
    for (i = k + 1; i < n; i++)
      if (fabs(a[k * n + i]) > fabs(a[k * n + pivot])) pivot = i;
    if (!(fabs(a[k * n + pivot]) > 0.0) || !isfinite(a[k * n + pivot])) return 1;
    if (pivot != k) {
      double swap;
      for (j = 0; j < n; j++) { swap = a[j * n + k]; a[j * n + k] = a[j * n + pivot]; a[j * n + pivot] = swap; }
      swap = b[k]; b[k] = b[pivot]; b[pivot] = swap;
    }
    for (i = k + 1; i < n; i++) {
      double factor = a[k * n + i] / a[k * n + k];
      if (factor == 0.0) continue;
      for (j = k + 1; j < n; j++) a[j * n + i] -= factor * a[j * n + k];
      b[i] -= factor * b[k];
    }
  }
  for (k = n - 1; k >= 0; k--) {
    for (j = k + 1; j < n; j++) b[k] -= a[j * n + k] * b[j];
    b[k] /= a[k * n + k];
  }
  return 0;
}

/* d(alg)/dz at (t, x, z) (output 7 of jac_dyad_dae) into the dense column-major nz x nz `a` */
static int algebraic_jacobian(Driver *d, double t, const double *x, const double *z, double *a) {
  const cs_int *sp = d->jac.sparsity_out(7);
  const double *v = d->jac_values[7];
  cs_int nrow, ncol, c, e;
  int k, nz = d->nz;
  memset(d->jac.arg, 0, 9 * sizeof(double *));
  d->jac.arg[0] = &t; d->jac.arg[1] = x; d->jac.arg[2] = z; d->jac.arg[3] = d->p;
  memset(d->jac.res, 0, d->jac.n_res * sizeof(double *));
  for (k = 0; k < 20; k++) d->jac.res[k] = d->jac_values[k];
  if (d->jac.eval(d->jac.arg, d->jac.res, d->jac.iw, d->jac.w, d->jac.mem)) return 1;
  memset(a, 0, (size_t)nz * nz * sizeof(double));
  nrow = sp[0]; ncol = sp[1];
  if (nrow != nz || ncol != nz) return 1;
  if (sp[2] == 1) {
    for (c = 0; c < ncol; c++) for (e = 0; e < nrow; e++) a[c * nz + e] = v[c * nrow + e];
    return 0;
  }
  for (c = 0; c < ncol; c++)
    for (e = sp[2 + c]; e < sp[3 + c]; e++) a[c * nz + sp[3 + ncol + e]] = v[e];
  return 0;
}

static double largest_magnitude(const double *v, int n) {
  double m = 0.0;
  int i;
  for (i = 0; i < n; i++) m = fabs(v[i]) > m ? fabs(v[i]) : m;
  return m;
}

/* Newton steps on alg(t, x, z, p) = 0 for z (in place), each kept only where it does not raise
 * the largest residual, until a step moves z by no more than round-off (ROUNDOFF_STEPS ulps of
 * the largest |z|, or of 1) or `max_steps` are taken. Returns 1 where such a step was found
 * (converged), 0 where not (z the best point found), -1 where the equations or their Jacobian
 * have no finite value or the Jacobian is singular (z unchanged). The driver's parameters are
 * left as they were. */
#define ROUNDOFF_STEPS 16.0
int dyad_solve_algebraic(Driver *d, double t, const double *x, double *z, const double *p, int max_steps) {
  int nz = d->nz, i, steps = 0, outcome = 0;
  double *a = malloc(((size_t)nz * nz + 3 * (size_t)nz + d->np + 1) * sizeof(double));
  double *step, *trial, *held, *p_held, residual = 0.0;
  if (!a) return -1;
  step = a + (size_t)nz * nz; trial = step + nz; held = trial + nz; p_held = held + nz;
  memcpy(p_held, d->p, d->np * sizeof(double));
  memcpy(d->p, p, d->np * sizeof(double));
  memcpy(held, z, nz * sizeof(double));
  if (dyad_eval_dae(d, t, x, z)) outcome = -1;
  else residual = largest_magnitude(d->alg, nz);
  if (outcome == 0 && residual == 0.0) outcome = 1;
  while (outcome == 0 && steps < max_steps) {
    double moved, size = largest_magnitude(z, nz);
    memcpy(step, d->alg, nz * sizeof(double));
    if (algebraic_jacobian(d, t, x, z, a) || solve_dense(a, step, nz)) { outcome = -1; break; }
    moved = largest_magnitude(step, nz);
    if (!isfinite(moved)) { outcome = -1; break; }
    for (i = 0; i < nz; i++) trial[i] = z[i] - step[i];
    if (moved <= ROUNDOFF_STEPS * DBL_EPSILON * (size > 1.0 ? size : 1.0)) outcome = 1;
    if (dyad_eval_dae(d, t, x, trial) || largest_magnitude(d->alg, nz) > residual) break;
    memcpy(z, trial, nz * sizeof(double));
    residual = largest_magnitude(d->alg, nz);
    steps++;
  }
  if (outcome < 0) memcpy(z, held, nz * sizeof(double));
  memcpy(d->p, p_held, d->np * sizeof(double));
  free(a);
  return outcome;
}
