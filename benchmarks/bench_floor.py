"""The floor: dyadc's `runtime.simulate` against a bare CasADi IDAS run of the same functions.

    .venv/bin/python benchmarks/bench_floor.py                  # excavator, 101/501/1201 points, VM and C
    .venv/bin/python benchmarks/bench_floor.py --repeats 9 --points 501

Model: the excavator scene (the golden tests' and benchmarks/suite/problems.py's), 12 s, rtol =
atol = 1e-6. The floor is what a user who wrote the IDAS call by hand would run on the model's own
compiled DAE (the SX function on the VM, the shared library with `--codegen c`): from the same
consistent initial point (not timed: ours includes its initialization), the same IDAS options
(compiler/runtime/idas.py), one `casadi.integrator` per segment between the model's time events
(built per call, as a bare call does; its event clock set per segment as the driver sets it), the
output grid's points as IDAS's output times, x and z returned, no derived outputs, no checks.

Ours is `runtime.simulate(model, 12, points=N)`: initialization, IDAS with the in-run checks
(bounds watched at 200 check times per segment), polishing and every output (631 signals), or
only the signals asked for (`signals=`, the 25 of the work-precision benchmark).

Both run interleaved in one process, medians of `repeats` after one warm-up each, in CPU seconds
of this process (time.process_time; see CLOCK). The per-phase
profile of ours times the runtime's functions (exclusive time, nested calls subtracted).
The command line also prints what the C library costs to build, with and without the per-point
functions (outputs, algebraic Newton step) that `--codegen c` compiles besides the DAE.
"""
from __future__ import annotations

import argparse
import contextlib
import functools
import os
import statistics
import sys
import time
import warnings
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")          # before numpy: one BLAS thread
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import casadi as ca  # noqa: E402

from compiler import runtime  # noqa: E402
from compiler.runtime import casadi_idas, driver, outputs, run_state, sampled_idas, stops, watches  # noqa: E402
from compiler.runtime.segments import with_clock  # noqa: E402
from compiler.runtime.idas import integrator_options  # noqa: E402
from compiler.runtime.watches import time_breakpoints  # noqa: E402

MODEL = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
STOP, RTOL, ATOL = 12.0, 1e-6, 1e-6
POINTS = (101, 501, 1201)
# CPU time of this process: on a machine shared with other work, wall time mostly measures the
# others (a 41 s wall run used 11 s of CPU); everything measured here is single-threaded
CLOCK = time.process_time
# "outputs" includes the polishing of z: for a small algebraic system both are one function
# (compiler/runtime/polishing.py), so their shares cannot be told apart
PHASES = ("IDAS", "integrator construction", "initialization", "outputs", "checks", "other")


def compiled_models() -> dict[str, runtime.CompiledModel]:
    """The excavator on the VM and, where a C compiler is found, in C."""
    from compiler import api
    from compiler.cache.c_code import compile_c, on_vm
    from compiler.lower import ccodegen
    vm = on_vm(api.compile(MODEL).model)     # asked for: an undecided model's run would build C
    models = {"VM": vm}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        native = compile_c(vm)
    if native.metadata.get("codegen") == "c":
        models["C"] = native
    return models


def asked_signals() -> list[str]:
    from suite.problems import EXCAVATOR_GROUPS
    return [name for group in EXCAVATOR_GROUPS.values() for name in group]


# ------------------------------------------------------------------------------------ the floor

def floor_dae(model: runtime.CompiledModel) -> ca.Function:
    native = model.native_dae()
    if native is not None:
        return native
    from compiler.lower.ccodegen import dae_function
    return dae_function(model)


def segment_ends(model, p) -> list[float]:
    return [b for b in time_breakpoints(model, p, 0.0, STOP)] + [STOP]


def floor_run(model, dae, p, point, grid, rtol: float = RTOL, atol: float = ATOL,
              stats: dict | None = None) -> tuple[np.ndarray, np.ndarray, float, int]:
    """x and z on the grid by one bare IDAS call per segment; the seconds spent building; steps.
    `stats`, where given, gets IDAS's counters (CasADi's names) summed over the calls."""
    options = integrator_options(model, rtol, atol, 100000, {})
    nx, nz = len(model.state_names), len(model.algebraic_names)
    xs, zs = np.empty((nx, len(grid))), np.empty((nz, len(grid)))
    xs[:, 0], zs[:, 0] = point.x, point.z
    t, x, z, k, building, steps = 0.0, point.x, point.z, 1, 0.0, 0
    for end in segment_ends(model, p):
        upto = int(np.searchsorted(grid, end, side="right"))
        times = [float(v) for v in grid[k:upto]]
        if not times or times[-1] != end:
            times.append(end)
        began = CLOCK()
        solver = ca.integrator("floor", "idas", dae, t, times, options)
        building += CLOCK() - began
        sol = solver(x0=x, z0=z, p=with_clock(model, p, t, end))
        steps += int(solver.stats()["nsteps"])
        if stats is not None:
            for key, value in solver.stats().items():
                if isinstance(value, (int, float)) and not isinstance(value, bool) and key.startswith("n"):
                    stats[key] = stats.get(key, 0) + value
        xf = np.asarray(sol["xf"]).reshape(nx, len(times))
        zf = np.asarray(sol["zf"]).reshape(nz, len(times))
        xs[:, k:upto], zs[:, k:upto] = xf[:, :upto - k], zf[:, :upto - k]
        t, x, z, k = end, xf[:, -1], zf[:, -1], upto
    return xs, zs, building, steps


# ------------------------------------------------------------------------------ phase profile

class PhaseClock:
    """Exclusive wall time per phase of the runtime functions patched in `patched()`."""

    def __init__(self):
        self.seconds = {phase: 0.0 for phase in PHASES}
        self._stack: list[list[float]] = []

    def wrap(self, phase: str, function):
        @functools.wraps(function)
        def timed(*args, **kwargs):
            frame = [CLOCK(), 0.0]          # start, time of nested timed calls
            self._stack.append(frame)
            try:
                return function(*args, **kwargs)
            finally:
                self._stack.pop()
                spent = CLOCK() - frame[0]
                self.seconds[phase] += spent - frame[1]
                if self._stack:
                    self._stack[-1][1] += spent
        return timed

    @contextlib.contextmanager
    def patched(self):
        targets = [(casadi_idas.IdasIntegrator, "run", "IDAS"), (casadi_idas.IdasIntegrator, "run_to", "IDAS"),
                   (ca, "integrator", "integrator construction"),
                   (driver, "consistent_initialization", "initialization"),
                   (driver, "restart_point", "initialization"),
                   (watches.Watch, "values", "checks"), (run_state, "build_watch", "checks"),
                   (sampled_idas, "check_divergence", "checks")]
        for module in (driver, run_state, stops, outputs):
            targets += [(module, name, "outputs") for name in ("polish_algebraics", "evaluate_outputs", "signals_at")
                        if hasattr(module, name)]
        saved = [(owner, name, getattr(owner, name)) for owner, name, _ in targets if hasattr(owner, name)]
        for owner, name, phase in targets:
            if hasattr(owner, name):
                setattr(owner, name, self.wrap(phase, getattr(owner, name)))
        try:
            yield self
        finally:
            for owner, name, original in saved:
                setattr(owner, name, original)


def profile(model, points: int, signals, repeats: int) -> dict[str, float]:
    """Median seconds per phase of ours (one profiled run per repeat)."""
    runs = []
    for _ in range(repeats):
        clock = PhaseClock()
        with clock.patched():
            began = CLOCK()
            ours(model, points, signals)
            total = CLOCK() - began
        clock.seconds["other"] = total - sum(clock.seconds.values())
        clock.seconds["total"] = total
        runs.append(clock.seconds)
    return {phase: statistics.median(r[phase] for r in runs) for phase in runs[0]}


# ------------------------------------------------------------------------------- measurement

def ours(model, points: int, signals):
    extra = {} if signals is None else {"signals": signals}
    return runtime.simulate(model, STOP, points=points, rtol=RTOL, atol=ATOL, progress=False, **extra)


def supports_signals() -> bool:
    return "signals" in runtime.SimulationOptions.__dataclass_fields__


def measure(repeats: int = 5, points=POINTS, models=None, log=print) -> list[dict]:
    """One row per (codegen, points): floor and ours side by side, medians, ratios, phases."""
    models = models or compiled_models()
    asked = asked_signals() if supports_signals() else None
    rows = []
    for codegen, model in models.items():
        p = model.parameter_vector()
        point = runtime.consistent_initialization(model, p, 0.0)
        dae = floor_dae(model)
        for n in points:
            grid = np.linspace(0.0, STOP, n)
            floor_xs, _, _, floor_steps = floor_run(model, dae, p, point, grid)      # warm-up
            result = ours(model, n, None)
            if asked is not None:
                ours(model, n, asked)
            floor_t, build_t, ours_t, asked_t = [], [], [], []
            for _ in range(repeats):
                began = CLOCK()
                build_t.append(floor_run(model, dae, p, point, grid)[2])
                floor_t.append(CLOCK() - began)
                began = CLOCK()
                ours(model, n, None)
                ours_t.append(CLOCK() - began)
                if asked is not None:
                    began = CLOCK()
                    ours(model, n, asked)
                    asked_t.append(CLOCK() - began)
            difference = max(float(np.max(np.abs(result[name] - floor_xs[i])) / max(1e-300, np.max(np.abs(floor_xs[i]))))
                             for i, name in enumerate(model.state_names))
            row = {"codegen": codegen, "points": n, "floor": statistics.median(floor_t),
                   "floor_build": statistics.median(build_t), "ours": statistics.median(ours_t),
                   "asked": statistics.median(asked_t) if asked_t else None,
                   "steps": result.stats["steps"], "floor_steps": floor_steps, "state_difference": difference,
                   "phases": profile(model, n, None, repeats)}
            row["ratio"] = row["ours"] / row["floor"]
            row["asked_ratio"] = row["asked"] / row["floor"] if row["asked"] else None
            rows.append(row)
            log(format_row(row))
    return rows


def _ms(seconds) -> str:
    return "-" if seconds is None else f"{seconds * 1e3:.1f}"


HEADER = ("| code | points | floor: bare IDAS [ms] (of it building) | ours, all outputs [ms] | ratio "
          "| ours, 25 signals asked [ms] | ratio | ratios to the floor's IDAS calls alone (all / asked) "
          "| IDAS steps ours / floor | max state diff vs floor (relative) |")


def _ratio(value) -> str:
    return "-" if value is None else f"{value:.2f}x"


def format_row(r: dict) -> str:
    calls = r["floor"] - r["floor_build"]          # a repeated bare run that kept its integrators
    return (f"| {r['codegen']} | {r['points']} | {_ms(r['floor'])} ({_ms(r['floor_build'])}) | "
            f"{_ms(r['ours'])} | {_ratio(r['ratio'])} | {_ms(r['asked'])} | {_ratio(r['asked_ratio'])} | "
            f"{_ratio(r['ours'] / calls)} / {_ratio(r['asked'] / calls if r['asked'] else None)} | "
            f"{r['steps']} / {r['floor_steps']} | {r['state_difference']:.1e} |")


def table(rows: list[dict]) -> list[str]:
    lines = [HEADER, "|---|---|---|---|---|---|---|---|---|---|"] + [format_row(r) for r in rows]
    lines += ["", "Phases of ours (all outputs), median ms per run:", "",
              "| code | points | " + " | ".join(PHASES) + " | total |", "|---|---|" + "---|" * (len(PHASES) + 1)]
    for r in rows:
        lines.append(f"| {r['codegen']} | {r['points']} | "
                     + " | ".join(_ms(r["phases"][ph]) for ph in PHASES) + f" | {_ms(r['phases']['total'])} |")
    return lines


def library_cost(model: runtime.CompiledModel, repeats: int = 3) -> dict[str, tuple[float, int]]:
    """(median CPU seconds of the C compiler, library bytes) of the model's C library as
    `--codegen c` builds it, and of one holding only the DAE and its Jacobian (what the library
    held before the per-point functions: outputs, algebraic Newton step), built afresh each time."""
    import resource
    import subprocess
    import tempfile
    from compiler.cache.c_code import compile_c
    from compiler.lower import ccodegen
    compiler = ccodegen.find_compiler()
    dae = ccodegen.dae_function(model)
    generator = ca.CodeGenerator("dyad_dae", {"with_header": False})
    generator.add(dae)
    generator.add(ccodegen.state_jacobian(dae))
    sources = {"DAE and Jacobian only": generator.dump(), "as built (with outputs and Newton step)":
               ccodegen.c_source(model)}
    cost = {}
    for name, source in sources.items():
        seconds = []
        with tempfile.TemporaryDirectory() as scratch:
            (Path(scratch) / "lib.c").write_text(source)
            for _ in range(repeats):
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                subprocess.run([compiler, *ccodegen.FLAGS, "lib.c", "-o", "lib.so", "-lm"], cwd=scratch, check=True)
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                seconds.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
            cost[name] = (statistics.median(seconds), (Path(scratch) / "lib.so").stat().st_size)
    return cost


def library_lines(cost: dict[str, tuple[float, int]]) -> list[str]:
    from compiler.lower.ccodegen import FLAGS
    return ["", f"C library of the excavator ({' '.join(FLAGS)}), median CPU time of the compiler:", "",
            "| library | build [s] | size [kB] |", "|---|---|---|"] + \
        [f"| {name} | {seconds:.2f} | {size / 1e3:.0f} |" for name, (seconds, size) in cost.items()]


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--points", type=int, nargs="*", default=list(POINTS))
    parser.add_argument("--codegen", choices=["VM", "C", "both"], default="both")
    args = parser.parse_args(argv)
    models = compiled_models()
    if args.codegen != "both":
        models = {args.codegen: models[args.codegen]}
    rows = measure(args.repeats, args.points, models, log=lambda line: None)
    print("\n".join(table(rows)))
    if "C" in models:
        print("\n".join(library_lines(library_cost(models["C"]))))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
