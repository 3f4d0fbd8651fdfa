"""`dataset_interpolation(...)` and `Kind(values, times)`: the interpolators a Dyad library builds
from data, in every form Dyad's documentation of BlockComponents uses (help.juliahub.com,
BlockComponents `Interpolation`, `ScalarInterpolation`, `Tables.InterpolatedTable`):

    dataset_interpolation(kind, dataset)                          # the dataset's one dependent var
    dataset_interpolation(kind, dataset["y"], dataset["t"])       # values, then times: columns
    dataset_interpolation(kind, dataset["y"], dataset["t"], extrapolation)  # an ExtrapolationType
    dataset_interpolation(kind, dataset[only(get_dependent_vars(dataset))],
                          dataset[get_independent_var(dataset)])
    dataset_interpolation(kind, "data.csv", "y", "t")             # a file, its value and time columns
    dataset_interpolation(kind1, axis1, kind2, axis2, data)       # a 2-D table (table2d.py)

Each gives the piecewise polynomial of compiler/model/interpolation.py (the two-dimensional form a
table2d.Table2D), or None when a value it needs is not given where it is used (a component checked
on its own). `evaluate_object` is compiler/model/object_values.py's, passed in so that this module
does not import it back.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

from compiler.errors import DyadError, Note, Span
from compiler.model import datasets, table2d
from compiler.model.interpolation import EXTRAPOLATIONS, KINDS, InterpolationError, \
    InterpolationKind, PiecewisePolynomial, extrapolated
from compiler.syntax import ast

Structural = Callable[[ast.Expr, Any], Any]
EvaluateObject = Callable[[ast.Expr, Any, Structural], Any]
_COLUMN_OF = {"get_independent_var": "independent"}     # `dataset[get_independent_var(dataset)]`
EXTRAPOLATION_TYPE = "BlockComponents.Tables.ExtrapolationType"
Interpolant = PiecewisePolynomial | table2d.Table2D


def dataset_interpolation(call: ast.Call, scope: Any, structural: Structural,
                          evaluate_object: EvaluateObject) -> Interpolant | None:
    if call.kwargs:
        raise DyadError("`dataset_interpolation` takes no keyword arguments in dyadc", call.span)
    if len(call.args) == 5:
        return _table(call, scope, structural)
    if len(call.args) not in (2, 3, 4):
        raise DyadError(f"`dataset_interpolation` takes (kind, dataset), (kind, values, times) or "
                        f"(kind, file, value_column, time_column), got {len(call.args)} "
                        f"arguments", call.span)
    kind = _kind(call.args[0], scope, structural, evaluate_object)
    if len(call.args) == 2:
        return _of_dataset(kind, call, scope, structural, evaluate_object)
    if len(call.args) == 4 and _is_file_name(call.args[1], scope, structural):
        return _of_file(kind, call, scope, structural)
    columns = [_column(arg, scope, structural, evaluate_object) for arg in call.args[1:3]]
    how = _extrapolation(call.args[3], scope, structural) if len(call.args) == 4 else "Extension"
    if kind is None or how is None or any(column is None for column in columns):
        return None
    (u, u_label), (t, t_label) = columns
    table = _build(kind, u, t, f"{kind.name} of {u_label} over {t_label}", call.span, None)
    try:
        return extrapolated(table, t[0], t[-1], how)
    except InterpolationError as exc:
        raise DyadError(f"cannot extrapolate {table.label}: {exc}", call.args[3].span) from None


def _table(call: ast.Call, scope: Any, structural: Structural) -> table2d.Table2D | None:
    """`dataset_interpolation(kind1, axis1, kind2, axis2, data)`: compiler/model/table2d.py."""
    kind1, kind2 = (_dimension(call.args[k], scope, structural) for k in (0, 2))
    values = [structural(call.args[k], scope) for k in (1, 3, 4)]
    if kind1 is None or kind2 is None or any(value is None for value in values):
        return None
    axis1, axis2 = (_floats(values[k], call.args[1 + 2 * k]) for k in (0, 1))
    try:
        return table2d.build(kind1, axis1, kind2, axis2, values[2], f"the table at {call.span}")
    except InterpolationError as exc:
        raise DyadError(f"cannot interpolate the two-dimensional table: {exc}", call.span) from None


def _dimension(expr: ast.Expr, scope: Any, structural: Structural) -> str | None:
    """The one-dimensional kind an `InterpolationDimension` member builds (None: not given here)."""
    if isinstance(expr, ast.Ref) and len(expr.parts) == 1 and expr.parts[0].name in KINDS:
        raise DyadError(f"a two-dimensional table interpolates along each axis as a member of "
                        f"`{table2d.DIMENSION_TYPE}` says, not `{expr.parts[0].name}`", expr.span,
                        hint=f"write e.g. {table2d.DIMENSION_TYPE}.LinearInterpolationDimension()")
    name = _enum_member(expr, scope, structural, table2d.DIMENSION_TYPE, "an argument")
    if name is not None and name not in table2d.DIMENSION_KINDS:
        raise DyadError(f"`{name}` is not supported by dyadc yet: Dyad documents only its "
                        f"highest derivative order, not the degree or the knots of its B-spline",
                        getattr(expr, "span", None),
                        hint=f"use one of {', '.join(table2d.DIMENSION_KINDS)}")
    return table2d.DIMENSION_KINDS.get(name)


def _enum_member(expr: ast.Expr, scope: Any, structural: Structural, enum: str,
                 which: str) -> str | None:
    """The member of `enum` that `expr` gives, by name (None: not given here)."""
    value = structural(expr, scope)
    if value is None:
        return None
    found = scope.lexical.library.find(enum)
    members = found.definition.members if found is not None else ()
    try:
        position = int(value)
    except (TypeError, ValueError):
        position = 0
    if not 1 <= position <= len(members):
        raise DyadError(f"{which} of `dataset_interpolation` is not a member of `{enum}`",
                        getattr(expr, "span", None), hint=f"write e.g. {enum}.{members[0]}()"
                        if members else None)
    return members[position - 1]


def _is_file_name(expr: ast.Expr, scope: Any, structural: Structural) -> bool:
    """The file form's second argument is a string; the column form's a column or a vector."""
    if isinstance(expr, ast.Ref) and expr.parts[-1].indices:
        return False
    return isinstance(structural(expr, scope), str)


def _extrapolation(expr: ast.Expr, scope: Any, structural: Structural) -> str | None:
    """The name of the `ExtrapolationType` member `expr` gives (None: not given here)."""
    how = _enum_member(expr, scope, structural, EXTRAPOLATION_TYPE, "the fourth argument")
    if how is not None and how not in EXTRAPOLATIONS:
        raise DyadError(f"extrapolation `{how}` is not supported by dyadc yet",
                        getattr(expr, "span", None), hint=f"use one of {', '.join(EXTRAPOLATIONS)}")
    return how


def _of_dataset(kind: InterpolationKind | None, call: ast.Call, scope: Any, structural: Structural,
                evaluate_object: EvaluateObject) -> PiecewisePolynomial | None:
    dataset = evaluate_object(call.args[1], scope, structural)
    if kind is None or dataset is None:
        return None                         # not given here (a component checked alone)
    if not isinstance(dataset, datasets.Dataset):
        raise DyadError("the second argument of `dataset_interpolation` is not a DyadDataset",
                        call.span)
    if len(dataset.dependent_vars) != 1:
        raise DyadError(f"`dataset_interpolation` interpolates one dependent variable, but the "
                        f"dataset names {len(dataset.dependent_vars)}", call.span,
                        notes=[Note("the dataset is declared here", dataset.span)])
    name = dataset.dependent_vars[0]
    return _build(kind, list(dataset.column(name)), list(dataset.column(dataset.independent_var)),
                  f"{kind.name} of `{name}` over `{dataset.independent_var}` in {dataset.label}",
                  call.span, dataset.span)


def _of_file(kind: InterpolationKind | None, call: ast.Call, scope: Any,
             structural: Structural) -> PiecewisePolynomial | None:
    name, dependent, independent = (_string(arg, scope, structural, what) for arg, what in zip(
        call.args[1:], ("the file", "the value column", "the time column")))
    if kind is None:
        return None
    dataset = read_file_dataset(name, independent, (dependent,), scope, call.span)
    return _build(kind, list(dataset.column(dependent)), list(dataset.column(independent)),
                  f"{kind.name} of `{dependent}` over `{independent}` in {dataset.label}",
                  call.span, None)


def read_file_dataset(name: str, independent: str, dependent: tuple[str, ...], scope: Any,
                      span: Span | None) -> datasets.Dataset:
    """The columns of data file `name` (found as DyadDataset finds it) written at `span`."""
    return datasets.from_csv(locate_data_file(name, scope, span), independent, dependent, span)


def locate_data_file(name: str, scope: Any, span: Span | None) -> Path:
    """Data file `name` as a DyadDataset written at `span` finds it, noted as a source read."""
    library = scope.lexical.library
    path = datasets.locate(name, span, list(getattr(library, "roots", [])))
    _note_read(library, datasets.candidates_read(name, span) + [path])
    return path


def _note_read(library: Any, paths: list[Path]) -> None:
    """A cached compile depends on the data file and on every place looked at before it (a file
    added there later would be read instead): the recording library notes them as sources."""
    noted = getattr(library, "read_files", None)
    if noted is not None:
        noted.update(paths)


def _column(expr: ast.Expr, scope: Any, structural: Structural,
            evaluate_object: EvaluateObject) -> tuple[list[float], str] | None:
    """A column `dataset[name]` (its values and a label), or a vector known at compile time."""
    if isinstance(expr, ast.Ref) and len(expr.parts[-1].indices) == 1:
        last = expr.parts[-1]
        base = ast.Ref(expr.parts[:-1] + (ast.RefPart(last.name, ()),), expr.span)
        dataset = evaluate_object(base, scope, structural)
        if dataset is None and _names_object(base, scope):
            return None
        if isinstance(dataset, datasets.Dataset):
            name = _column_name(last.indices[0], dataset, scope, structural)
            if name not in dict(dataset.columns):
                raise DyadError(f"the dataset has no column `{name}`; it has "
                                f"{', '.join(dict(dataset.columns))}", expr.span,
                                notes=[Note("the dataset is declared here", dataset.span)])
            return list(dataset.column(name)), f"`{name}` in {dataset.label}"
    return _floats(structural(expr, scope), expr), f"the values at {expr.span}"


def _names_object(ref: ast.Ref, scope: Any) -> bool:
    return len(ref.parts) == 1 and ref.parts[0].name in getattr(scope.node, "path_fields", {})


def _column_name(index: ast.Expr, dataset: datasets.Dataset, scope: Any,
                 structural: Structural) -> str:
    """`"y"`, `get_independent_var(ds)`, `only(get_dependent_vars(ds))`."""
    if isinstance(index, ast.Call) and index.function in _COLUMN_OF and len(index.args) == 1:
        return dataset.independent_var
    if isinstance(index, ast.Call) and index.function in ("only", "first") and len(index.args) == 1:
        inner = index.args[0]
        if isinstance(inner, ast.Call) and inner.function == "get_dependent_vars":
            if index.function == "only" and len(dataset.dependent_vars) != 1:
                raise DyadError(f"`only(get_dependent_vars(...))` needs one dependent variable, "
                                f"but the dataset names {len(dataset.dependent_vars)}", index.span,
                                notes=[Note("the dataset is declared here", dataset.span)])
            return dataset.dependent_vars[0]
    value = structural(index, scope)
    if not isinstance(value, str):
        raise DyadError("a dataset's column is selected by its name (a string)",
                        getattr(index, "span", None))
    return value


def direct_interpolation(call: ast.Call, scope: Any, structural: Structural) -> PiecewisePolynomial:
    """`LinearInterpolation(values, times)`."""
    if len(call.args) != 2 or call.kwargs:
        raise DyadError(f"`{call.function}(values, times)` takes two arrays (dyadc supports no "
                        f"options)", call.span)
    u, t = (_floats(structural(arg, scope), arg, call.function) for arg in call.args)
    return _build(InterpolationKind(call.function), u, t, f"{call.function} at {call.span}",
                  call.span, None)


def _kind(expr: ast.Expr, scope: Any, structural: Structural,
          evaluate_object: EvaluateObject) -> InterpolationKind | None:
    value = evaluate_object(expr, scope, structural)
    if value is None or isinstance(value, InterpolationKind):
        return value
    raise DyadError(f"not an interpolation kind; dyadc knows {', '.join(KINDS)}",
                    getattr(expr, "span", None))


def _string(expr: ast.Expr, scope: Any, structural: Structural, what: str) -> str:
    value = structural(expr, scope)
    if not isinstance(value, str):
        raise DyadError(f"`dataset_interpolation`: {what} must be a string",
                        getattr(expr, "span", None))
    return value


def _floats(value: Any, expr: Any, function: str = "dataset_interpolation") -> list[float]:
    import numpy as np
    span = getattr(expr, "span", None)
    if not isinstance(value, np.ndarray) or value.ndim != 1:
        raise DyadError(f"`{function}` takes vectors of numbers", span)
    try:
        return [float(v) for v in value]
    except (TypeError, ValueError):
        raise DyadError(f"`{function}` needs numbers known at compile time", span) from None


def _build(kind: InterpolationKind, u: list[float], t: list[float], label: str, span: Span | None,
           data_span: Span | None) -> PiecewisePolynomial:
    try:
        return kind.build(u, t, label)
    except InterpolationError as exc:
        raise DyadError(f"cannot interpolate {label}: {exc}", span,
                        notes=[Note("the dataset is declared here", data_span)] if data_span else
                        []) from None
