"""Functions callable from Dyad expressions: the elementary functions, array helpers and a registry
of library functions keyed by qualified name (see docs/functions.md).

A function implementation receives evaluated arguments (sympy scalars or numpy object arrays of
sympy scalars) and returns such a value. Implementations never see AST nodes; `der`, `ifelse` and
the array constructors that need structural integers are forms of the table of built-ins
(compiler/model/builtins.py), which lists ELEMENTARY as well.
"""
from __future__ import annotations

import importlib.util
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

import numpy as np
import sympy

Value = object  # sympy.Expr | np.ndarray (dtype=object) | str


class FunctionCallError(Exception):
    """Raised by an implementation for bad arguments; the evaluator turns it into a located
    DyadError at the call site."""


@dataclass(frozen=True)
class FunctionImpl:
    name: str
    impl: Callable[..., Value]
    min_args: int = 0
    max_args: int | None = None     # None: variadic
    doc: str = ""

    def __call__(self, args: Sequence[Value], kwargs: dict[str, Value]) -> Value:
        if len(args) < self.min_args or (self.max_args is not None and len(args) > self.max_args):
            expected = (f"{self.min_args}" if self.max_args == self.min_args
                        else f"{self.min_args} to {self.max_args}" if self.max_args is not None
                        else f"at least {self.min_args}")
            raise FunctionCallError(f"`{self.name}` takes {expected} argument(s), got {len(args)}")
        return self.impl(*args, **kwargs)


# ------------------------------------------------------------------------------ value helpers

def is_array(value: Value) -> bool:
    return isinstance(value, np.ndarray)


def as_array(values: Sequence[Value]) -> np.ndarray:
    out = np.empty(len(values), dtype=object)
    for i, v in enumerate(values):
        out[i] = v
    return out


def _scalar(value: Value, fname: str) -> sympy.Expr:
    if is_array(value):
        raise FunctionCallError(f"`{fname}` expects a scalar argument, got an array of shape "
                                f"{tuple(value.shape)}")
    if isinstance(value, str):
        raise FunctionCallError(f"`{fname}` expects a number, got a string")
    return value


def elementwise(fname: str, fn: Callable[..., sympy.Expr], arity: int) -> FunctionImpl:
    """A scalar function that is applied element-wise to a single array argument."""
    def impl(*args):
        if arity == 1 and is_array(args[0]):
            return np.vectorize(fn, otypes=[object])(args[0])
        return fn(*[_scalar(a, fname) for a in args])
    return FunctionImpl(fname, impl, arity, arity)


def _log10(x):
    return sympy.log(x) / sympy.log(10)


def _reduce(fname: str, op):
    def impl(*args):
        items: list[sympy.Expr] = []
        for a in args:
            items.extend(a.ravel().tolist() if is_array(a) else [_scalar(a, fname)])
        if not items:
            raise FunctionCallError(f"`{fname}` of nothing")
        return op(*items)
    return FunctionImpl(fname, impl, 1, None)


def _clamp(x, lo, hi):
    return sympy.Min(sympy.Max(_scalar(x, "clamp"), _scalar(lo, "clamp")), _scalar(hi, "clamp"))


def _vector(value: Value, fname: str) -> np.ndarray:
    if not is_array(value):
        raise FunctionCallError(f"`{fname}` expects an array argument, got a scalar")
    return value


def _norm(v):
    flat = _vector(v, "norm").ravel()
    return sympy.sqrt(sympy.Add(*[e ** 2 for e in flat]))


def _dot(a, b):
    a, b = _vector(a, "dot"), _vector(b, "dot")
    if a.shape != b.shape:
        raise FunctionCallError(f"`dot` of arrays with different shapes {tuple(a.shape)} and "
                                f"{tuple(b.shape)}")
    return sympy.Add(*[x * y for x, y in zip(a.ravel(), b.ravel())])


def _sum(v):
    if not is_array(v):
        return v
    return sympy.Add(*v.ravel().tolist())


def _cross(a, b):
    a, b = _vector(a, "cross"), _vector(b, "cross")
    if a.shape == (2,) and b.shape == (2,):
        return a[0] * b[1] - a[1] * b[0]
    if a.shape == (3,) and b.shape == (3,):
        return as_array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                         a[0] * b[1] - a[1] * b[0]])
    raise FunctionCallError("`cross` expects two vectors of length 2 or 3")


def _transpose(m):
    m = _vector(m, "transpose")
    if m.ndim == 1:
        return m.reshape(1, -1)
    return m.T.copy()


def _length(v):
    return sympy.Integer(_vector(v, "length").shape[0])


def _hcat(parts) -> np.ndarray:
    """Julia's `hcat`: vectors become the columns of a matrix, matrices add their columns."""
    columns = []
    for part in parts:
        part = part if is_array(part) else as_array([_scalar(part, "hcat")])
        if part.ndim > 2:
            raise FunctionCallError("`hcat` joins vectors and matrices")
        columns.append(part.reshape(-1, 1) if part.ndim == 1 else part)
    rows = sorted({column.shape[0] for column in columns})
    if len(rows) > 1:
        raise FunctionCallError(f"`hcat` of columns with different lengths {rows}")
    return np.concatenate(columns, axis=1)


def _gravity_acceleration_2d():
    # The World's g * n with the defaults g = 9.80665, n = [0, -1] (excavator scene 2.1).
    return as_array([sympy.Integer(0), sympy.Float(-9.80665)])


ELEMENTARY: dict[str, FunctionImpl] = {
    **{name: elementwise(name, fn, 1) for name, fn in {
        "sin": sympy.sin, "cos": sympy.cos, "tan": sympy.tan, "asin": sympy.asin,
        "acos": sympy.acos, "atan": sympy.atan, "sinh": sympy.sinh, "cosh": sympy.cosh,
        "tanh": sympy.tanh, "exp": sympy.exp, "log": sympy.log, "log10": _log10,
        "sqrt": sympy.sqrt, "abs": sympy.Abs, "sign": sympy.sign, "floor": sympy.floor,
        "ceil": sympy.ceiling,
    }.items()},
    "atan2": elementwise("atan2", sympy.atan2, 2),
    "min": _reduce("min", sympy.Min),
    "max": _reduce("max", sympy.Max),
    "clamp": FunctionImpl("clamp", _clamp, 3, 3),
    "norm": FunctionImpl("norm", _norm, 1, 1),
    "dot": FunctionImpl("dot", _dot, 2, 2),
    "sum": FunctionImpl("sum", _sum, 1, 1),
    "prod": FunctionImpl("prod", lambda v: sympy.Mul(*v.ravel().tolist()) if is_array(v) else v,
                         1, 1),
    "cross": FunctionImpl("cross", _cross, 2, 2),
    "transpose": FunctionImpl("transpose", _transpose, 1, 1),
    "length": FunctionImpl("length", _length, 1, 1),
    "hcat": FunctionImpl("hcat", lambda *columns: _hcat(columns), 1, None),
    # Julia's `identity`: published translations wrap selections in it
    "identity": FunctionImpl("identity", lambda value: value, 1, 1),
}

# ------------------------------------------------------------------------------ the registry

class FunctionRegistry:
    """Library functions keyed by fully qualified name, plus the elementary ones.

    Libraries add functions with `register_function(name, impl)` or by shipping a
    `dyad_functions.py` in a package folder (loaded lazily by `load_plugin`).
    """

    def __init__(self) -> None:
        self._functions: dict[str, FunctionImpl] = {}
        self._loaded_plugins: set[Path] = set()

    def register(self, name: str, impl: Callable[..., Value] | FunctionImpl,
                 min_args: int = 0, max_args: int | None = None, doc: str = "") -> None:
        if not isinstance(impl, FunctionImpl):
            impl = FunctionImpl(name, impl, min_args, max_args, doc)
        self._functions[name] = impl

    def get(self, qualified_name: str) -> FunctionImpl | None:
        return self._functions.get(qualified_name)

    def names(self) -> list[str]:
        return sorted(self._functions)

    def load_plugin(self, path: Path) -> None:
        """Execute a library's `dyad_functions.py`; it must define `register(registry)`."""
        path = path.resolve()
        if path in self._loaded_plugins or not path.is_file():
            return
        self._loaded_plugins.add(path)
        spec = importlib.util.spec_from_file_location(f"dyad_plugin_{len(self._loaded_plugins)}",
                                                      path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        register = getattr(module, "register", None)
        if register is None:
            raise FunctionCallError(f"{path}: a function plugin must define `register(registry)`")
        register(self)


GLOBAL_REGISTRY = FunctionRegistry()


def register_function(name: str, impl: Callable[..., Value] | FunctionImpl, min_args: int = 0,
                      max_args: int | None = None, doc: str = "") -> None:
    """Make `impl` callable from every model as `name` (a fully qualified name)."""
    GLOBAL_REGISTRY.register(name, impl, min_args, max_args, doc)


register_function("MultibodyComponents.PlanarMechanics.gravity_acceleration_2d",
                  _gravity_acceleration_2d, 0, 0, "world gravity vector g * n = [0, -9.80665]")


PI = sympy.Float(math.pi)
# Names every expression knows, unless a member or binding of the scope takes them.
CONSTANTS = {"pi": PI, "π": PI, "Inf": sympy.oo}
