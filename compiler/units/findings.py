"""Unit findings as a user reads them: `FILE:LINE:COL: error: units do not match in this
equation: left side V, right side A`, the term underlined, each term's unit in SI base form, the
instances that use the line, and a hint. Plain data, so that the compilation cache keeps them.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from compiler.errors import DyadError, Note, Span, source_line
from compiler.units.constraints import Mismatch
from compiler.units.system import Unit, describe

WHAT = {"equation": "this equation", "sum": "this sum", "binding": "this binding",
        "connect": "this connection", "branch": "the branches of this `if`",
        "comparison": "this comparison", "array": "this array", "range": "this range",
        "argument": "the arguments of this call", "exponent": "this power", "base": "this power"}
HINTS = {
    "equation": "every term of an equation has one unit; check the units declared for the names "
                "in it, or multiply the odd term by the quantity it lacks",
    "sum": "every term of a sum has one unit; check the units declared for the names in it",
    "binding": "the value must have the unit of the name it is given to; pass a parameter of "
               "that quantity type",
    "connect": "connected ends carry one quantity: connect connectors of the same physical domain, "
               "or signals of one unit",
    "argument": "exp, log, sin and the like take dimensionless arguments; divide by a reference "
                "value of the same unit",
    "base": "divide the base by a reference value of its unit (e.g. `(d / d_ref) ^ n` with "
            "`parameter d_ref::Length = 1`), or write a constant exponent",
    "exponent": "a power with a parameter or variable exponent needs a dimensionless base and "
                "exponent; write a constant exponent for a base with a unit",
}
MAX_PATHS = 3


@dataclass
class Finding:
    message: str
    span: Span | None
    notes: list[tuple[str, Span | None]] = field(default_factory=list)
    hint: str | None = None
    paths: list[str] = field(default_factory=list)
    instance: Span | None = None        # where the first instance in `paths` is declared

    def error(self) -> DyadError:
        """As the located error `--units error` raises (the instances as the last note)."""
        notes = [Note(text, span) for text, span in self.notes]
        notes.append(Note(self.where(), self.instance))
        return DyadError(self.message, self.span, self.hint, notes)

    def where(self) -> str:
        shown = ", ".join(f"`{p}`" if p else "the model itself" for p in self.paths[:MAX_PATHS])
        more = len(self.paths) - MAX_PATHS
        return f"in {shown}" + (f" and {more} more instances" if more > 0 else "")

    def to_dict(self) -> dict:
        return {"message": self.message, "span": _span_dict(self.span), "hint": self.hint,
                "notes": [[text, _span_dict(span)] for text, span in self.notes],
                "paths": list(self.paths), "instance": _span_dict(self.instance)}

    @staticmethod
    def from_dict(data: dict) -> "Finding":
        return Finding(str(data["message"]), _span(data["span"]),
                       [(str(text), _span(span)) for text, span in data["notes"]],
                       data["hint"], [str(p) for p in data["paths"]], _span(data.get("instance")))


def mismatch_finding(mismatch: Mismatch) -> Finding:
    site = mismatch.site
    term_label, reference_label = site.labels
    left_as, right_as = mismatch.labels
    what = WHAT.get(site.kind, "this expression")
    if site.kind in ("argument", "exponent", "base") and site.other is None:
        message = f"{term_label} must be dimensionless, but its unit is {_short(mismatch.right, right_as)}"
        if site.kind == "base":
            message = (f"the base of this power must be dimensionless, since its exponent is not a "
                       f"constant number, but its unit is {_short(mismatch.right, right_as)}")
        notes = [(f"{_text(site.span)} is {_described(mismatch.right, right_as)}", None)]
    else:
        left, right = mismatch.left, mismatch.right
        shown = f"{reference_label} {_short(left, left_as)}, {term_label} {_short(right, right_as)}"
        message = f"units do not match in {what}: {shown}"
        if mismatch.factor is not None:
            message += (f": the same dimension, but they differ by a factor of "
                        f"{_factor_text(mismatch.factor)}")
        reference = _text(site.other) if site.other is not None else reference_label
        notes = [(f"{reference} is {_described(left, left_as)}", site.other or declaration_line(site.declared)),
                 (f"{_text(site.span)} is {_described(right, right_as)}", None)]
    for name, span in mismatch.inferred:
        if span is not None and span != site.span and span != site.other:
            notes.append((f"the unit of `{name}` (declared without one) is inferred here", span))
    hint = HINTS.get(site.kind, HINTS["equation"])
    if mismatch.factor is not None:
        hint = ("declare both in one unit (prefixes included), or convert explicitly with the "
                f"factor {_factor_text(mismatch.factor)} written as a parameter with its unit")
    return Finding(message, site.span, notes, hint, [site.path], site.instance)


def declaration_finding(message: str, span: Span | None, units: Any, hint: str | None = None,
                        declared: Span | None = None) -> Finding:
    notes = [("declared here", declaration_line(declared))] if declared is not None and declared != span else []
    return Finding(message, span, notes, hint, [units.path], units.instance)


def declaration_line(span: Span | None) -> Span | None:
    """A declaration's span without its doc string: the first of its lines that is not one."""
    if span is None:
        return None
    for line in range(span.line, span.end_line + 1):
        text = source_line(span.file, line)
        if text is not None and text.strip() and not text.lstrip().startswith('"'):
            column = len(text) - len(text.lstrip()) + 1
            return Span(span.file, line, column, line, len(text.rstrip()))
    return span


def _short(unit: Unit, declared: str | None = None) -> str:
    return declared if declared else describe(unit).split(" (")[0]


def _described(unit: Unit, declared: str | None) -> str:
    """`kg/s (kg/s)` is said once; a declared unit keeps its spelling, with the SI base form."""
    if not declared:
        return describe(unit)
    base_form = unit.dimension()
    scale = "" if abs(unit.factor - 1.0) < 1e-9 else f"{unit.factor:g} "
    return declared if f"{scale}{base_form}" == declared else f"{declared} ({scale}{base_form})"


def _factor_text(factor: float) -> str:
    return f"{factor:.6g}"


def _text(span: Span | None) -> str:
    """The source text of a one-line span, in backquotes; `this term` when unavailable."""
    if span is None or span.end_line != span.line:
        return "this term"
    line = source_line(span.file, span.line)
    if line is None:
        return "this term"
    return f"`{line[span.column - 1:span.end_column]}`"


def _span_dict(span: Span | None) -> dict | None:
    if span is None:
        return None
    return {"file": span.file, "line": span.line, "column": span.column,
            "end_line": span.end_line, "end_column": span.end_column}


def _span(data: dict | None) -> Span | None:
    return None if data is None else Span(**data)
