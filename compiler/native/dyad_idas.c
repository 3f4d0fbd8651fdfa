/* dyadc's native IDAS driver: SUNDIALS IDAS on a model's CasADi-generated C functions, called
 * from Python through ctypes (compiler/runtime/native/library.py). The residual, its Jacobian and the
 * watched zero functions are evaluated in C (dyad_idas_model.c), from the model's shared library,
 * so a run makes no Python call per evaluation. One call of
 * dyad_ida_advance steps IDAS in one-step mode to a stop time, writes the output times it passes
 * by dense output, and stops early at a root of a watched row or where a state runs away. */
#include "dyad_idas.h"

#define MAX_ERROR_TEST_FAILURES 20

static void keep_message(int line, const char *func, const char *file, const char *msg,
                         SUNErrCode code, void *data, SUNContext ctx) {
  Driver *d = data;
  (void)line; (void)file; (void)code; (void)ctx;
  snprintf(d->message, sizeof d->message, "%s: %s", func ? func : "IDAS", msg ? msg : "");
}

DYAD_EXPORT const char *dyad_ida_message(Driver *d) { return d->message; }

DYAD_EXPORT void dyad_ida_free(Driver *d) {
  if (!d) return;
  if (d->ida) IDAFree(&d->ida);
  if (d->LS) SUNLinSolFree(d->LS);
  if (d->J) SUNMatDestroy(d->J);
  if (d->y) N_VDestroy(d->y);
  if (d->yp) N_VDestroy(d->yp);
  if (d->scratch) N_VDestroy(d->scratch);
  dyad_free_floors(d);
  if (d->ctx) SUNContext_Free(&d->ctx);
  dyad_free_function(&d->dae); dyad_free_function(&d->jac); dyad_free_function(&d->watch);
  free(d->p); free(d->ode); free(d->alg); free(d->active); free(d->found); free(d->zero_side);
  free(d->proposes); free(d->g);
  for (int k = 0; k < 20; k++) free(d->jac_values[k]);
  if (d->library) dlclose(d->library);
  free(d);
}

/* A driver on the model library at `path`; NULL with `error` filled where it cannot be made. */
DYAD_EXPORT Driver *dyad_ida_new(const char *path, int nx, int nz, int np, int nrows, char *error, int size) {
  Driver *d = calloc(1, sizeof(Driver));
  int ok;
  d->nx = nx; d->nz = nz; d->np = np; d->nrows = nrows;
  d->library = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!d->library) {
    snprintf(error, size, "%s", dlerror());
    free(d);
    return NULL;
  }
  ok = dyad_load_function(d, &d->dae, "dyad_dae") == 0 && dyad_load_function(d, &d->jac, "jac_dyad_dae") == 0
       && (nrows == 0 || dyad_load_function(d, &d->watch, "dyad_watch") == 0) && dyad_allocate_jacobian(d) == 0;
  d->p = calloc(np + 1, sizeof(double));
  d->ode = calloc(nx + 1, sizeof(double));
  d->alg = calloc(nz + 1, sizeof(double));
  d->active = calloc(nrows + 1, sizeof(int));
  d->zero_side = calloc(nrows + 1, sizeof(int));
  d->found = calloc(nrows + 1, sizeof(int));
  d->proposes = calloc(nrows + 1, sizeof(int));
  d->g = calloc(nrows + 1, sizeof(double));
  if (ok && SUNContext_Create(SUN_COMM_NULL, &d->ctx) != 0) {
    snprintf(d->message, sizeof d->message, "SUNContext_Create failed");
    ok = 0;
  }
  if (!ok) {
    snprintf(error, size, "%s", d->message);
    dyad_ida_free(d);
    return NULL;
  }
  SUNContext_ClearErrHandlers(d->ctx);
  SUNContext_PushErrHandler(d->ctx, keep_message, d);
  d->y = N_VNew_Serial(nx + nz, d->ctx);
  d->yp = N_VNew_Serial(nx + nz, d->ctx);
  d->scratch = N_VNew_Serial(nx + nz, d->ctx);
  if (dyad_allocate_floors(d) != 0) {
    snprintf(error, size, "the native IDAS driver's work arrays cannot be allocated");
    dyad_ida_free(d);
    return NULL;
  }
  return d;
}

/* IDAS for this driver: relative tolerance, absolute tolerance per unknown, the algebraic
 * unknowns out of the error test or not, the largest step and order (0: IDAS's own), dense LU on
 * our Jacobian, the watched rows with their directions (0 both ways, -1 from + to -), the
 * sides their exact zeros count as (+1 or -1) and which of them only propose a switch (1: a
 * state-set level of several rows, whose switch the caller decides at the point). */
DYAD_EXPORT int dyad_ida_setup(Driver *d, double rtol, const double *atol, int suppress_alg, double max_step,
                   int max_order, const int *directions, const int *zero_sides, const int *proposes,
                   double watch_atol) {
  int n = d->nx + d->nz, i, flag;
  for (i = 0; i < d->nrows; i++) {
    d->zero_side[i] = zero_sides[i] > 0 ? 1 : -1;
    d->proposes[i] = proposes[i] != 0;
  }
  N_Vector tolerances = N_VNew_Serial(n, d->ctx), id = N_VNew_Serial(n, d->ctx);
  for (i = 0; i < n; i++) {
    NV_Ith_S(tolerances, i) = atol[i];
    NV_Ith_S(id, i) = i < d->nx ? 1.0 : 0.0;
  }
  N_VConst(0.0, d->y);
  N_VConst(0.0, d->yp);
  d->watch_atol = watch_atol;
  d->rtol = rtol;
  d->suppress_alg = suppress_alg != 0;
  memcpy(d->atol, atol, n * sizeof(double));
  d->ida = IDACreate(d->ctx);
  flag = d->ida ? IDAInit(d->ida, dyad_residual, 0.0, d->y, d->yp) : IDA_MEM_FAIL;
  if (!flag) flag = IDASVtolerances(d->ida, rtol, tolerances);
  if (!flag) flag = IDASetUserData(d->ida, d);
  if (!flag) flag = IDASetId(d->ida, id);
  if (!flag) flag = IDASetSuppressAlg(d->ida, suppress_alg ? SUNTRUE : SUNFALSE);
  if (!flag && max_step > 0) flag = IDASetMaxStep(d->ida, max_step);
  if (!flag && max_order > 0) flag = IDASetMaxOrd(d->ida, max_order);
  /* a first step too large at the start of a stiff transient is cut by 0.25 per failed error
   * test; IDAS's 10 tests cut it 1e-6 at most, 20 cut it 1e-12 (a loop of gain 3e6 / s from rest,
   * tests/runtime/test_relation_locks.py, needs 1e-6 of its 2e-3) */
  if (!flag) flag = IDASetMaxErrTestFails(d->ida, MAX_ERROR_TEST_FAILURES);
  if (!flag) {
    d->J = SUNDenseMatrix(n, n, d->ctx);
    d->LS = SUNLinSol_Dense(d->y, d->J, d->ctx);
    flag = d->J && d->LS ? IDASetLinearSolver(d->ida, d->LS, d->J) : IDA_MEM_FAIL;
  }
  if (!flag) flag = IDASetJacFn(d->ida, dyad_jacobian);
  if (!flag && d->nrows > 0) {
    flag = IDARootInit(d->ida, d->nrows, dyad_roots);
    if (!flag) flag = IDASetRootDirection(d->ida, (int *)directions);
    if (!flag) flag = IDASetNoInactiveRootWarn(d->ida);
  }
  N_VDestroy(tolerances);
  N_VDestroy(id);
  return flag;
}

/* IDAS restarted cold at (t0, x0, z0) with parameters p: der(x) from the model there, der(z) 0
 * (the point solves the algebraic equations already), the algebraic unknowns' tolerances raised
 * to their round-off there (dyad_idas_floors.c); `active` the watched rows looked at, `step0`
 * the first step (0: IDAS's own). */
DYAD_EXPORT int dyad_ida_restart(Driver *d, double t0, const double *x0, const double *z0, const double *p,
                     const int *active, double step0) {
  int i, flag;
  double *y = N_VGetArrayPointer(d->y), *yp = N_VGetArrayPointer(d->yp);
  d->message[0] = '\0';
  memcpy(d->p, p, d->np * sizeof(double));
  for (i = 0; i < d->nrows; i++) d->active[i] = active[i];
  memcpy(y, x0, d->nx * sizeof(double));
  memcpy(y + d->nx, z0, d->nz * sizeof(double));
  if (dyad_eval_dae(d, t0, y, y + d->nx)) {
    snprintf(d->message, sizeof d->message, "the equations have no finite value at the start");
    return IDA_FIRST_RES_FAIL;
  }
  memcpy(yp, d->ode, d->nx * sizeof(double));
  for (i = 0; i < d->nz; i++) yp[d->nx + i] = 0.0;
  flag = IDAReInit(d->ida, t0, d->y, d->yp);
  if (!flag) flag = dyad_floor_tolerances(d, t0, y);
  if (!flag) flag = IDASetInitStep(d->ida, step0 > 0 ? step0 : 0.0);
  return flag;
}

static void copy_point(Driver *d, N_Vector v, double *x, double *z) {
  const double *y = N_VGetArrayPointer(v);
  memcpy(x, y, d->nx * sizeof(double));
  memcpy(z, y + d->nx, d->nz * sizeof(double));
}

static int runs_away(Driver *d, const double *limit) {
  const double *y = N_VGetArrayPointer(d->y);
  int i;
  for (i = 0; i < d->nx; i++)
    if (!isfinite(y[i]) || fabs(y[i]) > limit[i]) return 1;
  return 0;
}

static volatile sig_atomic_t interrupted = 0;

static void on_interrupt(int signal_number) {
  (void)signal_number;
  interrupted = 1;
}

/* The first active row that proposes a switch and is not positive at (t, y), the end of a step;
 * -1 where none is (or the rows cannot be evaluated: the next step's root finding says so). */
static int proposing_row(Driver *d, double t) {
  int i, any = 0;
  for (i = 0; i < d->nrows; i++) any |= d->proposes[i] && d->active[i];
  if (!any || dyad_roots(t, d->y, d->yp, d->g, d) != 0) return -1;
  for (i = 0; i < d->nrows; i++)
    if (d->proposes[i] && d->active[i] && !(d->g[i] > 0.0)) return i;
  return -1;
}

/* The stepping loop of dyad_ida_advance. */
static int step_to(Driver *d, double reach, int n_out, const double *outputs, double *xs,
                   double *zs, int *n_done, const double *limit, long max_steps, double *t,
                   double *x, double *z, int *row, int *direction) {
  double tret = 0.0;
  long steps = 0;
  int flag, k = 0, i;
  *n_done = 0;
  d->message[0] = '\0';
  *row = -1;
  *direction = 0;
  flag = IDASetStopTime(d->ida, reach);
  while (!flag) {
    flag = IDASolve(d->ida, reach, &tret, d->y, d->yp, IDA_ONE_STEP);
    if (flag < 0) break;
    for (; k < n_out && outputs[k] <= tret; k++, steps = 0) {
      if (IDAGetDky(d->ida, outputs[k], 0, d->scratch)) N_VScale(1.0, d->y, d->scratch);
      copy_point(d, d->scratch, xs + (size_t)k * d->nx, zs + (size_t)k * d->nz);
    }
    *n_done = k;
    *t = tret;
    copy_point(d, d->y, x, z);
    if (runs_away(d, limit)) return 2;
    if (flag == IDA_TSTOP_RETURN) return 0;
    if (flag == IDA_ROOT_RETURN) {
      IDAGetRootInfo(d->ida, d->found);
      for (i = 0; i < d->nrows && *row < 0; i++)
        if (d->found[i] && d->active[i] && !d->proposes[i]) { *row = i; *direction = d->found[i]; }
      if (*row >= 0) return 1;
      flag = 0;
    }
    if ((*row = proposing_row(d, tret)) >= 0) return 4;
    if (interrupted) return 3;
    if (++steps >= max_steps) {
      snprintf(d->message, sizeof d->message, "%ld steps taken before the next output time", steps);
      return IDA_TOO_MUCH_WORK;
    }
  }
  IDAGetCurrentTime(d->ida, t);
  return flag;
}

/* Step IDAS (one-step mode, stop time `reach`) from where it is. The states at the n_out output
 * times it passes go to xs, zs (one time after another), their count to n_done. Returns 0 at
 * `reach`, 1 at a root of watched row `row` (`direction` +1: it rose), 2 where a state is not
 * finite or beyond `limit`, 4 at the end of a step (or a root) where a row that proposes a switch
 * (dyad_ida_setup) is not positive: IDAS goes on from there when called again, 3 after a SIGINT (Ctrl-C, looked at after every step while
 * `watch_interrupt`; the caller raises it), IDA_TOO_MUCH_WORK after max_steps steps without an
 * output time, or IDAS's own negative flag; (t, x, z) is where it stopped. */
DYAD_EXPORT int dyad_ida_advance(Driver *d, double reach, int n_out, const double *outputs, double *xs,
                     double *zs, int *n_done, const double *limit, long max_steps, double *t,
                     double *x, double *z, int *row, int *direction, int watch_interrupt) {
  struct sigaction ours, previous;
  int flag;
  if (watch_interrupt) {
    memset(&ours, 0, sizeof ours);
    ours.sa_handler = on_interrupt;
    sigemptyset(&ours.sa_mask);
    interrupted = 0;
    sigaction(SIGINT, &ours, &previous);
  }
  flag = step_to(d, reach, n_out, outputs, xs, zs, n_done, limit, max_steps, t, x, z, row, direction);
  if (watch_interrupt) sigaction(SIGINT, &previous, NULL);
  return flag;
}

/* IDAS's counters since its last restart: steps, residual evaluations, Jacobian evaluations,
 * linear solver setups, error test failures, Newton iterations, Newton convergence failures. */
DYAD_EXPORT void dyad_ida_stats(Driver *d, long *out) {
  IDAGetNumSteps(d->ida, &out[0]);
  IDAGetNumResEvals(d->ida, &out[1]);
  IDAGetNumJacEvals(d->ida, &out[2]);
  IDAGetNumLinSolvSetups(d->ida, &out[3]);
  IDAGetNumErrTestFails(d->ida, &out[4]);
  IDAGetNumNonlinSolvIters(d->ida, &out[5]);
  IDAGetNumNonlinSolvConvFails(d->ida, &out[6]);
}

/* z solving the algebraic equations at (t, x) with parameters p by Newton steps from z (in place;
 * dyad_solve_algebraic): 1 converged to round-off, 0 not, -1 where no step can be taken. IDAS is
 * not touched. */
DYAD_EXPORT int dyad_ida_solve_algebraic(Driver *d, double t, const double *x, double *z, const double *p,
                                         int max_steps) {
  return dyad_solve_algebraic(d, t, x, z, p, max_steps);
}

/* The SUNDIALS version this library was built from. */
DYAD_EXPORT const char *dyad_ida_sundials_version(void) { return SUNDIALS_VERSION; }
