"""One model written several equivalent ways, every equation alike: as written, with its sides
swapped, scaled by 1000, or with all terms on one side. The hard cases' accuracy tests run each
formulation against the same independent reference (a number may not depend on how a model is
written, issue 25)."""
from __future__ import annotations

import dataclasses
from pathlib import Path

from compiler.syntax import ast
from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_file
from tests.metamorphic.rewrites import printable

THOUSAND = ast.Number(1000.0, text="1000.0")

FORMULATIONS = {
    "as written": lambda r: r,
    "sides swapped": lambda r: dataclasses.replace(r, lhs=r.rhs, rhs=r.lhs),
    "scaled by 1000": lambda r: dataclasses.replace(r, lhs=ast.BinaryOp("*", THOUSAND, r.lhs),
                                                    rhs=ast.BinaryOp("*", THOUSAND, r.rhs)),
    "one side": lambda r: dataclasses.replace(r, lhs=ast.BinaryOp("-", r.lhs, r.rhs), rhs=ast.Number(0.0, text="0.0")),
}


def every_equation(component: ast.ComponentDef, rewrite) -> ast.ComponentDef:
    relations = tuple(printable(rewrite(r)) if isinstance(r, ast.Equation) else r for r in component.relations)
    return dataclasses.replace(component, relations=relations)


def write_formulation(source: Path, formulation: str, folder: Path) -> Path:
    """`source` (one component) with every equation rewritten as FORMULATIONS[formulation] says,
    reprinted by the project's formatter into `folder` under the same file name."""
    file = parse_file(source)
    (component,) = file.definitions
    path = folder / source.name
    rewritten = every_equation(component, FORMULATIONS[formulation])
    path.write_text(format_file(dataclasses.replace(file, definitions=(rewritten,))), encoding="utf-8")
    return path
