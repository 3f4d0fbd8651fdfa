"""Values of parameters that hold Julia objects dyadc can build: datasets and interpolators.

A Dyad library passes data to its interpolation block as Julia objects:

    structural parameter dataset::DyadDataset = DyadDataset("data.csv", independent_var = "ts",
                                                            dependent_vars = ["data"])
    interp = Interpolation(interpolation_type = LinearInterpolation, dataset = dataset)
    ...
    final parameter interpolator::RealInterpolator = dataset_interpolation(interpolation_type, dataset)
    y = interpolator(u)

Such a parameter (a `Native` or function type, or a value naming an interpolation kind) keeps its
binding here instead of becoming a numeric parameter (compiler/model/instantiate.py). When an
equation calls it (`interpolator_call`, one of the object calls of compiler/model/object_calls.py),
`object_value` evaluates the binding with the rules below; a value it cannot build (no binding, a Julia call it does not know) is None, and
the call stays opaque as before: enough for `dyadc check`, refused by a run.

- `DyadDataset(...)`: compiler/model/datasets.py; `DyadInterpolationTable2D(...)`:
  compiler/model/datasets_2d.py, its parts read back by name (`object_part`);
  `LinearInterpolation`, ... : the kinds of
  compiler/model/interpolation.py;
- `dataset_interpolation(...)` in each of its forms and `Kind(values, times)` directly:
  compiler/model/interpolation_values.py (BlockComponents' Julia helper of that name, whose
  meaning dyadc implements itself);
- a name of another such parameter: its value, in the scope that binding was written in.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

from compiler.errors import DyadError, Span
from compiler.julia.objects import Evaluator, opaque, path_field_of
from compiler.model import datasets, datasets_2d, interpolation, interpolation_values, table2d
from compiler.model.interpolation import KINDS, InterpolationKind, PiecewisePolynomial
from compiler.syntax import ast

# DyadData's time series takes the same arguments as its dataset (help.juliahub.com, "Working
# with Data"): a file, `independent_var` and `dependent_vars`.
_DATASET_FUNCTIONS = ("DyadDataset", "DyadData.DyadDataset", "DyadTimeseries",
                      "DyadData.DyadTimeseries")
_INTERPOLATE_FUNCTION = "dataset_interpolation"
_TABLE_2D_FUNCTIONS = ("DyadInterpolationTable2D", "DyadData.DyadInterpolationTable2D")
_TABLE_2D_NAMES = ("axis1_name", "axis2_name", "data_name")

Structural = Callable[[ast.Expr, Any], Any]     # a compile-time value of an expression in a scope


@dataclass
class ObjectBinding:
    """The expression a Julia-object parameter is bound to and the scope it was written in."""
    path: str
    expr: ast.Expr | None
    scope: Any                                  # compiler.model.expressions.EvalScope
    span: Span | None
    _state: str = "new"
    _value: Any = field(default=None, repr=False)


def winning_binding(entries: list, decl: Any, own_scope: Any) -> tuple[ast.Expr | None, Any]:
    """The binding that wins among a declaration's modifiers (outermost first) and its default,
    as for numeric parameters."""
    valued = [entry for entry in entries if entry.mod.value is not None]
    if valued:
        return valued[0].mod.value, valued[0].scope
    return getattr(decl, "default", None), own_scope


def names_julia_object(expr: ast.Expr | None, scope: Any) -> bool:
    """Is a (numeric-typed) parameter's value a Julia object after all: an interpolation kind
    (`interpolation_type::Real = LinearInterpolation`), or another such parameter?"""
    if not isinstance(expr, ast.Ref) or len(expr.parts) != 1 or expr.parts[0].indices:
        return False
    name = expr.parts[0].name
    node = scope.node
    if name in getattr(node, "path_fields", {}):
        return True
    return name in KINDS and name not in scope.bindings and name not in node.member_names()


def record(node: Any, name: str, expr: ast.Expr | None, scope: Any, span: Span | None) -> None:
    path = f"{node.path}.{name}" if node.path else name
    node.object_bindings[name] = ObjectBinding(path, expr, scope, span)


def interpolator_call(call: ast.Call, scope: Any, evaluator: Evaluator) -> Any:
    """`interpolator(u)` through a Julia-object parameter of the scope's node: the interpolant
    applied to `u` when dyadc could build it, else an opaque function of the numeric arguments;
    None when `call` is not such a call."""
    node = scope.node
    if "." in call.function or call.function not in getattr(node, "path_fields", {}):
        return None
    numeric = [evaluator.value(arg, scope) for arg in call.args
               if path_field_of(arg, node) is None]
    table = object_value(node, call.function, evaluator.structural)
    path = f"{node.path}.{call.function}" if node.path else call.function
    if isinstance(table, PiecewisePolynomial):
        return applied(table, path, numeric, call.span)
    if isinstance(table, table2d.Table2D):
        return table2d.applied(table, path, numeric, call.span)
    return opaque(call.function, numeric)


def object_value(node: Any, name: str, structural: Structural) -> Any:
    """The value of Julia-object parameter `name` of `node`; None when dyadc cannot build it."""
    binding = getattr(node, "object_bindings", {}).get(name)
    if binding is None or binding.expr is None:
        return None
    if binding._state == "done":
        return binding._value
    if binding._state == "evaluating":
        raise DyadError(f"`{binding.path}` is defined in terms of itself", binding.span)
    binding._state = "evaluating"
    try:
        binding._value = evaluate_object(binding.expr, binding.scope, structural)
    finally:
        binding._state = "new"
    binding._state = "done"
    return binding._value


def applied(table: PiecewisePolynomial, path: str, arguments: list, span: Span | None) -> Any:
    """`interpolator(u)` in an equation: the interpolant named `path` applied to `u`."""
    if len(arguments) != 1:
        raise DyadError(f"`{path}` interpolates one argument, got {len(arguments)}", span)
    return interpolation.applied_to(table, path, arguments[0])


def evaluate_object(expr: ast.Expr, scope: Any, structural: Structural) -> Any:
    if isinstance(expr, ast.Ref):
        return _reference(expr, scope, structural)
    if isinstance(expr, ast.Call):
        function = expr.function
        if function in _DATASET_FUNCTIONS:
            return _dataset(expr, scope, structural)
        if function in _TABLE_2D_FUNCTIONS:
            return _table_2d(expr, scope, structural)
        if function.rpartition(".")[2] == _INTERPOLATE_FUNCTION:
            return interpolation_values.dataset_interpolation(expr, scope, structural,
                                                              evaluate_object)
        if function in KINDS and function not in scope.node.member_names():
            return interpolation_values.direct_interpolation(expr, scope, structural)
    return None


def _reference(ref: ast.Ref, scope: Any, structural: Structural) -> Any:
    if any(part.indices for part in ref.parts):
        return None
    node = scope.node
    for part in ref.parts[:-1]:
        node = getattr(node, "children", {}).get(part.name)
        if node is None:
            return None
    name = ref.parts[-1].name
    if name in getattr(node, "path_fields", {}):
        return object_value(node, name, structural)
    if len(ref.parts) == 1 and name in KINDS and name not in scope.bindings \
            and name not in node.member_names():
        return InterpolationKind(name)
    return None


# ------------------------------------------------------------------------------ DyadDataset

def _dataset(call: ast.Call, scope: Any, structural: Structural) -> datasets.Dataset:
    keywords = {k.name: k.value for k in call.kwargs}
    unknown = sorted(set(keywords) - {"independent_var", "dependent_vars"})
    if unknown:
        raise DyadError(f"DyadDataset: dyadc does not support the option `{unknown[0]}` (it reads "
                        f"comma-, tab- or semicolon-separated files with a header row)", call.span)
    for needed in ("independent_var", "dependent_vars"):
        if needed not in keywords:
            raise DyadError(f"DyadDataset needs `{needed} = ...`", call.span)
    independent = _string(keywords["independent_var"], scope, structural, "independent_var")
    dependent = _strings(keywords["dependent_vars"], scope, structural)
    if len(call.args) == 2:
        owner, name = (_string(arg, scope, structural, "a JuliaHub dataset's owner and name")
                       for arg in call.args)
        raise datasets.remote(owner, name, call.span)
    if len(call.args) != 1:
        raise DyadError(f"DyadDataset takes a file name or a matrix (or a JuliaHub owner and "
                        f"name), got {len(call.args)} arguments", call.span)
    value = structural(call.args[0], scope)
    if isinstance(value, str):
        return interpolation_values.read_file_dataset(value, independent, dependent, scope,
                                                      call.span)
    return datasets.from_matrix(value, independent, dependent, call.span)


def _string(expr: ast.Expr, scope: Any, structural: Structural, what: str) -> str:
    value = structural(expr, scope)
    if not isinstance(value, str):
        raise DyadError(f"DyadDataset: {what} must be a string", getattr(expr, "span", None))
    return value


def _strings(expr: ast.Expr, scope: Any, structural: Structural) -> tuple[str, ...]:
    if not isinstance(expr, ast.ArrayLit) or expr.is_matrix or not expr.elements:
        raise DyadError("DyadDataset: dependent_vars must be a list of column names, e.g. "
                        "[\"y\"]", getattr(expr, "span", None))
    return tuple(_string(element, scope, structural, "each dependent variable")
                 for element in expr.elements)




# ------------------------------------------------------------------- DyadInterpolationTable2D

def _table_2d(call: ast.Call, scope: Any, structural: Structural) -> datasets_2d.GridDataset:
    keywords = {k.name: k.value for k in call.kwargs}
    unknown = sorted(set(keywords) - set(_TABLE_2D_NAMES))
    missing = [name for name in _TABLE_2D_NAMES if name not in keywords]
    if unknown or missing or len(call.args) != 1:
        raise DyadError(f"DyadInterpolationTable2D takes a file name and "
                        f"{', '.join(f'`{n} = ...`' for n in _TABLE_2D_NAMES)}" +
                        (f"; dyadc does not support the option `{unknown[0]}`" if unknown else ""),
                        call.span)
    names = tuple(_string(keywords[name], scope, structural, name) for name in _TABLE_2D_NAMES)
    file = _string(call.args[0], scope, structural, "the file")
    path = interpolation_values.locate_data_file(file, scope, call.span)
    return datasets_2d.from_csv(path, names, call.span)


def object_part(ref: ast.Ref, scope: Any, structural: Structural) -> Any:
    """`table["name"]` as a value, `table` a dataset parameter of the scope's node: a 2-D table's
    axis (a vector) or data (a matrix), or a dataset's column (a vector)."""
    part = ref.parts[0]
    value = object_value(scope.node, part.name, structural)
    name = structural(part.indices[0], scope)
    if not isinstance(name, str):
        raise DyadError(f"a part of `{part.name}` is selected by its name (a string)", ref.span)
    if isinstance(value, datasets_2d.GridDataset):
        return value.part(name, ref.span)
    if isinstance(value, datasets.Dataset) and name in dict(value.columns):
        import numpy as np
        import sympy
        return np.array([sympy.Float(v) for v in value.column(name)], dtype=object)
    if isinstance(value, datasets.Dataset):
        raise DyadError(f"the dataset has no column `{name}`; it has "
                        f"{', '.join(dict(value.columns))}", ref.span)
    raise DyadError(f"`{part.name}` is not a dataset dyadc can read, so `{ref.dotted}[...]` has no "
                    f"value here", ref.span)
