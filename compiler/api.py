"""The Python API: what a user (or a test) calls instead of the command line.

Only the runtime is imported with this module; the compiler's stages are imported when a compile
runs (a run from the compilation cache imports neither sympy nor lark).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Mapping, Sequence

from compiler import runtime
from compiler.compiled_runs import simulate_compiled

if TYPE_CHECKING:
    from compiler.model.flat import FlatSystem
    from compiler.pipeline import Compilation


def flatten(model_spec: str, lib_dirs: Sequence[str] = (), *, units: str | None = None) -> FlatSystem:
    """`units`: the unit check's mode, "error" (default), "warn" or "off" (compiler/units/mode.py);
    the findings are in the result's `unit_findings`."""
    from compiler.pipeline import flatten_spec
    from compiler.units.mode import units_mode
    with units_mode(units):
        return flatten_spec(model_spec, lib_dirs)[0]


def compile(model_spec: str, lib_dirs: Sequence[str] = (), *,  # noqa: A001 - the verb users expect
            units: str | None = None) -> Compilation:
    from compiler.pipeline import compile_spec
    from compiler.units.mode import units_mode
    with units_mode(units):
        return compile_spec(model_spec, lib_dirs)


def simulate(model_spec: str, stop: float, *, lib_dirs: Sequence[str] = (), start: float = 0.0,
             rtol: float = 1e-6, atol: float = 1e-6, points: int = 501, saveat=None,
             params: Mapping[str, float] | None = None, progress: bool | None = None,
             cache: bool = False, units: str | None = None, codegen: str | None = None,
             integrator: str | None = None) -> runtime.Result:
    """Compile and run `model_spec`. `cache=True`: through the compilation cache, as
    `dyadc simulate` does (docs/cache.md). `units`: "error" (default), "warn" or "off", as
    `--units` (a warning is a compiler.units.mode.UnitWarning). `codegen`: "c" or "vm", as
    `--codegen`; default C where a C compiler is present, its libraries in the C library cache
    (content keyed) with or without `cache`; the choice is `result.stats["codegen"]`.
    `integrator`: "native" or "casadi", as `--integrator`; default the native IDAS driver where it
    can run the model ($DYADC_INTEGRATOR may say otherwise); the choice is
    `result.stats["integrator"]`, and why not the native one `result.stats["integrator_why"]`."""
    from compiler.pipeline import compile_or_load
    from compiler.units.mode import units_mode
    with units_mode(units):
        compilation = compile_or_load(model_spec, lib_dirs, cache=cache, for_runs=True, codegen=codegen)
    return simulate_compiled(compilation, stop, start=start, rtol=rtol, atol=atol, points=points,
                             saveat=saveat, params=params, progress=progress, integrator=integrator)


def linearize(model_spec: str, *, inputs: Sequence[str] = (), outputs: Sequence[str] = (),
              at: float | None = None, steady: bool = False, op: Mapping[str, float] | None = None,
              params: Mapping[str, float] | None = None, opened: Sequence[str] = (),
              minimal: bool = False, lib_dirs: Sequence[str] = (), cache: bool = True):
    """The linear model (A, B, C, D) of `model_spec` at an operating point (the initial point, the
    state of a run at time `at`, or a steady state), from its free inputs or analysis points to any
    variables or analysis points: a compiler.linear.system.LinearSystem (docs/analysis.md)."""
    from compiler.linear.request import Request, linearize_spec
    request = Request(inputs=tuple(inputs), outputs=tuple(outputs), at=at, steady=steady,
                      op=dict(op or {}), params=dict(params or {}), opened=tuple(opened), minimal=minimal)
    return linearize_spec(model_spec, request, lib_dirs, cache=cache)


def export_fmu(model_spec: str, output: str, *, lib_dirs: Sequence[str] = (),
               params: Mapping[str, float] | None = None, fmi: int = 2, kind: str = "me",
               stop_time: float | None = None, units: str | None = None):
    """Write `model_spec` as an FMU (`fmi` 2 or 3: FMI 2.0 or 3.0; `kind` "me": Model Exchange,
    "cs": Co-Simulation) to `output` and return its path: free inputs are its inputs, `params`
    start values of its parameters (docs/fmu.md)."""
    from compiler.fmu.export import export_fmu as export
    from compiler.units.mode import units_mode
    with units_mode(units):
        return export(model_spec, output, lib_dirs=lib_dirs, params=params, fmi=fmi, kind=kind,
                      stop_time=stop_time)
