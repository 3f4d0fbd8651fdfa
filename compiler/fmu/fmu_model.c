/* The core of a dyadc FMU, for FMI 2.0 and 3.0 alike (fmu_core.h). The model is
   der(x) = f(x, z, p, t), 0 = g(x, z, p, t), y = h(x, z, p, t) with g regular in z; its
   CasADi-generated functions and tables come from dyfmu_model.h (written by
   compiler/fmu/sources.py). The algebraic unknowns z are solved by Newton from their last values
   whenever x, p or t changed; relations on unknowns are locked between events and set by an event
   iteration at each event (as dyadc's runtime does, compiler/runtime/relations.py); time-only
   conditions read an event clock set in the middle of the coming segment between time events
   (compiler/runtime/segments.py). Value references: states, their derivatives, the rows of the
   output function, the parameter vector, the event indicators, then time. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmu_core.h"
#include "dyfmu_model.h"

#define LIVE 2.0
#define EVENT_ITERATIONS 20
#define VR_DERIVATIVE DY_NX
#define VR_OUTPUT (2 * DY_NX)
#define VR_PARAMETER (2 * DY_NX + DY_NY)
#define VR_END (2 * DY_NX + DY_NY + DY_NP)
#define VR_INDICATOR VR_END
#define VR_TIME (VR_END + DY_NEV)
#define DY_DEFAULT_TOLERANCE 1e-6

static void free_integrator(void *integrator);     /* fmu_cosimulation.inc */

static double *vec(int n) { return calloc((size_t)(n > 0 ? n : 1), sizeof(double)); }

void dy_log(DyInstance *c, int status, const char *category, const char *message) {
    if (c && c->logger.write && (c->logging || status >= DY_WARNING))
        c->logger.write(c->logger.environment, c->logger.function, c->name, status, category, message);
}

int dy_fail(DyInstance *c, const char *message) {
    char text[512];
    snprintf(text, sizeof text, "%s (t = %.17g)", message, c->t);
    dy_log(c, DY_ERROR, "logStatusError", text);
    return DY_ERROR;
}

/* ---- the model's vectors ---------------------------------------------------------------------- */
static int refresh_parameters(DyInstance *c) {
    if (c->parameters_fresh) return 0;
    {
        const double *in[2] = {c->p_user, c->mask};
        double *out[1] = {c->p};
        if (dy_call(c, DY_PARAMS, 2, in, 1, out)) return -1;
    }
    c->parameters_fresh = 1;
    c->values_fresh = 0;
    return 0;
}

static void set_internal(DyInstance *c, int index, double value) {
    c->p_user[index] = value;
    c->p[index] = value;
    c->mask[index] = 1.0;
    c->values_fresh = 0;
}

static int solve_values(DyInstance *c) {
    if (refresh_parameters(c)) return -1;
    if (c->values_fresh) return 0;
    if (dy_solve_algebraic(c, DY_NEWTON)) return -1;
    c->values_fresh = 1;
    return 0;
}

static int evaluate(DyInstance *c, double *ode, double *y) {
    double t = c->t;
    const double *in[4] = {c->x, c->z, c->p, &t};
    if (solve_values(c)) return -1;
    if (ode) { double *out[2] = {ode, NULL}; if (dy_call(c, DY_DAE, 4, in, 2, out)) return -1; }
    if (y) { double *out[1] = {y}; if (dy_call(c, DY_OUTPUTS, 4, in, 1, out)) return -1; }
    return 0;
}

/* The declared min/max of the model's variables at the current point (compiler/runtime/checks.py's
   indicators, negative outside by more than round-off): DY_OK, or DY_ERROR with the first bound
   left logged, as `dyadc simulate --strict-bounds` stops a run. */
static int check_bounds(DyInstance *c) {
#if DY_NBOUND > 0
    double rows[DY_NBOUND], y[DY_NY + 1], t = c->t;
    const double *in[4] = {c->x, c->z, c->p, &t};
    double *out[1] = {rows};
    int k;
    if (evaluate(c, NULL, y) || dy_call(c, DY_BOUNDS, 4, in, 1, out))
        return dy_fail(c, "the algebraic equations have no solution at these states");
    for (k = 0; k < DY_NBOUND; k++)
        if (!(rows[k] >= 0.0)) {
            char text[400];
            snprintf(text, sizeof text, "%s = %.6g is outside its declared %s = %g: the model left its domain",
                     DY_BOUND_NAME[k], y[DY_BOUND_ROW[k]], DY_BOUND_KIND[k] ? "max" : "min", DY_BOUND_VALUE[k]);
            return dy_fail(c, text);
        }
#else
    (void)c;
#endif
    return DY_OK;
}

/* ---- events ------------------------------------------------------------------------------------ */
/* The first time event strictly after t (0 when there is none). */
static int next_time_event(DyInstance *c, double t, double *found) {
#if DY_NTE > 0
    double offsets[DY_NTE], periods[DY_NTE], eps = 1e-12 * (1.0 + fabs(t));
    const double *in[1] = {c->p};
    double *out[2] = {offsets, periods};
    int i, any = 0;
    if (dy_call(c, DY_TIME_EVENTS, 1, in, 2, out)) return 0;
    for (i = 0; i < DY_NTE; i++) {
        double candidate = offsets[i];
        if (!isfinite(candidate)) continue;
        if (isfinite(periods[i]) && periods[i] > 0 && candidate <= t + eps)
            candidate += periods[i] * ceil((t + eps - candidate) / periods[i]);
        if (candidate <= t + eps && isfinite(periods[i]) && periods[i] > 0) candidate += periods[i];
        if (candidate > t + eps && (!any || candidate < *found)) { *found = candidate; any = 1; }
    }
    return any;
#else
    (void)c; (void)t; (void)found;
    return 0;
#endif
}

/* The segment from t on: the next time event and the event clock in its middle. */
static void start_segment(DyInstance *c) {
    double next = 0.0;
    c->next_event_defined = next_time_event(c, c->t, &next);
    c->next_event = next;
#if DY_CLOCK >= 0
    set_internal(c, DY_CLOCK, c->next_event_defined ? 0.5 * (c->t + next) : c->t + 1.0);
#endif
}

static int event_indicators(DyInstance *c, double *zeros) {
#if DY_NEV > 0
    double t = c->t;
    const double *in[4] = {c->x, c->z, c->p, &t};
    double *out[1] = {zeros};
    if (solve_values(c)) return -1;
    return dy_call(c, DY_EVENTS, 4, in, 1, out);
#else
    (void)c; (void)zeros;
    return 0;
#endif
}

#if DY_NLOCK > 0
/* The indicators a short explicit step ahead (x + h der(x), t + h): the side a relation takes
   when its zero function is exactly zero at the event (a sine source starting at 0). */
static int indicators_ahead(DyInstance *c, double *zeros) {
    double x0[DY_NX + 1], z0[DY_NZ + 1], ode[DY_NX + 1], t0 = c->t, h = 1e-8 * (1.0 + fabs(c->t));
    int i, status;
    if (evaluate(c, ode, NULL)) return -1;
    memcpy(x0, c->x, DY_NX * sizeof(double));
    memcpy(z0, c->z, DY_NZ * sizeof(double));
    for (i = 0; i < DY_NX; i++) c->x[i] += h * ode[i];
    c->t = t0 + h;
    c->values_fresh = 0;
    status = event_indicators(c, zeros);
    memcpy(c->x, x0, DY_NX * sizeof(double));
    memcpy(c->z, z0, DY_NZ * sizeof(double));
    c->t = t0;
    c->values_fresh = 1;
    return status;
}
#endif

/* Modelica's event iteration: every lock set to its relation's value, z solved again, until the
   relations no longer change; where they never settle, every relation is evaluated as written. */
static int settle_relations(DyInstance *c) {
#if DY_NLOCK > 0
    double zeros[DY_NEV], zeros_ahead[DY_NEV], z_start[DY_NZ + 1];
    int it, k;
    memcpy(z_start, c->z, DY_NZ * sizeof(double));
    for (it = 0; it < EVENT_ITERATIONS; it++) {
        int changed = 0;
        int ahead = 0;
        if (event_indicators(c, zeros)) break;
        for (k = 0; k < DY_NLOCK; k++) if (zeros[DY_LOCK_ROW[k]] == 0.0) ahead = 1;
        if (ahead && indicators_ahead(c, zeros_ahead)) break;
        for (k = 0; k < DY_NLOCK; k++) {
            double g0 = zeros[DY_LOCK_ROW[k]], g = DY_LOCK_SIGN[k] * (g0 == 0.0 ? zeros_ahead[DY_LOCK_ROW[k]] : g0);
            int op = DY_LOCK_OP[k];
            double value = (op == 0 ? g > 0 : op == 1 ? g >= 0 : op == 2 ? g < 0 : g <= 0) ? 1.0 : 0.0;
            if (c->p[DY_LOCK_PARAM[k]] != value) { set_internal(c, DY_LOCK_PARAM[k], value); changed = 1; }
        }
        if (!changed) return 0;
    }
    for (k = 0; k < DY_NLOCK; k++) set_internal(c, DY_LOCK_PARAM[k], LIVE);
    memcpy(c->z, z_start, DY_NZ * sizeof(double));
    return solve_values(c);
#else
    return solve_values(c);
#endif
}

static int initialize(DyInstance *c) {
    int k;
    if (refresh_parameters(c)) return -1;
    for (k = 0; k < DY_NLOCK; k++) set_internal(c, DY_LOCK_PARAM[k], LIVE);
    start_segment(c);
    memcpy(c->x, DY_X_GUESS, DY_NX * sizeof(double));
    memcpy(c->z, DY_Z_GUESS, DY_NZ * sizeof(double));
    if (dy_solve_initial(c, DY_INIT, DY_NINIT)) return -1;
    c->values_fresh = 0;           /* z polished by Newton to round-off from the initial point */
    return settle_relations(c);
}

/* ---- instances --------------------------------------------------------------------------------- */
static void free_instance(DyInstance *c) {
    if (!c) return;
    free(c->name); free(c->x); free(c->z); free(c->p_user); free(c->mask); free(c->p);
    free(c->residual); free(c->jacobian); free(c->work); free(c->scratch); free(c->pivots);
    free(c->iw); free(c->w); free((void *)c->arg); free(c->res);
    free_integrator(c->integrator);
    free(c);
}

static int allocate_work(DyInstance *c) {
    dy_int most[4] = {8, 8, 1, 1}, sizes[4];
    int i, j, n = DY_NX + DY_NZ + DY_NU, rows = DY_NX + DY_NZ + DY_NOUT;
    for (i = 0; i < (int)(sizeof DY_WORKS / sizeof DY_WORKS[0]); i++) {
        if (DY_WORKS[i](&sizes[0], &sizes[1], &sizes[2], &sizes[3])) return -1;
        for (j = 0; j < 4; j++) if (sizes[j] > most[j]) most[j] = sizes[j];
    }
    c->arg = calloc((size_t)most[0], sizeof(double *));
    c->res = calloc((size_t)most[1], sizeof(double *));
    c->iw = calloc((size_t)most[2], sizeof(dy_int));
    c->w = calloc((size_t)most[3], sizeof(double));
    c->residual = vec(DY_NZ);
    c->jacobian = vec(DY_NZ * DY_NZ);
    c->work = vec(n);
    c->scratch = vec(rows * n + rows + n);
    c->pivots = calloc((size_t)(DY_NZ + DY_NX + 1), sizeof(int));
    c->x = vec(DY_NX); c->z = vec(DY_NZ); c->p = vec(DY_NP);
    c->p_user = vec(DY_NP); c->mask = vec(DY_NP);
    return (c->arg && c->res && c->iw && c->w && c->residual && c->jacobian && c->work && c->scratch
            && c->pivots && c->x && c->z && c->p && c->p_user && c->mask) ? 0 : -1;
}

static void reset_values(DyInstance *c) {
    memcpy(c->p_user, DY_P_DEFAULT, DY_NP * sizeof(double));
    memcpy(c->mask, DY_P_MASK, DY_NP * sizeof(double));
    memcpy(c->x, DY_X_GUESS, DY_NX * sizeof(double));
    memcpy(c->z, DY_Z_GUESS, DY_NZ * sizeof(double));
    c->parameters_fresh = 0;
    c->values_fresh = 0;
    c->mode = DY_INSTANTIATED;
    c->t = 0.0;
    c->step = 0.0;                 /* Co-Simulation: the first step size is chosen again */
}

DyInstance *dy_instantiate(const char *name, const char *token, int cosimulation, int logging, DyLogger logger) {
    DyInstance *c = calloc(1, sizeof(DyInstance));
    if (!c) return NULL;
    c->logger = logger;
    name = name ? name : "dyadc";
    c->name = malloc(strlen(name) + 1);
    if (c->name) memcpy(c->name, name, strlen(name) + 1);
    c->logging = logging;
    c->nx = DY_NX; c->nz = DY_NZ; c->np = DY_NP;
    c->cosimulation = cosimulation;
    c->tolerance = DY_DEFAULT_TOLERANCE;
    if (!token || strcmp(token, DY_GUID) != 0) {
        dy_log(c, DY_ERROR, "logStatusError", "the GUID (instantiation token) does not match this FMU's "
                                               "modelDescription.xml");
        free_instance(c); return NULL;
    }
    if (allocate_work(c)) { free_instance(c); return NULL; }
    reset_values(c);
    return c;
}

void dy_free_instance(DyInstance *c) { free_instance(c); }
void dy_reset(DyInstance *c) { reset_values(c); }
int dy_set_mode(DyInstance *c, int mode) { c->mode = mode; return DY_OK; }

int dy_setup_experiment(DyInstance *c, double tolerance, double start) {
    c->t = start;
    c->values_fresh = 0;
    if (tolerance > 0) c->tolerance = tolerance;
    return DY_OK;
}

int dy_exit_initialization(DyInstance *c) {
    if (initialize(c)) return dy_fail(c, "initialization failed: the initial conditions are inconsistent or have no "
                                         "solution near the guesses");
    c->mode = c->cosimulation ? DY_STEP : DY_EVENT;
    return check_bounds(c);
}

#include "fmu_values.inc"
#include "fmu_state.inc"
#include "fmu_cosimulation.inc"
