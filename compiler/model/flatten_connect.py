"""Connection sets: union-find over (connector instance, inside/outside) elements.

Modelica's rule: a connector referenced as `c` inside component P (P's own connector) is an
*outside* element of that connect; `sub.c` is an *inside* element. Potentials of a set are equal,
flows sum to zero with inside elements counted +1 and outside ones -1. A physical connector that is
never an inside element of any set gets `flow = 0` for each flow field. Signal sets are driven by
their one source (an inside output or an outside input).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import sympy

from compiler.errors import DyadError, Note, Span
from compiler.model.expressions import EvalScope, apply_indices
from compiler.model.flat import Equation, Origin
from compiler.model.instantiate import Instance, VariableInstance, join_path
from compiler.syntax import ast

INSIDE, OUTSIDE = "inside", "outside"


@dataclass
class Element:
    target: Any                       # Instance (physical connector) or VariableInstance (signal)
    side: str
    span: Span | None

    @property
    def key(self) -> tuple[str, str]:
        return self.target.path, self.side

    @property
    def is_signal(self) -> bool:
        return isinstance(self.target, (VariableInstance, SignalElements))

    @property
    def is_source(self) -> bool:
        causality = self.target.causality
        return (self.side == INSIDE and causality == "output") or \
               (self.side == OUTSIDE and causality == "input")


@dataclass(frozen=True)
class SignalElements:
    """Some elements of an array signal, connected on their own: `m.u[2]` of a signal connector
    array `u = [RealInput() for i in 1:n]` (or of `input u::Real[n]`)."""
    variable: VariableInstance
    path: str                         # `m.u[2]`, as written
    symbols: Any                      # the element's symbol, or an array of them
    names: tuple[str, ...]

    @property
    def causality(self) -> str | None:
        return self.variable.causality

    @property
    def shape(self) -> tuple[int, ...]:
        return getattr(self.symbols, "shape", ())


def _signal_elements(variable: VariableInstance, part: ast.RefPart, scope: EvalScope,
                     span: Span | None) -> SignalElements:
    picked = apply_indices(variable.symbols, part.indices, variable.path, scope, span)
    names = tuple(str(s) for s in picked.ravel()) if hasattr(picked, "ravel") else (str(picked),)
    path = names[0] if len(names) == 1 and not hasattr(picked, "ravel") else \
        f"{variable.path}[{', '.join(names)}]"
    return SignalElements(variable, path, picked, names)


@dataclass
class ConnectSet:
    elements: list[Element] = field(default_factory=list)
    origin: Origin | None = None


class _Disabled:
    pass


DISABLED = _Disabled()


def resolve_connector(ref: ast.Ref, scope: EvalScope) -> Any:
    """The connector a `connect` argument names: an Instance of a connector, a signal
    VariableInstance, or DISABLED when it lies in a conditionally removed component."""
    current: Any = scope.node
    walked = ""
    last = len(ref.parts) - 1
    for k, part in enumerate(ref.parts):
        walked = join_path(walked, part.name)
        if not isinstance(current, Instance):
            raise DyadError(f"`{walked}` does not name a connector", ref.span)
        if part.name in current.disabled:
            return DISABLED
        variable = current.variables.get(part.name)
        if variable is not None:
            if k != last:
                raise DyadError(f"`{walked}` is a variable; cannot access `.{ref.parts[k + 1].name}`",
                                ref.span)
            if not (variable.is_signal or variable.connector_kind == "signal"):
                raise DyadError(f"`{ref.dotted}` is a variable, not a connector; write an "
                                f"equation instead", ref.span)
            return _signal_elements(variable, part, scope, ref.span) if part.indices else variable
        child = current.children.get(part.name)
        if child is None:
            from compiler.errors import suggest_name
            where = current.path or "the model"
            raise DyadError(f"unknown connector `{walked}` in {where}", ref.span,
                            hint=suggest_name(part.name, current.member_names()))
        current = apply_indices(child, part.indices, walked, scope, ref.span)
    if not isinstance(current, Instance):
        raise DyadError(f"`{ref.dotted}` is an array of components; index it to connect", ref.span)
    if current.kind != "connector":
        raise DyadError(f"`{ref.dotted}` is a component, not a connector", ref.span)
    return current


def _layout(target: Any) -> tuple:
    if isinstance(target, (VariableInstance, SignalElements)):
        return ("signal", target.shape)
    return tuple(sorted((v.name, v.connector_kind, v.shape) for v in target.variables.values()))


def _describe(target: Any) -> str:
    if isinstance(target, (VariableInstance, SignalElements)):
        return f"signal {target.causality or ''}".strip()
    return f"connector {target.resolved.name}"


class ConnectionGraph:
    def __init__(self) -> None:
        self._parent: dict[tuple[str, str], tuple[str, str]] = {}
        self._elements: dict[tuple[str, str], Element] = {}
        self._order: dict[tuple[str, str], int] = {}
        self._origins: dict[tuple[str, str], Origin] = {}
        # `name: analysis_point(out, in)`: name -> (output signal names, input signal names, span)
        self.analysis_points: dict[str, tuple[list[str], list[str], Span | None]] = {}

    def _find(self, key: tuple[str, str]) -> tuple[str, str]:
        root = key
        while self._parent[root] != root:
            root = self._parent[root]
        while self._parent[key] != root:
            self._parent[key], key = root, self._parent[key]
        return root

    def _add(self, element: Element, origin: Origin) -> tuple[str, str]:
        key = element.key
        if key not in self._parent:
            self._parent[key] = key
            self._elements[key] = element
            self._order[key] = len(self._order)
            self._origins[key] = origin
        return key

    def add(self, connect: ast.Connect, scope: EvalScope) -> None:
        if len(connect.refs) < 2:
            raise DyadError("`connect` needs at least two connectors", connect.span)
        elements: list[Element] = []
        for ref in connect.refs:
            target = resolve_connector(ref, scope)
            if target is DISABLED:
                return  # connections to conditionally removed components are dropped
            side = OUTSIDE if len(ref.parts) == 1 else INSIDE
            elements.append(Element(target, side, ref.span))
        first = elements[0]
        for other in elements[1:]:
            if first.is_signal != other.is_signal or _layout(first.target) != _layout(other.target):
                raise DyadError(
                    f"cannot connect {_describe(first.target)} `{first.target.path}` with "
                    f"{_describe(other.target)} `{other.target.path}`: incompatible connectors",
                    other.span or connect.span,
                    notes=[Note(f"`{first.target.path}` is {_describe(first.target)}", first.span)])
        origin = Origin(scope.node.path, connect.span)
        if connect.analysis_point is not None and first.is_signal:
            self.analysis_points[join_path(scope.node.path, connect.analysis_point)] = (
                list(first.target.names), list(elements[-1].target.names), connect.span)
        keys = [self._add(e, origin) for e in elements]
        for key in keys[1:]:
            a, b = self._find(keys[0]), self._find(key)
            if a != b:
                # the older element stays the representative: deterministic set order
                if self._order[a] < self._order[b]:
                    self._parent[b] = a
                else:
                    self._parent[a] = b

    def is_inside_connected(self, path: str) -> bool:
        return (path, INSIDE) in self._parent

    def is_connected(self, path: str) -> bool:
        """Named in some `connect`, from inside or from outside."""
        return (path, INSIDE) in self._parent or (path, OUTSIDE) in self._parent

    def sets(self) -> list[ConnectSet]:
        groups: dict[tuple[str, str], ConnectSet] = {}
        for key in sorted(self._parent, key=self._order.__getitem__):
            root = self._find(key)
            group = groups.get(root)
            if group is None:
                group = groups[root] = ConnectSet(origin=self._origins[key])
            group.elements.append(self._elements[key])
        return list(groups.values())


def connection_equations(graph: ConnectionGraph) -> tuple[list[Equation], dict[str, bool]]:
    """Equations of every set, and for each signal element path whether its set has a source."""
    equations: list[Equation] = []
    driven: dict[str, bool] = {}
    for group in graph.sets():
        first = group.elements[0]
        if first.is_signal:
            equations.extend(_signal_equations(group, driven))
        else:
            equations.extend(_physical_equations(group))
    return equations, driven


def _pairs(reference: Any, other: Any) -> list[sympy.Expr]:
    if hasattr(reference, "ravel"):
        return [o - r for o, r in zip(other.ravel(), reference.ravel())]
    return [other - reference]


def _physical_equations(group: ConnectSet) -> list[Equation]:
    out: list[Equation] = []
    reference = group.elements[0].target
    for name, variable in reference.variables.items():
        if variable.connector_kind == "potential":
            for element in group.elements[1:]:
                for residual in _pairs(variable.symbols, element.target.variables[name].symbols):
                    out.append(Equation(residual, group.origin, "connect"))
        elif variable.connector_kind == "flow":
            terms = []
            for element in group.elements:
                symbols = element.target.variables[name].symbols
                sign = 1 if element.side == INSIDE else -1
                terms.append((sign, symbols))
            if hasattr(variable.symbols, "ravel"):
                for i in range(variable.symbols.size):
                    out.append(Equation(sympy.Add(*[s * sym.ravel()[i] for s, sym in terms]),
                                        group.origin, "flow"))
            else:
                out.append(Equation(sympy.Add(*[s * sym for s, sym in terms]), group.origin, "flow"))
        elif variable.connector_kind == "signal":
            for element in group.elements[1:]:
                for residual in _pairs(variable.symbols, element.target.variables[name].symbols):
                    out.append(Equation(residual, group.origin, "connect"))
    return out


def _signal_equations(group: ConnectSet, driven: dict[str, bool]) -> list[Equation]:
    sources = [e for e in group.elements if e.is_source]
    if len(sources) > 1:
        a, b = sources[0], sources[1]
        raise DyadError(f"two outputs connected: `{a.target.path}` and `{b.target.path}` both "
                        f"drive the same signal", b.span or (group.origin and group.origin.span),
                        notes=[Note(f"`{a.target.path}` connected here", a.span)])
    reference = sources[0] if sources else group.elements[0]
    out = []
    for element in group.elements:
        driven[element.target.path] = bool(sources)
        for name in element.target.names:
            driven[name] = driven.get(name, False) or bool(sources)
        if element is reference:
            continue
        for residual in _pairs(reference.target.symbols, element.target.symbols):
            out.append(Equation(residual, group.origin, "connect"))
    return out
