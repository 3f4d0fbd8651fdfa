"""From a model name to its linear model: compile (from the cache when nothing needs the flat
model), choose the operating point, linearize; and the closed-loop functions at an analysis
point (sensitivity S, complementary sensitivity T, loop transfer L) in one sign convention:

    u_P = y_P + d (the perturbation d at P's input signal)   S = d u_P / d d,  T = -d y_P / d d
    P opened, u_P = d                                        L = -d y_P / d d

so that S + T = I exactly and S = (I + L)^-1 for a loop closed through P with negative feedback.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Mapping, Sequence

import numpy as np

from compiler.errors import DyadError
from compiler.linear.operating_point import initial_point, point_of_run, steady_point
from compiler.linear.system import LinearSystem, linearize_at

if TYPE_CHECKING:                    # the flat model's module imports sympy: not on the cached path
    from compiler.model.flat import FlatSystem


@dataclass(frozen=True)
class Request:
    """What to linearize: `inputs` are free top-level inputs or analysis points (default: every
    free input); `outputs` any variable or analysis point (default: the top-level outputs, else the
    states); `at` a time to run to, `steady` a Newton solve for a steady state, else the initial
    point; `op` input values at the point; `params` parameter overrides; `opened` analysis points
    whose connection is removed."""
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    at: float | None = None
    steady: bool = False
    op: Mapping[str, float] = field(default_factory=dict)
    params: Mapping[str, float] = field(default_factory=dict)
    opened: tuple[str, ...] = ()
    minimal: bool = False
    # (model parameters, their declared units) -> params: the command line's `-p L=100mm`
    convert_params: Callable[[Mapping[str, float], Mapping[str, str]], dict] | None = None


def linearize_spec(spec: str | FlatSystem, request: Request, lib_dirs: Sequence[str] = (), cache: bool = True
                   ) -> LinearSystem:
    compiled = compile_linear(spec, request, lib_dirs, cache)
    return _linearize(compiled, request)


def closed_loop_function(spec: str | FlatSystem, kind: str, point: str, request: Request,
                         lib_dirs: Sequence[str] = ()) -> LinearSystem:
    """`kind` "sensitivity", "comp_sensitivity" or "loop_transfer" at analysis point `point`."""
    opened = tuple(request.opened) + ((point,) if kind == "loop_transfer" else ())
    asked = dataclasses.replace(request, inputs=(point,), outputs=(point,), opened=opened, minimal=False)
    compiled = compile_linear(spec, asked, lib_dirs, cache=False)
    from compiler.linear.inputs import analysis_points
    ap = analysis_points(compiled.flat)[point]
    measured = list(ap.inputs if kind == "sensitivity" else ap.outputs)
    labels = ap.scalar_names()
    system = _linearize(compiled, dataclasses.replace(asked, outputs=()), inputs=labels,
                        outputs=measured, labels=labels)
    if kind != "sensitivity":
        system = dataclasses.replace(system, C=-system.C, D=-system.D)
    return system.minimal_realization() if request.minimal else system


@dataclass
class LinearCompilation:
    """The compiled model behind a linearization, with the flat model it was compiled from (None
    when it came from the cache) and the names of its parameters that are inputs."""
    compilation: object
    flat: object | None
    inputs: list[str]            # every parameter that is an input
    free: list[str] = field(default_factory=list)     # the free top-level inputs among them


def compile_linear(spec: str | FlatSystem, request: Request, lib_dirs: Sequence[str], cache: bool
                   ) -> LinearCompilation:
    """`spec` a model name or its flat model. From the cache when nothing needs the flat model;
    else with free inputs and the analysis points the request perturbs or opens made parameters
    (compiler/linear/inputs.py)."""
    from compiler.pipeline import compile_flat, compile_or_load, flatten_spec
    given = None if isinstance(spec, str) else spec
    # the cache holds the model alone: enough when the outputs are named (the default outputs,
    # the top-level ones, need the flat model) and nothing is perturbed or opened
    if given is None and cache and request.outputs and not request.inputs and not request.opened:
        from compiler.cache import models
        from compiler.cache.store import CacheError
        try:
            found = models.load(spec, lib_dirs)
        except (OSError, CacheError):
            found = None
        if found is not None and all(n in found.model.output_names for n in request.outputs):
            return LinearCompilation(found, None, [])
    from compiler.linear.inputs import analysis_points, check_not_differentiated, free_inputs, \
        with_linear_inputs
    flat = given or flatten_spec(spec, lib_dirs)[0]
    points = analysis_points(flat)
    free = free_inputs(flat)
    for name in (*request.inputs, *request.opened):
        if name not in points and (name in request.opened or name not in free):
            _unknown(flat, name, points, free, opening=name in request.opened)
    perturbed = [n for n in request.inputs if n in points]
    if not (perturbed or request.opened or free):
        compilation = compile_flat(flat) if given else compile_or_load(spec, lib_dirs, cache=cache)
        return LinearCompilation(compilation, flat, [])
    changed = with_linear_inputs(flat, perturbed, list(request.opened))
    compilation = compile_flat(changed)
    inputs = list(changed.metadata["linear_inputs"])
    # an input held constant at the operating point is right; one linearized from must not need der()
    check_not_differentiated(changed, compilation.analysis, list(request.inputs) or free)
    return LinearCompilation(compilation, changed, inputs, free)


def _unknown(flat, name: str, points, free, opening: bool):
    from compiler.errors import suggest_name
    candidates = list(points) if opening else list(points) + list(free)
    close = suggest_name(name, candidates)
    what = "an analysis point" if opening else "a free top-level input or an analysis point"
    raise DyadError(f"`{name}` is not {what} of `{flat.name}`" + (f"; {close}" if close else ""),
                    hint=f"its free inputs: {', '.join(free) or 'none'}; its analysis points: "
                         f"{', '.join(sorted(points)) or 'none'}")


def _linearize(compiled: LinearCompilation, request: Request, inputs: Sequence[str] | None = None,
               outputs: Sequence[str] | None = None, labels: Sequence[str] | None = None) -> LinearSystem:
    model = compiled.compilation.model
    if inputs is None:
        inputs = list(request.inputs) or list(compiled.free)
    for name in request.op:
        if name not in compiled.inputs:
            raise DyadError(f"--op {name}=...: `{name}` is not an input of this linearization (only "
                            f"an input takes a value at the operating point)",
                            hint=f"its inputs: {', '.join(compiled.inputs) or 'none'}; a parameter "
                                 f"takes -p NAME=VALUE")
    if outputs is None:
        outputs, labels = _outputs(compiled, request)
    params = dict(request.params)
    if request.convert_params is not None:
        params = request.convert_params(model.parameters, model.metadata.get("units", {}))
    overrides = {**params, **dict(request.op)}
    p = model.parameter_vector(overrides)
    point = initial_point(model, p)
    if request.at is not None:
        point = point_of_run(model, p, _run(compiled, request.at, overrides))
    if request.steady:
        point = steady_point(point)
    system = linearize_at(point, list(inputs), list(outputs), labels)
    _require_finite(system, compiled, overrides)
    return system.minimal_realization() if request.minimal else system


def _require_finite(system: LinearSystem, compiled: LinearCompilation, overrides: Mapping[str, float]) -> None:
    """A linearization with an infinite or nan entry (a mass of 1e-400, which is 0, divides a
    force) is refused: with the located error a run from the start gives where it fails there (the
    equation and the parameter whose value makes it singular), else naming the first entry."""
    matrices = {"A": system.A, "B": system.B, "C": system.C, "D": system.D}
    bad = [(name, index) for name, matrix in matrices.items() for index in zip(*np.nonzero(~np.isfinite(matrix)))]
    if not bad:
        return
    _run(compiled, system.time + 1e-9 * max(1.0, abs(system.time)), overrides)     # raises where it fails
    name, (row, column) = bad[0]
    rows = system.outputs if name in "CD" else [f"der({state})" for state in system.states]
    columns = system.inputs if name in "BD" else system.states
    raise DyadError(f"the linearization at t = {system.time:g} is not finite: d {rows[row]} / d {columns[column]} "
                    f"= {matrices[name][row, column]} ({len(bad)} entries of A, B, C, D not finite)",
                    hint="a parameter value that makes a coefficient 0 or infinite (an underflow like 1e-400 "
                         "is 0): check the parameters at this point")


def _outputs(compiled: LinearCompilation, request: Request) -> tuple[list[str], list[str]]:
    model = compiled.compilation.model
    points = {}
    if compiled.flat is not None:
        from compiler.linear.inputs import analysis_points
        points = analysis_points(compiled.flat)
    if not request.outputs:
        from compiler.model.flat import OUTPUT
        tops = [v.name for v in compiled.flat.variables if v.kind == OUTPUT] if compiled.flat else []
        names = [n for n in tops if n in model.output_names] or list(model.state_names)
        return names, names
    names, labels = [], []
    for name in request.outputs:
        if name in points and name not in model.output_names:
            signals = points[name].outputs
            names += list(signals)
            labels += points[name].scalar_names()
        else:
            model.output_index(name)          # unknown names: an error with "did you mean"
            names.append(name)
            labels.append(name)
    return names, labels


def _run(compiled: LinearCompilation, at: float, overrides: Mapping[str, float]):
    """The run to the operating time, on the one run path (located errors; the runtime picks the
    state-set switcher the model needs)."""
    from compiler.compiled_runs import simulate_compiled
    return simulate_compiled(compiled.compilation, float(at), points=2, params=dict(overrides) or None)

