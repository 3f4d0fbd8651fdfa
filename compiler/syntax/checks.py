"""Checks that need only one file's AST (no library): duplicate names, `der` of a parameter,
malformed `der` calls."""
from __future__ import annotations

import dataclasses

from compiler.errors import DyadError, Note
from compiler.syntax import ast


def check_file(file: ast.File) -> None:
    _check_unique([(d.name, d.span) for d in file.definitions], "definition", "this file")
    for definition in file.definitions:
        if isinstance(definition, (ast.ComponentDef, ast.AnalysisDef)):
            _check_body(definition)
        elif isinstance(definition, ast.ConnectorDef):
            _check_unique([(f.name, f.span) for f in definition.fields], "field",
                          f"connector `{definition.name}`")
        elif isinstance(definition, ast.EnumDef):
            _check_unique([(m, definition.span) for m in definition.members], "member",
                          f"enum `{definition.name}`")


def _check_unique(named: list, what: str, where: str) -> None:
    first_seen = {}
    for name, span in named:
        if name in first_seen:
            raise DyadError(f"duplicate {what} `{name}` in {where}", span,
                            notes=[Note(f"`{name}` is first declared here", first_seen[name])])
        first_seen[name] = span


def _check_body(definition) -> None:
    kind = "analysis" if isinstance(definition, ast.AnalysisDef) else "component"
    _check_unique([(d.name, d.span) for d in definition.declarations], "declaration",
                  f"{kind} `{definition.name}`")
    parameters = {d.name: d for d in definition.declarations if isinstance(d, ast.ParameterDecl)}
    for call in _calls(definition.relations):
        if call.function not in ("der", "D"):
            continue
        if len(call.args) != 1 or call.kwargs:
            raise DyadError(f"`{call.function}` takes exactly one argument, the expression to "
                            "differentiate in time", call.span)
        target = call.args[0]
        if isinstance(target, ast.Ref) and len(target.parts) == 1 \
                and target.parts[0].name in parameters:
            parameter = parameters[target.parts[0].name]
            raise DyadError(
                f"`{call.function}({parameter.name})` differentiates a parameter, which is "
                "constant in time",
                call.span, hint=f"declare `{parameter.name}` as a `variable` if it changes",
                notes=[Note(f"`{parameter.name}` is declared as a parameter here",
                            parameter.span)])


def _calls(root):
    """Every Call inside a tree of AST nodes and tuples (an explicit stack: sums can be long)."""
    stack = [root]
    while stack:
        node = stack.pop()
        if isinstance(node, tuple):
            stack.extend(reversed(node))
            continue
        if not dataclasses.is_dataclass(node):
            continue
        if isinstance(node, ast.Call):
            yield node
        stack.extend(getattr(node, field.name) for field in reversed(dataclasses.fields(node))
                     if field.name != "span")
