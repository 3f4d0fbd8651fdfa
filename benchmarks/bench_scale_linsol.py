"""`bench_scale.py linsol` and `forms`: the whole simulation of the N-link chain per form of the
DAE (torn, sparse, the automatic choice) and per linear solver of CasADi's IDAS, and the tables."""
from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

from bench_scale_common import fit, read_rows

SOLVERS = ["qr", "csparse", "lapacklu", "lapackqr", "mumps", "gmres"]


def linsol_rows(sizes: list[int], repeats: int, solvers: list[str] = SOLVERS, form: str = "chosen"):
    """`form`: "torn" (every block torn, today's form), "sparse" (compiler/structure/causalize.py's
    sparse form wherever the torn form is dense, at every N) or "chosen" (the automatic choice);
    solver "auto": no option (compiler/runtime/linear_solver.py chooses)."""
    import casadi as ca
    import numpy as np
    from suite.chain_model import write_chain
    from compiler import runtime
    from compiler.cache.c_code import on_vm
    from compiler.pipeline import compile_spec
    from compiler.structure import causalize

    if form == "torn":
        causalize.DENSE_FROM = 2.0
    elif form == "sparse":
        causalize.SPARSE_FORM_FROM = 0
    with tempfile.TemporaryDirectory(prefix="dyadc-scale-") as tmp:
        for n in sizes:
            # on the VM, as measured before runs settled an undecided model on C (2026-11-28)
            model = on_vm(compile_spec(write_chain(n, Path(tmp))).model)
            nx, nz, npar = model.sizes
            x, z, p, t = ca.SX.sym("x", nx), ca.SX.sym("z", nz), ca.SX.sym("p", npar), ca.SX.sym("t")
            ode, alg = model.dae(x, z, p, t)
            nnz = ca.jacobian(ca.vertcat(ode, alg), ca.vertcat(x, z)).sparsity().nnz()
            row = {"n": n, "form": form, "unknowns": nx + nz, "jacobian_nnz": nnz, "density": nnz / (nx + nz) ** 2}
            reference = None
            for solver in solvers:
                options = {"newton_scheme": solver} if solver == "gmres" else \
                    {} if solver == "auto" else {"linear_solver": solver}
                times = []
                try:
                    for _ in range(repeats):
                        began = time.process_time()
                        result = runtime.simulate(model, 0.5, rtol=1e-6, atol=1e-6, points=51,
                                                  progress=False, integrator_options=options)
                        times.append(time.process_time() - began)
                except Exception as err:                      # a solver that fails is reported
                    row[solver] = {"failed": str(err).splitlines()[-1][:120]}
                    continue
                last = np.asarray(result[model.state_names[-1]])
                if reference is None:
                    reference, row["last_joint"] = last, [float(v) for v in last]
                row[solver] = {"seconds": statistics.median(times), "steps": int(result.stats.get("steps", 0)),
                               "deviation": float(np.max(np.abs(last - reference)))}
            yield row


def linsol_table(rows: list[dict]) -> list[str]:
    lines = ["| N | unknowns | Jacobian nnz (density) | " + " | ".join(SOLVERS) + " | steps |",
             "|---" * (len(SOLVERS) + 4) + "|"]
    for r in rows:
        cells = []
        for s in SOLVERS:
            v = r.get(s, {})
            cells.append(f"{v['seconds']:.3f} ({v['deviation']:.0e})" if "seconds" in v
                         else "failed" if "failed" in v else "-")
        steps = "/".join(str(r[s]["steps"]) for s in ("qr", "gmres") if "steps" in r.get(s, {}))
        lines.append(f"| {r['n']} | {r['unknowns']} | {r['jacobian_nnz']} ({r['density']:.2f}) | "
                     + " | ".join(cells) + f" | {steps} |")
    fits = [(s, fit(rows, lambda r, s=s: r.get(s, {}).get("seconds"))) for s in SOLVERS]
    lines += ["", "Growth exponents (N >= 8): " + ", ".join(f"{s} {f:.2f}" for s, f in fits if f is not None), ""]
    return lines


def forms_table(torn: str, sparse: str, chosen: str) -> list[str]:
    """Markdown: per N the torn and the sparse form with each solver measured, the automatic
    choice, growth exponents (fit over N >= 8), and how far the forms' last joint angles differ."""
    import numpy as np
    forms = {"torn": {r["n"]: r for r in read_rows(torn)}, "sparse": {r["n"]: r for r in read_rows(sparse)},
             "chosen": {r["n"]: r for r in read_rows(chosen)}}
    columns = [(form, s) for form in ("torn", "sparse")
               for s in SOLVERS + ["auto"] if any(s in r for r in forms[form].values())]
    columns.append(("chosen", "auto"))
    header = ["N", "torn: unknowns (density)", "sparse: unknowns (density)"] + \
        [f"{form} {s}" for form, s in columns] + ["chosen form", "torn vs sparse"]
    lines = ["| " + " | ".join(header) + " |", "|---" * len(header) + "|"]
    for n in sorted(forms["chosen"]):
        cells = [str(n)]
        for form in ("torn", "sparse"):
            r = forms[form].get(n)
            cells.append(f"{r['unknowns']} ({r['density']:.3f})" if r else "-")
        for form, s in columns:
            v = forms[form].get(n, {}).get(s, {})
            cells.append(f"{v['seconds']:.3f}" if "seconds" in v else "failed" if "failed" in v else "-")
        c, t, sp = forms["chosen"][n], forms["torn"].get(n), forms["sparse"].get(n)
        cells.append("sparse" if t and c["unknowns"] != t["unknowns"] else "torn")
        gap = np.max(np.abs(np.subtract(t["last_joint"], sp["last_joint"]))) \
            if t and sp and "last_joint" in t and "last_joint" in sp else None
        cells.append(f"{gap:.1e}" if gap is not None else "-")
        lines.append("| " + " | ".join(cells) + " |")
    fits = []
    for form, s in columns:
        rows = [forms[form][n] for n in sorted(forms[form])]
        f = fit(rows, lambda r, s=s: r.get(s, {}).get("seconds"))
        if f is not None:
            fits.append(f"{form} {s} {f:.2f}")
    return lines + ["", "Growth exponents (fit over N >= 8): " + ", ".join(fits), ""]
