"""Andrews' squeezing mechanism (seven-body mechanism), index-1 (ODE) formulation.

Source of the model and data: the Test Set for IVP Solvers (F. Mazzia, C. Magherini et al.,
University of Bari), problem ANDREWS, itself from Hairer & Wanner, Solving ODEs II,
sec. VII.7, and Schiehlen (1990). The equations below (mass matrix M, forces f, constraint
Jacobian G, constraints g) are restated from the Test Set's description of the index-3 DAE

    q' = v,   M(q) v' = f(q, v) - G(q)^T lambda,   0 = g(q)          (q: 7 angles, 6 multipliers)

Here the constraint is differentiated twice (index 1): with g'' = G v' + g_qq(q, v) = 0,

    [ M  G^T ] [ v'     ]   [ f       ]
    [ G  0   ] [ lambda ] = [ -g_qq   ]

where g_qq = sum_jk d2g/dq_j dq_k v_j v_k is derived by hand from g (every term of g is
a*cos or a*sin of one angle or of a sum of two angles, whose second time derivative at
zero acceleration is minus itself times the squared rate). Consistent initial values and
the reference solution at t = 0.03 (PSIDE on a Cray C90, rtol = atol = 1e-14) are the Test
Set's: andsoln in andrews.f, y(1..7) = the angles beta, Theta, gamma, Phi, delta, Omega,
epsilon; y(8..14) their rates.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

PARAMS = dict(
    m1=.04325, m2=.00365, m3=.02373, m4=.00706, m5=.07050, m6=.00706, m7=.05498,
    xa=-.06934, ya=-.00227, xb=-0.03635, yb=.03273, xc=.014, yc=.072, c0=4530.0,
    i1=2.194e-6, i2=4.410e-7, i3=5.255e-6, i4=5.667e-7, i5=1.169e-5, i6=5.667e-7, i7=1.912e-5,
    d=28e-3, da=115e-4, e=2e-2, ea=1421e-5, rr=7e-3, ra=92e-5, l0=7785e-5,
    ss=35e-3, sa=1874e-5, sb=1043e-5, sc=18e-3, sd=2e-2, ta=2308e-5, tb=916e-5,
    u=4e-2, ua=1228e-5, ub=449e-5, zf=2e-2, zt=4e-2, fa=1421e-5, mom=33e-3,
)
ANGLE_NAMES = ("beta", "Theta", "gamma", "Phi", "delta", "Omega", "epsilon")
Q0 = np.array([
    -0.0617138900142764496358948458001, 0.0, 0.455279819163070380255912382449,
    0.222668390165885884674473185609, 0.487364979543842550225598953530,
    -0.222668390165885884674473185609, 1.23054744454982119249735015568,
])
Y0 = np.concatenate([Q0, np.zeros(7)])
# Test Set's consistent initial accelerations (beta'', Theta''; the others are 0) and multipliers
INITIAL_ACCELERATIONS = np.array([14222.4439199541138705911625887, -10666.8329399655854029433719415,
                                  0.0, 0.0, 0.0, 0.0, 0.0])
INITIAL_MULTIPLIERS = np.array([98.5668703962410896057654982170, -6.12268834425566265503114393122,
                                0.0, 0.0, 0.0, 0.0])
T_END = 0.03
REFERENCE_ANGLES = np.array([
    0.1581077119629904e+2, -0.1575637105984298e+2, 0.4082224013073101e-1, -0.5347301163226948e+0,
    0.5244099658805304e+0, 0.5347301163226948e+0, 0.1048080741042263e+1,
])
REFERENCE_RATES = np.array([
    0.1139920302151208e+4, -0.1424379294994111e+4, 0.1103291221937134e+2, 0.1929337464421385e+2,
    0.5735699284790808e+0, -0.1929337464421385e+2, 0.3231791658026955e+0,
])
REFERENCE_MULTIPLIERS = np.array([
    0.1991753333731910e+3, -0.2975531228015052e+2, 0.2306654119098399e+2, 0.3145271365475927e+2,
    0.2264249232082739e+2, 0.1161740700019673e+2,
])


def _trig(q):
    be, th, ga, ph, de, om, ep = q
    return dict(
        sibe=np.sin(be), sith=np.sin(th), siga=np.sin(ga), siph=np.sin(ph), side=np.sin(de),
        siom=np.sin(om), siep=np.sin(ep), cobe=np.cos(be), coth=np.cos(th), coga=np.cos(ga),
        coph=np.cos(ph), code=np.cos(de), coom=np.cos(om), coep=np.cos(ep),
        sibeth=np.sin(be + th), cobeth=np.cos(be + th), siphde=np.sin(ph + de),
        cophde=np.cos(ph + de), siomep=np.sin(om + ep), coomep=np.cos(om + ep),
    )


def mass_matrix(q, P=PARAMS):
    c = _trig(q)
    p = P
    M = np.zeros((7, 7), dtype=np.result_type(q, float))
    M[0, 0] = p["m1"] * p["ra"] ** 2 + p["m2"] * (p["rr"] ** 2 - 2 * p["da"] * p["rr"] * c["coth"] + p["da"] ** 2) + p["i1"] + p["i2"]
    M[1, 0] = p["m2"] * (p["da"] ** 2 - p["da"] * p["rr"] * c["coth"]) + p["i2"]
    M[1, 1] = p["m2"] * p["da"] ** 2 + p["i2"]
    M[2, 2] = p["m3"] * (p["sa"] ** 2 + p["sb"] ** 2) + p["i3"]
    eea = p["e"] - p["ea"]
    M[3, 3] = p["m4"] * eea ** 2 + p["i4"]
    M[4, 3] = p["m4"] * (eea ** 2 + p["zt"] * eea * c["siph"]) + p["i4"]
    M[4, 4] = (p["m4"] * (p["zt"] ** 2 + 2 * p["zt"] * eea * c["siph"] + eea ** 2)
               + p["m5"] * (p["ta"] ** 2 + p["tb"] ** 2) + p["i4"] + p["i5"])
    zfa = p["zf"] - p["fa"]
    M[5, 5] = p["m6"] * zfa ** 2 + p["i6"]
    M[6, 5] = p["m6"] * (zfa ** 2 - p["u"] * zfa * c["siom"]) + p["i6"]
    M[6, 6] = (p["m6"] * (zfa ** 2 - 2 * p["u"] * zfa * c["siom"] + p["u"] ** 2)
               + p["m7"] * (p["ua"] ** 2 + p["ub"] ** 2) + p["i6"] + p["i7"])
    lower = np.tril(M, -1)
    return M + lower.T


def forces(q, v, P=PARAMS):
    """Applied torque, spring force and velocity-dependent terms f(q, v)."""
    c = _trig(q)
    p = P
    bep, thp, _, php, dep, omp, epp = v
    xd = p["sd"] * c["coga"] + p["sc"] * c["siga"] + p["xb"]
    yd = p["sd"] * c["siga"] - p["sc"] * c["coga"] + p["yb"]
    lang = np.sqrt((xd - p["xc"]) ** 2 + (yd - p["yc"]) ** 2)
    force = -p["c0"] * (lang - p["l0"]) / lang
    fx, fy = force * (xd - p["xc"]), force * (yd - p["yc"])
    eea, zfa = p["e"] - p["ea"], p["zf"] - p["fa"]
    return np.array([
        p["mom"] - p["m2"] * p["da"] * p["rr"] * thp * (thp + 2 * bep) * c["sith"],
        p["m2"] * p["da"] * p["rr"] * bep ** 2 * c["sith"],
        fx * (p["sc"] * c["coga"] - p["sd"] * c["siga"]) + fy * (p["sd"] * c["coga"] + p["sc"] * c["siga"]),
        p["m4"] * p["zt"] * eea * dep ** 2 * c["coph"],
        -p["m4"] * p["zt"] * eea * php * (php + 2 * dep) * c["coph"],
        -p["m6"] * p["u"] * zfa * epp ** 2 * c["coom"],
        p["m6"] * p["u"] * zfa * omp * (omp + 2 * epp) * c["coom"],
    ])


def constraints(q, P=PARAMS):
    c = _trig(q)
    p = P
    common_x = p["rr"] * c["cobe"] - p["d"] * c["cobeth"]
    common_y = p["rr"] * c["sibe"] - p["d"] * c["sibeth"]
    return np.array([
        common_x - p["ss"] * c["siga"] - p["xb"],
        common_y + p["ss"] * c["coga"] - p["yb"],
        common_x - p["e"] * c["siphde"] - p["zt"] * c["code"] - p["xa"],
        common_y + p["e"] * c["cophde"] - p["zt"] * c["side"] - p["ya"],
        common_x - p["zf"] * c["coomep"] - p["u"] * c["siep"] - p["xa"],
        common_y - p["zf"] * c["siomep"] + p["u"] * c["coep"] - p["ya"],
    ])


def constraint_jacobian(q, P=PARAMS):
    c = _trig(q)
    p = P
    G = np.zeros((6, 7), dtype=np.result_type(q, float))
    for row in (0, 2, 4):
        G[row, 0] = -p["rr"] * c["sibe"] + p["d"] * c["sibeth"]
        G[row, 1] = p["d"] * c["sibeth"]
    for row in (1, 3, 5):
        G[row, 0] = p["rr"] * c["cobe"] - p["d"] * c["cobeth"]
        G[row, 1] = -p["d"] * c["cobeth"]
    G[0, 2] = -p["ss"] * c["coga"]
    G[1, 2] = -p["ss"] * c["siga"]
    G[2, 3] = -p["e"] * c["cophde"]
    G[2, 4] = -p["e"] * c["cophde"] + p["zt"] * c["side"]
    G[3, 3] = -p["e"] * c["siphde"]
    G[3, 4] = -p["e"] * c["siphde"] - p["zt"] * c["code"]
    G[4, 5] = p["zf"] * c["siomep"]
    G[4, 6] = p["zf"] * c["siomep"] - p["u"] * c["coep"]
    G[5, 5] = -p["zf"] * c["coomep"]
    G[5, 6] = -p["zf"] * c["coomep"] - p["u"] * c["siep"]
    return G


def constraint_curvature(q, v, P=PARAMS):
    """g_qq(q, v): the part of d2g/dt2 that does not contain the accelerations."""
    c = _trig(q)
    p = P
    bep, thp, gap, php, dep, omp, epp = v
    common_x = -p["rr"] * c["cobe"] * bep ** 2 + p["d"] * c["cobeth"] * (bep + thp) ** 2
    common_y = -p["rr"] * c["sibe"] * bep ** 2 + p["d"] * c["sibeth"] * (bep + thp) ** 2
    return np.array([
        common_x + p["ss"] * c["siga"] * gap ** 2,
        common_y - p["ss"] * c["coga"] * gap ** 2,
        common_x + p["e"] * c["siphde"] * (php + dep) ** 2 + p["zt"] * c["code"] * dep ** 2,
        common_y - p["e"] * c["cophde"] * (php + dep) ** 2 + p["zt"] * c["side"] * dep ** 2,
        common_x + p["zf"] * c["coomep"] * (omp + epp) ** 2 + p["u"] * c["siep"] * epp ** 2,
        common_y + p["zf"] * c["siomep"] * (omp + epp) ** 2 - p["u"] * c["coep"] * epp ** 2,
    ])


def accelerations_and_multipliers(q, v, P=PARAMS):
    M = mass_matrix(q, P)
    G = constraint_jacobian(q, P)
    kkt = np.zeros((13, 13), dtype=M.dtype)
    kkt[:7, :7] = M
    kkt[:7, 7:] = G.T
    kkt[7:, :7] = G
    sol = np.linalg.solve(kkt, np.concatenate([forces(q, v, P), -constraint_curvature(q, v, P)]))
    return sol[:7], sol[7:]


def rhs(t, y, P=PARAMS):
    acc, _ = accelerations_and_multipliers(y[:7], y[7:], P)
    return np.concatenate([y[7:], acc])


def jacobian(t, y, P=PARAMS):
    """Complex-step derivative of rhs (all operations are analytic)."""
    step = 1e-30
    J = np.empty((14, 14))
    for j in range(14):
        yc = y.astype(complex)
        yc[j] += 1j * step
        J[:, j] = rhs(t, yc, P).imag / step
    return J


def solve(t_eval=None, method="Radau", rtol=1e-10, atol=1e-10, use_jacobian=True):
    """solve_ivp of the index-1 formulation from the Test Set's consistent initial values."""
    t_eval = np.linspace(0.0, T_END, 31) if t_eval is None else np.asarray(t_eval, dtype=float)
    options = {"jac": jacobian} if method in ("Radau", "BDF", "LSODA") and use_jacobian else {}
    return solve_ivp(rhs, (0.0, float(t_eval[-1])), Y0, method=method, t_eval=t_eval, rtol=rtol,
                     atol=atol, **options)
