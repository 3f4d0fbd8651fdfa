"""Scaling of compile and simulation on the N-link pendulum chain (issue 15 item 5).

    .venv/bin/python benchmarks/bench_scale.py compile 8 16 32 64 128 256   -> JSON lines, per stage
    .venv/bin/python benchmarks/bench_scale.py linsol 8 16 32 64 128         -> JSON lines, per solver
    .venv/bin/python benchmarks/bench_scale.py linsol --form=torn|sparse|chosen --solvers=qr,auto N...
    .venv/bin/python benchmarks/bench_scale.py forms TORN SPARSE CHOSEN      -> markdown table (stdout)
    .venv/bin/python benchmarks/bench_scale.py cartesian N STOP              -> one JSON line
    .venv/bin/python benchmarks/bench_scale.py report FILE...                -> docs/scaling.md
    .venv/bin/python benchmarks/bench_scale.py compile-section B1,B2 A1,A2 NOTES [TITLE_B TITLE_A]
                                                        -> only the compile section of docs/scaling.md

`compile` times every structure pass separately (wrapping the pass functions, CPU time of this
process, so that other work on a shared machine inflates the numbers less than wall time would).
`linsol` simulates each chain (0.5 s, rtol = atol = 1e-6, 51 points, as benchmarks/suite/
compile_time.py does) with each linear solver CasADi's IDAS offers, median CPU time of `--repeats`.
Each mode runs in its own process; `report` turns saved JSON lines into docs/scaling.md.
"""
from __future__ import annotations

import functools
import importlib
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

# (module, function, label): the passes of one compile, in pipeline order
PASSES = [
    ("compiler.model.model_check", "require_standalone", "checks"),
    ("compiler.structure.reduce", "eliminate_aliases", "alias"),
    ("compiler.structure.reduce", "remove_derivative_dependencies", "derivative rank"),
    ("compiler.structure.index_reduction", "pantelides", "Pantelides"),
    ("compiler.structure.reduce", "reduce_index", "index reduction"),
    ("compiler.structure.reduce", "select_states", "dummy derivatives"),
    ("compiler.structure.reduce", "causalize", "causalize+tearing"),
    ("compiler.structure.reduce", "build_initial_problem", "initialization"),
    ("compiler.lower.state_set_variants", "monitored_levels", "state-set check"),
    ("compiler.lower.to_casadi", "lower", "lower"),
]
STAGES = ["parse", "flatten", "structure", "lower", "compile"]
SOLVERS = ["qr", "csparse", "lapacklu", "lapackqr", "mumps", "gmres"]


def _timed(spent: dict, label: str, function):
    @functools.wraps(function)
    def timed(*args, **kwargs):
        began = time.process_time()
        try:
            return function(*args, **kwargs)
        finally:
            spent[label] = spent.get(label, 0.0) + time.process_time() - began
    return timed


def compile_rows(sizes: list[int]):
    from suite.chain_model import write_chain
    from compiler.model.flatten import flatten_resolved
    from compiler.model.library import Library, resolve_model
    from compiler.pipeline import compile_flat
    from compiler.syntax.parser import parse_file

    spent: dict[str, float] = {}
    pipeline = importlib.import_module("compiler.pipeline")
    for module, name, label in PASSES:
        owner = importlib.import_module(module)
        timed = _timed(spent, label, getattr(owner, name))
        setattr(owner, name, timed)
        if getattr(pipeline, name, None) is not None:      # older pipelines import them eagerly
            setattr(pipeline, name, timed)
    parse = _timed(spent, "parse", parse_file)
    with tempfile.TemporaryDirectory(prefix="dyadc-scale-") as tmp:
        for n in [1, *sizes]:                       # N = 1: warm-up (parser tables, library)
            spent.clear()
            began = time.process_time()
            library = Library(parser=parse)
            flat = flatten_resolved(resolve_model(write_chain(n, Path(tmp)), library), library)
            flattened = time.process_time()
            compilation = compile_flat(flat)
            done = time.process_time()
            if n == 1 and 1 not in sizes:
                continue
            row = {"n": n, "equations": len(flat.equations), "states": len(compilation.model.state_names),
                   "algebraics": len(compilation.model.algebraic_names), **spent,
                   "flatten": flattened - began - spent.get("parse", 0.0),
                   "lower": spent.get("state-set check", 0.0) + spent.get("lower", 0.0),
                   "compile": done - began}
            row["structure"] = done - flattened - row["lower"]
            row["Pantelides"] = spent.get("Pantelides", 0.0)
            row["index reduction"] = spent.get("index reduction", 0.0) - row["Pantelides"]
            yield row


def linsol_rows(sizes: list[int], repeats: int, solvers: list[str] = SOLVERS, form: str = "chosen"):
    """`form`: "torn" (every block torn, today's form), "sparse" (compiler/structure/causalize.py's
    sparse form wherever the torn form is dense, at every N) or "chosen" (the automatic choice);
    solver "auto": no option (compiler/runtime/linear_solver.py chooses)."""
    import casadi as ca
    import numpy as np
    from suite.chain_model import write_chain
    from compiler import runtime
    from compiler.pipeline import compile_spec
    from compiler.structure import causalize

    if form == "torn":
        causalize.DENSE_FROM = 2.0
    elif form == "sparse":
        causalize.SPARSE_FORM_FROM = 0
    with tempfile.TemporaryDirectory(prefix="dyadc-scale-") as tmp:
        for n in sizes:
            model = compile_spec(write_chain(n, Path(tmp))).model
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


def cartesian_chain(n: int, theta0: float = 2.0) -> str:
    """N point masses on rigid rods in plain Cartesian equations (index 3), released from theta0:
    every rod passes the horizontal, so no single state set is valid for the whole run."""
    import math
    lines = [f'"""{n} point masses on rigid rods in Cartesian coordinates (generated by benchmarks)."""',
             f"component CartesianChain{n}", "  parameter L::Real = 1.0", "  parameter m::Real = 1.0",
             "  parameter g::Real = 9.80665", f"  parameter theta0::Real = {theta0}"]
    for i in range(1, n + 1):
        lines += [f"  variable x{i}::Real", f"  variable y{i}::Real(guess = {-i * math.cos(theta0):.6g})",
                  f"  variable u{i}::Real", f"  variable v{i}::Real", f"  variable lam{i}::Real(guess = 10)"]
    lines.append("relations")
    for i in range(1, n + 1):
        xp, yp = ("0", "0") if i == 1 else (f"x{i - 1}", f"y{i - 1}")
        pull_x = f" + lam{i + 1} * (x{i + 1} - x{i})" if i < n else ""
        pull_y = f" + lam{i + 1} * (y{i + 1} - y{i})" if i < n else ""
        lines += [f"  initial x{i} = {i} * L * sin(theta0)", f"  initial u{i} = 0",
                  f"  der(x{i}) = u{i}", f"  der(y{i}) = v{i}",
                  f"  m * der(u{i}) = -lam{i} * (x{i} - {xp}){pull_x}",
                  f"  m * der(v{i}) = -lam{i} * (y{i} - {yp}){pull_y} - m * g",
                  f"  (x{i} - {xp}) ^ 2 + (y{i} - {yp}) ^ 2 = L ^ 2"]
    return "\n".join(lines + ["end"]) + "\n"


def cartesian_row(n: int, stop: float) -> dict:
    """CPU seconds to compile and to simulate the Cartesian chain (the state-set monitor's load)."""
    from compiler import api
    with tempfile.TemporaryDirectory(prefix="dyadc-scale-") as tmp:
        path = Path(tmp) / f"CartesianChain{n}.dyad"
        path.write_text(cartesian_chain(n), encoding="utf-8")
        began = time.process_time()
        compilation = api.compile(f"{path}:CartesianChain{n}")
        compiled = time.process_time()
        result = api.simulate_compiled(compilation, stop, rtol=1e-6, atol=1e-6, points=201, progress=False)
        return {"n": n, "stop": stop, "compile": compiled - began, "simulate": time.process_time() - compiled,
                "switches": len(result.stats.get("state_switches", [])), "steps": int(result.stats.get("steps", 0))}


def _fit(rows: list[dict], key, lo: int = 8) -> float | None:
    import numpy as np
    points = [(r["n"], key(r)) for r in rows if r["n"] >= lo and key(r)]
    if len(points) < 2:
        return None
    n, t = zip(*points)
    return float(np.polyfit(np.log(n), np.log(t), 1)[0])


def _local(rows: list[dict], key) -> float | None:
    import math
    if len(rows) < 2 or not key(rows[-1]) or not key(rows[-2]):
        return None
    return math.log(key(rows[-1]) / key(rows[-2])) / math.log(rows[-1]["n"] / rows[-2]["n"])


def compile_table(rows: list[dict], title: str) -> list[str]:
    columns = ["parse", "flatten", "checks", "alias", "derivative rank", "Pantelides", "index reduction",
               "dummy derivatives", "causalize+tearing", "initialization", "structure", "lower", "compile"]
    lines = [f"#### {title}", "", "| N | equations | " + " | ".join(columns) + " |",
             "|---" * (len(columns) + 2) + "|"]
    for r in rows:
        lines.append(f"| {r['n']} | {r['equations']} | " + " | ".join(f"{r.get(c, 0.0):.2f}" for c in columns) + " |")
    fits = [(c, _fit(rows, lambda r, c=c: r.get(c)), _local(rows, lambda r, c=c: r.get(c))) for c in columns]
    lines += ["", "Growth exponents, least-squares over N >= 8 / local between the two largest N: "
              + ", ".join(f"{c} {f:.2f} / {l:.2f}" for c, f, l in fits if f is not None and l is not None), ""]
    return lines


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
    fits = [(s, _fit(rows, lambda r, s=s: r.get(s, {}).get("seconds"))) for s in SOLVERS]
    lines += ["", "Growth exponents (N >= 8): " + ", ".join(f"{s} {f:.2f}" for s, f in fits if f is not None), ""]
    return lines


def forms_table(torn: str, sparse: str, chosen: str) -> list[str]:
    """Markdown: per N the torn and the sparse form with each solver measured, the automatic
    choice, growth exponents (fit over N >= 8), and how far the forms' last joint angles differ."""
    import numpy as np
    forms = {"torn": {r["n"]: r for r in _read(torn)}, "sparse": {r["n"]: r for r in _read(sparse)},
             "chosen": {r["n"]: r for r in _read(chosen)}}
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
        f = _fit(rows, lambda r, s=s: r.get(s, {}).get("seconds"))
        if f is not None:
            fits.append(f"{form} {s} {f:.2f}")
    return lines + ["", "Growth exponents (fit over N >= 8): " + ", ".join(fits), ""]


def main(argv: list[str]) -> None:
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    mode, args = argv[0], argv[1:]
    if mode == "compile":
        for row in compile_rows([int(a) for a in args]):
            print(json.dumps(row), flush=True)
    elif mode == "linsol":
        repeats, solvers, form = 3, SOLVERS, "chosen"
        while args and args[0].startswith("--"):
            key, value = args[0][2:].split("=")
            repeats = int(value) if key == "repeats" else repeats
            solvers = value.split(",") if key == "solvers" else solvers
            form = value if key == "form" else form
            args = args[1:]
        for row in linsol_rows([int(a) for a in args], repeats, solvers, form):
            print(json.dumps(row), flush=True)
    elif mode == "cartesian":
        print(json.dumps(cartesian_row(int(args[0]), float(args[1]))), flush=True)
    elif mode == "forms":
        print("\n".join(forms_table(*args)))
    elif mode == "report":
        write_report(*args)
    elif mode == "compile-section":
        write_compile_section(*args)
    else:
        raise SystemExit(__doc__)


def _read(path: str) -> list[dict]:
    return [json.loads(line) for line in Path(path).read_text().splitlines() if line.startswith("{")]


def _median_rows(paths: str) -> list[dict]:
    """Rows of several `compile` runs (comma-separated files), each number the median per N."""
    runs = [_read(path) for path in paths.split(",")]
    rows = []
    for same_n in zip(*runs):
        row = dict(same_n[0])
        for key, value in row.items():
            if isinstance(value, float):
                row[key] = statistics.median(r.get(key, 0.0) for r in same_n)
        rows.append(row)
    return rows


def write_compile_section(before: str, after: str, notes: str, before_title: str = "Before",
                          after_title: str = "After", out: str = str(ROOT / "docs" / "scaling.md")) -> None:
    """Rewrite only the section `## Compile time per pass` of docs/scaling.md (up to the next
    `## ` heading): the per-pass tables of two sets of `compile` runs (BEFORE and AFTER are
    comma-separated JSON-line files: medians over the runs) and the text of NOTES."""
    from suite.machine import describe
    lines = Path(out).read_text(encoding="utf-8").splitlines()
    start = lines.index("## Compile time per pass")
    end = next(i for i in range(start + 1, len(lines)) if lines[i].startswith("## "))
    runs = len(before.split(","))
    section = ["## Compile time per pass", "",
               "The chain of benchmarks/suite/chain_model.py (World + N x (Revolute + BodyShape)); one "
               "process per run, warmed up on N = 1; `structure` is everything between flattening and "
               "lowering, `lower` includes the state-set check; `compile` = parse + flatten + structure + "
               f"lower. CPU seconds, median of {runs} runs per N. Machine (at report time): "
               + ", ".join(f"{k} {v}" for k, v in describe().items()) + ".", ""]
    section += compile_table(_median_rows(before), before_title)
    section += compile_table(_median_rows(after), after_title)
    section += [Path(notes).read_text(encoding="utf-8").rstrip(), ""]
    Path(out).write_text("\n".join(lines[:start] + section + lines[end:]) + "\n", encoding="utf-8")


def write_report(before: str, after: str, linsol: str, notes: str | None = None,
                 out: str = str(ROOT / "docs" / "scaling.md")) -> None:
    """docs/scaling.md from saved JSON lines: compile per pass before/after, linear solvers."""
    from suite.machine import describe
    machine = describe()
    lines = ["# Scaling on the N-link pendulum chain", "",
             "*Generated by `benchmarks/bench_scale.py report` from measurements of `bench_scale.py "
             "compile` and `linsol` (see its docstring); do not edit by hand.*", "",
             "Machine (at report time): " + ", ".join(f"{k} {v}" for k, v in machine.items()) + ". "
             "Times are CPU seconds of the measuring process: the machine was shared with other work "
             "(load average 10-17 on 2 cores), under which wall times were up to 10x larger.", "",
             "## Compile time per pass", "",
             "The chain of benchmarks/suite/chain_model.py (World + N x (Revolute + BodyShape)); one "
             "process, warmed up on N = 1; `structure` is everything between flattening and lowering, "
             "`lower` includes the state-set check; `compile` = parse + flatten + structure + lower.", ""]
    lines += compile_table(_read(before), "Before (commit c48eb60)")
    lines += compile_table(_read(after), "After")
    lines += ["## Linear solver of IDAS", "",
              "CPU seconds of one simulation (0.5 s, rtol = atol = 1e-6, 51 points; median of 3) per "
              "linear solver (CasADi's `linear_solver` option of the idas plugin; `gmres` is "
              "`newton_scheme: gmres`); in brackets the largest deviation of the last joint angle "
              "from the `qr` run. `ma27` is not in this CasADi build.", ""]
    lines += linsol_table(_read(linsol))
    if notes:
        lines += [Path(notes).read_text().rstrip(), ""]
    Path(out).write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main(sys.argv[1:])
