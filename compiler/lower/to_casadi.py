"""Lower a ReducedSystem (sympy) to CasADi SX Functions: the numerical CompiledModel.

The walk over the sympy expression DAG (compiler/lower/sx_lowering.py) is memoized on the sympy
node, so a subexpression shared between equations (or reached through an assignment symbol)
becomes one shared SX node. Here: the dae, init, outputs, params and event Functions built from
one such walk, and the metadata a CompiledModel carries.
"""
from __future__ import annotations

import casadi as ca

from compiler.errors import Span
from compiler.lower.events import EVENT_CLOCK, Events, find_events, lock_timed_conditions
from compiler.lower.relation_locks import lock_state_relations
from compiler.lower.sx_lowering import LoweringError, SXLowering
from compiler.model.flat import TIME
from compiler.runtime import CompiledModel
from compiler.structure.reduced import ReducedSystem

__all__ = ["LoweringError", "SXLowering", "lower"]

def _span(origin) -> Span | None:
    return getattr(origin, "span", None) if origin is not None else None


def _describe(origin) -> str:
    if origin is None:
        return ""
    describe = getattr(origin, "describe", None)
    return describe() if callable(describe) else str(origin)


def lower(reduced: ReducedSystem, events: bool = True) -> CompiledModel:
    """Build the dae, init, outputs and params CasADi Functions of `reduced`. With `events` off the
    model knows none of its time and state events and IDAS steps across every kink (kept to
    measure what event handling buys)."""
    found = find_events(reduced) if events else Events((), ())
    reduced, locks = lock_state_relations(reduced, found)
    reduced = lock_timed_conditions(reduced, found)
    x, z, p, t, env, walker = _symbols(reduced)
    for a in reduced.assignments:
        _define(env, a.target, walker.lower(a.expr, f"the assignment to '{a.target}'", _span(a.origin)))
    ode = [walker.lower(e, f"der({name})") for name, e in zip(reduced.states, reduced.ode)]
    alg_origins = list(reduced.alg_origins) + [None] * len(reduced.alg)
    alg = [walker.lower(e, f"algebraic equation {j} {_describe(alg_origins[j])}".strip(),
                        _span(alg_origins[j])) for j, e in enumerate(reduced.alg)]
    # Observables come after the DAE so that the DAE can never silently depend on them.
    for a in reduced.observables:
        _define(env, a.target, walker.lower(a.expr, f"the observable '{a.target}'", _span(a.origin)))

    inputs, names_in = [x, z, p, t], ["x", "z", "p", "t"]
    dae = ca.Function("dae", inputs, [ca.vertcat(*ode), ca.vertcat(*alg)], names_in, ["ode", "alg"])
    init_origins = list(reduced.initial.origins) + [None] * len(reduced.initial.residuals)
    residuals = [walker.lower(e, f"initial equation {i} {_describe(init_origins[i])}".strip(),
                              _span(init_origins[i]))
                 for i, e in enumerate(reduced.initial.residuals)]
    init = ca.Function("init", inputs, [ca.vertcat(*residuals)], names_in, ["residuals"])
    output_names, values = _output_values(reduced, env, dict(zip(
        (f"der({s})" for s in reduced.states), ode)))
    outputs = ca.Function("outputs", inputs, [ca.vertcat(*values)], names_in, ["values"])

    events, event_labels, time_events, time_event_labels = _event_functions(found, walker, x, z, p, t)
    return CompiledModel(
        name=reduced.name,
        events=events, event_labels=event_labels,
        time_events=time_events, time_event_labels=time_event_labels,
        state_names=reduced.states,
        algebraic_names=reduced.algebraics,
        parameter_names=[q.name for q in reduced.parameters],
        parameter_defaults=[float(q.value) for q in reduced.parameters],
        parameter_tunable=[q.tunable for q in reduced.parameters],
        output_names=output_names,
        x_guess=[float(reduced.initial.guesses.get(s, 0.0)) for s in reduced.states],
        z_guess=[float(reduced.initial.guesses.get(s, 0.0)) for s in reduced.algebraics],
        dae=dae, init=init, outputs=outputs,
        params=_parameter_function(reduced),
        init_residual_labels=[_describe(o) for o in init_origins[:len(residuals)]],
        nominals={k: float(v) for k, v in sorted(reduced.metadata.get("nominals", {}).items())},
        metadata=_metadata(reduced, output_names, found, locks),
    )


def _symbols(reduced: ReducedSystem) -> tuple:
    """The SX symbols x, z, p, t of `reduced`, the environment naming each scalar, and a walker
    over that environment."""
    nx, nz, npar = len(reduced.states), len(reduced.algebraics), len(reduced.parameters)
    if len(reduced.ode) != nx:
        raise LoweringError(f"model {reduced.name}: {nx} states but {len(reduced.ode)} ode expressions")
    if len(reduced.alg) != nz:
        raise LoweringError(f"model {reduced.name}: {nz} algebraic unknowns but {len(reduced.alg)} "
                            "algebraic residuals")
    x = ca.SX.sym("x", nx)
    z = ca.SX.sym("z", nz)
    p = ca.SX.sym("p", npar)
    t = ca.SX.sym("t")
    env: dict[str, ca.SX] = {TIME.name: t}
    _bind(env, reduced.states, x, "state")
    _bind(env, reduced.algebraics, z, "algebraic unknown")
    _bind(env, [q.name for q in reduced.parameters], p, "parameter")
    return x, z, p, t, env, SXLowering(env, f"model {reduced.name}")


def _output_values(reduced: ReducedSystem, env: dict[str, ca.SX],
                   derivative_of: dict[str, ca.SX]) -> tuple[list[str], list[ca.SX]]:
    """The output names (declared, else every named value) and their SX values."""
    output_names = list(reduced.output_names) or _default_outputs(reduced)
    values = []
    for name in output_names:
        if name in env:
            values.append(env[name])
        elif name in derivative_of:
            values.append(derivative_of[name])
        else:
            raise LoweringError(f"output '{name}' of model {reduced.name} is not a state, "
                                "algebraic unknown, parameter, assignment or observable")
    return output_names, values


def _metadata(reduced: ReducedSystem, output_names: list[str], found: Events, locks: list) -> dict:
    """What a CompiledModel carries besides its Functions (JSON-safe)."""
    return {"statistics": _plain(reduced.statistics),
            "assignments": len(reduced.assignments),
            "observables": len(reduced.observables),
            "bounds": {name: dict(sorted(b.items()))
                       for name, b in sorted(reduced.metadata.get("bounds", {}).items())
                       if name in set(output_names)},
            "units": _declared_units(reduced, output_names),
            **({"event_clock": EVENT_CLOCK.name} if found.timed_conditions else {}),
            **({"relation_locks": [lock.as_metadata() for lock in locks]} if locks else {})}


def _event_functions(found, walker: "SXLowering", x, z, p, t):
    """events(x, z, p, t) -> zero functions of the state events; time_events(p) -> (offsets,
    periods) of the time events (see compiler/lower/events.py). None where the model has none."""
    events = labels = time_events = time_labels = None
    if found.state_events:
        zeros = [walker.lower(e.zero, f"the event condition {e.label}") for e in found.state_events]
        events = ca.Function("events", [x, z, p, t], [ca.vertcat(*zeros)], ["x", "z", "p", "t"], ["zero"])
        labels = [e.label for e in found.state_events]
    usable = []
    for e in found.time_events:
        offset = ca.substitute(walker.lower(e.offset, f"the event time of {e.label}"), t, ca.SX(0))
        period = ca.substitute(walker.lower(e.period, f"the event period of {e.label}"), t, ca.SX(0))
        if not ca.depends_on(ca.vertcat(offset, period), ca.vertcat(x, z)):
            usable.append((offset, period, e.label))
    if usable:
        time_events = ca.Function("time_events", [p], [ca.vertcat(*[u[0] for u in usable]),
                                                       ca.vertcat(*[u[1] for u in usable])],
                                  ["p"], ["offset", "period"])
        time_labels = [u[2] for u in usable]
    return events, labels, time_events, time_labels


def _declared_units(reduced: ReducedSystem, output_names: list[str]) -> dict[str, str]:
    """Declared units of the parameters and outputs: `-p L=100mm` converts with them, output
    files and plots label with them."""
    known = set(output_names) | {q.name for q in reduced.parameters}
    return {name: unit for name, unit in sorted(reduced.metadata.get("units", {}).items()) if name in known}


def _bind(env: dict, names: list[str], vector: ca.SX, kind: str) -> None:
    for i, name in enumerate(names):
        _define(env, name, vector[i], kind)


def _define(env: dict, name: str, value: ca.SX, kind: str = "assignment") -> None:
    if name in env:
        raise LoweringError(f"'{name}' is defined twice (again as {kind})")
    env[name] = value


def _default_outputs(reduced: ReducedSystem) -> list[str]:
    return (list(reduced.states) + list(reduced.algebraics)
            + [a.target for a in reduced.assignments] + [a.target for a in reduced.observables])


def _parameter_function(reduced: ReducedSystem) -> ca.Function:
    """params(p_user, override_mask) -> p_full.

    A parameter with a binding takes its user value only where the mask says it was overridden;
    otherwise its binding is evaluated from the already-resolved earlier parameters, so that
    overriding `Kv` re-derives `Kv_b = Kv * area_b / area_a`.
    """
    n = len(reduced.parameters)
    user = ca.SX.sym("p_user", n)
    mask = ca.SX.sym("override_mask", n)
    env: dict[str, ca.SX] = {}
    walker = SXLowering(env, f"the parameters of {reduced.name}")
    full = []
    for i, q in enumerate(reduced.parameters):
        if q.binding is None:
            value = user[i]
        else:
            bound = walker.lower(q.binding, f"the default of parameter '{q.name}'")
            value = ca.if_else(mask[i], user[i], bound)
        env[q.name] = value
        full.append(value)
    return ca.Function("params", [user, mask], [ca.vertcat(*full)], ["p_user", "override_mask"],
                       ["p_full"])


def _plain(value):
    """Statistics as JSON-safe plain data (they travel inside generated modules)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in sorted(value.items(), key=lambda kv: str(kv[0]))}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (int, float, str, bool)) or value is None:
        return value
    return str(value)
