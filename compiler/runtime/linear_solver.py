"""Which linear solver IDAS's Newton iteration uses, chosen from the size of the model.

CasADi's IDAS factorizes the iteration matrix dF/dy' * c + dF/dy with one of CasADi's linear
solver plugins (option `linear_solver`; its default is CasADi's own sparse QR, "qr"). Measured
on the N-link pendulum chain (benchmarks/bench_scale.py linsol, table in docs/scaling.md; CPU
time of a 0.5 s run at rtol 1e-6): with 24 unknowns all direct solvers are within 2 % (noise);
with 48 CSparse's LU and LAPACK's dense LU are 7-9 % faster than the default; with 96 and 192
CSparse is 23 % and 49 % faster, dense LU 16 % and 40 % (and falls further behind above: the
Jacobian has a third of its entries filled, but LAPACK here is reference BLAS); LAPACK QR and
MUMPS are slower everywhere; the Krylov scheme (newton_scheme gmres) moves the trajectories by
1e-8 where the direct solvers agree to 1e-13. So: CSparse from SPARSE_LU_FROM unknowns on, no
dense LU (it never wins beyond noise).

Below the threshold the default stays: small models (the excavator, every golden trajectory)
keep bit-for-bit the trajectories they had. Options the caller passes (integrator_options) win.
"""
from __future__ import annotations

import casadi as ca

# Unknowns (states + IDAS algebraics) from which CSparse's LU replaces CasADi's default QR.
SPARSE_LU_FROM = 40
SPARSE_LU = "csparse"


def linear_solver_options(n_unknowns: int) -> dict:
    """IDAS options for a DAE with `n_unknowns` unknowns: {} keeps CasADi's default."""
    if n_unknowns >= SPARSE_LU_FROM and ca.has_linsol(SPARSE_LU):
        return {"linear_solver": SPARSE_LU}
    return {}
