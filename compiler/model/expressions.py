"""AST expressions -> sympy values, inside an instance scope.

A value is a sympy scalar, a numpy object array of sympy scalars (vectors, matrices; 1-based in
the language, 0-based here), or a Python str. Component arrays are numpy object arrays of instance
nodes, so indexing works the same way for both.

Three evaluation modes:
- SYMBOLIC: equations. Variables and ordinary parameters stay symbols; structural parameters and
  constants are replaced by their values.
- NUMERIC: parameter values. Every parameter is replaced by its numeric value; variables and `time`
  are errors. A parameter without a value raises MissingValue.
- STRUCTURAL: like NUMERIC, for array sizes, indices, ranges and `if` conditions; the parameters
  read are recorded as structural (no longer tunable) and a missing value is a located error.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
import sympy
from sympy.core.relational import Relational
from sympy.logic.boolalg import BooleanAtom, BooleanFunction

from compiler.errors import DyadError, Span
from compiler.model.flat import TIME, der_name
from compiler.model import object_calls
from compiler.model.functions import PI, FunctionCallError, FunctionImpl, as_array, is_array
from compiler.model.ranges import float_range, is_fractional
from compiler.model.size_limits import check_elements, check_shape, checked_power, range_length
from compiler.syntax import ast

if TYPE_CHECKING:
    from compiler.model.library import Library


# sympy.Symbol is itself a sympy Boolean, so conditions are recognised by these classes instead.
CONDITION_TYPES = (Relational, BooleanFunction, BooleanAtom)


class Mode(enum.Enum):
    SYMBOLIC = "symbolic"
    NUMERIC = "numeric"
    STRUCTURAL = "structural"


class MissingValue(Exception):
    """A parameter without a value was needed for a numeric evaluation."""

    def __init__(self, name: str):
        super().__init__(name)
        self.name = name


END_BINDING = "\0end"     # the size of the dimension being indexed, for `end`
_NOT_FOUND = object()


class Node(Protocol):
    """An instance in the tree (component or connector), as seen by the evaluator."""
    path: str

    def member(self, name: str, mode: Mode, span: Span | None) -> Any: ...
    def member_names(self) -> list[str]: ...


class DerivativeTracker(Protocol):
    def is_unknown(self, name: str) -> bool: ...
    def note_derivative(self, name: str) -> None: ...


@dataclass(frozen=True)
class Lexical:
    """Where a piece of source was written: resolves function (and type) names."""
    library: "Library"
    package: str
    file: ast.File | None


class EvalScope:
    __slots__ = ("node", "lexical", "bindings", "tracker")

    def __init__(self, node: Node, lexical: Lexical, tracker: DerivativeTracker,
                 bindings: dict[str, Any] | None = None):
        self.node = node
        self.lexical = lexical
        self.tracker = tracker
        self.bindings = bindings or {}

    def bind(self, **values: Any) -> "EvalScope":
        return EvalScope(self.node, self.lexical, self.tracker, {**self.bindings, **values})

    def with_lexical(self, lexical: Lexical) -> "EvalScope":
        return EvalScope(self.node, lexical, self.tracker, self.bindings)

    def function_body(self, package: str, bindings: dict[str, Any]) -> "EvalScope":
        """The scope of an inlined function's body: no component members, only `bindings`, its
        calls resolved in `package`."""
        return EvalScope(_NoMembers(self.node), Lexical(self.lexical.library, package, None),
                         self.tracker, bindings)

    def lookup(self, name: str, mode: Mode, span: Span | None) -> Any:
        if name in self.bindings:
            return self.bindings[name]
        found = self.node.member(name, mode, span)
        if found is not _NOT_FOUND and found is not None:
            return found
        if name == "time":
            if mode is not Mode.SYMBOLIC:
                raise DyadError("a parameter expression cannot depend on `time`", span)
            return TIME
        if name in ("pi", "π"):
            return PI
        if name == "Inf":
            return sympy.oo
        from compiler.errors import suggest_name
        hint = suggest_name(name, list(self.bindings) + self.node.member_names())
        where = self.node.path or "the model"
        raise DyadError(f"unknown name `{name}` in {where}", span, hint=hint)


NOT_FOUND = _NOT_FOUND


# ------------------------------------------------------------------------------------- helpers

def is_node_like(value: Any) -> bool:
    return hasattr(value, "member") and hasattr(value, "path")


def is_node_array(value: Any) -> bool:
    return is_array(value) and value.size > 0 and is_node_like(value.flat[0])


def to_bool(value: Any, span: Span | None) -> Any:
    if isinstance(value, CONDITION_TYPES):
        return value
    if is_array(value) or isinstance(value, str):
        raise DyadError("a condition must be a scalar", span)
    if value.is_Number:
        return sympy.true if value != 0 else sympy.false
    # A Boolean variable is 1 or 0 (Booleans are numbers in Dyad); "above one half" says the same
    # for those values and, unlike `!= 0`, crosses zero, so the run can locate where it changes.
    return sympy.Gt(value, sympy.Rational(1, 2))


def _num(value: Any, span: Span | None) -> Any:
    """Booleans enter arithmetic as 1/0, a symbolic condition as a 1/0 selection."""
    if isinstance(value, BooleanAtom):
        return sympy.Integer(1 if value else 0)
    if isinstance(value, CONDITION_TYPES):
        # A Boolean is a number in Dyad (true = 1, false = 0): `y = u > 1` on a Boolean output.
        return sympy.Piecewise((sympy.Integer(1), value), (sympy.Integer(0), True))
    if isinstance(value, str):
        raise DyadError("a string cannot be used in arithmetic", span)
    if is_node_like(value) or is_node_array(value):
        raise DyadError(f"`{value.path if is_node_like(value) else 'component array'}` is a "
                        f"component, not a value", span)
    if is_array(value):
        return np.vectorize(lambda v: _num(v, span), otypes=[object])(value) if value.size else value
    return value


def shape_of(value: Any) -> tuple[int, ...]:
    return tuple(value.shape) if is_array(value) else ()


def structural_int(value: Any, span: Span | None, what: str = "an index") -> int:
    if isinstance(value, BooleanAtom):
        return 1 if value else 0
    if is_array(value) or not getattr(value, "is_number", False):
        raise DyadError(f"{what} must be an integer known at compile time", span)
    if value.is_Integer:            # exact, however large (float() of 10^400 overflows)
        return int(value)
    number = float(value)
    if number != int(number):
        raise DyadError(f"{what} must be an integer, got {number:g}", span)
    return int(number)


def structural_bool(value: Any, span: Span | None) -> bool:
    value = to_bool(value, span)
    if value is sympy.true:
        return True
    if value is sympy.false:
        return False
    raise DyadError("this condition must be known at compile time (structural); use "
                    "ifelse(c, a, b) for a continuous selection", span)


def time_invariant(expr: Any, tracker: DerivativeTracker) -> bool:
    values = expr.ravel().tolist() if is_array(expr) else [expr]
    for value in values:
        for sym in getattr(value, "free_symbols", ()):
            if sym == TIME or tracker.is_unknown(sym.name):
                return False
    return True


def time_derivative(expr: Any, tracker: DerivativeTracker) -> Any:
    """d/dt by the chain rule; unknowns x become der(x) symbols, parameters are constant."""
    if is_array(expr):
        return np.vectorize(lambda e: time_derivative(e, tracker), otypes=[object])(expr)
    if isinstance(expr, sympy.Symbol):
        if tracker.is_unknown(expr.name):
            tracker.note_derivative(expr.name)
            return sympy.Symbol(der_name(expr.name))
        return sympy.Integer(1) if expr == TIME else sympy.Integer(0)
    total = sympy.Integer(0)
    for sym in sorted(expr.free_symbols, key=lambda s: s.name):
        if sym == TIME:
            total += sympy.diff(expr, sym)
        elif tracker.is_unknown(sym.name):
            tracker.note_derivative(sym.name)
            total += sympy.diff(expr, sym) * sympy.Symbol(der_name(sym.name))
    return total


# ------------------------------------------------------------------------------------ evaluator

def evaluate(expr: ast.Expr, scope: EvalScope, mode: Mode) -> Any:
    handler = _HANDLERS.get(type(expr))
    if handler is None:
        raise DyadError(f"unsupported expression {type(expr).__name__}", getattr(expr, "span", None))
    return handler(expr, scope, mode)


def evaluate_numeric_value(expr: ast.Expr, scope: EvalScope, mode: Mode) -> Any:
    return _num(evaluate(expr, scope, mode), getattr(expr, "span", None))


def _number(expr: ast.Number, scope: EvalScope, mode: Mode) -> Any:
    if isinstance(expr.value, bool):
        return sympy.Integer(int(expr.value))
    if isinstance(expr.value, int):
        return sympy.Integer(expr.value)
    return sympy.Float(expr.value)


def _string(expr: ast.String, scope: EvalScope, mode: Mode) -> Any:
    return expr.value


def _boolean(expr: ast.Boolean, scope: EvalScope, mode: Mode) -> Any:
    return sympy.true if expr.value else sympy.false


def _end(expr: ast.End, scope: EvalScope, mode: Mode) -> Any:
    if END_BINDING not in scope.bindings:
        raise DyadError("`end` can only be used inside an index", expr.span)
    return scope.bindings[END_BINDING]


def _colon(expr: ast.Colon, scope: EvalScope, mode: Mode) -> Any:
    raise DyadError("`:` can only be used as an index", expr.span)


def resolve_ref(ref: ast.Ref, scope: EvalScope, mode: Mode) -> Any:
    """The value or node a reference names (components and connectors are returned as nodes)."""
    first = ref.parts[0]
    if len(ref.parts) > 1 and not any(p.indices for p in ref.parts) \
            and first.name not in scope.bindings and first.name not in scope.node.member_names():
        member = enum_member_value(ref.dotted, scope.lexical, ref.span)
        if member is not None:
            return member
    current = scope.lookup(first.name, mode, ref.span)
    current = apply_indices(current, first.indices, first.name, scope, ref.span)
    walked = first.name
    for part in ref.parts[1:]:
        if not is_node_like(current):
            kind = "an array of components" if is_node_array(current) else "not a component"
            raise DyadError(f"`{walked}` is {kind}; cannot access `.{part.name}`", ref.span)
        found = current.member(part.name, mode, ref.span)
        if found is NOT_FOUND or found is None:
            from compiler.errors import suggest_name
            raise DyadError(f"`{walked}` has no member `{part.name}`", ref.span,
                            hint=suggest_name(part.name, current.member_names()))
        current = apply_indices(found, part.indices, f"{walked}.{part.name}", scope, ref.span)
        walked = f"{walked}.{part.name}"
    return current


def _ref(expr: ast.Ref, scope: EvalScope, mode: Mode) -> Any:
    value = resolve_ref(expr, scope, mode)
    if is_node_like(value) or is_node_array(value):
        raise DyadError(f"`{expr.dotted}` is a component or connector, not a value", expr.span)
    return value


def apply_indices(value: Any, indices: tuple[ast.Expr, ...], name: str, scope: EvalScope,
                  span: Span | None) -> Any:
    if not indices:
        return value
    if not is_array(value):
        raise DyadError(f"`{name}` is not an array and cannot be indexed", span)
    if len(indices) > value.ndim:
        raise DyadError(f"`{name}` has {value.ndim} dimension(s) but {len(indices)} indices were "
                        f"given", span)
    result = value
    axis = 0
    for dim, index in enumerate(indices):
        size = value.shape[dim]
        if isinstance(index, ast.Colon):
            axis += 1
            continue
        inner = scope.bind(**{END_BINDING: sympy.Integer(size)})
        picked = evaluate(index, inner, Mode.STRUCTURAL)
        if is_array(picked):
            positions = [structural_int(p, span) for p in picked.ravel()]
            for p in positions:
                _check_bounds(p, size, name, span)
            result = np.take(result, [p - 1 for p in positions], axis=axis)
            axis += 1
        else:
            position = structural_int(picked, span)
            _check_bounds(position, size, name, span)
            result = np.take(result, position - 1, axis=axis)
    if is_array(result) and result.ndim == 0:
        return result.item()
    return result


def _check_bounds(position: int, size: int, name: str, span: Span | None) -> None:
    if not 1 <= position <= size:
        raise DyadError(f"index {position} is out of bounds for `{name}` of size {size}", span)


def iteration_values(expr: ast.Expr, scope: EvalScope) -> list[Any]:
    """The values a `for` iterator runs through (structural)."""
    value = evaluate(expr, scope, Mode.STRUCTURAL)
    if is_array(value):
        return list(value.ravel())
    raise DyadError("a `for` loop needs a range or an array to iterate over",
                    getattr(expr, "span", None))


def _range(expr: ast.Range, scope: EvalScope, mode: Mode) -> Any:
    bounds = [None if part is None else evaluate(part, scope, Mode.STRUCTURAL)
              for part in (expr.start, expr.step, expr.stop)]
    if any(is_fractional(bound) for bound in bounds):      # `0:0.1:1`: Julia's float range
        return as_array(float_range(*bounds, expr.span))
    start = structural_int(bounds[0], expr.span, "a range bound")
    stop = structural_int(bounds[2], expr.span, "a range bound")
    step = 1
    if expr.step is not None:
        step = structural_int(bounds[1], expr.span, "a range step")
        if step == 0:
            raise DyadError("a range step cannot be zero", expr.span)
    check_elements(range_length(start, stop, step), expr.span, "this range")
    return as_array([sympy.Integer(i) for i in range(start, stop + (1 if step > 0 else -1), step)])


def _unary(expr: ast.UnaryOp, scope: EvalScope, mode: Mode) -> Any:
    value = evaluate(expr.operand, scope, mode)
    if expr.op in ("!", "not"):
        return sympy.Not(to_bool(value, expr.span))
    value = _num(value, expr.span)
    return -value if expr.op == "-" else value


_COMPARISONS = {"<": sympy.Lt, "<=": sympy.Le, ">": sympy.Gt, ">=": sympy.Ge,
                "==": sympy.Eq, "!=": sympy.Ne}


# Left-associated chains of one family: evaluated in a loop, not by recursing down the left operand.
_CHAIN_FAMILIES = (frozenset({"+", "-", ".+", ".-"}), frozenset({"*", "/", ".*", "./"}),
                   frozenset({"and", "&&"}), frozenset({"or", "||"}))


def _binary(expr: ast.BinaryOp, scope: EvalScope, mode: Mode) -> Any:
    op = expr.op
    for family in _CHAIN_FAMILIES:
        if op in family and isinstance(expr.left, ast.BinaryOp) and expr.left.op in family:
            return _chain(expr, family, scope, mode)
    if op in _INTEGER_OPERATORS:
        return _integer_operator(op, evaluate(expr.left, scope, mode),
                                 evaluate(expr.right, scope, mode), expr.span)
    left = evaluate(expr.left, scope, mode)
    right = evaluate(expr.right, scope, mode)
    if op in ("and", "or", "&&", "||"):
        a, b = to_bool(left, expr.span), to_bool(right, expr.span)
        return sympy.And(a, b) if op in ("and", "&&") else sympy.Or(a, b)
    if op in _COMPARISONS:
        if is_array(left) or is_array(right):
            raise DyadError(f"comparison `{op}` needs scalars", expr.span)
        if isinstance(left, str) or isinstance(right, str):
            if op not in ("==", "!="):
                raise DyadError(f"strings cannot be compared with `{op}`", expr.span)
            equal = left == right
            return sympy.true if equal == (op == "==") else sympy.false
        return _COMPARISONS[op](_num(left, expr.span), _num(right, expr.span))
    left, right = _num(left, expr.span), _num(right, expr.span)
    try:
        return _arith(op, left, right, expr.span)
    except TypeError as exc:
        raise DyadError(f"invalid operands for `{op}`: {exc}", expr.span) from exc


def _chain(expr: ast.BinaryOp, family: frozenset, scope: EvalScope, mode: Mode) -> Any:
    """`a + b - c + ...` (a 20000-term sum is a 20000-deep left chain): one loop, and for
    scalars one flat sympy Add or Mul instead of re-flattening a growing sum at every term."""
    first, links = ast.left_chain(expr, family)
    if "and" in family or "or" in family:
        conditions = [to_bool(evaluate(first, scope, mode), expr.span)]
        conditions += [to_bool(evaluate(link.right, scope, mode), link.span) for link in links]
        return sympy.And(*conditions) if "and" in family else sympy.Or(*conditions)
    values = [_num(evaluate(first, scope, mode), expr.span)]
    values += [_num(evaluate(link.right, scope, mode), link.span) for link in links]
    if not any(is_array(v) for v in values):
        if "+" in family:
            return sympy.Add(values[0], *(v if link.op in ("+", ".+") else -v
                                          for link, v in zip(links, values[1:])))
        return sympy.Mul(values[0], *(v if link.op in ("*", ".*") else sympy.Pow(v, -1)
                                      for link, v in zip(links, values[1:])))
    result = values[0]
    for link, value in zip(links, values[1:]):
        try:
            result = _arith(link.op, result, value, link.span)
        except TypeError as exc:
            raise DyadError(f"invalid operands for `{link.op}`: {exc}", link.span) from exc
    return result


# Julia's integer operators: `%` and rem() keep the sign of the dividend, mod() that of the
# divisor, `÷` and div() truncate toward zero. Written with floor/sign/abs, which every later pass
# (sympy, CasADi, C code) knows.
_INTEGER_OPERATORS = {"%": "rem", "÷": "div"}


def _truncate(x: Any) -> Any:
    return sympy.sign(x) * sympy.floor(sympy.Abs(x))


def _integer_operator(name: str, left: Any, right: Any, span: Span | None) -> Any:
    name = _INTEGER_OPERATORS.get(name, name)
    a, b = _num(left, span), _num(right, span)
    if is_array(a) or is_array(b):
        raise DyadError(f"`{name}` needs scalars", span)
    a, b = sympy.sympify(a), sympy.sympify(b)
    if b.is_zero:
        raise DyadError(f"`{name}` by zero", span)
    if name == "mod":
        return a - b * sympy.floor(a / b)
    if name == "rem":
        return a - b * _truncate(a / b)
    return _truncate(a / b)


def _arith(op: str, left: Any, right: Any, span: Span | None) -> Any:
    la, ra = is_array(left), is_array(right)
    if op.startswith(".") and op != ".":
        base = op[1:]
        if la and ra and left.shape != right.shape:
            raise _mismatch(op, left, right, span)
        return _apply(base, left, right, span)
    if op in ("+", "-"):
        if la != ra:
            raise DyadError(f"cannot `{op}` a scalar and an array of shape "
                            f"{shape_of(left if la else right)}; use `.{op}`", span)
        if la and left.shape != right.shape:
            raise _mismatch(op, left, right, span)
        return _apply(op, left, right)
    if op == "*":
        if la and ra:
            if left.ndim == 2 and right.ndim in (1, 2) and left.shape[1] == right.shape[0]:
                return left @ right
            if left.ndim == 1 and right.ndim == 2 and right.shape[0] == 1:
                return np.outer(left, right[0])
            raise _mismatch(op, left, right, span, hint="use dot(a, b) or `.*` for element-wise")
        return _apply(op, left, right)
    if op == "/":
        if ra:
            raise DyadError("cannot divide by an array", span)
        return _apply(op, left, right)
    if op == "^":
        if la or ra:
            raise DyadError("`^` needs scalars; use `.^` for element-wise powers", span)
        return checked_power(left, right, span)
    raise DyadError(f"unknown operator `{op}`", span)


def _apply(op: str, left: Any, right: Any, span: Span | None = None) -> Any:
    if op == "+":
        return left + right
    if op == "-":
        return left - right
    if op == "*":
        return left * right
    if op == "/":
        return left / right
    if op == "^":
        if is_array(left) or is_array(right):
            return np.vectorize(lambda a, b: checked_power(a, b, span), otypes=[object])(left, right)
        return checked_power(left, right, span)
    raise ValueError(op)


def _mismatch(op: str, left: Any, right: Any, span: Span | None, hint: str | None = None
              ) -> DyadError:
    return DyadError(f"array size mismatch in `{op}`: {shape_of(left)} and {shape_of(right)}",
                     span, hint=hint)


def _piecewise(cond: Any, then: Any, otherwise: Any, span: Span | None) -> Any:
    if cond is sympy.true:
        return then
    if cond is sympy.false:
        return otherwise
    if is_array(then) or is_array(otherwise):
        if shape_of(then) != shape_of(otherwise):
            raise DyadError(f"the branches have different shapes {shape_of(then)} and "
                            f"{shape_of(otherwise)}", span)
        return np.vectorize(lambda a, b: sympy.Piecewise((a, cond), (b, True)),
                            otypes=[object])(then, otherwise)
    return sympy.Piecewise((then, cond), (otherwise, True))


def _if(expr: ast.IfExpr, scope: EvalScope, mode: Mode) -> Any:
    cond = to_bool(evaluate(expr.condition, scope, mode), expr.span)
    if cond is sympy.true:
        return evaluate(expr.then, scope, mode)
    if cond is sympy.false:
        return evaluate(expr.otherwise, scope, mode)
    return _piecewise(cond, _num(evaluate(expr.then, scope, mode), expr.span),
                      _num(evaluate(expr.otherwise, scope, mode), expr.span), expr.span)


def _array_lit(expr: ast.ArrayLit, scope: EvalScope, mode: Mode) -> Any:
    if expr.is_matrix:
        rows = []
        for row in expr.elements:
            items = row.elements if isinstance(row, ast.ArrayLit) else (row,)
            values = []
            for item in items:
                v = _num(evaluate(item, scope, mode), expr.span)
                values.extend(v.ravel().tolist() if is_array(v) else [v])
            rows.append(values)
        if len({len(r) for r in rows}) > 1:
            raise DyadError("the rows of a matrix literal have different lengths", expr.span)
        out = np.empty((len(rows), len(rows[0]) if rows else 0), dtype=object)
        for i, r in enumerate(rows):
            for j, v in enumerate(r):
                out[i, j] = v
        return out
    values = [_num(evaluate(e, scope, mode), expr.span) for e in expr.elements]
    return _stack(values, expr.span)


def _stack(values: list[Any], span: Span | None) -> Any:
    if not values:
        return np.empty(0, dtype=object)
    shapes = {shape_of(v) for v in values}
    if len(shapes) > 1:
        raise DyadError(f"array literal elements have different shapes: "
                        f"{', '.join(str(s) for s in sorted(shapes))}", span)
    shape = shapes.pop()
    if shape == ():
        return as_array(values)
    out = np.empty((len(values),) + shape, dtype=object)
    for i, v in enumerate(values):
        out[i] = v
    return out


def _comprehension(expr: ast.Comprehension, scope: EvalScope, mode: Mode) -> Any:
    def expand(level: int, inner: EvalScope, outer: int) -> Any:
        if level == len(expr.iterators):
            return _num(evaluate(expr.expr, inner, mode), expr.span)
        it = expr.iterators[level]
        values = iteration_values(it.iterable, inner)
        # nested iterators multiply: each level's range may be small, their product not
        check_elements(outer * len(values), expr.span, "this comprehension")
        items = [expand(level + 1, inner.bind(**{it.variable: v}), outer * len(values))
                 for v in values]
        return _stack(items, expr.span)
    return expand(0, scope, 1)


def _shape_args(args: tuple[ast.Expr, ...], scope: EvalScope, span: Span | None) -> tuple:
    return check_shape(tuple(structural_int(evaluate(a, scope, Mode.STRUCTURAL), span, "an array size")
                             for a in args), span, "this array")


def _filled(value: Any, shape: tuple[int, ...]) -> np.ndarray:
    out = np.empty(shape, dtype=object)
    for index in np.ndindex(*shape):
        out[index] = value
    return out


def _call(expr: ast.Call, scope: EvalScope, mode: Mode) -> Any:
    name, span = expr.function, expr.span
    if name in ("mod", "rem", "div") and not expr.kwargs:
        if len(expr.args) != 2:
            raise DyadError(f"`{name}` takes two arguments", span)
        return _integer_operator(name, evaluate(expr.args[0], scope, mode),
                                 evaluate(expr.args[1], scope, mode), span)
    if name in ("minimum", "maximum"):
        name = name[:3]         # Julia's reductions over an array; min/max take arrays too
    if name == "not":           # `not(c)` is `!c`
        if len(expr.args) != 1 or expr.kwargs:
            raise DyadError("`not` takes one argument", span)
        return sympy.Not(to_bool(evaluate(expr.args[0], scope, mode), span))
    if name in ("der", "D"):    # `D(x)` is Dyad's spelling of der(x)
        if len(expr.args) != 1:
            raise DyadError(f"`{name}` takes one argument", span)
        if mode is not Mode.SYMBOLIC:
            raise DyadError("`der` cannot be used in a parameter expression", span)
        value = _num(evaluate(expr.args[0], scope, mode), span)
        if time_invariant(value, scope.tracker):
            what = f"`{expr.args[0].dotted}`" if isinstance(expr.args[0], ast.Ref) else "this"
            raise DyadError(f"der of {what}: it does not depend on time (a parameter or "
                            f"constant has no derivative)", span)
        return time_derivative(value, scope.tracker)
    if name == "ifelse":
        if len(expr.args) != 3:
            raise DyadError("`ifelse` takes three arguments (condition, then, else)", span)
        cond = to_bool(evaluate(expr.args[0], scope, mode), span)
        if cond is sympy.true:
            return evaluate(expr.args[1], scope, mode)
        if cond is sympy.false:
            return evaluate(expr.args[2], scope, mode)
        return _piecewise(cond, _num(evaluate(expr.args[1], scope, mode), span),
                          _num(evaluate(expr.args[2], scope, mode), span), span)
    if name in ("zeros", "ones"):
        shape = _shape_args(expr.args, scope, span)
        return _filled(sympy.Integer(0 if name == "zeros" else 1), shape)
    if name == "fill":
        if len(expr.args) < 2:
            raise DyadError("`fill` takes a value and at least one size", span)
        value = _num(evaluate(expr.args[0], scope, mode), span)
        return _filled(value, _shape_args(expr.args[1:], scope, span))
    if name == "size":
        if not 1 <= len(expr.args) <= 2:
            raise DyadError("`size` takes an array and optionally a dimension", span)
        # A size is known at compile time even when the elements are unknowns: read the array
        # symbolically (in a parameter expression, `size(u, 1)` of a variable `u` is allowed).
        value = _num(evaluate(expr.args[0], scope, Mode.SYMBOLIC), span)
        shape = shape_of(value)
        if len(expr.args) == 2:
            dim = structural_int(evaluate(expr.args[1], scope, Mode.STRUCTURAL), span)
            if dim < 1:
                raise DyadError(f"`size`: dimension {dim} out of range", span)
            # as in Julia, a scalar (and any array past its last dimension) has size 1
            return sympy.Integer(shape[dim - 1] if dim <= len(shape) else 1)
        return as_array([sympy.Integer(s) for s in shape])
    lex = scope.lexical
    if "." in name:                 # `Gear.High()`: an enum member written as a constructor
        member = enum_member_value(name, lex, span)
        if member is not None:
            if expr.args or expr.kwargs:
                raise DyadError(f"enum members with fields (`{name}(...)`) are not supported yet",
                                span)
            return member
    if mode is Mode.SYMBOLIC:       # a function of a Julia object (compiler/model/object_calls.py)
        value = object_calls.object_call(expr, scope, object_calls.Evaluator(
            value=lambda arg, at: _num(evaluate(arg, at, mode), span),
            structural=lambda arg, at: evaluate(arg, at, Mode.STRUCTURAL),
            inline=lambda function, args: _julia_call(function, args, expr, scope, mode)))
        if value is not None:
            return value
    impl = lex.library.resolve_function(name, lex.package, lex.file, span)
    args = [_num(evaluate(a, scope, mode), span) for a in expr.args]
    if not isinstance(impl, FunctionImpl):      # a function read from Julia source
        return _julia_call(impl, args, expr, scope, mode)
    kwargs = {k.name: _num(evaluate(k.value, scope, mode), span) for k in expr.kwargs}
    try:
        return impl(args, kwargs)
    except FunctionCallError as exc:
        raise DyadError(str(exc), span) from exc
    except TypeError as exc:
        raise DyadError(f"bad arguments for `{name}`: {exc}", span) from exc


def enum_member_value(qualified_member: str, lexical: Lexical, span: Span | None) -> Any:
    """`Gear.High` (or `Pkg.Gear.High`) as its 1-based position among the members of enum `Gear`;
    None when the prefix names no enum."""
    enum_name, _, member = qualified_member.rpartition(".")
    if not enum_name:
        return None
    found = lexical.library.lookup(enum_name, lexical.package, lexical.file)
    if found is None or not isinstance(found.definition, ast.EnumDef):
        return None
    members = found.definition.members
    if member not in members:
        from compiler.errors import suggest_name
        raise DyadError(f"enum `{enum_name}` has no member `{member}`", span,
                        hint=suggest_name(member, list(members)))
    return sympy.Integer(members.index(member) + 1)


def switch_branch(relation: ast.Switch, scope: EvalScope) -> tuple:
    """The relations of the case of `switch subject` that the subject's structural value selects
    (its `else` when no case names it)."""
    value = structural_int(evaluate(relation.subject, scope, Mode.STRUCTURAL), relation.span,
                           "a switch subject")
    enum_name = _subject_enum(relation.subject, scope)
    for case in relation.cases:
        for name in case.names:
            qualified = name if "." in name else f"{enum_name}.{name}" if enum_name else None
            index = enum_member_value(qualified, scope.lexical, case.span) if qualified else None
            if index is None:
                raise DyadError(f"cannot tell which enum `{name}` belongs to", case.span,
                                hint="switch on a parameter declared with an enum type, or write "
                                     "the case as `EnumName.Member`")
            if int(index) == value:
                return case.body
    return relation.otherwise


def _subject_enum(subject: ast.Expr, scope: EvalScope) -> str | None:
    """The qualified enum type of a switch subject that names a parameter, else None."""
    if not isinstance(subject, ast.Ref) or any(p.indices for p in subject.parts):
        return None
    node = scope.node
    for part in subject.parts[:-1]:
        node = node.member(part.name, Mode.STRUCTURAL, subject.span)
        if not is_node_like(node):
            return None
    parameter = getattr(node, "parameters", {}).get(subject.parts[-1].name)
    type_name = getattr(getattr(parameter, "type", None), "name", None)
    found = scope.lexical.library.find(type_name) if type_name else None
    return type_name if found is not None and isinstance(found.definition, ast.EnumDef) else None


def _julia_call(function: Any, args: list, expr: ast.Call, scope: EvalScope, mode: Mode) -> Any:
    """Inline a function read from a package's Julia source (compiler/julia/inline.py)."""
    return object_calls.inline(function, args, expr, scope,
                               lambda body, inner: evaluate(body, inner, mode))


class _NoMembers:
    """The scope node of a Julia function body: it sees no component members."""

    def __init__(self, node: Node):
        self.path = node.path

    def member(self, name: str, mode: Mode, span: Span | None) -> Any:
        return _NOT_FOUND

    def member_names(self) -> list[str]:
        return []


_HANDLERS = {
    ast.Number: _number, ast.String: _string, ast.Boolean: _boolean, ast.End: _end,
    ast.Colon: _colon, ast.Ref: _ref, ast.Range: _range, ast.UnaryOp: _unary,
    ast.BinaryOp: _binary, ast.IfExpr: _if, ast.ArrayLit: _array_lit,
    ast.Comprehension: _comprehension, ast.Call: _call,
}
