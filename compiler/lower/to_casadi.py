"""Lower a ReducedSystem (sympy) to CasADi SX Functions: the numerical CompiledModel.

The walk over the sympy expression DAG is memoized on the sympy node, so a subexpression shared
between equations (or reached through an assignment symbol) becomes one shared SX node. Nothing
is printed, parsed, expanded or simplified on the way.
"""
from __future__ import annotations

from typing import Callable

import casadi as ca
import sympy

from compiler.errors import DyadError, Span
from compiler.lower.events import EVENT_CLOCK, Events, find_events, lock_timed_conditions
from compiler.lower.relation_locks import lock_state_relations
from compiler.model.flat import TIME
from compiler.model.interpolation import InterpolatedFunction
from compiler.runtime import CompiledModel
from compiler.structure.reduced import ReducedSystem

# Integer powers up to this are multiplied out (exact, cheap derivatives); larger use constpow.
_MAX_MULTIPLIED_POWER = 16


def _fold(op: Callable) -> Callable:
    def apply(*args):
        result = args[0]
        for a in args[1:]:
            result = op(result, a)
        return result
    return apply


# SX + and * without the Python operator wrappers (which first ask numpy about priority)
_SUM = _fold(ca.plus)
_PRODUCT = _fold(ca.times)

_UNARY = {
    sympy.sin: ca.sin, sympy.cos: ca.cos, sympy.tan: ca.tan,
    sympy.asin: ca.asin, sympy.acos: ca.acos, sympy.atan: ca.atan,
    sympy.sinh: ca.sinh, sympy.cosh: ca.cosh, sympy.tanh: ca.tanh,
    sympy.asinh: ca.asinh, sympy.acosh: ca.acosh, sympy.atanh: ca.atanh,
    sympy.exp: ca.exp, sympy.Abs: ca.fabs, sympy.sign: ca.sign,
    sympy.floor: ca.floor, sympy.ceiling: ca.ceil, sympy.erf: ca.erf,
    sympy.cot: lambda a: 1 / ca.tan(a), sympy.sec: lambda a: 1 / ca.cos(a),
    sympy.csc: lambda a: 1 / ca.sin(a),
}

_RELATIONAL = {
    sympy.StrictLessThan: ca.lt, sympy.LessThan: ca.le,
    sympy.StrictGreaterThan: ca.gt, sympy.GreaterThan: ca.ge,
    sympy.Equality: ca.eq, sympy.Unequality: ca.ne,
}

_VARIADIC = {
    sympy.Min: _fold(ca.fmin), sympy.Max: _fold(ca.fmax),
    sympy.And: _fold(ca.logic_and), sympy.Or: _fold(ca.logic_or),
    sympy.atan2: ca.atan2, sympy.Mod: ca.fmod,
    # sympy writes a condition chosen by a condition as ITE (a locked condition inside a Piecewise)
    sympy.ITE: lambda c, a, b: ca.if_else(c, a, b),
}


class LoweringError(DyadError):
    pass


class SXLowering:
    """Memoized sympy -> SX translation against an environment of named SX values."""

    def __init__(self, env: dict[str, ca.SX], where: str):
        self.env = env
        self.memo: dict[sympy.Basic, ca.SX] = {}
        self.where = where

    def lower(self, expr: sympy.Basic, context: str = "", span: Span | None = None) -> ca.SX:
        expr = sympy.sympify(expr)
        if expr in self.memo:
            return self.memo[expr]
        # Explicit post-order stack: deep expression chains must not hit Python's recursion limit.
        stack: list[tuple[sympy.Basic, bool]] = [(expr, False)]
        while stack:
            node, children_done = stack.pop()
            if node in self.memo:
                continue
            args = self._operands(node)
            if not children_done and any(a not in self.memo for a in args):
                stack.append((node, True))
                stack.extend((a, False) for a in args if a not in self.memo)
                continue
            self.memo[node] = self._convert(node, context, span)
        return self.memo[expr]

    @staticmethod
    def _operands(node: sympy.Basic) -> tuple:
        if node.is_Symbol or node.is_Number or isinstance(node, sympy.NumberSymbol):
            return ()
        if isinstance(node, sympy.Piecewise):
            return tuple(x for pair in node.args for x in pair)
        if isinstance(node, sympy.Pow) and node.exp.is_Rational:
            return (node.base,)
        if isinstance(node, sympy.Mul):
            return tuple(_split_power(f)[0] for f in node.args)
        return node.args

    def _convert(self, node: sympy.Basic, context: str, span: Span | None) -> ca.SX:
        memo = self.memo
        if node.is_Symbol:
            if node.name in self.env:
                return self.env[node.name]
            raise LoweringError(f"unknown symbol '{node}' in {context or self.where}: it is not a "
                                "state, algebraic unknown, parameter, assignment or time", span)
        if node is sympy.true:
            return ca.SX(1.0)
        if node is sympy.false:
            return ca.SX(0.0)
        if node.is_Number or isinstance(node, sympy.NumberSymbol):
            if node is sympy.zoo or node is sympy.nan:
                raise LoweringError(f"undefined value '{node}' (e.g. a division by zero) in "
                                    f"{context or self.where}", span)
            return ca.SX(float(node))
        if isinstance(node, sympy.Add):
            return _SUM(*[memo[a] for a in node.args])
        if isinstance(node, sympy.Mul):
            return self._mul(node)
        if isinstance(node, sympy.Pow):
            if node.exp.is_Rational:
                return _rational_power(memo[node.base], node.exp)
            if node.base is sympy.E:
                return ca.exp(memo[node.exp])
            return ca.power(memo[node.base], memo[node.exp])
        func = node.func
        if func in _UNARY:
            return _UNARY[func](memo[node.args[0]])
        if func is sympy.log:
            value = ca.log(memo[node.args[0]])
            return value / ca.log(memo[node.args[1]]) if len(node.args) == 2 else value
        if func in _VARIADIC:
            return _VARIADIC[func](*[memo[a] for a in node.args])
        if func in _RELATIONAL:
            return _RELATIONAL[func](memo[node.args[0]], memo[node.args[1]])
        if func is sympy.Not:
            return ca.logic_not(memo[node.args[0]])
        if func is sympy.Heaviside:
            a = memo[node.args[0]]
            at_zero = memo[node.args[1]] if len(node.args) > 1 else ca.SX(0.5)
            return ca.if_else(a > 0, 1.0, ca.if_else(a < 0, 0.0, at_zero))
        if isinstance(node, sympy.Piecewise):
            return self._piecewise(node)
        if isinstance(node, InterpolatedFunction):      # tabulated data: compiler/model/interpolation.py
            return ca.SX(node.table.evaluate(memo[node.args[0]], ca.if_else))
        raise LoweringError(f"cannot lower '{type(node).__name__}' (in `{_short(node)}`) to CasADi "
                            f"in {context or self.where}: unsupported function or construct", span)

    def _mul(self, node: sympy.Mul) -> ca.SX:
        """Factors with negative exponents go to one denominator: a*b/(c*d), not a*b*c^-1*d^-1."""
        numerator: list[ca.SX] = []
        denominator: list[ca.SX] = []
        for factor in node.args:
            base, exponent = _split_power(factor)
            if exponent is None:
                numerator.append(self.memo[factor])
            else:
                target = denominator if exponent < 0 else numerator
                target.append(_rational_power(self.memo[base], abs(exponent)))
        num = _PRODUCT(*numerator) if numerator else ca.SX(1.0)
        if not denominator:
            return num
        return num / _PRODUCT(*denominator)

    def _piecewise(self, node: sympy.Piecewise) -> ca.SX:
        result = ca.SX(float("nan"))                   # no branch applies: undefined
        for value, condition in reversed(node.args):
            if condition is sympy.true:
                result = self.memo[value]
            else:
                result = ca.if_else(self.memo[condition], self.memo[value], result)
        return result


def _split_power(factor: sympy.Basic) -> tuple[sympy.Basic, sympy.Rational | None]:
    """(base, rational exponent) for a power factor with a rational exponent, else (factor, None)."""
    if isinstance(factor, sympy.Pow) and factor.exp.is_Rational:
        return factor.base, factor.exp
    return factor, None


def _rational_power(base: ca.SX, exponent: sympy.Rational) -> ca.SX:
    if exponent.is_Integer:
        n = int(exponent)
        if n == 0:
            return ca.SX(1.0)
        if abs(n) > _MAX_MULTIPLIED_POWER:
            return ca.constpow(base, float(n))
        result = _integer_power(base, abs(n))
        return 1.0 / result if n < 0 else result
    if exponent == sympy.Rational(1, 2):
        return ca.sqrt(base)
    if exponent == sympy.Rational(-1, 2):
        return 1.0 / ca.sqrt(base)
    if exponent.q == 2 and abs(exponent.p) <= _MAX_MULTIPLIED_POWER:
        value = ca.sqrt(base) * _integer_power(base, (abs(exponent.p) - 1) // 2) \
            if abs(exponent.p) > 1 else ca.sqrt(base)
        return 1.0 / value if exponent < 0 else value
    return ca.constpow(base, float(exponent))


def _integer_power(base: ca.SX, n: int) -> ca.SX:
    """base**n by binary exponentiation (n >= 1)."""
    result = None
    square = base
    while n:
        if n & 1:
            result = square if result is None else result * square
        n >>= 1
        if n:
            square = square * square
    return result if result is not None else ca.SX(1.0)


def _short(node: sympy.Basic, limit: int = 80) -> str:
    text = str(node)
    return text if len(text) <= limit else text[:limit - 3] + "..."


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
    walker = SXLowering(env, f"model {reduced.name}")

    for a in reduced.assignments:
        _define(env, a.target, walker.lower(a.expr, f"the assignment to '{a.target}'", _span(a.origin)))
    ode = [walker.lower(e, f"der({name})") for name, e in zip(reduced.states, reduced.ode)]
    alg_origins = list(reduced.alg_origins) + [None] * nz
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

    derivative_of = {f"der({s})": e for s, e in zip(reduced.states, ode)}
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
        metadata={"statistics": _plain(reduced.statistics),
                  "assignments": len(reduced.assignments),
                  "observables": len(reduced.observables),
                  "bounds": {name: dict(sorted(b.items()))
                             for name, b in sorted(reduced.metadata.get("bounds", {}).items())
                             if name in set(output_names)},
                  "units": _declared_units(reduced, output_names),
                  **({"event_clock": EVENT_CLOCK.name} if found.timed_conditions else {}),
                  **({"relation_locks": [lock.as_metadata() for lock in locks]} if locks else {})},
    )


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
