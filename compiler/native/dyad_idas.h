/* The native IDAS driver's shared declarations: the model's CasADi-generated functions as the
 * driver holds them (dyad_idas_model.c evaluates them for IDAS) and the driver's state
 * (dyad_idas.c steps IDAS with it). */
#ifndef DYAD_IDAS_H
#define DYAD_IDAS_H

#include <dlfcn.h>
#include <float.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <idas/idas.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#define DYAD_EXPORT __attribute__((visibility("default")))
/* the most algebraic unknowns whose round-off floors a restart works out (dyad_idas_floors.c:
 * an inverse of J_zz, nz^3 operations); above it the set-up tolerances stand */
#define DYAD_FLOOR_MOST_UNKNOWNS 100

typedef long long int cs_int;
typedef int (*cs_eval)(const double **arg, double **res, cs_int *iw, double *w, int mem);
typedef int (*cs_work)(cs_int *sz_arg, cs_int *sz_res, cs_int *sz_iw, cs_int *sz_w);
typedef const cs_int *(*cs_sparsity)(cs_int i);
typedef int (*cs_checkout)(void);
typedef void (*cs_release)(int mem);

/* One CasADi-generated function with its own work arrays. */
typedef struct {
  cs_eval eval;
  cs_sparsity sparsity_out;
  cs_release release;
  const double **arg;
  double **res;
  cs_int *iw;
  double *w;
  int mem;
  int n_res;
} Function;

typedef struct {
  void *library;
  Function dae, jac, watch;
  int nx, nz, np, nrows;
  double t_model;          /* the time the functions were last asked at (for messages) */
  double *p, *ode, *alg;
  double watch_atol;
  int *active;             /* watched rows looked at (1) or ignored (0: a constant 1.0) */
  int *zero_side;          /* the sign a row's exact zero is taken as (its relation's value there) */
  int *found;
  int *proposes;           /* rows whose crossing only proposes a state-set switch (the caller decides) */
  double *g;               /* the watched rows at the end of a step */
  double *jac_values[20];  /* the Jacobian blocks d(ode, alg)/d(x, z), by output of jac_dyad_dae */
  double rtol, *atol;      /* the set-up tolerances */
  int suppress_alg;        /* the algebraic unknowns out of the error test */
  N_Vector floor_tolerances;   /* atol with the algebraic unknowns' round-off floors (a restart's) */
  double *jzz, *jzx, *inverse_column, *terms, **jzz_columns;   /* dyad_idas_floors.c's work */
  sunindextype *pivots;
  SUNContext ctx;
  void *ida;
  N_Vector y, yp, scratch;
  SUNMatrix J;
  SUNLinearSolver LS;
  char message[1024];
} Driver;

int dyad_load_function(Driver *d, Function *f, const char *name);
void dyad_free_function(Function *f);
int dyad_allocate_jacobian(Driver *d);
int dyad_eval_dae(Driver *d, double t, const double *x, const double *z);
int dyad_residual(sunrealtype t, N_Vector y, N_Vector yp, N_Vector rr, void *data);
int dyad_jacobian(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector rr,
                  SUNMatrix J, void *data, N_Vector t1, N_Vector t2, N_Vector t3);
int dyad_allocate_floors(Driver *d);
void dyad_free_floors(Driver *d);
int dyad_floor_tolerances(Driver *d, double t, const double *y);
int dyad_roots(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype *g, void *data);
int dyad_solve_algebraic(Driver *d, double t, const double *x, double *z, const double *p, int max_steps);

#endif
