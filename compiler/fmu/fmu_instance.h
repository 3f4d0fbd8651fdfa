/* One instance of a dyadc FMU: the model's vectors (states x, algebraic unknowns z, parameters
   p) and the work space of its CasADi-generated functions. The model's sizes and tables come from
   the generated dyfmu_model.h; the numerics (dense LU, Newton on the algebraic equations,
   Levenberg-Marquardt on the initialization system) are in fmu_numerics.c. Nothing here names an
   FMI version: fmi2_functions.c and fmi3_functions.c wrap the one core (fmu_core.h). */
#ifndef DYADC_FMU_INSTANCE_H
#define DYADC_FMU_INSTANCE_H

#include <stddef.h>

/* Statuses numbered as fmi2Status and fmi3Status both number their first five. */
enum { DY_OK, DY_WARNING, DY_DISCARD, DY_ERROR, DY_FATAL };

typedef long long dy_int;
typedef int (*dy_eval)(const double **arg, double **res, dy_int *iw, double *w, int mem);
typedef int (*dy_work)(dy_int *sz_arg, dy_int *sz_res, dy_int *sz_iw, dy_int *sz_w);

/* Where log messages go: `write` is the FMI wrapper's adapter to its importer's callback, which it
   keeps in `environment` and `function` (their meaning is the wrapper's). */
typedef struct {
    void (*write)(const void *environment, void (*function)(void), const char *instance, int status,
                  const char *category, const char *message);
    const void *environment;
    void (*function)(void);
} DyLogger;

enum { DY_INSTANTIATED, DY_INITIALIZATION, DY_EVENT, DY_CONTINUOUS, DY_STEP, DY_TERMINATED };

typedef struct {
    DyLogger logger;
    char *name;
    int logging;
    int mode;
    double t;
    int nx, nz, np;
    double *x, *z, *p_user, *mask, *p;
    double *residual, *jacobian, *work, *scratch;   /* linear algebra work */
    int *pivots;
    dy_int *iw;
    double *w;
    const double **arg;
    double **res;
    int values_fresh;        /* z (and what follows from it) solved for the current x, p, t */
    int parameters_fresh;    /* p derived from p_user and mask */
    int next_event_defined;
    double next_event;
    int cosimulation;        /* instantiated for Co-Simulation: the FMU integrates (fmu_cosimulation.inc) */
    double tolerance;        /* the integrator's relative (and absolute) tolerance */
    double step;             /* its last step size */
    void *integrator;        /* its work space, made on the first step */
} DyInstance;

/* Evaluate a generated function: arguments and results in order; returns 0 on success. */
int dy_call(DyInstance *c, dy_eval f, int n_in, const double **in, int n_out, double **out);

/* Solve A s = b in place (A column-major n x n, overwritten by its LU factors; b by s).
   Returns 0, or -1 when A is singular. */
int dy_lu_solve(int n, double *a, double *b, int *pivots);

/* The LU factors of A in place (row swaps in `pivots`), and a solve with them. */
int dy_lu_factor(int n, double *a, int *pivots);
void dy_lu_apply(int n, const double *lu, const int *pivots, double *b);

/* z with alg(x, z, p, t) = 0 by Newton with the exact Jacobian from the current z. `newton`
   evaluates (alg, dense d alg / d z). Returns 0, or -1 when it did not converge. */
int dy_solve_algebraic(DyInstance *c, dy_eval newton);

/* (x, z) minimizing the initialization residuals r(x, z, p, t) from the guesses in c->x, c->z
   (Levenberg-Marquardt on row-equilibrated residuals, exact Jacobian). `init` evaluates (r, dense
   dr / d(x, z)) with `rows` residuals. Returns 0, or -1 when the residuals stay above tolerance. */
int dy_solve_initial(DyInstance *c, dy_eval init, int rows);

void dy_log(DyInstance *c, int status, const char *category, const char *message);

#endif
