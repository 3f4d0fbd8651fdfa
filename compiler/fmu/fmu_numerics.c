/* Dense numerics of a dyadc FMU: LU with partial pivoting, Newton on the algebraic equations and
   Levenberg-Marquardt on the initialization system, the same methods as dyadc's runtime
   (compiler/runtime/initialization.py, compiler/linear/elimination.py) written for C. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmu_instance.h"

#define NEWTON_TOL 1e-12
#define NEWTON_ITERATIONS 50
#define INIT_TOL 1e-10
#define INIT_ITERATIONS 200

int dy_call(DyInstance *c, dy_eval f, int n_in, const double **in, int n_out, double **out) {
    int i;
    for (i = 0; i < n_in; i++) c->arg[i] = in[i];
    for (i = 0; i < n_out; i++) c->res[i] = out[i];
    return f(c->arg, c->res, c->iw, c->w, 0);
}

int dy_lu_factor(int n, double *a, int *pivots) {
    int i, j, k;
    for (k = 0; k < n; k++) {
        int best = k;
        double largest = fabs(a[k + k * n]);
        for (i = k + 1; i < n; i++)
            if (fabs(a[i + k * n]) > largest) { largest = fabs(a[i + k * n]); best = i; }
        if (!(largest > 0.0) || !isfinite(largest)) return -1;
        pivots[k] = best;
        if (best != k)
            for (j = 0; j < n; j++) { double s = a[k + j * n]; a[k + j * n] = a[best + j * n]; a[best + j * n] = s; }
        for (i = k + 1; i < n; i++) {
            double factor = a[i + k * n] / a[k + k * n];
            a[i + k * n] = factor;
            for (j = k + 1; j < n; j++) a[i + j * n] -= factor * a[k + j * n];
        }
    }
    return 0;
}

void dy_lu_apply(int n, const double *lu, const int *pivots, double *b) {
    int i, j, k;
    for (k = 0; k < n; k++)          /* every row swap first: the factors hold the rows swapped */
        if (pivots[k] != k) { double s = b[k]; b[k] = b[pivots[k]]; b[pivots[k]] = s; }
    for (k = 0; k < n; k++)
        for (i = k + 1; i < n; i++) b[i] -= lu[i + k * n] * b[k];
    for (k = n - 1; k >= 0; k--) {
        double s = b[k];
        for (j = k + 1; j < n; j++) s -= lu[k + j * n] * b[j];
        b[k] = s / lu[k + k * n];
    }
}

int dy_lu_solve(int n, double *a, double *b, int *pivots) {
    if (dy_lu_factor(n, a, pivots)) return -1;
    dy_lu_apply(n, a, pivots, b);
    return 0;
}

static double max_abs(int n, const double *v) {
    double m = 0.0;
    int i;
    for (i = 0; i < n; i++) if (fabs(v[i]) > m) m = fabs(v[i]);
    return m;
}

/* Converged: every step component below NEWTON_TOL relative to its own unknown, or (round-off
   in unknowns of mixed scales) the whole step below NEWTON_TOL relative to the largest unknown
   and no longer shrinking quadratically. */
static int newton_converged(int nz, const double *step, const double *z, double previous) {
    int i;
    double largest = max_abs(nz, step);
    for (i = 0; i < nz; i++) if (fabs(step[i]) > NEWTON_TOL * (1.0 + fabs(z[i]))) break;
    if (i == nz) return 1;
    return largest <= NEWTON_TOL * (1.0 + max_abs(nz, z)) && largest >= 0.25 * previous;
}

int dy_solve_algebraic(DyInstance *c, dy_eval newton) {
    int nz = c->nz, it, i;
    double t = c->t, previous = INFINITY;
    if (nz == 0) return 0;
    for (it = 0; it < NEWTON_ITERATIONS; it++) {
        const double *in[4] = {c->x, c->z, c->p, &t};
        double *out[2] = {c->residual, c->jacobian};
        if (dy_call(c, newton, 4, in, 2, out)) return -1;
        for (i = 0; i < nz; i++) if (!isfinite(c->residual[i])) return -1;
        if (dy_lu_solve(nz, c->jacobian, c->residual, c->pivots)) return -1;
        for (i = 0; i < nz; i++) c->z[i] -= c->residual[i];
        if (newton_converged(nz, c->residual, c->z, previous)) return 0;
        previous = max_abs(nz, c->residual);
    }
    return -1;
}

/* r and J at w = (x, z); J column-major rows x n with non-finite entries read as 0. */
static int init_evaluate(DyInstance *c, dy_eval init, int rows, const double *w, double *r, double *jac) {
    double t = c->t;
    const double *in[4] = {w, w + c->nx, c->p, &t};
    double *out[2] = {r, jac};
    int i, n = c->nx + c->nz;
    if (dy_call(c, init, 4, in, 2, out)) return -1;
    for (i = 0; i < rows * n; i++) if (!isfinite(jac[i])) jac[i] = 0.0;
    return 0;
}

/* Row scales (largest |J| of each row) and the scaled cost 0.5 |r / scale|^2. */
static double scaled_cost(int rows, int n, const double *r, const double *jac, double *scales) {
    double cost = 0.0;
    int i, j;
    for (i = 0; i < rows; i++) {
        double m = 0.0;
        for (j = 0; j < n; j++) if (fabs(jac[i + j * rows]) > m) m = fabs(jac[i + j * rows]);
        scales[i] = m > 1e-300 ? m : 1.0;
        if (!isfinite(r[i])) return INFINITY;
        cost += 0.5 * (r[i] / scales[i]) * (r[i] / scales[i]);
    }
    return cost;
}

static double largest_scaled_residual(int rows, const double *r, const double *scales, int n, const double *w) {
    double m = 0.0, size = 1.0 + max_abs(n, w);
    int i;
    for (i = 0; i < rows; i++) {
        double v = fabs(r[i]) / scales[i] / size;
        if (!isfinite(v)) return INFINITY;
        if (v > m) m = v;
    }
    return m;
}

/* The damped step: (Jr' Jr + lam diag(Jr' Jr)) s = -Jr' rr, Jr and rr row-scaled. */
static int damped_step(int rows, int n, const double *r, const double *jac, const double *scales,
                       double lam, double *normal, double *s, int *pivots) {
    int i, j, k;
    for (j = 0; j < n; j++) {
        double g = 0.0;
        for (k = 0; k < rows; k++) g += jac[k + j * rows] / scales[k] * r[k] / scales[k];
        s[j] = -g;
        for (i = 0; i < n; i++) {
            double v = 0.0;
            for (k = 0; k < rows; k++) v += jac[k + i * rows] * jac[k + j * rows] / (scales[k] * scales[k]);
            normal[i + j * n] = v;
        }
    }
    for (j = 0; j < n; j++) normal[j + j * n] += lam * (normal[j + j * n] > 1e-300 ? normal[j + j * n] : 1.0) + 1e-300;
    return dy_lu_solve(n, normal, s, pivots);
}

int dy_solve_initial(DyInstance *c, dy_eval init, int rows) {
    int n = c->nx + c->nz, it, tries, j, status = -1;
    size_t big = (size_t)(rows > n ? rows : n);
    double *w = calloc(n + 1, sizeof(double)), *trial = calloc(n + 1, sizeof(double));
    double *r = calloc(rows + 1, sizeof(double)), *r_new = calloc(rows + 1, sizeof(double));
    double *jac = calloc(big * n + 1, sizeof(double)), *jac_new = calloc(big * n + 1, sizeof(double));
    double *scales = calloc(rows + 1, sizeof(double)), *scales_new = calloc(rows + 1, sizeof(double));
    double *normal = calloc((size_t)n * n + 1, sizeof(double)), *s = calloc(n + 1, sizeof(double));
    double lam = 0.0, cost;
    if (!w || !trial || !r || !r_new || !jac || !jac_new || !scales || !scales_new || !normal || !s) goto done;
    memcpy(w, c->x, c->nx * sizeof(double));
    memcpy(w + c->nx, c->z, c->nz * sizeof(double));
    if (init_evaluate(c, init, rows, w, r, jac)) goto done;
    cost = scaled_cost(rows, n, r, jac, scales);
    for (it = 0; it < INIT_ITERATIONS && isfinite(cost); it++) {
        int accepted = 0;
        if (largest_scaled_residual(rows, r, scales, n, w) <= INIT_TOL * 1e-3) break;
        for (tries = 0; tries < 30; tries++) {
            double cost_new;
            if (damped_step(rows, n, r, jac, scales, lam, normal, s, c->pivots)) { lam = lam > 0 ? 10 * lam : 1e-6; continue; }
            for (j = 0; j < n; j++) trial[j] = w[j] + s[j];
            if (init_evaluate(c, init, rows, trial, r_new, jac_new)) goto done;
            cost_new = scaled_cost(rows, n, r_new, jac_new, scales_new);
            if (cost_new < cost) { accepted = 1; lam = lam / 3.0 < 1e-9 ? 0.0 : lam / 3.0; break; }
            lam = lam > 0 ? 10 * lam : 1e-6;
        }
        if (!accepted) break;
        memcpy(w, trial, n * sizeof(double));
        memcpy(r, r_new, rows * sizeof(double));
        memcpy(jac, jac_new, (size_t)rows * n * sizeof(double));
        cost = scaled_cost(rows, n, r, jac, scales);
        if (max_abs(n, s) <= 1e-15 * (1.0 + max_abs(n, w))) break;
    }
    if (largest_scaled_residual(rows, r, scales, n, w) <= INIT_TOL) {
        memcpy(c->x, w, c->nx * sizeof(double));
        memcpy(c->z, w + c->nx, c->nz * sizeof(double));
        status = 0;
    }
done:
    free(w); free(trial); free(r); free(r_new); free(jac); free(jac_new);
    free(scales); free(scales_new); free(normal); free(s);
    return status;
}
