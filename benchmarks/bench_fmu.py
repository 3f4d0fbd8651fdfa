"""The excavator's FMUs run by FMPy beside dyadc's own run, and the cost of one derivative
evaluation in the FMU beside dyadc's C function (issue 30 step 6).

    .venv/bin/python benchmarks/bench_fmu.py [--repeats N] [--evaluations N] [--doc docs/fmu.md]

Runs (12 s, 101 output points, tolerance 1e-6): FMPy's `simulate_fmu` of the FMI 2.0 Model
Exchange FMU (FMPy's CVode integrates; its loop is FMPy's, in Python) and of the Co-Simulation FMU
(the FMU's own TR-BDF2, stepped every 0.12 s), each including FMPy's unzip, load and
initialization; dyadc's own `simulate_compiled` of the compiled model on C (initialization, IDAS,
outputs). CPU seconds of this process (time.process_time: FMPy runs the FMU in this process) and
wall seconds, medians of `repeats` after a warm-up.

Derivative evaluations, through ctypes in all rows (the first row is ctypes' own cost): the FMU's
fmi2GetDerivatives with the states unchanged (the generated f alone), after fmi2SetContinuousStates
(the algebraic unknowns solved again by Newton from their last values, then f), and dyadc's C
function `dyad_dae` (f and g at given x and z) from the model's library, at the same point.
The FMU's C is compiled with -O1 (compiler/fmu/export.py), dyadc's with -Og (ccodegen.FLAGS).
"""
from __future__ import annotations

import argparse
import ctypes
import datetime
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from suite.doc_blocks import write_block  # noqa: E402

EXCAVATOR = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
STOP, TOLERANCE, POINTS = 12.0, 1e-6, 101
BEGIN, END = "<!-- bench_fmu: begin -->", "<!-- bench_fmu: end -->"
CLOCK = time.process_time


def medians(run, repeats: int) -> tuple[float, float]:
    """CPU and wall seconds of `run()`: the medians of `repeats` after one warm-up."""
    run()
    cpu, wall = [], []
    for _ in range(repeats):
        began, began_wall = CLOCK(), time.perf_counter()
        run()
        cpu.append(CLOCK() - began)
        wall.append(time.perf_counter() - began_wall)
    return statistics.median(cpu), statistics.median(wall)


def export_fmus(model: str, lib_dirs: list[str], folder: Path) -> dict[str, Path]:
    from compiler import api
    return {kind: api.export_fmu(model, folder / f"model_{kind}.fmu", lib_dirs=lib_dirs, kind=kind, fmi=2)
            for kind in ("me", "cs")}


def run_times(model: str, lib_dirs: list[str], stop: float, fmus: dict[str, Path], repeats: int) -> dict:
    from fmpy import simulate_fmu

    from compiler.compiled_runs import simulate_compiled
    from compiler.pipeline import compile_or_load
    compilation = compile_or_load(model, lib_dirs, for_runs=True, codegen="c")
    interval = stop / (POINTS - 1)
    own = simulate_compiled(compilation, stop, rtol=TOLERANCE, atol=TOLERANCE, points=POINTS)

    def fmpy(kind: str):
        return lambda: simulate_fmu(str(fmus[kind]), stop_time=stop, relative_tolerance=TOLERANCE,
                                    output_interval=interval)
    return {"dyadc": medians(lambda: simulate_compiled(compilation, stop, rtol=TOLERANCE, atol=TOLERANCE,
                                                       points=POINTS), repeats),
            "me": medians(fmpy("me"), repeats), "cs": medians(fmpy("cs"), repeats),
            "codegen": own.stats.get("codegen", "?"), "model": compilation.model}


def _native_dae(library: str, sizes: tuple[int, int, int]):
    """dyad_dae of dyadc's C library as a ctypes call: f(t, x, z, p) -> (ode, alg) into buffers."""
    lib = ctypes.CDLL(library)
    counts = [ctypes.c_longlong() for _ in range(4)]
    lib.dyad_dae_work(*(ctypes.byref(c) for c in counts))
    arg = (ctypes.POINTER(ctypes.c_double) * max(counts[0].value, 5))()
    res = (ctypes.POINTER(ctypes.c_double) * max(counts[1].value, 4))()
    iw = (ctypes.c_longlong * max(counts[2].value, 1))()
    w = (ctypes.c_double * max(counts[3].value, 1))()
    nx, nz, _ = sizes
    ode, alg = (ctypes.c_double * max(nx, 1))(), (ctypes.c_double * max(nz, 1))()
    res[0] = ctypes.cast(ode, ctypes.POINTER(ctypes.c_double))
    res[1] = ctypes.cast(alg, ctypes.POINTER(ctypes.c_double))
    function = lib.dyad_dae
    function.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int]
    return lib, function, arg, res, iw, w, ode


def _algebraic(model, x: np.ndarray, p: np.ndarray, t: float) -> np.ndarray:
    """z with g(x, z, p, t) = 0: Newton with the exact Jacobian from the model's guesses (some of
    z are dummy derivatives, which a result does not hold)."""
    import casadi as ca
    xs, zs, ps, ts = model.symbols()
    alg = model.dae(xs, zs, ps, ts)[1]
    newton = ca.Function("newton", [xs, zs, ps, ts], [alg, ca.jacobian(alg, zs)])
    z = np.array(model.z_guess, dtype=float)
    for _ in range(50):
        residual, jacobian = (np.array(v, dtype=float) for v in newton(x, z, p, t))
        step = np.linalg.solve(jacobian.reshape(len(z), len(z)), residual.ravel())
        z -= step
        if np.max(np.abs(step), initial=0.0) <= 1e-13 * (1.0 + np.max(np.abs(z), initial=0.0)):
            return z
    raise RuntimeError(f"the algebraic equations of {model.name} did not converge at t = {t}")


def evaluation_costs(compiled, fmu: Path, at: float, x: np.ndarray, evaluations: int, repeats: int,
                     folder: Path) -> dict:
    """Seconds per call of each row (docstring above) at states `x` and time `at` (the initial
    point is a steady one, its derivatives round-off), dyad_dae given the FMU's parameter vector
    (its event clock and relation locks included: value references 2 nx + ny on, layout.py) and z
    solved for it; the FMU's derivatives there are checked against dyad_dae's."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Model

    description = read_model_description(str(fmu))
    instance = FMU2Model(guid=description.guid, unzipDirectory=extract(str(fmu), unzipdir=str(folder / "me")),
                         modelIdentifier=description.modelExchange.modelIdentifier, instanceName="bench")
    instance.instantiate()
    instance.setupExperiment(startTime=0.0)
    instance.enterInitializationMode()
    instance.exitInitializationMode()
    instance.newDiscreteStates()
    instance.enterContinuousTimeMode()
    nx, ny, n_p = len(compiled.state_names), len(compiled.output_names), len(compiled.parameter_names)
    dll, component = instance.dll, instance.component
    states, derivatives = (ctypes.c_double * nx)(*x), (ctypes.c_double * nx)()
    dll.fmi2SetTime(component, at)
    dll.fmi2SetContinuousStates(component, states, nx)
    dll.fmi2GetDerivatives(component, derivatives, nx)
    p = np.array(instance.getReal(list(range(2 * nx + ny, 2 * nx + ny + n_p))))
    z = _algebraic(compiled, x, p, at)
    lib, dae, arg, res, iw, w, ode = _native_dae(compiled.native_library, compiled.sizes)
    buffers = [(ctypes.c_double * max(len(v), 1))(*v) for v in ([at], x, z, p)]
    for i, buffer in enumerate(buffers):
        arg[i] = ctypes.cast(buffer, ctypes.POINTER(ctypes.c_double))
    dae(arg, res, iw, w, 0)
    agreement = float(np.max(np.abs(np.array(list(derivatives)) - np.array(list(ode))))
                      / max(1.0, float(np.max(np.abs(np.array(list(ode)))))))

    def loop(call):
        def run_loop():
            for _ in range(evaluations):
                call()
        return lambda: medians(run_loop, repeats)[0] / evaluations

    def fresh():
        dll.fmi2SetContinuousStates(component, states, nx)
        dll.fmi2GetDerivatives(component, derivatives, nx)
    costs = {"ctypes": loop(lambda: dll.fmi2SetTime(component, at))(),
             "fmu_f": loop(lambda: dll.fmi2GetDerivatives(component, derivatives, nx))(),
             "fmu_newton": loop(fresh)(),
             "dyadc": loop(lambda: dae(arg, res, iw, w, 0))()}
    instance.terminate()
    instance.freeInstance()
    del lib
    return {**costs, "agreement": agreement, "evaluations": evaluations}


def simulate_compiled_at(model: str, lib_dirs: list[str], at: float):
    from compiler import api
    return api.simulate(model, at, lib_dirs=lib_dirs, rtol=1e-8, atol=1e-8, saveat=[0.0, at])


def measure(model: str = EXCAVATOR, lib_dirs: list[str] | None = None, stop: float = STOP, repeats: int = 5,
            evaluations: int = 20000, fmus: dict[str, Path] | None = None) -> dict:
    """Every figure of the table; `fmus` ({"me": path, "cs": path}, FMI 2.0): FMUs already
    exported (the export is then not timed)."""
    lib_dirs = list(lib_dirs or [])
    load = f"{os.getloadavg()[0]:.1f}"
    with tempfile.TemporaryDirectory(prefix="dyadc-bench-fmu-") as tmp:
        folder = Path(tmp)
        began = time.perf_counter()
        fmus = fmus or export_fmus(model, lib_dirs, folder)
        export_wall = (time.perf_counter() - began) / 2
        runs = run_times(model, lib_dirs, stop, fmus, repeats)
        compiled = runs.pop("model")
        at = stop / 12
        run = simulate_compiled_at(model, lib_dirs, at)
        x = np.array([run[n][-1] for n in compiled.state_names], dtype=float)
        costs = evaluation_costs(compiled, fmus["me"], at, x, evaluations, repeats, folder)
    return {"model": model, "stop": stop, "repeats": repeats, "export_wall": export_wall, "runs": runs,
            "costs": costs, "sizes": compiled.sizes, "date": datetime.date.today().isoformat(), "load": load,
            "at": at}


def render(found: dict) -> str:
    runs, costs = found["runs"], found["costs"]
    nx, nz, _ = found["sizes"]
    us = lambda s: f"{s * 1e6:.2f} µs"  # noqa: E731
    seconds = lambda pair: f"{pair[0]:.3f} s | {pair[1]:.3f} s"  # noqa: E731
    return "\n".join([
        BEGIN,
        f"Measured {found['date']} by benchmarks/bench_fmu.py: `{found['model'].rsplit('.', 1)[-1]}` ({nx} states, "
        f"{nz} algebraic unknowns), {found['stop']:g} s, tolerance {TOLERANCE:g}, {POINTS} output points; "
        f"medians of {found['repeats']} runs, CPU of this process and wall, load {found['load']} at the start.",
        "",
        "| run | CPU | wall |", "|---|---|---|",
        f"| dyadc's own run (`simulate_compiled`, IDAS, code: {runs['codegen']}) | {seconds(runs['dyadc'])} |",
        f"| FMPy, Model Exchange FMU (FMPy's CVode and Python loop) | {seconds(runs['me'])} |",
        f"| FMPy, Co-Simulation FMU (the FMU's TR-BDF2) | {seconds(runs['cs'])} |",
        f"| exporting one FMU (`api.export_fmu`: compile, code generation, gcc) | | {found['export_wall']:.2f} s |"
        if found["export_wall"] > 1e-3 else "| exporting one FMU | (exported before, not timed) | |",
        "",
        f"| one derivative evaluation (ctypes call, median of {found['repeats']} loops of "
        f"{costs['evaluations']}) | CPU per call |", "|---|---|",
        f"| an empty call (fmi2SetTime at the same time): ctypes' own cost | {us(costs['ctypes'])} |",
        f"| FMU: fmi2GetDerivatives, states unchanged (f alone) | {us(costs['fmu_f'])} |",
        f"| FMU: fmi2SetContinuousStates + fmi2GetDerivatives (Newton on z, then f) | {us(costs['fmu_newton'])} |",
        f"| dyadc's C function `dyad_dae` (f and g at given x, z) | {us(costs['dyadc'])} |",
        "",
        f"Evaluated at the state of dyadc's run at t = {found['at']:g} s; there the FMU's der(x) equals "
        f"dyad_dae's to {costs['agreement']:.1e} of the largest derivative.",
        END])


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--evaluations", type=int, default=20000)
    parser.add_argument("--doc", default=str(ROOT / "docs" / "fmu.md"), help="the FMU page (its Speed table)")
    parser.add_argument("--bench-doc", default=str(ROOT / "docs" / "benchmarks.md"),
                        help="the benchmarks page (its FMU export table)")
    args = parser.parse_args(argv)
    table = render(measure(repeats=args.repeats, evaluations=args.evaluations))
    write_block(Path(args.doc), table, BEGIN, END, heading="Speed")
    write_block(Path(args.bench_doc), table, BEGIN, END, heading="FMU export (bench_fmu.py)")
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
