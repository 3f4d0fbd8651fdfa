"""Parameters of an instance, evaluated lazily: in dependency order with cycle detection, numeric
values checked to be finite reals of the declared shape, structural use propagated to the
parameters a value was computed from, and the symbolic default (a binding in other parameters'
symbols) for tunable parameters."""
from __future__ import annotations

import math
from typing import Any

import numpy as np
import sympy

from compiler.errors import DyadError, Note, Span
from compiler.model.expressions import CONDITION_TYPES, EvalScope, MissingValue, Mode, evaluate, \
    is_array, numeric, shape_of, structural_int
from compiler.model.size_limits import check_shape
from compiler.model.templates import BoundMod, ElementTemplate, check_final, resolve_value_type
from compiler.model.variables import PARAMETER_ATTRIBUTES, collect_attributes, element_names, \
    join_path, symbols_for
from compiler.syntax import ast

_UNEVALUATED, _EVALUATING, _DONE = 0, 1, 2


class ParameterInstance:
    """A declared parameter of an instance; `read` serves the evaluator, `value` is memoized."""

    def __init__(self, node: Any, element: ElementTemplate, entries: list[BoundMod]):
        decl: ast.ParameterDecl = element.decl
        self.node = node
        self.decl = decl
        self.name = decl.name
        self.path = join_path(node.path, decl.name)
        self.owner = element.owner
        self.lexical = element.lexical
        self.variability = decl.variability
        self.final = decl.final
        self.type = resolve_value_type(decl.type, element.lexical)
        check_final(entries, decl.final, decl.span, decl.name)
        valued = [e for e in entries if e.mod.value is not None]
        own_scope = node.scope(element.lexical)
        if valued:
            self.binding: tuple[ast.Expr, EvalScope] | None = (valued[0].mod.value, valued[0].scope)
        elif decl.default is not None:
            self.binding = (decl.default, own_scope)
        else:
            self.binding = None
        self.attributes = collect_attributes(self.type, entries, own_scope, PARAMETER_ATTRIBUTES,
                                              self.name)
        self._shape: tuple[int, ...] | None = None
        self._state = _UNEVALUATED
        self._value: Any = None
        self._symbolic_default: Any = None
        self._symbolic_done = False
        self.deps: list[ParameterInstance] = []
        self.structural_use = False

    @property
    def span(self) -> Span | None:
        return self.decl.span

    @property
    def fixed_at_compile_time(self) -> bool:
        return self.variability in ("structural", "constant")

    @property
    def is_string(self) -> bool:
        return self.type.primitive == "String"

    def shape(self) -> tuple[int, ...]:
        if self._shape is None:
            self._shape = check_shape(tuple(
                self._size_from_value(i, d.span) if isinstance(d, ast.Colon) else
                structural_int(evaluate(d, self.node.scope(lex), Mode.STRUCTURAL), d.span,
                               "an array size") for i, (d, lex) in enumerate(self.type.dims)),
                self.decl.span, f"the array `{self.path}`")
        return self._shape

    def _size_from_value(self, index: int, span: Span | None) -> int:
        """A dimension declared `:` (`parameter a::Real[:] = [1.0, 1.0]`) has the size of the
        parameter's value, whichever binding gives it (its default or a modifier)."""
        if self.binding is None:
            raise DyadError(f"parameter `{self.path}` takes its size from its value (`:`) but has "
                            f"no value", span, hint=f"give it one: `{self.name} = [...]`")
        expr, scope = self.binding
        value_shape = shape_of(numeric(evaluate(expr, scope, Mode.NUMERIC), expr.span))
        if len(value_shape) != len(self.type.dims):
            raise DyadError(f"array size mismatch: parameter `{self.path}` is declared with "
                            f"{len(self.type.dims)} dimension(s) but its value has size "
                            f"{value_shape or 'scalar'}", expr.span)
        return value_shape[index]

    def symbols(self) -> Any:
        return symbols_for(self.path, self.shape())

    def flat_names(self) -> list[str]:
        return element_names(self.path, self.shape())

    def scalar_count(self) -> int:
        """Its number of scalars if its shape is known already, else 1 (nothing is evaluated)."""
        return len(self.flat_names()) if self._shape is not None else 1

    # -- access from expressions
    def read(self, mode: Mode, span: Span | None) -> Any:
        model = self.node.model
        if mode is Mode.SYMBOLIC:
            if self.fixed_at_compile_time or self.is_string:
                value = self.value()
                if value is None:
                    raise DyadError(f"{self.variability} parameter `{self.path}` has no value",
                                    span)
                return value
            return self.symbols()
        if model.parameter_stack:
            model.parameter_stack[-1].deps.append(self)
        value = self.value()
        if mode is Mode.STRUCTURAL:
            self.mark_structural()
            if value is None:
                raise DyadError(f"parameter `{self.path}` has no value but is needed at compile "
                                f"time", span)
        elif value is None:
            raise MissingValue(self.path)
        return value

    def mark_structural(self) -> None:
        if self.structural_use:
            return
        self.structural_use = True
        for dep in self.deps:
            dep.mark_structural()

    def value(self) -> Any:
        """The numeric value (sympy number or array of them), None if it has none."""
        if self._state == _DONE:
            return self._value
        model = self.node.model
        if self._state == _EVALUATING:
            chain = model.parameter_stack[model.parameter_stack.index(self):] + [self]
            raise DyadError("cyclic parameter defaults: "
                            + " -> ".join(p.path for p in chain), self.span,
                            notes=[Note(f"`{p.path}` declared here", p.span) for p in chain[1:-1]])
        self._state = _EVALUATING
        model.parameter_stack.append(self)
        try:
            self._value = self._evaluate_checked_value()
        finally:
            model.parameter_stack.pop()
        self._state = _DONE
        return self._value

    def _evaluate_checked_value(self) -> Any:
        if self.binding is None:
            return None
        expr, scope = self.binding
        try:
            raw = evaluate(expr, scope, Mode.NUMERIC)
        except MissingValue:
            return None
        if self.is_string:
            if not isinstance(raw, str):
                raise DyadError(f"parameter `{self.path}` is a String but its value is not",
                                expr.span)
            return raw
        value = numeric(raw, expr.span)
        self._check_shape(value, expr.span)
        return _checked_value(value, expr.span, self.path)

    def _check_shape(self, value: Any, span: Span | None) -> None:
        if shape_of(value) != self.shape():
            declared = self.shape() or "scalar"
            raise DyadError(f"array size mismatch: parameter `{self.path}` is declared "
                            f"{declared if declared == 'scalar' else 'with size ' + str(declared)}"
                            f" but its value has size {shape_of(value) or 'scalar'}", span)

    def symbolic_default(self) -> Any:
        """The binding in other parameters' symbols (structural ones substituted)."""
        if not self._symbolic_done:
            self._symbolic_done = True
            if self.binding is not None and not self.is_string:
                expr, scope = self.binding
                value = evaluate(expr, scope, Mode.SYMBOLIC)
                if self.type.primitive == "Boolean":
                    value = _boolean_as_number(value, expr.span)
                value = numeric(value, expr.span)
                self._check_shape(value, expr.span)
                for sym in (value.ravel() if is_array(value) else [value]):
                    unknowns = [s.name for s in getattr(sym, "free_symbols", ())
                                if self.node.model.is_unknown(s.name) or s.name == "time"]
                    if unknowns:
                        raise DyadError(f"parameter `{self.path}` cannot depend on "
                                        f"`{unknowns[0]}` (not a parameter)", expr.span)
                self._symbolic_default = value
        return self._symbolic_default


def _boolean_as_number(value: Any, span: Span | None) -> Any:
    if is_array(value):
        return np.vectorize(lambda v: _boolean_as_number(v, span), otypes=[object])(value)
    if isinstance(value, CONDITION_TYPES):
        if value is sympy.true:
            return sympy.Integer(1)
        if value is sympy.false:
            return sympy.Integer(0)
        return sympy.Piecewise((sympy.Integer(1), value), (sympy.Integer(0), True))
    return value


def _checked_value(value: Any, span: Span | None, name: str) -> Any:
    """A parameter value must be a real number that a float can hold: the runtime computes in
    doubles, so `sqrt(-1)` or `1e400` would otherwise fail later, far from the declaration."""
    if is_array(value):
        return np.vectorize(lambda v: _checked_value(v, span, name), otypes=[object])(value)
    if not getattr(value, "is_number", False) or value.has(sympy.zoo, sympy.nan):
        raise DyadError(f"the value of `{name}` is not a finite number ({value})", span,
                        hint="check for a division by zero or a logarithm of zero")
    if value.is_extended_real is False:
        raise DyadError(f"the value of `{name}` is not a real number ({value})", span,
                        hint="a square root or logarithm of a negative number, or asin/acos "
                             "outside [-1, 1], has no real value")
    try:
        as_float = float(value)
    except (TypeError, ValueError):
        raise DyadError(f"the value of `{name}` is not a real number ({value})", span) from None
    if not math.isfinite(as_float):
        shown = "infinite" if value.is_infinite else f"about {sympy.N(value, 3)}"
        raise DyadError(f"the value of `{name}` overflows a floating-point number: it is {shown}, "
                        f"beyond the largest double (about 1.8e308)", span,
                        hint="use a smaller value or other units")
    return value
